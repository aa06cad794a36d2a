//! The conditioning of the retraction's system matrix for the irregular tail
//! ([`super::irregular`]): diagonal balancing ([`balance`]), which brings the norm that sets a
//! series' terms to the dynamics instead of the units, and the fast real modes split off
//! ([`without_fast_modes`]), which a tail's state has lost from its first grid point on.

use super::expm::dotn as dot;

/// Diagonal scales `d` (powers of two, so that `D^-1 A D` is exact) that balance the rows and
/// columns of `a` (Parlett and Reinsch, as LAPACK's `dgebal` without its permutations): each
/// off-diagonal row sum and column sum brought within a factor of two of the other, until no
/// scale lowers their sum by 5 %. The norm of the balanced matrix is near its spectral radius
/// when the unbalanced one's is set by units (a stiffness over a mass next to a 1).
pub(super) fn balance<const N: usize>(a: &[[f64; N]; N]) -> [f64; N] {
    let mut b = *a;
    let mut d = [1.0; N];
    for _ in 0..64 {
        let mut done = true;
        for i in 0..N {
            let (mut c, mut r) = (0.0f64, 0.0f64);
            for j in (0..N).filter(|&j| j != i) {
                c += b[j][i].abs();
                r += b[i][j].abs();
            }
            if c == 0.0 || r == 0.0 || !(c + r).is_finite() {
                continue;
            }
            let s = c + r;
            let mut f = 1.0;
            while c < r / 2.0 && f < 1e150 {
                c *= 2.0;
                r /= 2.0;
                f *= 2.0;
            }
            while c >= 2.0 * r && f > 1e-150 {
                c /= 2.0;
                r *= 2.0;
                f /= 2.0;
            }
            if c + r < 0.95 * s {
                done = false;
                d[i] *= f;
                for row in b.iter_mut() {
                    row[i] *= f;
                }
                for v in b[i].iter_mut() {
                    *v /= f;
                }
            }
        }
        if done {
            break;
        }
    }
    d
}

/// `Re(lambda) h` at or below which a mode is fast: it decays by `e^-45` (3e-20) within one grid
/// step, so from the first grid point on it is gone below rounding.
pub(super) const FAST_DECAY: f64 = -45.0;

/// Most power iterations spent on one fast mode.
const POWER_ITERATIONS: usize = 400;

/// Largest condition number `|x| |y| / |y . x|` of a fast mode's right and left eigenvectors
/// `x`, `y` accepted: a fast mode nearly parallel to a slow one is not split off.
const FAST_CONDITION: f64 = 1e4;

