//! The three-equation piezo mechanism model of thesis ch. 3 (physics.md §1, with its two typo
//! fixes: `Kg*l` in the plunger equation, `y - l` in the electrical one).

use crate::{MECH_STATES, Mechanism, VoltageCommand};

/// Parameters of one mechanism (thesis Tab. "Example of estimated model parameters").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PiezoParams {
    /// Circuit resistance `R` [ohm].
    pub r_ohm: f64,
    /// Tip mass `m` [kg].
    pub m_kg: f64,
    /// Piezo capacitance `Ca` [F].
    pub ca_f: f64,
    /// Piezo stiffness `k` [N/m].
    pub k_n_m: f64,
    /// Plunger support stiffness `Kg` [N/m].
    pub kg_n_m: f64,
    /// Piezo damping `b` [N s/m].
    pub b_ns_m: f64,
    /// Plunger mass `Mg` [kg].
    pub mg_kg: f64,
    /// Electromechanical coupling `T` [C/m] (= [N/V]).
    pub t_c_m: f64,
}

impl PiezoParams {
    /// Nominal parameters (physics.md §1).
    pub const NOMINAL: PiezoParams = PiezoParams {
        r_ohm: 371.2,
        m_kg: 9e-4,
        ca_f: 2.3e-7,
        k_n_m: 4.91e7,
        kg_n_m: 2.15e6,
        b_ns_m: 9.77,
        mg_kg: 0.019,
        t_c_m: 5.73,
    };

    /// Nominal parameters (physics.md §1).
    pub fn nominal() -> Self {
        Self::NOMINAL
    }

    /// The parameters as `(name, value)` pairs in a fixed order (R, m, Ca, k, Kg, b, Mg, T).
    pub fn as_array(&self) -> [f64; 8] {
        [
            self.r_ohm,
            self.m_kg,
            self.ca_f,
            self.k_n_m,
            self.kg_n_m,
            self.b_ns_m,
            self.mg_kg,
            self.t_c_m,
        ]
    }

    /// Builds parameters from the order of [`PiezoParams::as_array`].
    pub fn from_array(a: [f64; 8]) -> Self {
        Self {
            r_ohm: a[0],
            m_kg: a[1],
            ca_f: a[2],
            k_n_m: a[3],
            kg_n_m: a[4],
            b_ns_m: a[5],
            mg_kg: a[6],
            t_c_m: a[7],
        }
    }

    /// Parameter names in the order of [`PiezoParams::as_array`].
    pub const NAMES: [&'static str; 8] = ["R", "m", "Ca", "k", "Kg", "b", "Mg", "T"];

    /// Static piezo elongation `d = (T E - F_c) / k` [m] at voltage `e_v` [V] under a compressive
    /// contact force `f_c_n` [N] (physics.md §1 static check: 14.0 um at 120 V, no load).
    pub fn static_extension_m(&self, e_v: f64, f_c_n: f64) -> f64 {
        (self.t_c_m * e_v - f_c_n) / self.k_n_m
    }

    /// Electrical time constant `tau = R (Ca + T^2/k)` [s] of the unloaded retraction after an
    /// ideal voltage step, neglecting the tip and plunger inertia.
    pub fn retraction_time_constant_s(&self) -> f64 {
        self.r_ohm * (self.ca_f + self.t_c_m * self.t_c_m / self.k_n_m)
    }
}

/// The piezo mechanism of physics.md §1 with a command voltage:
///
/// ```text
/// R*Ca*q' + q - T*(y - l) = Ca*E(t)                                   (electrical)
/// Mg*l'' + Kg*l - b*(y' - l') - (k + T^2/Ca)*(y - l) + (T/Ca)*q = 0   (plunger)
/// m*y''  + b*(y' - l') + (k + T^2/Ca)*(y - l) - (T/Ca)*q + F_c = 0    (tip)
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PiezoMechanism {
    /// Mechanism parameters.
    pub params: PiezoParams,
    /// Command voltage.
    pub command: VoltageCommand,
    // precomputed coefficients of the right-hand side
    inv_rca: f64,
    k_eff: f64,
    t_over_ca: f64,
    inv_m: f64,
    inv_mg: f64,
}

impl PiezoMechanism {
    /// A mechanism with parameters `params` driven by `command`.
    pub fn new(params: PiezoParams, command: VoltageCommand) -> Self {
        let p = params;
        Self {
            params,
            command,
            inv_rca: 1.0 / (p.r_ohm * p.ca_f),
            k_eff: p.k_n_m + p.t_c_m * p.t_c_m / p.ca_f,
            t_over_ca: p.t_c_m / p.ca_f,
            inv_m: 1.0 / p.m_kg,
            inv_mg: 1.0 / p.mg_kg,
        }
    }

