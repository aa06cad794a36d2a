//! What drives the release velocity: variance-based global sensitivity of `|v_TM|` to each
//! uncertainty group of the budget, and the shift of the 99.73 % point when a group is frozen
//! at nominal (the thesis's adhesion-only / mechanisms-only split, ch. 6, generalised).
//!
//! Estimators (Saltelli et al. 2010, "Variance based sensitivity analysis of model output",
//! Table 2): two independent sample matrices `A` and `B` of `n` draws, and for each group `g`
//! the matrix `A_B^g` (rows of `A` with the group's inputs taken from `B`). With `V` the variance
//! of the outputs of `A` and `B` together,
//!
//! * first order `S_g = mean(f(B) (f(A_B^g) - f(A))) / V` (Saltelli 2010),
//! * total `ST_g = mean((f(A) - f(A_B^g))^2) / (2 V)` (Jansen 1999),
//!
//! with 95 % percentile intervals from a bootstrap over the `n` rows (200 resamples, a fixed
//! ChaCha stream). Cost: `(groups + 2) n` releases for the indices and `groups n` for the
//! frozen-group shifts, all with common random numbers (the same draws, the group replaced),
//! deterministic for a seed whatever the thread count.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::budget::Budget;
use crate::expgauss::ExpGauss;
use crate::inputs::ReleaseInputs;
use crate::montecarlo::{Case, McError, describe, draw_inputs};
use crate::stats::quantile_sorted;

/// Bootstrap resamples of the confidence intervals.
pub const BOOTSTRAP: usize = 200;

/// An uncertainty group: its name and how to copy it from one draw into another.
pub struct Group<T> {
    /// Name.
    pub name: &'static str,
    /// Copies the group's inputs from the second argument into the first.
    pub take: fn(&mut T, &T),
}

/// Indices of one group.
#[derive(Debug, Clone, PartialEq)]
pub struct Indices {
    /// Group.
    pub group: String,
    /// First-order index.
    pub first: f64,
    /// 95 % interval of the first-order index.
    pub first_ci: [f64; 2],
    /// Total index.
    pub total: f64,
    /// 95 % interval of the total index.
    pub total_ci: [f64; 2],
}

fn estimate(fa: &[f64], fb: &[f64], fab: &[f64], rows: &[usize]) -> (f64, f64) {
    let n = rows.len() as f64;
    let all: Vec<f64> = rows.iter().flat_map(|&i| [fa[i], fb[i]]).collect();
    let m = all.iter().sum::<f64>() / all.len() as f64;
    let v = all.iter().map(|y| (y - m) * (y - m)).sum::<f64>() / (all.len() as f64 - 1.0);
    if v.is_nan() || v <= 0.0 {
        return (0.0, 0.0);
    }
    let s1 = rows.iter().map(|&i| fb[i] * (fab[i] - fa[i])).sum::<f64>() / n / v;
    let st = rows.iter().map(|&i| (fa[i] - fab[i]).powi(2)).sum::<f64>() / (2.0 * n * v);
    (s1, st)
}

