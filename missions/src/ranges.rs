//! The plausible ranges of every model input parameter of the root mission (issue 49; the
//! Drag-Free CubeSat's are in its own crate), each with its unit and the physical argument behind it, cited to the thesis where it
//! can be. A value outside its range is refused before anything runs (exit 2,
//! `file:line: PARAM = V is outside its plausible range [A, B] UNIT (why)`) unless the file's
//! `pedigree:` entry for it sets another range with a reason
//! ([`geodesic_core::pedigree`]). The ranges are wide enough for any design variant of the same
//! hardware and narrow enough to refuse a slip of unit or of a decimal point where the physics
//! pins the value (the TM's mass, capacitances in pF, a stress in MPa).

use geodesic_core::pedigree::Range;

const fn r(path: &'static str, unit: &'static str, min: f64, max: f64, why: &'static str) -> Range {
    Range {
        path,
        unit,
        min,
        max,
        why,
    }
}

/// The release Monte Carlo's budget (`models/release/budget.yaml`), SI units.
pub const BUDGET: &[Range] = &[
    r(
        "mechanism.R_ohm",
        "ohm",
        10.0,
        1.0e4,
        "the piezo drive's discharge resistance: 371.2 ohm fitted on the flight model, thesis ch. 3 Tab. 'Example of estimated model parameters'",
    ),
    r(
        "mechanism.m_kg",
        "kg",
        1.0e-4,
        1.0e-2,
        "the release tip and half its 3 x 3 x 18 mm piezo stack (0.6 g of PZT): 0.9 g fitted, thesis ch. 3",
    ),
    r(
        "mechanism.Ca_f",
        "F",
        1.0e-9,
        1.0e-5,
        "a piezo stack's capacitance: 0.23 uF fitted, thesis ch. 3",
    ),
    r(
        "mechanism.k_n_m",
        "N/m",
        1.0e6,
        1.0e9,
        "the washer springs and the piezo in series: 4.91e7 N/m fitted, thesis ch. 3",
    ),
    r(
        "mechanism.Kg_n_m",
        "N/m",
        1.0e5,
        1.0e8,
        "the plunger's load-cell stiffness to ground: 2.15e6 N/m fitted, thesis ch. 3",
    ),
    r(
        "mechanism.b_ns_m",
        "N s/m",
        1.0e-2,
        1.0e3,
        "the mechanism's viscous damping: 9.77 N s/m fitted, thesis ch. 3",
    ),
    r(
        "mechanism.Mg_kg",
        "kg",
        1.0e-3,
        1.0,
        "the whole plunger: 19 g fitted, thesis ch. 3",
    ),
    r(
        "mechanism.T_c_m",
        "C/m",
        0.1,
        100.0,
        "the piezo's electromechanical transduction: 5.73 C/m fitted, thesis ch. 3",
    ),
    r(
        "em_v_s",
        "V/s",
        0.0,
        1.0e9,
        "the slope of the dropping command voltage: 120 V in microseconds, 5e7 V/s (sd 1.02e7) measured, thesis ch. 3",
    ),
    r(
        "tip_radius_m",
        "m",
        1.0e-4,
        0.1,
        "the release tip's spherical edge: 10 mm radius, thesis ch. 3 (0.73 mm in the tip-radius what-if)",
    ),
    r(
        "preload_n",
        "N",
        0.0,
        3.0,
        "the contact force left by the passover: 300 mN, sd 16.6 mN, thesis ch. 5; the ground campaigns used 1 to 400 mN",
    ),
    r(
        "adhesion.A1_n_m",
        "N/m",
        0.0,
        4.0e6,
        "a pull-off A1 lambda / e of at most about 1 N at lambda 0.7 um (thesis ch. 4: 'a force up to 1 N could be expected for a preload of 400 mN'); the TMMF campaigns bound A1 by 1.5e5 N/m",
    ),
    r(
        "adhesion.lambda_m",
        "m",
        0.0,
        1.0e-5,
        "the adhesion's elongation constant: sub-micron in every TMMF fit (bounds [0, 0.8] um, thesis ch. 4); 10 um is beyond any bond of a 35 um contact patch",
    ),
    r(
        "adhesion.A1_lambda_correlation",
        "-",
        -1.0,
        1.0,
        "a correlation coefficient",
    ),
    r(
        "e_star_pa",
        "Pa",
        1.0e9,
        5.0e11,
        "the effective modulus of two metal contacts (gold 79 GPa, steels about 200 GPa): 59 GPa in the thesis's JKR example, ch. 3",
    ),
    r(
        "tm_mass_kg",
        "kg",
        1.9,
        2.0,
        "each TM is a 1.96 kg 30 % Pt-70 % Au 46 mm cube, thesis ch. 2",
    ),
    r(
        "e0_v",
        "V",
        0.0,
        200.0,
        "the piezo's command voltage: 0 to 120 V at full extraction, thesis ch. 3",
    ),
];

