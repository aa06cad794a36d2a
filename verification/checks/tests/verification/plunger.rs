//! Traced tests of the plunger attraction after the release (thesis ch. 7; issue 16 item 1):
//! the check's evidence against the requirements' limits, and the simulation against an
//! independent closed form (the impulse of `A / g^2 + B / g` over a gap opening at a constant
//! rate, the TM drifting at its initial velocity).

use geodesic_charge::EPS0_F_M;
use geodesic_charge::plunger::{PlungerCapacitance, Retraction, default_model, simulate};
use geodesic_checks::plunger::{PlungerAttraction, case, v_tm_2sigma_v};
use geodesic_core::trace::{assert_limit, assert_reference};
use geodesic_core::{Check, Outcome};
use proptest::prelude::*;
use std::f64::consts::PI;

/// `int_0^T (A / g^2 + B / g) dt` with `g = g0 + k t` [N s per unit A, B].
fn impulse(a: f64, b: f64, g0: f64, k: f64, t: f64) -> f64 {
    let g1 = g0 + k * t;
    a / k * (1.0 / g0 - 1.0 / g1) + b / k * (g1 / g0).ln()
}

/// The closed-form velocity change of a 1.96 kg TM: each side's gap opens at the plunger rate
/// minus (or plus) the TM's drift during the ramp, then closes (or opens) at the drift alone
/// while held.
fn closed_form_dv(v_tm: f64, v0: f64, r: Retraction) -> f64 {
    closed_form_dv_of(1.96, v_tm, v0, r)
}

/// [`closed_form_dv`] for a TM of `mass_kg`.
fn closed_form_dv_of(mass_kg: f64, v_tm: f64, v0: f64, r: Retraction) -> f64 {
    let disc = default_model();
    let rad = disc.radius_m;
    let (a, b) = (
        EPS0_F_M * PI * rad * rad * v_tm * v_tm / 2.0,
        EPS0_F_M * rad * v_tm * v_tm / 2.0,
    );
    let rate = (r.g_end_m - r.g0_m) / r.ramp_s;
    let hold = 25.0 - r.ramp_s;
    let side = |sign: f64| {
        let k = rate - sign * v0;
        let g_t = r.g0_m + k * r.ramp_s;
        impulse(a, b, r.g0_m, k, r.ramp_s) + impulse(a, b, g_t, -sign * v0, hold)
    };
    (side(1.0) - side(-1.0)) / mass_kg
}

/// The check's values, the TM starting from the release Monte Carlo's 99.73 % bound (2000
/// draws here), against both limits and against the closed-form impulse at that velocity.
#[test]
fn revised_retraction_meets_both_limits() {
    geodesic_core::verifies!("PLG-EXTRA-VEL", "PLG-FORCE-RATIO");
    let tmp = tempfile::tempdir().unwrap();
    let ctx = geodesic_checks::builtin_context(tmp.path().to_path_buf(), 2000, 1);
    let ev = PlungerAttraction::standalone().run(&ctx).unwrap();
    let get = |id: &str| ev.iter().find(|e| e.requirement == id).unwrap();
    let val = |id: &str| match &get(id).outcome {
        Outcome::Measured(q) => q.value,
        Outcome::NotVerified(w) => panic!("{w}"),
    };
    let dv = val("PLG-EXTRA-VEL");
    assert_limit("PLG-EXTRA-VEL", dv);
    assert_limit("PLG-FORCE-RATIO", val("PLG-FORCE-RATIO"));
    let e = get("PLG-EXTRA-VEL");
    let v0 = e.inputs["v0_um_s"].as_f64().unwrap() * 1e-6;
    assert!(
        v0 > 0.5e-6 && v0 < 5e-6,
        "v0 {v0} from the Monte Carlo, not a limit"
    );
    assert_eq!(e.inputs["tm_mass_kg"], 1.96);
    assert_eq!(e.model_inputs, ["budget", "charge"]);
    let reference = closed_form_dv(v_tm_2sigma_v(), v0, Retraction::REVISED);
    assert_reference(
        "PLG-EXTRA-VEL",
        "closed-form impulse of the disc's A/g^2 + B/g at constant gap rates",
        dv,
        reference,
        0.01,
    );
    assert!(tmp.path().join("plunger-attraction.svg").is_file());
}

