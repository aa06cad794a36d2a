//! The housing's model (thesis ch. 8): the design inputs and the simple models that give its
//! requirement rows evidence where a simple model exists.
//!
//! - **Magnetic shielding**: the foil around the housing as a spherical shell of relative
//!   permeability `mu_r` in a uniform field (Jackson, *Classical Electrodynamics*, sec. 5.12):
//!   `B_in / B_0 = 9 mu_r / ((2 mu_r + 1)(mu_r + 2) - 2 (a/b)^3 (mu_r - 1)^2)`, `a` the inner
//!   and `b = a + t` the outer radius. The housing cube is replaced by the sphere of equal volume
//!   (ASSUMPTION; its corners make the real box shield somewhat less, which the thesis's FE
//!   analysis resolves and this model does not).
//! - **Static stress**: the thesis's FE Von Mises stress under the caging load (an accepted,
//!   cited result) scaled linearly with the load (linear elasticity), and the yield safety
//!   factor `sigma_y / sigma_VM` of each material from its yield strength.
//! - **Modes**: the thesis's FE frequencies (accepted).

use serde::Deserialize;
use std::collections::BTreeMap;

/// The built-in copy of the mission's `design.yaml`.
pub const DEFAULT_DESIGN_YAML: &str = include_str!("../design.yaml");

/// A material's data.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Yield strength [MPa].
    pub yield_mpa: f64,
    /// Where the number comes from.
    pub source: String,
}

/// The housing's box.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Box3 {
    /// Outer side [mm].
    pub outer_side_mm: f64,
    /// Inner side [mm].
    pub inner_side_mm: f64,
}

/// A magnetic shield foil.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shield {
    /// Material name.
    pub material: String,
    /// Relative permeability [-].
    pub mu_r: f64,
    /// Foil thickness [mm].
    pub thickness_mm: f64,
}

/// An alternative shield material (thickness is solved for).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShieldMaterial {
    /// Material name.
    pub material: String,
    /// Relative permeability [-].
    pub mu_r: f64,
}

/// FE modal frequencies [Hz].
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Modes {
    /// Housing alone.
    pub housing_alone: Vec<f64>,
    /// Housing mounted in the spacecraft.
    pub mounted_in_spacecraft: Vec<f64>,
}

/// The design inputs.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Design {
    /// Free text.
    pub description: String,
    /// Caging load [N].
    pub caging_load_n: f64,
    /// FE maximum Von Mises stress [MPa] at `fe_load_n`.
    pub fe_von_mises_mpa: f64,
    /// Load of the FE analysis [N].
    pub fe_load_n: f64,
    /// Materials by name.
    pub materials: BTreeMap<String, Material>,
    /// The box.
    pub housing: Box3,
    /// The shield as designed.
    pub shield: Shield,
    /// Other shield materials compared.
    #[serde(default)]
    pub shield_alternatives: Vec<ShieldMaterial>,
    /// FE modes.
    pub modes_hz: Modes,
    /// The parameters' pedigree (issue 49), read by `geodesic_core::pedigree`, not here.
    #[serde(default)]
    pub pedigree: Option<serde::de::IgnoredAny>,
}

impl Design {
    /// Parses and checks a design file; errors are one line, `label:line: cause` where the
    /// parser knows the line.
    pub fn from_yaml(text: &str, label: &str) -> Result<Design, String> {
        let d: Design = serde_saphyr::from_str(text).map_err(|e| {
            let y = geodesic_util::yaml_error(&e);
            format!("{label}:{}: {}", y.line.unwrap_or(0), y.cause)
        })?;
        let pos = |v: f64, what: &str| -> Result<(), String> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!(
                    "{label}: {what} must be a positive number, not {v}"
                ))
            }
        };
        pos(d.caging_load_n, "caging_load_n")?;
        pos(d.fe_von_mises_mpa, "fe_von_mises_mpa")?;
        pos(d.fe_load_n, "fe_load_n")?;
        pos(d.housing.outer_side_mm, "housing.outer_side_mm")?;
        pos(d.housing.inner_side_mm, "housing.inner_side_mm")?;
        if d.housing.inner_side_mm >= d.housing.outer_side_mm {
            return Err(format!(
                "{label}: housing.inner_side_mm must be below outer_side_mm"
            ));
        }
        pos(d.shield.thickness_mm, "shield.thickness_mm")?;
        for (name, mu) in std::iter::once((&d.shield.material, d.shield.mu_r))
            .chain(d.shield_alternatives.iter().map(|m| (&m.material, m.mu_r)))
        {
            if !(mu.is_finite() && mu >= 1.0) {
                return Err(format!(
                    "{label}: mu_r of {name} must be a number >= 1, not {mu}"
                ));
            }
        }
        for (name, m) in &d.materials {
            pos(m.yield_mpa, &format!("materials.{name}.yield_mpa"))?;
        }
        for f in d
            .modes_hz
            .housing_alone
            .iter()
            .chain(&d.modes_hz.mounted_in_spacecraft)
        {
            pos(*f, "every modes_hz value")?;
        }
        if d.modes_hz.mounted_in_spacecraft.is_empty() {
            return Err(format!("{label}: modes_hz.mounted_in_spacecraft is empty"));
        }
        Ok(d)
    }

    /// The built-in design.
    pub fn builtin() -> Design {
        Design::from_yaml(
            DEFAULT_DESIGN_YAML,
            "<built-in>/missions/drag-free-cubesat/design.yaml",
        )
        .expect("the built-in design parses")
    }

    /// Radius of the sphere of the housing's outer volume [m] (the shield's inner radius).
    pub fn equivalent_radius_m(&self) -> f64 {
        let side = self.housing.outer_side_mm * 1e-3;
        (3.0 / (4.0 * std::f64::consts::PI)).cbrt() * side
    }

    /// Von Mises stress at the caging load [Pa] (the FE result scaled linearly).
    pub fn von_mises_pa(&self) -> f64 {
        self.fe_von_mises_mpa * 1e6 * self.caging_load_n / self.fe_load_n
    }

    /// Yield safety factor of `material` at the caging load [-].
    pub fn yield_safety_factor(&self, material: &str) -> Option<f64> {
        self.materials
            .get(material)
            .map(|m| m.yield_mpa * 1e6 / self.von_mises_pa())
    }

    /// Shielding factor `B_in / B_0` of the designed shield [-].
    pub fn shielding_factor(&self) -> f64 {
        shell_shielding_factor(
            self.shield.mu_r,
            self.equivalent_radius_m(),
            self.shield.thickness_mm * 1e-3,
        )
    }
}