const POS: &str = "a TM position within the millimetre gaps of the electrode housing; the thesis's xlim is 526 um, ch. 7";
const VEL: &str = "a TM velocity of micrometres per second: the z velocity alone is captured up to 12 um/s, thesis ch. 7";
const ANG: &str = "a TM attitude of milliradians; the thesis's xlim is 5.3 mrad, ch. 7";
const RATE: &str = "a TM rate of microradians per second; the thesis's xlim is 263 urad/s, ch. 7";

/// The capture inputs (`models/capture/capture.yaml`), SI units.
pub const CAPTURE: &[Range] = &[
    r("xlim.values.x", "m", 1.0e-6, 4.0e-3, POS),
    r("xlim.values.y", "m", 1.0e-6, 4.0e-3, POS),
    r("xlim.values.z", "m", 1.0e-6, 4.0e-3, POS),
    r("xlim.values.vx", "m/s", 1.0e-7, 1.0e-3, VEL),
    r("xlim.values.vy", "m/s", 1.0e-7, 1.0e-3, VEL),
    r("xlim.values.vz", "m/s", 1.0e-7, 1.0e-3, VEL),
    r("xlim.values.thx", "rad", 1.0e-5, 0.1, ANG),
    r("xlim.values.thy", "rad", 1.0e-5, 0.1, ANG),
    r("xlim.values.thz", "rad", 1.0e-5, 0.1, ANG),
    r("xlim.values.wx", "rad/s", 1.0e-7, 1.0e-2, RATE),
    r("xlim.values.wy", "rad/s", 1.0e-7, 1.0e-2, RATE),
    r("xlim.values.wz", "rad/s", 1.0e-7, 1.0e-2, RATE),
    r(
        "xlim.box_scale",
        "-",
        1.0,
        10.0,
        "the factor the whole requirement box is scaled by: 1.4, thesis ch. 7",
    ),
    r(
        "drift_time_s",
        "s",
        1.0,
        100.0,
        "from the release to the start of control: 15 s, while the plungers retract, thesis ch. 3 and 7",
    ),
    r(
        "states.*.flow-down",
        "-",
        0.0,
        1.0,
        "a fraction of the state's own limit (1/3: the limit at 3 sigma)",
    ),
    r("states.x", "m", -4.0e-3, 4.0e-3, POS),
    r("states.y", "m", -4.0e-3, 4.0e-3, POS),
    r("states.z", "m", -4.0e-3, 4.0e-3, POS),
    r("states.vx", "m/s", -1.0e-3, 1.0e-3, VEL),
    r("states.vy", "m/s", -1.0e-3, 1.0e-3, VEL),
    r("states.vz", "m/s", -1.0e-3, 1.0e-3, VEL),
    r("states.thx", "rad", -0.1, 0.1, ANG),
    r("states.thy", "rad", -0.1, 0.1, ANG),
    r("states.thz", "rad", -0.1, 0.1, ANG),
    r("states.wx", "rad/s", -1.0e-2, 1.0e-2, RATE),
    r("states.wy", "rad/s", -1.0e-2, 1.0e-2, RATE),
    r("states.wz", "rad/s", -1.0e-2, 1.0e-2, RATE),
];

const CAP: &str = "a capacitance of the 46 mm TM to its surroundings across millimetre gaps: tens of pF (thesis ch. 7: 34.4, 35 and 10 pF by FE)";