/// The plunger rows move with their model inputs: a TM of half the budget's mass leaves the
/// release twice as fast and gains twice the velocity per force (the rows moved not at all
/// when they started from a limit and a constant mass), and a smaller pyramidal-plunger
/// capacitance in the charge inputs raises the TM voltage.
#[test]
fn plunger_rows_move_with_the_budget_and_the_charge_inputs() {
    let tmp = tempfile::tempdir().unwrap();
    let base_ctx = geodesic_checks::builtin_context(tmp.path().to_path_buf(), 2000, 1);
    let dv = |ctx: &geodesic_core::CheckContext| {
        let ev = PlungerAttraction::standalone().run(ctx).unwrap();
        let e = ev
            .iter()
            .find(|e| e.requirement == "PLG-EXTRA-VEL")
            .unwrap();
        match &e.outcome {
            Outcome::Measured(q) => (q.value, e.inputs["v0_um_s"].as_f64().unwrap()),
            Outcome::NotVerified(w) => panic!("{w}"),
        }
    };
    let (base, v0) = dv(&base_ctx);
    let mut lighter = base_ctx.clone();
    let mut inputs = (*lighter.inputs).clone();
    inputs.insert(
        "budget",
        "release budget",
        geodesic_core::check::InputFile::new(
            "lighter.yaml",
            geodesic_release::budget::DEFAULT_BUDGET_YAML
                .replace("tm_mass_kg: {fixed: 1.96}", "tm_mass_kg: {fixed: 0.98}"),
        ),
    );
    lighter.inputs = std::sync::Arc::new(inputs);
    let (light, v0_light) = dv(&lighter);
    assert!(
        (v0_light / v0 - 2.0).abs() < 0.1,
        "v0 {v0} -> {v0_light} um/s"
    );
    assert!(light > 1.5 * base, "PLG-EXTRA-VEL {base} -> {light} m/s");
    let mut charged = base_ctx.clone();
    let mut inputs = (*charged.inputs).clone();
    inputs.insert(
        "charge",
        "charge inputs",
        geodesic_core::check::InputFile::new(
            "charge.yaml",
            geodesic_charge::DEFAULT_CHARGE_YAML.replace("c_eh_f: 34.4e-12", "c_eh_f: 20e-12"),
        ),
    );
    charged.inputs = std::sync::Arc::new(inputs);
    let (more, _) = dv(&charged);
    assert!(
        more > 2.0 * base,
        "PLG-EXTRA-VEL {base} -> {more} m/s at a higher V_TM"
    );
}

#[test]
fn force_ratio_at_4_3_s_matches_the_gaps_then() {
    geodesic_core::verifies!("PLG-FORCE-RATIO");
    let disc = default_model();
    let r = Retraction::REVISED;
    let v = v_tm_2sigma_v();
    let run = simulate(&disc, &case(v, 5e-6, r));
    // the TM's position at 4.3 s from the simulation's own trace (every 0.05 s): the
    // reference recomputes the force from the capacitance model at those gaps
    let z = run
        .trace
        .iter()
        .find(|p| (p.0 - 4.3).abs() < 1e-9)
        .expect("a trace sample at 4.3 s")
        .1;
    let p = r.p_m(4.3);
    let (g1, g2) = (p - z, p + z);
    let f = 0.5 * v * v * (disc.dc_dg_f_m(g2) - disc.dc_dg_f_m(g1));
    assert_reference(
        "PLG-FORCE-RATIO",
        "1/2 V^2 (dC/dg(g2) - dC/dg(g1)) at the drifted gaps, / 5e-7 N",
        run.force_ratio_at_compare,
        f.abs() / 5e-7,
        1e-9,
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// The simulation agrees with the closed form, and the velocity change grows as V^2, over
    /// voltages, release velocities and parking distances where the closed form's assumption
    /// holds: the TM drifts at its initial velocity (the velocity change stays below 2 % of it;
    /// at 1 um/s and 2 V near a 0.3 mm parking gap it reaches 13 % and the closed form is off
    /// by as much, which is the approximation, not the simulation).
    #[test]
    fn simulation_matches_the_closed_form(v in 0.2f64..1.5, v0 in 3e-6f64..7.5e-6, end in 1e-3f64..3e-3) {
        geodesic_core::verifies!("PLG-EXTRA-VEL");
        let r = Retraction { g0_m: 15e-6, g_end_m: end, ramp_s: 15.0 };
        let run = simulate(&default_model(), &case(v, v0, r));
        prop_assert!(run.touched_at_s.is_none());
        assert_reference("PLG-EXTRA-VEL", "closed-form impulse", run.extra_velocity_m_s, closed_form_dv(v, v0, r), 0.02);
        let run2 = simulate(&default_model(), &case(2.0 * v, v0, r));
        prop_assert!((run2.extra_velocity_m_s / run.extra_velocity_m_s / 4.0 - 1.0).abs() < 0.02);
    }
}
