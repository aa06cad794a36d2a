//! The housing's checks (thesis ch. 8), the second mission geodesic verifies (issue 16, item 4).
//! They read the mission's design file
//! (`geodesic verify --design`, by default `design.yaml` beside the requirements folder, else the
//! built-in copy):
//!
//! - `dfc-structure`: DFC-MODE-1 from the thesis's FE modal table (`accepted`), and the yield
//!   safety factors DFC-STR-SF-6061/-7075 from the FE Von Mises stress scaled with the design's
//!   caging load and each material's yield strength (`accepted`: the stress is a cited result);
//! - `dfc-magnetic-shield`: DFC-MAG-SHIELD from the spherical-shell model of
//!   [`crate::housing`] (`model`), with the thickness each compared material needs.

use crate::housing::{DEFAULT_DESIGN_YAML, Design, thickness_for};
use geodesic_core::{Basis, Check, CheckContext, CheckError, Dim, Evidence, Quantity};

/// The checks of this family.
pub fn checks() -> Vec<Box<dyn Check>> {
    vec![Box::new(Structure), Box::new(MagneticShield)]
}

/// The design of the run: `--design`, else the built-in copy; with its label and hash.
pub fn design_of(ctx: &CheckContext) -> Result<(Design, String, String), CheckError> {
    match ctx.inputs.get("design") {
        Some(f) => Ok((
            Design::from_yaml(&f.text, &f.label)
                .map_err(|e| CheckError::input(e).in_file(&f.label, 0))?,
            f.label.clone(),
            f.sha256.clone(),
        )),
        None => {
            let f = geodesic_core::check::InputFile::new(
                "<built-in>/missions/drag-free-cubesat/design.yaml",
                DEFAULT_DESIGN_YAML,
            );
            Ok((Design::builtin(), f.label, f.sha256))
        }
    }
}

/// `dfc-structure`.
pub struct Structure;

/// The material each safety-factor requirement is about.
const SF_ROWS: [(&str, &str); 2] = [
    ("DFC-STR-SF-6061", "Al6061-T6"),
    ("DFC-STR-SF-7075", "Al7075-T6"),
];

impl Check for Structure {
    fn name(&self) -> &'static str {
        "dfc-structure"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["DFC-MODE-1", "DFC-STR-SF-6061", "DFC-STR-SF-7075"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let (d, label, sha) = design_of(ctx)?;
        let first = d
            .modes_hz
            .mounted_in_spacecraft
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        let mut out = vec![
            Evidence::measured(
                "DFC-MODE-1",
                Quantity::new(first, Dim::FREQUENCY),
                Basis::Accepted,
                "Lowest FE natural frequency of the housing mounted in the spacecraft (thesis ch. 8 Tab. 'Modal analysis results', COMSOL with a convergence analysis)",
            )
            .with_input("design", label.clone())
            .with_input("design_sha256", sha.clone())
            .with_input("modes_mounted_hz", d.modes_hz.mounted_in_spacecraft.clone())
            .with_input("modes_housing_alone_hz", d.modes_hz.housing_alone.clone()),
        ];
        let vm = d.von_mises_pa();
        for (id, material) in SF_ROWS {
            let Some(sf) = d.yield_safety_factor(material) else {
                out.push(Evidence::not_verified(
                    id,
                    format!("material {material} is not in the design file {label}"),
                    "yield strength / Von Mises stress",
                ));
                continue;
            };
            let m = &d.materials[material];
            out.push(
                Evidence::measured(
                    id,
                    Quantity::new(sf, Dim::DIMENSIONLESS),
                    Basis::Accepted,
                    format!(
                        "{material} yield {:.0} MPa / FE Von Mises {:.1} MPa ({} MPa at {} N, cited, scaled to the caging load {} N)",
                        m.yield_mpa,
                        vm * 1e-6,
                        d.fe_von_mises_mpa,
                        d.fe_load_n,
                        d.caging_load_n
                    ),
                )
                .with_input("design", label.clone())
                .with_input("design_sha256", sha.clone())
                .with_input("yield_mpa", m.yield_mpa)
                .with_input("yield_source", m.source.clone())
                .with_input("von_mises_mpa", vm * 1e-6)
                .with_input("caging_load_n", d.caging_load_n),
            );
        }
        Ok(out)
    }
}

/// `dfc-magnetic-shield`.
pub struct MagneticShield;

impl Check for MagneticShield {
    fn name(&self) -> &'static str {
        "dfc-magnetic-shield"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["DFC-MAG-SHIELD"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let (d, label, sha) = design_of(ctx)?;
        let a = d.equivalent_radius_m();
        let s = d.shielding_factor();
        let target = ctx
            .requirements
            .get("DFC-MAG-SHIELD")
            .and_then(|r| r.limit.as_ref())
            .map_or(0.01, |l| l.value.value);
        let mut ev = Evidence::measured(
            "DFC-MAG-SHIELD",
            Quantity::new(s, Dim::DIMENSIONLESS),
            Basis::Model,
            format!(
                "Spherical-shell shielding B_in/B_0 (Jackson 5.12) of {} (mu_r {:.0}, {} mm) on the sphere of the housing's volume (radius {:.1} mm)",
                d.shield.material,
                d.shield.mu_r,
                d.shield.thickness_mm,
                a * 1e3
            ),
        )
        .with_input("design", label)
        .with_input("design_sha256", sha)
        .with_input("equivalent_radius_mm", a * 1e3)
        .with_input("mu_r", d.shield.mu_r)
        .with_input("thickness_mm", d.shield.thickness_mm);
        for m in std::iter::once((d.shield.material.clone(), d.shield.mu_r)).chain(
            d.shield_alternatives
                .iter()
                .map(|m| (m.material.clone(), m.mu_r)),
        ) {
            let key = format!(
                "thickness_for_limit_mm_{}",
                m.0.to_lowercase().replace([' ', '-'], "_")
            );
            ev = ev.with_input(
                &key,
                thickness_for(m.1, a, target).map_or(serde_json::Value::Null, |t| (t * 1e3).into()),
            );
        }
        Ok(vec![ev])
    }
}