/// The charge inputs (`models/charge/charge.yaml`), SI units.
pub const CHARGE: &[Range] = &[
    r("capacitances.c_eh_f", "F", 1.0e-13, 1.0e-9, CAP),
    r("capacitances.c_pyr_f", "F", 1.0e-13, 1.0e-9, CAP),
    r("capacitances.c_cyl_f", "F", 1.0e-13, 1.0e-9, CAP),
    r(
        "contact_voltage_2sigma_v",
        "V",
        0.01,
        10.0,
        "contact potential differences of metal surfaces: tens of mV to about a volt (thesis ch. 7: 1 V at 2 sigma)",
    ),
    r(
        "release_tip.radius_m",
        "m",
        1.0e-4,
        0.1,
        "the release tip's radius of curvature: 10 mm, thesis ch. 3 and 7",
    ),
    r(
        "release_tip.cap_radius_m",
        "m",
        1.0e-6,
        1.0e-2,
        "the radius of the tip's cap facing the TM: 0.4 mm, thesis ch. 7",
    ),
    r(
        "release_tip.gap_m",
        "m",
        1.0e-10,
        1.0e-5,
        "the tip-TM gap when the contact breaks: 100 nm, thesis ch. 7; no gap is below an atomic spacing",
    ),
];

/// The ranges of the root mission's input `name` (its name in `mission.yaml`), empty for an
/// input it states none for.
pub fn of(name: &str) -> &'static [Range] {
    match name {
        "budget" => BUDGET,
        "capture" => CAPTURE,
        "charge" => CHARGE,
        _ => &[],
    }
}

/// Questions an input file with its ranges: `Ok` or the one-line cause.
pub fn question(text: &str, label: &str, ranges: &[Range]) -> Result<(), String> {
    geodesic_core::pedigree::question(text, label, ranges).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesic_core::pedigree::{Kind, question};

    fn file(rel: &str) -> String {
        std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join(rel),
        )
        .unwrap()
    }

    #[test]
    fn every_parameter_of_every_mission_input_has_a_pedigree_and_a_range_of_the_mission() {
        for (rel, ranges) in [
            ("models/release/budget.yaml", BUDGET),
            ("models/capture/capture.yaml", CAPTURE),
            ("models/charge/charge.yaml", CHARGE),
        ] {
            let q = question(&file(rel), rel, ranges).unwrap_or_else(|e| panic!("{e}"));
            assert!(q.len() >= 5, "{rel}: {}", q.len());
            for (p, v) in &q {
                assert!(v.pedigree.range.is_none(), "{rel}: {p} overrides its range");
                assert!(!v.range.2.is_empty(), "{rel}: {p} has no unit");
            }
        }
    }

    #[test]
    fn the_audits_unit_slips_are_refused_with_line_range_and_unit() {
        for (rel, ranges, from, to, want) in [
            (
                "models/release/budget.yaml",
                BUDGET,
                "tm_mass_kg: {fixed: 1.96}",
                "tm_mass_kg: {fixed: 19.6}",
                "tm_mass_kg = 19.6 is outside its plausible range [1.9, 2] kg",
            ),
            (
                "models/charge/charge.yaml",
                CHARGE,
                "c_eh_f: 34.4e-12",
                "c_eh_f: 34.4",
                "capacitances.c_eh_f = 34.4 is outside its plausible range [1e-13, 1e-9] F",
            ),
        ] {
            let text = file(rel);
            let edited = text.replacen(from, to, 1);
            assert_ne!(edited, text, "{rel}: {from}");
            let line = text.lines().position(|l| l.contains(from)).unwrap() + 1;
            let e = question(&edited, rel, ranges).unwrap_err();
            assert!(e.starts_with(&format!("{rel}:{line}: ")), "{e}");
            assert!(e.contains(want), "{e}");
        }
    }

    #[test]
    fn the_tm_mass_is_cited_to_the_thesis() {
        let q = question(&file("models/release/budget.yaml"), "b", BUDGET).unwrap();
        assert_eq!(q["tm_mass_kg"].pedigree.kind, Kind::Cited);
        assert!(q["tm_mass_kg"].pedigree.reference.contains("1.96 kg"));
    }
}
