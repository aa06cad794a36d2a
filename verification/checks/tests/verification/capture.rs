//! Traced tests of the capture family (quartic criterion, xlim consistency, single-state limit,
//! capture probability) and of the TM state bounds the capture models give (shear illustration,
//! free drift).

use geodesic_capture::{
    CaptureInputs, PulseShape, ShearInputs, StateModel, StateName, THESIS_BOX, TmState, Xlim,
    box_corner, consistency_sum, derive_xlim, is_captured, max_box_scale, quartic_sum,
};
use geodesic_checks::capture::{CaptureCriterion, CaptureSetup, ReleaseVz, ReleaseVzSource};
use geodesic_checks::tm_state::TmStateBounds;
use geodesic_core::trace::{assert_limit, assert_reference};
use geodesic_core::{Basis, Outcome};
use proptest::prelude::*;
use std::sync::Arc;

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

    /// z velocity alone: captured strictly below xlim_vz (12 um/s), not at or above it. Not
    /// traced to CAP-VZ-SINGLE: its 12 um/s is accepted from the thesis's E2E result and xlim_vz
    /// was set from it, so a test comparing the two compares a number with itself (the row says
    /// so: `compliant (accepted; by construction)`).
    #[test]
    fn vz_alone_is_captured_below_12_um_s(v in 0.0f64..30e-6, neg in any::<bool>()) {
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
        let p = StateModel::vz_only().capture_probability(&vz, &x, seed);
        let want = vz.iter().filter(|v| v.abs() < 12e-6).count();
        prop_assert_eq!(p.captured, want);
        prop_assert_eq!(p.n, vz.len());
        // independent reference: the fraction counted directly
        assert_reference(
            "CAP-RELEASE-PROB",
            "fraction of |vz| < 12 um/s counted directly",
            p.probability,
            want as f64 / vz.len() as f64,
            0.0,
        );
    }
}

/// The probability with the default distributions is deterministic for a seed and can only
/// fall when the release velocities grow.
#[test]
fn probability_is_seeded_and_falls_with_velocity() {
    geodesic_core::verifies!("CAP-RELEASE-PROB");
    let x = Xlim::default_set();
    let d = StateModel::new(&CaptureInputs::default_inputs(), THESIS_BOX);
    let vz: Vec<f64> = (0..5000).map(|k| (k % 100) as f64 * 1e-7).collect();
    let a = d.capture_probability(&vz, &x, 9);
    assert_eq!(a, d.capture_probability(&vz, &x, 9));
    let fast: Vec<f64> = vz.iter().map(|v| v + 8e-6).collect();
    let b = d.capture_probability(&fast, &x, 9);
    assert!(b.captured <= a.captured, "{b:?} vs {a:?}");
    assert!(b.captured < b.n, "8-18 um/s must lose some draws: {b:?}");
    // release velocities of 0-10 um/s with the flow-down states: at least 99.73 % captured
    assert_limit("CAP-RELEASE-PROB", a.probability);
}

/// The capture-criterion evidence on the repository's requirements and capture inputs, with
/// rounded values: CAP-QUARTIC asserts its limit; the snapshot is change detection.
#[test]
fn capture_criterion_evidence_snapshot() {
    geodesic_core::verifies!("CAP-QUARTIC", "CAP-XLIM-CONSISTENCY");
    let ctx = geodesic_checks::builtin_context(std::env::temp_dir(), 10, 1);
    let setup = CaptureSetup::of(&ctx).unwrap().unwrap();
    let ev = CaptureCriterion::evidence(&setup, None);
    let value = |i: usize| match &ev[i].outcome {
        Outcome::Measured(q) => q.value,
        Outcome::NotVerified(r) => panic!("{r}"),
    };
    // the corner of the box sits at 1/1.4^4 of the capture boundary (independent reference:
    // thesis ch. 7, the box scales by 1.4)
    geodesic_core::trace::assert_limit("CAP-QUARTIC", value(0));
    geodesic_core::trace::assert_reference(
        "CAP-QUARTIC",
        "thesis ch. 7: box scale 1.4",
        value(0),
        1.4f64.powi(-4),
        1e-6,
    );
    // 7 significant digits stored: the residual is of order 1e-8
    geodesic_core::trace::assert_limit("CAP-XLIM-CONSISTENCY", value(1));
    let rows: Vec<String> = ev
        .iter()
        .map(|e| match &e.outcome {
            Outcome::Measured(q) => format!(
                "{} ({}): {:.6e}",
                e.requirement,
                e.basis.map_or("none", |b| b.as_str()),
                q.value
            ),
            Outcome::NotVerified(r) => format!("{}: not verified ({r})", e.requirement),
        })
        .collect();
    insta::assert_yaml_snapshot!(vec![rows[0].clone(), rows[2].clone()]);
}

