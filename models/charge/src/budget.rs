//! TM charge and voltage after release from contact electrification (thesis ch. 7;
//! physics.md section 7):
//!
//! `Q = C_EH dV_EH + C_Pyr dV_Pyr + C_Cyl dV_Cyl + C_RT dV_RT`,
//! `V_TM = (C_Pyr dV_Pyr + C_Cyl dV_Cyl + C_RT dV_RT) / C_EH`,
//!
//! each `dV` an independent zero-mean normal with 2 sigma = `dv_2sigma_v` (thesis: 1 V). The
//! 2-sigma bounds follow analytically (thesis eqs. for `Q_TM` and `|V_TM|`):
//! `Q_2s = sqrt(C_EH^2 + C_Pyr^2 + C_Cyl^2 + C_RT^2) dV_2s`,
//! `V_2s = sqrt(C_Pyr^2 + C_Cyl^2 + C_RT^2) / C_EH dV_2s`;
//! [`monte_carlo`] estimates the same by sampling.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// Elementary charge (exact, SI 2019) [C].
pub const ELEMENTARY_CHARGE_C: f64 = 1.602_176_634e-19;

/// Two-sided coverage of +-2 sigma of a normal, `erf(sqrt 2)` [-].
pub const COVERAGE_2SIGMA: f64 = 0.954_499_736_103_641_6;

/// Inputs of the charge budget.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChargeInputs {
    /// TM - electrode housing capacitance `C_TM,EH` [F] (thesis: 34.4 pF, FE analysis).
    pub c_eh_f: f64,
    /// TM - pyramidal plunger capacitance `C_TM,Pyr` [F] (thesis: 35 pF).
    pub c_pyr_f: f64,
    /// TM - cylindrical plunger capacitance `C_TM,Cyl` [F] (thesis: 10 pF).
    pub c_cyl_f: f64,
    /// TM - release tip capacitance `C_TM,RT` [F] (from the cap integral, about 2.4 pF).
    pub c_rt_f: f64,
    /// 2-sigma contact voltage difference `dV` of each contact [V] (thesis: 1 V).
    pub dv_2sigma_v: f64,
}

impl ChargeInputs {
    /// The thesis's capacitances and voltage spread with the given `C_RT` [F].
    pub fn thesis_with_c_rt(c_rt_f: f64) -> ChargeInputs {
        ChargeInputs {
            c_eh_f: 34.4e-12,
            c_pyr_f: 35e-12,
            c_cyl_f: 10e-12,
            c_rt_f,
            dv_2sigma_v: 1.0,
        }
    }

    /// Analytic 2-sigma bound of `|Q|` [C].
    pub fn q_2sigma_c(&self) -> f64 {
        let c = [self.c_eh_f, self.c_pyr_f, self.c_cyl_f, self.c_rt_f];
        c.iter().map(|x| x * x).sum::<f64>().sqrt() * self.dv_2sigma_v
    }

    /// Analytic 2-sigma bound of `|Q|` in elementary charges [e].
    pub fn q_2sigma_e(&self) -> f64 {
        self.q_2sigma_c() / ELEMENTARY_CHARGE_C
    }

    /// Analytic 2-sigma bound of `|V_TM|` [V].
    pub fn v_2sigma_v(&self) -> f64 {
        let c = [self.c_pyr_f, self.c_cyl_f, self.c_rt_f];
        c.iter().map(|x| x * x).sum::<f64>().sqrt() / self.c_eh_f * self.dv_2sigma_v
    }

    /// `(Q [C], V_TM [V])` for one set of voltage differences `[dV_EH, dV_Pyr, dV_Cyl, dV_RT]` [V].
    pub fn charge_and_voltage(&self, dv: [f64; 4]) -> (f64, f64) {
        let plungers_rt = self.c_pyr_f * dv[1] + self.c_cyl_f * dv[2] + self.c_rt_f * dv[3];
        (self.c_eh_f * dv[0] + plungers_rt, plungers_rt / self.c_eh_f)
    }
}