    /// The nominal mechanism with the nominal ramp.
    pub fn nominal() -> Self {
        Self::new(PiezoParams::nominal(), VoltageCommand::nominal())
    }
}

impl Mechanism for PiezoMechanism {
    fn initial_state(&self, preload_n: f64) -> [f64; MECH_STATES] {
        // physics.md §3: d0 = (T E - F0)/k, l0 = -F0/Kg, y0 = l0 + d0, q0 = Ca E + T d0
        let p = &self.params;
        let e = self.command.e0_v;
        let d0 = p.static_extension_m(e, preload_n);
        let l0 = -preload_n / p.kg_n_m;
        [p.ca_f * e + p.t_c_m * d0, l0, 0.0, l0 + d0, 0.0]
    }

    #[inline]
    fn derivatives(
        &self,
        t_s: f64,
        s: &[f64; MECH_STATES],
        contact_force_n: f64,
        ds: &mut [f64; MECH_STATES],
    ) {
        let p = &self.params;
        let [q, l, lv, y, yv] = *s;
        let e = self.command.voltage_v(t_s);
        let d = y - l;
        // internal force of the stack on the tip (positive extends it), shared by tip and plunger
        let stack = self.t_over_ca * q - self.k_eff * d - p.b_ns_m * (yv - lv);
        ds[0] = (p.ca_f * e - q + p.t_c_m * d) * self.inv_rca;
        ds[1] = lv;
        ds[2] = (-p.kg_n_m * l - stack) * self.inv_mg;
        ds[3] = yv;
        ds[4] = (stack - contact_force_n) * self.inv_m;
    }

    fn breakpoints_s(&self) -> Vec<f64> {
        let t = self.command.ramp_end_s();
        if t.is_finite() && t > 0.0 {
            vec![t]
        } else {
            vec![]
        }
    }

    fn state_scales(&self) -> [f64; MECH_STATES] {
        let p = &self.params;
        let e = self.command.e0_v;
        let d = p.static_extension_m(e, 0.0);
        // charge, plunger travel (~F/Kg), plunger speed, tip stroke, tip speed (~ mm/s .. 0.1 m/s)
        [p.ca_f * e + p.t_c_m * d, 1e-6, 1e-3, d, 0.05]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn static_extension_at_120v_is_14um() {
        let p = PiezoParams::nominal();
        assert_relative_eq!(
            p.static_extension_m(120.0, 0.0),
            5.73 * 120.0 / 4.91e7,
            max_relative = 1e-15
        );
        assert!((p.static_extension_m(120.0, 0.0) - 14.0e-6).abs() < 0.01e-6);
    }

    #[test]
    fn initial_state_is_an_equilibrium() {
        let m = PiezoMechanism::nominal();
        let s = m.initial_state(0.3);
        let mut ds = [0.0; MECH_STATES];
        m.derivatives(-1e-9, &s, 0.3, &mut ds);
        // q' relative to q/(R Ca), accelerations relative to F0/m
        assert!(ds[0].abs() < 1e-12 * s[0] * m.inv_rca, "{ds:?}");
        assert!(ds[2].abs() < 1e-9 * 0.3 / 0.019, "{ds:?}");
        assert!(ds[4].abs() < 1e-9 * 0.3 / 9e-4, "{ds:?}");
    }

    #[test]
    fn time_constant() {
        let tau = PiezoParams::nominal().retraction_time_constant_s();
        assert!((tau - 3.34e-4).abs() < 0.01e-4, "{tau}");
    }
}
