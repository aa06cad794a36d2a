//! The three-equation piezo mechanism model of thesis ch. 3 (physics.md §1, with its two typo
//! fixes: `Kg*l` in the plunger equation, `y - l` in the electrical one).

use crate::{MECH_STATES, Mechanism, Modes, VoltageCommand};
use num_complex::Complex64;

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

    fn modes(&self) -> Option<Modes> {
        let p = &self.params;
        let (m, mg, kg, b, t) = (p.m_kg, p.mg_kg, p.kg_n_m, p.b_ns_m, p.t_c_m);
        let tau = p.r_ohm * p.ca_f;
        let poly = self.characteristic_polynomial();
        // starting points: electrical pole -1/(R (Ca + T^2/k)), plunger on Kg with both masses,
        // tip on the stack stiffness k_eff (thesis ch. 3 orders of magnitude)
        let guesses = [
            Complex64::new(-1.0 / p.retraction_time_constant_s(), 0.0),
            Complex64::new(-b / (2.0 * (mg + m)), (kg / (mg + m)).sqrt()),
            Complex64::new(-b / (2.0 * m), (self.k_eff / m).sqrt()),
        ];
        let mut roots = [Complex64::new(0.0, 0.0); 3];
        for (r, n) in roots.iter_mut().zip(newton_roots(&poly, guesses)) {
            *r = n?;
        }
        roots[0].im = 0.0;
        let lam = [
            roots[0],
            roots[1],
            roots[1].conj(),
            roots[2],
            roots[2].conj(),
        ];
        // Vieta: the sum and the product of the five roots must be those of the polynomial, or
        // two starting points converged to the same root
        let sum: Complex64 = lam.iter().sum();
        let prod: Complex64 = lam.iter().product();
        let ok = |x: Complex64, want: f64| {
            (x.re - want).abs() <= 1e-9 * want.abs() && x.im.abs() <= 1e-9 * want.abs()
        };
        if !ok(sum, -poly[4] / poly[5]) || !ok(prod, -poly[0] / poly[5]) {
            return None;
        }
        if roots[1].im.abs() < 1e-9 * roots[1].norm() || roots[2].im.abs() < 1e-9 * roots[2].norm()
        {
            return None; // a real pair: the conjugate layout does not hold
        }
        // eigenvector with unit stack force S d = 1 (derivation in `characteristic_polynomial`):
        // y and -l are then sums of same-signed terms, with no cancellation even where S is small
        let mut vectors = [[Complex64::new(0.0, 0.0); MECH_STATES]; MECH_STATES];
        for (j, &l) in lam.iter().enumerate() {
            let y = 1.0 / (m * l * l);
            let lp = -1.0 / (mg * l * l + kg);
            let q = t * (y - lp) / (1.0 + l * tau);
            let v = [q, lp, l * lp, y, l * y];
            if v.iter().any(|c| !c.re.is_finite() || !c.im.is_finite()) {
                return None;
            }
            for i in 0..MECH_STATES {
                vectors[i][j] = v[i];
            }
        }
        Some(Modes {
            eigenvalues: lam,
            vectors,
            b_voltage: [1.0 / p.r_ohm, 0.0, 0.0, 0.0, 0.0],
            b_force: [0.0, 0.0, 0.0, 0.0, -self.inv_m],
            command: self.command,
        })
    }
}

impl PiezoMechanism {
    /// Coefficients `[c0, ..., c5]` of the characteristic polynomial of the linear system.
    ///
    /// An eigenvector `(q, l, l', y, y')` of eigenvalue `s` has `l' = s l`, `y' = s y`,
    /// `q = T d / (1 + s R Ca)` with `d = y - l`, and the stack force `S(s) d` with
    /// `S(s) = T^2 / (Ca (1 + s R Ca)) - k_eff - b s`; the tip and plunger equations give
    /// `y = S d / (m s^2)`, `l = -S d / (Mg s^2 + Kg)`, so `1 = S (1/(m s^2) + 1/(Mg s^2 + Kg))`.
    /// Multiplied out (`k_eff - T^2/Ca = k`):
    /// `(1 + s tau) m s^2 (Mg s^2 + Kg) + (k + (b + k_eff tau) s + b tau s^2)((Mg + m) s^2 + Kg)`
    /// with `tau = R Ca`; every coefficient is a sum of positive terms (no cancellation).
    pub fn characteristic_polynomial(&self) -> [f64; 6] {
        let p = &self.params;
        let (m, mg, kg, b) = (p.m_kg, p.mg_kg, p.kg_n_m, p.b_ns_m);
        let tau = p.r_ohm * p.ca_f;
        let (alpha, beta, gamma, m2) = (p.k_n_m, b + self.k_eff * tau, b * tau, mg + m);
        [
            alpha * kg,
            beta * kg,
            m * kg + alpha * m2 + gamma * kg,
            m * kg * tau + beta * m2,
            m * mg + gamma * m2,
            m * mg * tau,
        ]
    }
}

