//! The charge inputs file (`models/charge/charge.yaml`): the TM's capacitances to the electrode
//! housing and the plungers, the 2-sigma contact voltage difference and the release tip's
//! geometry. `geodesic verify` reads it at run time (and names it with its SHA-256 in every
//! report), so that CHG-Q, CHG-V and the plunger rows move with it.

use crate::budget::ChargeInputs;
use crate::capacitance::{TipGeometry, c_rt_quadrature_f};
use serde::Deserialize;
use serde_saphyr::Spanned;

/// The repository's charge inputs (embedded copy of `models/charge/charge.yaml`).
pub const DEFAULT_CHARGE_YAML: &str = include_str!("../charge.yaml");

/// Relative tolerance of the `C_RT` quadrature [-].
pub const QUAD_REL_TOL: f64 = 1e-12;

/// A charge inputs file that cannot be used: one line starting with `file:line:`.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{file}:{line}:{column}: {cause}")]
pub struct InputsError {
    /// File path (or label).
    pub file: String,
    /// 1-based line (0 when unknown).
    pub line: u64,
    /// 1-based column (0 when unknown).
    pub column: u64,
    /// One-line cause.
    pub cause: String,
}

/// The checked charge inputs.
#[derive(Clone, Debug, PartialEq)]
pub struct ChargeFile {
    /// The capacitances and the voltage spread (`c_rt_f` from the tip geometry).
    pub inputs: ChargeInputs,
    /// The release tip's geometry.
    pub tip: TipGeometry,
    /// The file the inputs came from.
    pub file: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    capacitances: RawCaps,
    contact_voltage_2sigma_v: Spanned<f64>,
    release_tip: RawTip,
    /// The parameters' pedigree (issue 49), read by `geodesic_core::pedigree`, not here.
    #[serde(default, rename = "pedigree")]
    _pedigree: Option<serde::de::IgnoredAny>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCaps {
    c_eh_f: Spanned<f64>,
    c_pyr_f: Spanned<f64>,
    c_cyl_f: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTip {
    radius_m: Spanned<f64>,
    cap_radius_m: Spanned<f64>,
    gap_m: Spanned<f64>,
}

fn yaml_error(file: &str, e: &serde_saphyr::Error) -> InputsError {
    let y = geodesic_util::yaml_error(e);
    InputsError {
        file: file.to_owned(),
        line: y.line.unwrap_or(0),
        column: y.column.unwrap_or(0),
        cause: y.cause,
    }
}

impl ChargeFile {
    /// The repository's default inputs (embedded copy).
    pub fn default_inputs() -> ChargeFile {
        ChargeFile::from_yaml_str(DEFAULT_CHARGE_YAML, "<built-in>/models/charge/charge.yaml")
            .expect("the embedded charge.yaml is valid (unit-tested)")
    }

    /// Parses and checks a charge inputs file; every error names `file:line:column`.
    pub fn from_yaml_str(text: &str, file: &str) -> Result<ChargeFile, InputsError> {
        let raw: Raw = serde_saphyr::from_str(text).map_err(|e| yaml_error(file, &e))?;
        let positive = |name: &str, v: &Spanned<f64>| {
            if v.value.is_finite() && v.value > 0.0 {
                Ok(v.value)
            } else {
                Err(InputsError {
                    file: file.to_owned(),
                    line: v.referenced.line(),
                    column: v.referenced.column(),
                    cause: format!("{name} = {}: must be finite and positive", v.value),
                })
            }
        };
        let tip = TipGeometry {
            radius_m: positive("release_tip.radius_m", &raw.release_tip.radius_m)?,
            cap_radius_m: positive("release_tip.cap_radius_m", &raw.release_tip.cap_radius_m)?,
            gap_m: positive("release_tip.gap_m", &raw.release_tip.gap_m)?,
        };
        let inputs = ChargeInputs {
            c_eh_f: positive("capacitances.c_eh_f", &raw.capacitances.c_eh_f)?,
            c_pyr_f: positive("capacitances.c_pyr_f", &raw.capacitances.c_pyr_f)?,
            c_cyl_f: positive("capacitances.c_cyl_f", &raw.capacitances.c_cyl_f)?,
            c_rt_f: c_rt_quadrature_f(&tip, QUAD_REL_TOL),
            dv_2sigma_v: positive("contact_voltage_2sigma_v", &raw.contact_voltage_2sigma_v)?,
        };
        if !(inputs.c_rt_f.is_finite() && inputs.c_rt_f > 0.0) {
            return Err(InputsError {
                file: file.to_owned(),
                line: raw.release_tip.radius_m.referenced.line(),
                column: raw.release_tip.radius_m.referenced.column(),
                cause: "the release tip's geometry gives no finite capacitance".into(),
            });
        }
        Ok(ChargeFile {
            inputs,
            tip,
            file: file.to_owned(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_file_holds_the_thesis_inputs() {
        let f = ChargeFile::default_inputs();
        assert_eq!(f.tip, TipGeometry::THESIS);
        let want = ChargeInputs::thesis_with_c_rt(c_rt_quadrature_f(&TipGeometry::THESIS, 1e-12));
        assert_eq!(f.inputs, want);
    }

    #[test]
    fn bad_values_and_keys_name_file_and_line() {
        let bad = DEFAULT_CHARGE_YAML.replace("c_cyl_f: 10.0e-12", "c_cyl_f: -1");
        let e = ChargeFile::from_yaml_str(&bad, "q.yaml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("q.yaml:") && e.contains("c_cyl_f"), "{e}");
        let line: usize = e.split(':').nth(1).unwrap().parse().unwrap();
        assert!(
            DEFAULT_CHARGE_YAML
                .lines()
                .nth(line - 1)
                .unwrap()
                .contains("c_cyl_f")
        );
        let bad = DEFAULT_CHARGE_YAML.replace("c_eh_f:", "c_eh_pf:");
        let e = ChargeFile::from_yaml_str(&bad, "q.yaml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("q.yaml:") && e.contains("c_eh_pf"), "{e}");
        assert!(!e.contains('\n'));
    }

    #[test]
    fn an_edited_capacitance_moves_the_charge() {
        let base = ChargeFile::default_inputs().inputs.q_2sigma_e();
        let t = DEFAULT_CHARGE_YAML.replace("c_eh_f: 34.4e-12", "c_eh_f: 30e-12");
        let q = ChargeFile::from_yaml_str(&t, "q.yaml")
            .unwrap()
            .inputs
            .q_2sigma_e();
        assert!(q < base - 1e7, "{q} vs {base}");
    }
}
