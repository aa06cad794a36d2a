//! Traced tests of the capture family (quartic criterion, xlim consistency, single-state limit,
//! capture probability) and of the TM state bounds the capture models give (shear illustration,
//! free drift).

use geodesic_capture::{
    PulseShape, ShearInputs, StateDistribution, StateName, TmState, Xlim, box_corner,
    capture_probability, consistency_sum, derive_xlim, is_captured, max_box_scale, quartic_sum,
};
use geodesic_checks::capture::CaptureCriterion;
use geodesic_checks::tm_state::model_evidence;
use geodesic_core::Outcome;
use geodesic_core::trace::{assert_limit, assert_reference};
use proptest::prelude::*;

/// A state with every component within +-3 x its limit.
fn any_state() -> impl Strategy<Value = TmState> {
    let x = Xlim::default_set();
    let comps: Vec<_> = x.xlim.iter().map(|&l| -3.0 * l..3.0 * l).collect();
    comps.prop_map(|v| TmState(v.try_into().unwrap()))
}

proptest! {
    /// The quartic sum does not decrease when any |x0_i| grows.
    #[test]
    fn criterion_is_monotone_in_every_magnitude(s in any_state(), i in 0usize..12, grow in 1.0f64..4.0) {
        geodesic_core::verifies!("CAP-QUARTIC");
        let x = Xlim::default_set();
        let mut t = s;
        t.0[i] *= grow;
        prop_assert!(quartic_sum(&x, &t) >= quartic_sum(&x, &s));
        // and a captured state stays captured when it shrinks
        let mut u = s;
        u.0[i] /= grow;
        prop_assert!(!is_captured(&x, &s) || is_captured(&x, &u));
    }

    /// Flipping the sign of any state leaves the sum unchanged.
    #[test]
    fn criterion_is_symmetric_in_sign(s in any_state(), i in 0usize..12) {
        geodesic_core::verifies!("CAP-QUARTIC");
        let x = Xlim::default_set();
        let mut t = s;
        t.0[i] = -t.0[i];
        prop_assert_eq!(quartic_sum(&x, &t), quartic_sum(&x, &s));
    }

    /// Any corner of the requirement box scaled to the largest capturable scale sums to 1;
    /// the unscaled corner is captured.
    #[test]
    fn scaled_box_corner_sums_to_one(signs in proptest::collection::vec(any::<bool>(), 12)) {
        geodesic_core::verifies!("CAP-QUARTIC", "CAP-XLIM-CONSISTENCY");
        let x = Xlim::default_set();
        let mut c = box_corner(&x, max_box_scale(&x));
        for (v, neg) in c.0.iter_mut().zip(&signs) {
            if *neg { *v = -*v; }
        }
        assert_reference("CAP-QUARTIC", "analytic: 1 at the largest box scale", quartic_sum(&x, &c), 1.0, 1e-12);
        let mut r = box_corner(&x, 1.0);
        for (v, neg) in r.0.iter_mut().zip(&signs) {
            if *neg { *v = -*v; }
        }
        assert_limit("CAP-QUARTIC", quartic_sum(&x, &r));
    }

    /// The derivation of xlim satisfies the consistency constraint for any requirement box
    /// and any admissible anchor, and then the largest box scale is the box scale.
    #[test]
    fn derived_xlim_is_consistent(
        req in proptest::collection::vec(1e-7f64..1e-2, 12),
        scale in 1.0f64..2.0,
        anchor in 0usize..12,
        room in 1.01f64..10.0,
    ) {
        geodesic_core::verifies!("CAP-XLIM-CONSISTENCY");
        let req: [f64; 12] = req.try_into().unwrap();
        let a = StateName::ALL[anchor];
        let xl = derive_xlim(&req, scale, a, room * scale * req[anchor]).unwrap();
        let x = Xlim { req, xlim: xl, box_scale: scale, source: "test".into() };
        assert_reference("CAP-XLIM-CONSISTENCY", "analytic: 1", consistency_sum(&x), 1.0, 1e-12);
        prop_assert!((max_box_scale(&x) / scale - 1.0).abs() < 1e-12);
    }

    /// z velocity alone: captured strictly below xlim_vz (12 um/s), not at or above it.
    #[test]
    fn vz_alone_is_captured_below_12_um_s(v in 0.0f64..30e-6, neg in any::<bool>()) {
        geodesic_core::verifies!("CAP-VZ-SINGLE");
        let x = Xlim::default_set();
        let mut s = TmState::zero();
        s.set(StateName::Vz, if neg { -v } else { v });
        prop_assert_eq!(is_captured(&x, &s), v < 12e-6);
    }

    /// With the other states at zero, the capture probability is the fraction of |v_z| below
    /// 12 um/s, whatever the seed.
    #[test]
    fn probability_with_zero_states_counts_vz(vz in proptest::collection::vec(-20e-6f64..20e-6, 1..200), seed in any::<u64>()) {
        geodesic_core::verifies!("CAP-RELEASE-PROB");
        let x = Xlim::default_set();
        let p = capture_probability(&vz, &StateDistribution::zeros(), &x, seed);
        let want = vz.iter().filter(|v| v.abs() < 12e-6).count();
        prop_assert_eq!(p.captured, want);
        prop_assert_eq!(p.n, vz.len());
    }
}