/// Newton's method on a real polynomial `c[0] + c[1] s + ... + c[5] s^5` from each of `xs`;
/// `None` for a start that does not converge to full precision. The starts' iterations run side
/// by side (each a chain of dependent complex multiply-adds: latency-bound alone; perf put the
/// roots at a twentieth of a Monte Carlo release), each with its own stopping rule: the bits of
/// one run per start.
fn newton_roots<const L: usize>(c: &[f64; 6], mut x: [Complex64; L]) -> [Option<Complex64>; L] {
    let eval = |x: &[Complex64; L]| {
        let (mut p, mut dp) = (
            [Complex64::new(c[5], 0.0); L],
            [Complex64::new(0.0, 0.0); L],
        );
        for &ck in c[..5].iter().rev() {
            for b in 0..L {
                dp[b] = dp[b] * x[b] + p[b];
                p[b] = p[b] * x[b] + ck;
            }
        }
        (p, dp)
    };
    let mut out = [None; L];
    let mut live = [true; L];
    for _ in 0..60 {
        let (p, dp) = eval(&x);
        for b in 0..L {
            if !live[b] {
                continue;
            }
            if dp[b].norm_sqr() == 0.0 {
                live[b] = false;
                continue;
            }
            let dx = p[b] / dp[b];
            x[b] -= dx;
            if !x[b].re.is_finite() || !x[b].im.is_finite() {
                live[b] = false;
            } else if dx.norm_sqr() <= 1e-24 * x[b].norm_sqr() {
                // quadratic convergence: one more step reaches rounding level
                let (p, dp) = eval(&x);
                out[b] = Some(x[b] - p[b] / dp[b]);
                live[b] = false;
            }
        }
        if !live.contains(&true) {
            break;
        }
    }
    out
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

    /// `A V = V diag(eigenvalues)` with `A` taken from `derivatives` (unit states at fixed voltage),
    /// and the input vectors reproduce the voltage and contact-force terms.
    #[test]
    #[allow(clippy::needless_range_loop)] // matrix algebra: rows and columns of several arrays
    fn modes_diagonalise_the_mechanism() {
        let mut params = vec![PiezoParams::nominal()];
        let mut q = PiezoParams::nominal().as_array();
        for (i, f) in [0.7, 1.3, 0.8, 1.2, 0.75, 1.35, 1.25, 0.7]
            .iter()
            .enumerate()
        {
            q[i] *= f;
        }
        params.push(PiezoParams::from_array(q));
        for p in params {
            let mech = PiezoMechanism::new(p, VoltageCommand::nominal());
            let modes = mech.modes().expect("modes");
            let scales = mech.state_scales();
            let d = |s: &[f64; MECH_STATES], f: f64| {
                let mut ds = [0.0; MECH_STATES];
                mech.derivatives(-1.0, s, f, &mut ds);
                ds
            };
            let base = d(&[0.0; MECH_STATES], 0.0);
            let mut a = [[0.0; MECH_STATES]; MECH_STATES];
            for k in 0..MECH_STATES {
                let mut e = [0.0; MECH_STATES];
                e[k] = 1.0;
                let col = d(&e, 0.0);
                for i in 0..MECH_STATES {
                    a[i][k] = col[i] - base[i];
                }
            }
            for i in 0..MECH_STATES {
                assert!(
                    (base[i] - modes.b_voltage[i] * 120.0).abs()
                        <= 1e-12 * base[i].abs().max(1e-30)
                );
                let f = d(&[0.0; MECH_STATES], 1.0)[i] - base[i];
                assert!(
                    (f - modes.b_force[i]).abs() <= 1e-12 * f.abs().max(1e-30),
                    "{f}"
                );
            }
            for m in 0..MECH_STATES {
                let lam = modes.eigenvalues[m];
                // residual in state scales, relative to |lambda| |v|
                let v: Vec<Complex64> = (0..MECH_STATES)
                    .map(|i| modes.vectors[i][m] / scales[i])
                    .collect();
                let vn = v.iter().map(|c| c.norm()).fold(0.0, f64::max);
                for i in 0..MECH_STATES {
                    let mut av = Complex64::new(0.0, 0.0);
                    for k in 0..MECH_STATES {
                        av += a[i][k] * modes.vectors[k][m];
                    }
                    let r = (av - lam * modes.vectors[i][m]) / scales[i];
                    assert!(
                        r.norm() <= 1e-9 * lam.norm() * vn,
                        "mode {m} row {i}: {r} ({lam})"
                    );
                }
            }
        }
    }

    #[test]
    fn time_constant() {
        let tau = PiezoParams::nominal().retraction_time_constant_s();
        assert!((tau - 3.34e-4).abs() < 0.01e-4, "{tau}");
    }
}