/// The shear case is an illustration beside TMS-X/Y-VEL and TMS-X/Y-RATE: both pulse forms,
/// the thesis's printed figures as the independent reference, and never a verdict.
#[test]
fn shear_is_an_illustration() {
    let s = ShearInputs::THESIS;
    let tri_w = s.angular_rate_rad_s(PulseShape::Triangular);
    let rect_w = s.angular_rate_rad_s(PulseShape::Rectangular);
    assert!((rect_w / tri_w - 2.0).abs() < 1e-12);
    // thesis prints 330 urad/s and 2.5 um/s: the rectangular form, rounded
    assert!((rect_w - 330e-6).abs() < 5e-6, "{rect_w}");
    assert!((s.velocity_m_s(PulseShape::Rectangular) - 2.5e-6).abs() < 0.06e-6);
    let ctx = geodesic_checks::builtin_context(std::env::temp_dir(), 10, 1);
    let ev = geodesic_core::Check::run(&TmStateBounds { release: None }, &ctx).unwrap();
    for id in ["TMS-X-VEL", "TMS-Y-VEL", "TMS-X-RATE", "TMS-Y-RATE"] {
        let decided = ev.iter().any(|e| {
            e.requirement == id
                && matches!(e.outcome, Outcome::Measured(_))
                && e.basis != Some(Basis::Illustration)
        });
        assert!(
            !decided,
            "{id} must not be decided by the shear illustration"
        );
        assert!(
            ev.iter()
                .any(|e| e.requirement == id && e.basis == Some(Basis::Illustration))
        );
    }
}

/// Positions and angles at the start of control are flow-downs of the loaded rate limits. The
/// check's closed form (the rate's 99.73 % value, 3 sigma = its limit, times 15 s) against an
/// independent computation: the 99.73 % of |state| over 200 000 states drawn from the capture
/// inputs' state model (the rates drawn, the positions drifted in the same draw), within 2 %
/// (the quantile's sampling sd is 0.44 %). The limit is not asserted: a flow-down meets it only
/// if the assumed rate requirement does, and that one is not verified (the rows say so), so an
/// assertion of the limit on 15 s x the rate limit would be circular.
#[test]
fn drift_flow_downs_match_the_drawn_states() {
    geodesic_core::verifies!(
        "TMS-X-POS",
        "TMS-Y-POS",
        "TMS-X-ANG",
        "TMS-Y-ANG",
        "TMS-Z-ANG"
    );
    let ctx = geodesic_checks::builtin_context(std::env::temp_dir(), 10, 1);
    let ev = geodesic_core::Check::run(&TmStateBounds { release: None }, &ctx).unwrap();
    let model = StateModel::new(&CaptureInputs::default_inputs(), THESIS_BOX);
    let n = 200_000u64;
    let draws: Vec<TmState> = (0..n).map(|k| model.draw(1e-6, 17, k)).collect();
    for (id, s) in [
        ("TMS-X-POS", StateName::X),
        ("TMS-Y-POS", StateName::Y),
        ("TMS-X-ANG", StateName::Thx),
        ("TMS-Y-ANG", StateName::Thy),
        ("TMS-Z-ANG", StateName::Thz),
    ] {
        let e = ev
            .iter()
            .find(|e| e.requirement == id && e.basis == Some(Basis::FlowDown))
            .unwrap_or_else(|| panic!("{id}: no flow-down"));
        let Outcome::Measured(q) = &e.outcome else {
            panic!()
        };
        let mut a: Vec<f64> = draws.iter().map(|d| d.get(s).abs()).collect();
        a.sort_by(f64::total_cmp);
        let sampled = a[(0.9973 * n as f64).ceil() as usize - 1];
        assert_reference(
            id,
            "99.73 % of |state| over 200 000 drawn states",
            q.value,
            sampled,
            0.02,
        );
        // and it takes the rate's requirement as met, which the matrix reports
        assert_eq!(e.assumes.len(), 1, "{id}");
    }
}

/// TMS-Z-POS: offset after 15 s at the release 99.73 % z velocity, from the source the
/// registry wires to the release Monte Carlo (here a known set of velocities).
#[test]
fn z_offset_from_release_velocity() {
    geodesic_core::verifies!("TMS-Z-POS");
    let v: Vec<f64> = (0..10_000).map(|k| f64::from(k) * 1.5e-10).collect();
    let source: ReleaseVzSource = Arc::new(move |_| {
        Ok(ReleaseVz {
            vz_m_s: v.clone(),
            inputs: Default::default(),
        })
    });
    let ctx = geodesic_checks::builtin_context(std::env::temp_dir(), 10, 1);
    let ev = geodesic_core::Check::run(
        &TmStateBounds {
            release: Some(source),
        },
        &ctx,
    )
    .unwrap();
    let e = ev
        .iter()
        .find(|e| e.requirement == "TMS-Z-POS" && e.basis == Some(Basis::Model))
        .unwrap();
    let Outcome::Measured(q) = &e.outcome else {
        panic!()
    };
    // nearest-rank 99.73 % of k x 1.5e-10 (k = 0..9999) is k = 9972, times 15 s
    geodesic_core::trace::assert_reference(
        "TMS-Z-POS",
        "9972 x 1.5e-10 m/s x 15 s",
        q.value,
        9972.0 * 1.5e-10 * 15.0,
        1e-12,
    );
    geodesic_core::trace::assert_limit("TMS-Z-POS", q.value);
}