/// Saltelli/Jansen indices of `f` for `groups`, from the draws `a` and `b` (independent, the
/// same length), with bootstrap intervals drawn with `seed`.
pub fn saltelli<T: Clone + Sync>(
    a: &[T],
    b: &[T],
    groups: &[Group<T>],
    f: &(dyn Fn(&T) -> Result<f64, McError> + Sync),
    seed: u64,
) -> Result<Vec<Indices>, McError> {
    let eval = |xs: &[T]| -> Result<Vec<f64>, McError> { xs.par_iter().map(f).collect() };
    let fa = eval(a)?;
    let fb = eval(b)?;
    let n = a.len();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let boots: Vec<Vec<usize>> = (0..BOOTSTRAP)
        .map(|_| (0..n).map(|_| rng.random_range(0..n)).collect())
        .collect();
    let all: Vec<usize> = (0..n).collect();
    let mut out = Vec::new();
    for g in groups {
        let ab: Vec<T> = a
            .iter()
            .zip(b)
            .map(|(x, y)| {
                let mut z = x.clone();
                (g.take)(&mut z, y);
                z
            })
            .collect();
        let fab = eval(&ab)?;
        let (s1, st) = estimate(&fa, &fb, &fab, &all);
        let mut bs: Vec<(f64, f64)> = boots.iter().map(|r| estimate(&fa, &fb, &fab, r)).collect();
        let ci = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            [quantile_sorted(v, 0.025), quantile_sorted(v, 0.975)]
        };
        let mut b1: Vec<f64> = bs.iter().map(|x| x.0).collect();
        let mut bt: Vec<f64> = bs.drain(..).map(|x| x.1).collect();
        out.push(Indices {
            group: g.name.to_string(),
            first: s1,
            first_ci: ci(&mut b1),
            total: st,
            total_ci: ci(&mut bt),
        });
    }
    Ok(out)
}

/// The uncertainty groups of the release budget.
pub fn release_groups() -> Vec<Group<ReleaseInputs>> {
    vec![
        Group {
            name: "adhesion, side 1",
            take: |x, y| {
                x.a1_n_m[0] = y.a1_n_m[0];
                x.lambda_m[0] = y.lambda_m[0];
            },
        },
        Group {
            name: "adhesion, side 2",
            take: |x, y| {
                x.a1_n_m[1] = y.a1_n_m[1];
                x.lambda_m[1] = y.lambda_m[1];
            },
        },
        Group {
            name: "mechanism 1",
            take: |x, y| x.mech[0] = y.mech[0],
        },
        Group {
            name: "mechanism 2",
            take: |x, y| x.mech[1] = y.mech[1],
        },
        Group {
            name: "command slope",
            take: |x, y| x.em_v_s = y.em_v_s,
        },
        Group {
            name: "tip radii",
            take: |x, y| x.tip_radius_m = y.tip_radius_m,
        },
        Group {
            name: "preload",
            take: |x, y| x.preload_n = y.preload_n,
        },
    ]
}

/// A draw with every input at the budget's nominal (mean) value, for freezing groups.
pub fn nominal_inputs(budget: &Budget, template: &ReleaseInputs) -> ReleaseInputs {
    let a = &budget.adhesion;
    let mut r = *template;
    r.mech = [budget.mechanism.mean(); 2];
    r.em_v_s = [budget.em_v_s.mean(); 2];
    r.tip_radius_m = [budget.tip_radius_m.mean(); 2];
    r.preload_n = budget.preload_n.mean();
    r.a1_n_m = [a.A1_n_m.mean(); 2];
    r.lambda_m = [a.lambda_m.mean(); 2];
    r
}

/// Result of [`release_sensitivity`].
#[derive(Debug, Clone)]
pub struct Sensitivity {
    /// Draws per sample matrix.
    pub n: usize,
    /// Seed.
    pub seed: u64,
    /// Indices per group, with the 99.73 % shift when the group is frozen [um/s].
    pub groups: Vec<(Indices, f64)>,
    /// 99.73 % point of |v| with every group free [um/s].
    pub p9973_um_s: f64,
    /// Variance of |v| [(um/s)^2].
    pub variance_um2_s2: f64,
}