/// Monte Carlo estimate of the charge and voltage spread.
#[derive(Clone, Debug, PartialEq)]
pub struct ChargeMonteCarlo {
    /// Number of draws.
    pub n: usize,
    /// Seed (draw `k` uses ChaCha8 stream `k`).
    pub seed: u64,
    /// Twice the sample standard deviation of `Q` [e].
    pub q_2sd_e: f64,
    /// 95.45 % quantile of `|Q|` (the two-sided 2-sigma coverage) [e].
    pub q_p9545_e: f64,
    /// Twice the sample standard deviation of `V_TM` [V].
    pub v_2sd_v: f64,
    /// 95.45 % quantile of `|V_TM|` [V].
    pub v_p9545_v: f64,
}

/// Samples `n` releases: each `dV` ~ Normal(0, dv_2sigma/2), draw `k` on stream `k` of `seed`
/// (deterministic whatever the thread count). Returns NaN statistics for `n = 0`.
pub fn monte_carlo(inputs: &ChargeInputs, n: usize, seed: u64) -> ChargeMonteCarlo {
    let sigma = 0.5 * inputs.dv_2sigma_v;
    let mut q = Vec::with_capacity(n);
    let mut v = Vec::with_capacity(n);
    for k in 0..n {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(k as u64);
        let dv: [f64; 4] = std::array::from_fn(|_| {
            let z: f64 = StandardNormal.sample(&mut rng);
            sigma * z
        });
        let (qc, vv) = inputs.charge_and_voltage(dv);
        q.push(qc / ELEMENTARY_CHARGE_C);
        v.push(vv);
    }
    ChargeMonteCarlo {
        n,
        seed,
        q_2sd_e: 2.0 * sample_sd(&q),
        q_p9545_e: abs_quantile(&q, COVERAGE_2SIGMA),
        v_2sd_v: 2.0 * sample_sd(&v),
        v_p9545_v: abs_quantile(&v, COVERAGE_2SIGMA),
    }
}

fn sample_sd(x: &[f64]) -> f64 {
    if x.len() < 2 {
        return f64::NAN;
    }
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// `p` quantile of `|x|` (nearest rank).
fn abs_quantile(x: &[f64], p: f64) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let mut a: Vec<f64> = x.iter().map(|v| v.abs()).collect();
    a.sort_by(f64::total_cmp);
    let idx = ((p * a.len() as f64).ceil() as usize).clamp(1, a.len()) - 1;
    a[idx]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn thesis() -> ChargeInputs {
        ChargeInputs::thesis_with_c_rt(2.5e-12)
    }

    #[test]
    fn analytic_bounds_with_the_thesis_c_rt() {
        // sqrt(34.4^2 + 35^2 + 10^2 + 2.5^2) pF * 1 V = 50.146 pF V = 3.130e8 e
        let q = thesis().q_2sigma_e();
        assert!((q - 3.1299e8).abs() < 1e5, "{q}");
        // sqrt(35^2 + 10^2 + 2.5^2) / 34.4 = 1.0607 V
        let v = thesis().v_2sigma_v();
        assert!((v - 1.06066).abs() < 1e-4, "{v}");
    }

    #[test]
    fn monte_carlo_agrees_with_analytic() {
        let i = thesis();
        let mc = monte_carlo(&i, 200_000, 11);
        // standard error of the sd: 1/sqrt(2n) = 0.16 %; of the 95.45 % quantile about 0.3 %.
        assert!((mc.q_2sd_e / i.q_2sigma_e() - 1.0).abs() < 0.01, "{mc:?}");
        assert!((mc.v_2sd_v / i.v_2sigma_v() - 1.0).abs() < 0.01, "{mc:?}");
        assert!((mc.q_p9545_e / i.q_2sigma_e() - 1.0).abs() < 0.02, "{mc:?}");
        assert!((mc.v_p9545_v / i.v_2sigma_v() - 1.0).abs() < 0.02, "{mc:?}");
    }

    #[test]
    fn monte_carlo_is_deterministic() {
        let i = thesis();
        assert_eq!(monte_carlo(&i, 1000, 5), monte_carlo(&i, 1000, 5));
        assert_ne!(monte_carlo(&i, 1000, 5), monte_carlo(&i, 1000, 6));
    }

    #[test]
    fn voltage_excludes_the_housing_term() {
        let (q, v) = thesis().charge_and_voltage([1.0, 0.0, 0.0, 0.0]);
        assert!((q - 34.4e-12).abs() < 1e-24);
        assert_eq!(v, 0.0);
    }
}
