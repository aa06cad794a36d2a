//! The fidelity table of the housing: its figures against the thesis's (ch. 8), computed on
//! every `geodesic verify --mission drag-free-cubesat` and stated in the reports beside the
//! matrix.

use crate::checks::design_of;
use crate::housing::thickness_for;
use geodesic_core::check::ReferenceRow;
use geodesic_core::{CheckContext, CheckError};

/// The housing's figures against the thesis (ch. 8), from the run's design file (issue 16,
/// item 4).
pub fn table(ctx: &CheckContext) -> Result<Vec<ReferenceRow>, CheckError> {
    let (d, label, sha) = design_of(ctx)?;
    let note = format!("design {label} (sha256 {})", &sha[..12]);
    let mut rows = Vec::new();
    for (material, thesis) in [("Al6061-T6", 11.0), ("Al7075-T6", 16.5)] {
        if let Some(sf) = d.yield_safety_factor(material) {
            let y = d.materials[material].yield_mpa;
            rows.push(ReferenceRow::new(
                &format!("yield safety factor of {material} at the caging load"),
                format!("{sf:.2} (yield {y:.0} MPa / {:.1} MPa)", d.von_mises_pa() * 1e-6),
                format!("{thesis} (thesis ch. 8)"),
                ReferenceRow::percent(sf, thesis),
                &format!(
                    "{note}; the thesis's factor implies a strength of {:.1} MPa: other material data than the design file's (e.g. 6061-T6 ultimate 310 MPa, 7075-T73 yield 435-455 MPa)",
                    thesis * d.fe_von_mises_mpa
                ),
            ));
        }
    }
    let first = d
        .modes_hz
        .mounted_in_spacecraft
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    rows.push(ReferenceRow::new(
        "first mode of the housing mounted in the spacecraft",
        format!("{first:.0} Hz (accepted: the FE table of the design file)"),
        "227 Hz (thesis ch. 8, FE)".into(),
        ReferenceRow::percent(first, 227.0),
        "no geodesic model: cited FE result",
    ));
    let a = d.equivalent_radius_m();
    let target = ctx
        .requirements
        .get("DFC-MAG-SHIELD")
        .and_then(|r| r.limit.as_ref())
        .map_or(0.01, |l| l.value.value);
    let mut needs = Vec::new();
    for (m, mu) in std::iter::once((d.shield.material.clone(), d.shield.mu_r)).chain(
        d.shield_alternatives
            .iter()
            .map(|m| (m.material.clone(), m.mu_r)),
    ) {
        needs.push(match thickness_for(mu, a, target) {
            Some(t) => format!("{m} (mu_r {mu:.0}) {:.3} mm", t * 1e3),
            None => format!("{m}: not reachable"),
        });
    }
    rows.push(ReferenceRow::new(
        &format!("shield thickness for a shielding factor {target}"),
        needs.join("; "),
        "2714A: thinner than 0.1 mm; 10x better than mu-metal (thesis ch. 8, FE)".into(),
        "-".into(),
        &format!(
            "spherical shell of radius {:.1} mm (the housing's volume), DC permeabilities of the design file; the FE box model has corners this one lacks",
            a * 1e3
        ),
    ));
    Ok(rows)
}