/// The dominant eigenvalue of `b` and its unit eigenvector by power iteration (deterministic
/// start), `None` unless it converged to a real eigenvalue (a residual `|b x - lambda x|` within
/// 1e-13 of `|lambda|`): a complex dominant pair, or two of nearly equal size, never do.
fn dominant<const N: usize>(b: &[[f64; N]; N]) -> Option<(f64, [f64; N])> {
    let mul = |x: &[f64; N]| -> [f64; N] { std::array::from_fn(|i| dot(&b[i], x)) };
    let unit = |x: [f64; N]| -> Option<[f64; N]> {
        let n = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        (n > 0.0 && n.is_finite()).then(|| x.map(|v| v / n))
    };
    let mut x = unit(std::array::from_fn(|i| 1.0 + 0.1 * i as f64))?;
    // converged to 1e-13, then on while the residual still falls (to rounding)
    let mut best: Option<(f64, f64, [f64; N])> = None;
    for _ in 0..POWER_ITERATIONS {
        let bx = mul(&x);
        let lambda = dot(&x, &bx);
        let res = (0..N)
            .map(|i| (bx[i] - lambda * x[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        if let Some((r0, l0, x0)) = best
            && res >= 0.5 * r0
        {
            return Some((l0, x0));
        }
        if res <= 1e-13 * lambda.abs() {
            best = Some((res, lambda, x));
        }
        x = unit(bx)?;
    }
    best.map(|(_, l, x)| (l, x))
}

/// The system matrix `a` (balanced) with its fast modes taken out (issue 50, item 5): each
/// real eigenvalue with `lambda h <= FAST_DECAY`, found largest first by power iteration,
/// is sent to zero by the deflation `b - lambda x y^T / (y . x)` with its right and left
/// eigenvectors, which leaves every other eigenvalue and eigenvector as it is. What remains,
/// `A P_s` (`P_s` the projector on the slow modes), is `A` on every state whose fast part has
/// decayed, as a tail's state has from its first grid point on; its norm is that of the slow
/// dynamics, so a stiff model (a search start whose piezo relaxes in a thousandth of a step:
/// `|A| h` 640 to 4 600) is read with the few bins of a compliant one instead of 4 096 bins of
/// 10 to 14 terms in two levels. `None` when there is no fast mode, or one that does not
/// split cleanly (complex, close to another, or ill-conditioned: the bins then cover `A`
/// itself).
pub(super) fn without_fast_modes<const N: usize>(
    a: &[[f64; N]; N],
    h: f64,
) -> Option<[[f64; N]; N]> {
    let mut b = *a;
    let mut split = false;
    for _ in 1..N {
        let Some((lambda, x)) = dominant(&b) else {
            break;
        };
        if lambda * h > FAST_DECAY {
            break;
        }
        let bt: [[f64; N]; N] = std::array::from_fn(|i| std::array::from_fn(|j| b[j][i]));
        let (mu, y) = dominant(&bt)?;
        let yx = dot(&y, &x);
        if (mu - lambda).abs() > 1e-10 * lambda.abs() || yx.abs() * FAST_CONDITION < 1.0 {
            return None;
        }
        let f = lambda / yx;
        b = std::array::from_fn(|i| std::array::from_fn(|j| b[i][j] - f * x[i] * y[j]));
        split = true;
    }
    split.then_some(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::retraction::RtConfig;
    use crate::retraction::expm::{N_HOM, expm_n as expm};

    /// The largest absolute row sum of a 5 x 5 matrix times the 1 us step.
    fn norm_h(m: &[[f64; N_HOM]; N_HOM]) -> f64 {
        m.iter()
            .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max)
            * 1e-6
    }

    /// The balanced leading 5 x 5 block of `cfg`'s scaled system matrix and its scaled start.
    fn balanced(cfg: &RtConfig) -> ([[f64; N_HOM]; N_HOM], [f64; N_HOM]) {
        let (_, a, z) = cfg.scaled_start();
        let a5: [[f64; N_HOM]; N_HOM] = std::array::from_fn(|i| std::array::from_fn(|j| a[i][j]));
        let d = balance(&a5);
        (
            std::array::from_fn(|i| std::array::from_fn(|j| a5[i][j] * d[j] / d[i])),
            std::array::from_fn(|i| z[i] / d[i]),
        )
    }

    /// The fast modes split off are those of the model, and what remains reads a state whose
    /// fast part has decayed as the model does: a light model (`m` 9 ug, `b` 977 N s/m: real
    /// modes at `lambda h` -100 and -113) keeps its slow dynamics, `|A_s| h` 2.6 against 143
    /// for `A` (measured), and `exp(A_s e) v` is `exp(A e) v` to 1e-12 for a state one step after
    /// the start; a ringing plunger (a complex pair at 46 radians a step, no fast real mode)
    /// is left whole.
    #[test]
    fn fast_modes_split_off_leave_the_slow_dynamics() {
        let light = RtConfig {
            m_kg: 9e-6,
            b_ns_m: 977.0,
            plunger: Some((1.9e-4, 2.15e6)),
            ..RtConfig::default()
        };
        let h = 1e-6;
        let (b, v0) = balanced(&light);
        let s = without_fast_modes(&b, h).expect("fast modes");
        let (nb, ns) = (norm_h(&b), norm_h(&s));
        assert!(nb > 100.0 && ns < 3.0, "{nb} {ns}");
        let m = expm(&b, h);
        let v1: [f64; N_HOM] = std::array::from_fn(|i| dot(&m[i], &v0));
        let size = v1.iter().map(|x| x.abs()).fold(0.0, f64::max);
        for e in [0.05e-6, 0.3e-6, 0.7e-6, 0.99e-6] {
            let (full, split) = (expm(&b, e), expm(&s, e));
            for i in 0..N_HOM {
                let (x, y) = (dot(&full[i], &v1), dot(&split[i], &v1));
                assert!((x - y).abs() <= 1e-12 * size, "{e} {i}: {x} {y}");
            }
            // ... and not so for the state at the start, whose fast part is still there
            let off = (0..N_HOM)
                .map(|i| (dot(&full[i], &v0) - dot(&split[i], &v0)).abs())
                .fold(0.0, f64::max);
            assert!(off > 1e-9 * size, "{e}: {off} {size}");
        }
        let ringing = RtConfig {
            b_ns_m: 1e-6,
            plunger: Some((1e-9, 2.15e6)),
            ..RtConfig::default()
        };
        let (b, _) = balanced(&ringing);
        assert!(norm_h(&b) > 45.0, "{}", norm_h(&b));
        assert!(without_fast_modes(&b, h).is_none());
    }
}