/// Sensitivity of the release velocity `|v_TM|` [um/s] to the budget's uncertainty groups, with
/// `n` draws per sample matrix: `A` = draws `0..n` of `seed`, `B` = draws `n..2n`.
pub fn release_sensitivity(
    budget: &Budget,
    n: usize,
    seed: u64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Sensitivity, McError> {
    let a: Vec<ReleaseInputs> = (0..n as u64)
        .map(|i| draw_inputs(budget, Case::All, seed, i))
        .collect();
    let b: Vec<ReleaseInputs> = (n as u64..2 * n as u64)
        .map(|i| draw_inputs(budget, Case::All, seed, i))
        .collect();
    let integ = ExpGauss::fast();
    let f = |r: &ReleaseInputs| -> Result<f64, McError> {
        let out = r.simulate_fast(&integ).map_err(|source| McError::Release {
            index: 0,
            inputs: describe(r),
            source,
        })?;
        progress(1);
        Ok(out.v_tm_m_s.abs() * 1e6)
    };
    let groups = release_groups();
    let idx = saltelli(&a, &b, &groups, &f, seed ^ 0x5EED_B007)?;
    let p = |ys: Vec<f64>| {
        let mut ys = ys;
        ys.sort_by(f64::total_cmp);
        quantile_sorted(&ys, 0.9973)
    };
    let fa: Vec<f64> = a.par_iter().map(f).collect::<Result<_, _>>()?;
    let p_all = p(fa.clone());
    let fb: Vec<f64> = b.par_iter().map(f).collect::<Result<_, _>>()?;
    let all: Vec<f64> = fa.iter().chain(&fb).copied().collect();
    let m = all.iter().sum::<f64>() / all.len() as f64;
    let var = all.iter().map(|y| (y - m) * (y - m)).sum::<f64>() / (all.len() as f64 - 1.0);
    let mut out = Vec::new();
    for (g, ix) in groups.iter().zip(idx) {
        let frozen: Vec<f64> = a
            .par_iter()
            .map(|x| {
                let mut z = *x;
                (g.take)(&mut z, &nominal_inputs(budget, x));
                f(&z)
            })
            .collect::<Result<_, _>>()?;
        out.push((ix, p(frozen) - p_all));
    }
    Ok(Sensitivity {
        n,
        seed,
        groups: out,
        p9973_um_s: p_all,
        variance_um2_s2: var,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Ishigami function (a = 7, b = 0.1) on U(-pi, pi)^3: first-order indices 0.3139,
    /// 0.4424, 0 and total 0.5576, 0.4424, 0.2437 (Saltelli et al. 2008, "Global Sensitivity
    /// Analysis: The Primer", section 4.7; analytic).
    #[test]
    fn ishigami_indices_fall_within_their_intervals_of_the_analytic_values() {
        let n = 20_000;
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let pi = std::f64::consts::PI;
        let mut draw = || [0; 3].map(|_| rng.random_range(-pi..pi));
        let a: Vec<[f64; 3]> = (0..n).map(|_| draw()).collect();
        let b: Vec<[f64; 3]> = (0..n).map(|_| draw()).collect();
        let groups: Vec<Group<[f64; 3]>> = vec![
            Group {
                name: "x1",
                take: |x, y| x[0] = y[0],
            },
            Group {
                name: "x2",
                take: |x, y| x[1] = y[1],
            },
            Group {
                name: "x3",
                take: |x, y| x[2] = y[2],
            },
        ];
        let f = |x: &[f64; 3]| -> Result<f64, McError> {
            Ok(x[0].sin() + 7.0 * x[1].sin().powi(2) + 0.1 * x[2].powi(4) * x[0].sin())
        };
        let idx = saltelli(&a, &b, &groups, &f, 3).unwrap();
        let want = [(0.3139, 0.5576), (0.4424, 0.4424), (0.0, 0.2437)];
        for (ix, (s1, st)) in idx.iter().zip(want) {
            // about three standard errors of the estimators at n = 20 000 (Saltelli 2010,
            // fig. 2: ~0.01 for the Ishigami function), and intervals around the estimates
            assert!(
                ix.first_ci[0] <= ix.first && ix.first <= ix.first_ci[1],
                "{ix:?}"
            );
            assert!(
                ix.total_ci[0] <= ix.total && ix.total <= ix.total_ci[1],
                "{ix:?}"
            );
            assert!(
                (ix.first - s1).abs() < 0.03 && (ix.total - st).abs() < 0.03,
                "{ix:?}"
            );
        }
    }
}