/// The probability with the default distributions is deterministic for a seed and can only
/// fall when the release velocities grow.
#[test]
fn probability_is_seeded_and_falls_with_velocity() {
    geodesic_core::verifies!("CAP-RELEASE-PROB");
    let x = Xlim::default_set();
    let d = StateDistribution::default_set();
    let vz: Vec<f64> = (0..5000).map(|k| (k % 100) as f64 * 1e-7).collect();
    let a = capture_probability(&vz, &d, &x, 9);
    assert_eq!(a, capture_probability(&vz, &d, &x, 9));
    let fast: Vec<f64> = vz.iter().map(|v| v + 8e-6).collect();
    let b = capture_probability(&fast, &d, &x, 9);
    assert!(b.captured <= a.captured, "{b:?} vs {a:?}");
    assert!(b.captured < b.n, "8-18 um/s must lose some draws: {b:?}");
}

/// The capture-criterion evidence, with rounded values.
#[test]
fn capture_criterion_evidence_snapshot() {
    geodesic_core::verifies!("CAP-QUARTIC", "CAP-XLIM-CONSISTENCY", "CAP-VZ-SINGLE");
    let ev = CaptureCriterion::evidence(&Xlim::default_set());
    let rows: Vec<String> = ev
        .iter()
        .map(|e| match &e.outcome {
            Outcome::Measured(q) => format!("{}: {:.6e}", e.requirement, q.value),
            Outcome::NotVerified(r) => format!("{}: not verified ({r})", e.requirement),
        })
        .collect();
    // The consistency residual is of order 1e-8 (7 significant digits stored): pin its order.
    let Outcome::Measured(res) = &ev[1].outcome else {
        panic!()
    };
    assert!(res.value < 1e-6);
    insta::assert_yaml_snapshot!(vec![rows[0].clone(), rows[2].clone()]);
}

/// The shear illustration: both forms, which one is used, and the TM state rows it gives.
#[test]
fn shear_illustration_rows() {
    geodesic_core::verifies!("TMS-X-VEL", "TMS-Y-VEL", "TMS-X-RATE", "TMS-Y-RATE");
    let s = ShearInputs::THESIS;
    let tri_w = s.angular_rate_rad_s(PulseShape::Triangular);
    let rect_w = s.angular_rate_rad_s(PulseShape::Rectangular);
    assert!((rect_w / tri_w - 2.0).abs() < 1e-12);
    // thesis prints 330 urad/s and 2.5 um/s: the rectangular form, rounded
    for id in ["TMS-X-RATE", "TMS-Y-RATE"] {
        assert_reference(id, "thesis: 330 urad/s", rect_w, 330e-6, 5.0 / 330.0);
    }
    for id in ["TMS-X-VEL", "TMS-Y-VEL"] {
        let v = s.velocity_m_s(PulseShape::Rectangular);
        assert_reference(id, "thesis: 2.5 um/s", v, 2.5e-6, 0.06 / 2.5);
    }
    assert_eq!(PulseShape::USED, PulseShape::Rectangular);
    let ev = model_evidence();
    let get = |id: &str| {
        let e = ev.iter().find(|e| e.requirement == id).unwrap();
        match &e.outcome {
            Outcome::Measured(q) => q.value,
            Outcome::NotVerified(r) => panic!("{id}: {r}"),
        }
    };
    assert_eq!(get("TMS-X-RATE"), rect_w);
    assert_eq!(get("TMS-Y-RATE"), rect_w);
    assert_eq!(get("TMS-X-VEL"), s.velocity_m_s(PulseShape::Rectangular));
}

/// Offsets after 15 s of free drift at the 5 um/s requirement, and the rows that stay
/// not-verified name a reason.
#[test]
fn drift_offsets_and_reasons() {
    geodesic_core::verifies!(
        "TMS-X-POS",
        "TMS-Y-POS",
        "TMS-X-ANG",
        "TMS-Y-ANG",
        "TMS-Z-ANG",
        "TMS-Z-RATE"
    );
    for e in model_evidence() {
        match (&e.outcome, e.requirement.as_str()) {
            (Outcome::Measured(q), id @ ("TMS-X-POS" | "TMS-Y-POS")) => {
                assert_reference(id, "analytic: 5 um/s x 15 s", q.value, 75e-6, 1e-15 / 75e-6)
            }
            (Outcome::NotVerified(r), "TMS-X-ANG" | "TMS-Y-ANG" | "TMS-Z-ANG" | "TMS-Z-RATE") => {
                assert!(r.len() > 40, "{r}")
            }
            (Outcome::Measured(_), "TMS-X-VEL" | "TMS-Y-VEL" | "TMS-X-RATE" | "TMS-Y-RATE") => {}
            (o, id) => panic!("unexpected {id}: {o:?}"),
        }
    }
}

/// TMS-Z-POS: offset after 15 s at the release 99.73 % z velocity, from the function the
/// registry wires to the release Monte Carlo.
#[test]
fn z_offset_from_release_velocity() {
    geodesic_core::verifies!("TMS-Z-POS");
    let v: Vec<f64> = (0..10_000).map(|k| f64::from(k) * 1e-10).collect();
    let p = geodesic_checks::tm_state::abs_p9973(&v);
    assert!((p - 9972e-10).abs() < 1e-18, "{p}");
    let e = geodesic_checks::tm_state::z_position_evidence(1.5e-6, &Default::default());
    let Outcome::Measured(q) = &e.outcome else {
        panic!()
    };
    // 1.5 um/s (the thesis's 99.73 % release velocity) for 15 s: 22.5 um
    assert_reference(
        "TMS-Z-POS",
        "analytic: 1.5 um/s x 15 s",
        q.value,
        22.5e-6,
        1e-15 / 22.5e-6,
    );
}
