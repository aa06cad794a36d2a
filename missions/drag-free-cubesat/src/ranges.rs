//! The plausible ranges of the housing's design inputs (issue 49), each with its unit and the
//! physical argument behind it, cited to the thesis where it can be. A value outside its range
//! is refused before anything runs (exit 2, `file:line: PARAM = V is outside its plausible
//! range [A, B] UNIT (why)`) unless the file's `pedigree:` entry for it sets another range with
//! a reason ([`geodesic_core::pedigree`]).

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

const MU: &str = "a relative permeability of a real material: 1 (non-magnetic) up to about 1e6 (the best annealed cobalt-based amorphous and nanocrystalline alloys, e.g. Metglas 2714A)";
const MODES: &str = "modal frequencies of a 70 mm Al housing: kHz alone, hundreds of Hz mounted (thesis ch. 8, Tab. 'Modal analysis results')";

/// The design file's (`design.yaml`) ranges, units in the keys.
pub const DESIGN: &[Range] = &[
    r(
        "caging_load_n",
        "N",
        1.0,
        1.0e4,
        "the caging force: at least 200 N, LISA's 3000 N scaled by mass, thesis ch. 8",
    ),
    r(
        "fe_von_mises_mpa",
        "MPa",
        0.4,
        2000.0,
        "the FE's largest Von Mises stress under the caging load: 27.5 MPa at 200 N (thesis ch. 8); 200 N over the 25.4 mm TM's whole recess (507 mm^2) is already 0.4 MPa, and no structural metal holds 2 GPa",
    ),
    r(
        "fe_load_n",
        "N",
        1.0,
        1.0e4,
        "the load of the FE analysis: 200 N, thesis ch. 8",
    ),
    r(
        "materials.*.yield_mpa",
        "MPa",
        10.0,
        2500.0,
        "a structural metal's yield strength: annealed pure Al about 10-35 MPa, maraging steels up to about 2.5 GPa (ASM Handbook); Al 6061-T6 276 MPa",
    ),
    r(
        "housing.outer_side_mm",
        "mm",
        10.0,
        300.0,
        "a housing inside a CubeSat: 70 mm, thesis ch. 8 (a 6U is 226 mm long)",
    ),
    r(
        "housing.inner_side_mm",
        "mm",
        25.4,
        300.0,
        "the cavity holds the 25.4 mm TM: 50 mm, thesis ch. 8",
    ),
    r("shield.mu_r", "-", 1.0, 1.0e6, MU),
    r(
        "shield.thickness_mm",
        "mm",
        1.0e-3,
        10.0,
        "a shield foil: thinner than 0.1 mm suffices with 2714A, thesis ch. 8",
    ),
    r("shield_alternatives[*].mu_r", "-", 1.0, 1.0e6, MU),
    r("modes_hz.housing_alone", "Hz", 1.0, 1.0e5, MODES),
    r("modes_hz.mounted_in_spacecraft", "Hz", 1.0, 1.0e5, MODES),
];

/// Questions a design file with [`DESIGN`]: `Ok` or the one-line cause.
pub fn question(text: &str, label: &str) -> Result<(), String> {
    geodesic_core::pedigree::question(text, label, DESIGN).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DEFAULT_DESIGN_YAML;

    #[test]
    fn every_design_parameter_has_a_pedigree_and_a_range() {
        let q = geodesic_core::pedigree::question(DEFAULT_DESIGN_YAML, "design.yaml", DESIGN)
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(q.len() >= 5, "{}", q.len());
        for (p, v) in &q {
            assert!(v.pedigree.range.is_none(), "{p} overrides its range");
            assert!(!v.range.2.is_empty(), "{p} has no unit");
        }
    }

    #[test]
    fn the_audits_unit_slips_are_refused_with_line_range_and_unit() {
        for (from, to, want) in [
            (
                "mu_r: 200000.0",
                "mu_r: 2e12",
                "shield.mu_r = 2e12 is outside its plausible range [1, 1e6] -",
            ),
            (
                "fe_von_mises_mpa: 27.5",
                "fe_von_mises_mpa: 0.0275",
                "fe_von_mises_mpa = 0.0275 is outside its plausible range [0.4, 2000] MPa",
            ),
        ] {
            let text = DEFAULT_DESIGN_YAML;
            let edited = text.replacen(from, to, 1);
            assert_ne!(edited, text, "{from}");
            let line = text.lines().position(|l| l.contains(from)).unwrap() + 1;
            let e = question(&edited, "design.yaml").unwrap_err();
            assert!(e.starts_with(&format!("design.yaml:{line}: ")), "{e}");
            assert!(e.contains(want), "{e}");
        }
    }
}