/// `B_in / B_0` of a spherical shell of relative permeability `mu_r`, inner radius `a_m` [m] and
/// thickness `t_m` [m] in a uniform field (Jackson sec. 5.12).
pub fn shell_shielding_factor(mu_r: f64, a_m: f64, t_m: f64) -> f64 {
    let b = a_m + t_m;
    let q = (a_m / b).powi(3);
    9.0 * mu_r / ((2.0 * mu_r + 1.0) * (mu_r + 2.0) - 2.0 * q * (mu_r - 1.0).powi(2))
}

/// Thickness [m] of a shell of `mu_r` and inner radius `a_m` whose shielding factor is `target`
/// (bisection on [1 nm, a_m]); `None` if even a shell as thick as its radius does not reach it.
pub fn thickness_for(mu_r: f64, a_m: f64, target: f64) -> Option<f64> {
    let (mut lo, mut hi) = (1e-9, a_m);
    if shell_shielding_factor(mu_r, a_m, hi) > target {
        return None;
    }
    if shell_shielding_factor(mu_r, a_m, lo) <= target {
        return Some(lo);
    }
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if shell_shielding_factor(mu_r, a_m, mid) > target {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi / lo < 1.0 + 1e-12 {
            break;
        }
    }
    Some(hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn shell_limits() {
        // mu_r = 1: no shielding; no shell: none either
        assert_relative_eq!(
            shell_shielding_factor(1.0, 0.04, 0.001),
            1.0,
            max_relative = 1e-12
        );
        assert_relative_eq!(
            shell_shielding_factor(5e4, 0.04, 0.0),
            1.0,
            max_relative = 1e-9
        );
        // thin shell, mu_r >> 1: B_in / B_0 -> 1 / (1 + 2 mu_r t / (3 a)) (Jackson's limit)
        let (mu, a, t) = (1e4, 0.05, 1e-5);
        let thin = 1.0 / (1.0 + 2.0 * mu * t / (3.0 * a));
        assert_relative_eq!(shell_shielding_factor(mu, a, t), thin, max_relative = 2e-3);
        // thicker is better, more permeable is better
        assert!(shell_shielding_factor(mu, a, 2.0 * t) < shell_shielding_factor(mu, a, t));
        assert!(shell_shielding_factor(2.0 * mu, a, t) < shell_shielding_factor(mu, a, t));
    }

    #[test]
    fn thickness_inverts_the_factor() {
        let t = thickness_for(2e4, 0.0434, 0.01).unwrap();
        assert_relative_eq!(
            shell_shielding_factor(2e4, 0.0434, t),
            0.01,
            max_relative = 1e-9
        );
        assert!(thickness_for(1.5, 0.0434, 1e-6).is_none());
    }

    #[test]
    fn builtin_design_figures() {
        let d = Design::builtin();
        assert_relative_eq!(d.von_mises_pa(), 27.5e6, max_relative = 1e-12);
        assert_relative_eq!(
            d.yield_safety_factor("Al6061-T6").unwrap(),
            276.0 / 27.5,
            max_relative = 1e-12
        );
        assert!(d.shielding_factor() < 0.01);
    }

    #[test]
    fn bad_design_says_where() {
        let e = Design::from_yaml(
            &DEFAULT_DESIGN_YAML.replace("caging_load_n: 200.0", "caging_load_n: -1"),
            "d.yaml",
        )
        .unwrap_err();
        assert!(e.contains("caging_load_n"), "{e}");
        let e = Design::from_yaml(
            &DEFAULT_DESIGN_YAML.replace("fe_load_n:", "fe_lod_n:"),
            "d.yaml",
        )
        .unwrap_err();
        assert!(e.starts_with("d.yaml:") && e.contains("fe_lod_n"), "{e}");
    }
}
