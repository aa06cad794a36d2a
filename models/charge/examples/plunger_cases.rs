//! Prints the plunger-attraction cases of thesis ch. 7 (baseline and revised retraction, TM
//! voltages 0.5, 1, 1.06 and 2 V, release velocity 5 um/s): `cargo run -p geodesic-charge
//! --example plunger_cases`.
use geodesic_charge::plunger::{PlungerCase, Retraction, SpherePlane, default_model, simulate};

fn main() {
    let disc = default_model();
    let sphere = SpherePlane {
        radius_m: 10e-3,
        rel_tol: 1e-10,
    };
    for (name, cap) in [
        (
            "disc",
            &disc as &dyn geodesic_charge::plunger::PlungerCapacitance,
        ),
        ("sphere 10 mm", &sphere),
    ] {
        println!("{name}: {}", cap.describe());
        for (pname, r) in [
            ("baseline", Retraction::BASELINE),
            ("revised", Retraction::REVISED),
        ] {
            for v in [0.5, 1.0, 1.06, 2.0] {
                let c = PlungerCase {
                    mass_kg: 1.96,
                    v_tm_v: v,
                    v0_m_s: 5e-6,
                    retraction: r,
                    duration_s: 25.0,
                    authority_n: 5e-7,
                    compare_at_s: 4.3,
                };
                let run = simulate(cap, &c);
                println!(
                    "  {pname:8} {v:4} V: dv {:.4} um/s ({:.2} %), min gap {:.2} um at {:.2} s, F/u at 4.3 s {:.4}, >=1% until {:.2} s, touched {:?}",
                    run.extra_velocity_m_s * 1e6,
                    100.0 * run.extra_velocity_m_s / 5e-6,
                    run.min_gap_m * 1e6,
                    run.min_gap_at_s,
                    run.force_ratio_at_compare,
                    run.force_above_1pct_until_s,
                    run.touched_at_s
                );
            }
        }
    }
}
