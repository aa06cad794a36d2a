//! The uncertainties of the values a fit holds for a model's exact symmetries
//! ([`crate::identify::holds`]), folded into the fit's sigmas and combinations.

use nalgebra::{DMatrix, DVector};

use super::FitOutcome;
use crate::identify::{Held, combination_exponents, dot};
use crate::prepare::Prepared;

/// Folds the held values' uncertainties into a fit: for each held parameter `h`, the free
/// parameters' optimum moves by `G_h = (J^T J)^-1 J^T J_h` per unit of `ln h` (the regression
/// of its whitened Jacobian column on the free ones, central differences at the optimum), so
/// the covariance of the free parameters gains `r_h^2 G_h G_h^T` and `h` itself has the
/// relative sigma `r_h`. The parameters' sigmas, and the combinations' (with
/// [`crate::identify::combinations`]), include it; a combination that the held values move is not resolved by
/// the data and gets no sigma.
pub(super) fn propagate_held(prep: &Prepared, o: &mut FitOutcome, held: &[Held]) {
    if held.is_empty() {
        return;
    }
    let model = o.model.clone();
    let specs = model.specs();
    let t = &prep.dataset.t;
    let fidx: Vec<usize> = (0..o.p.len()).filter(|&i| o.free[i]).collect();
    let hidx: Vec<usize> = held.iter().filter_map(|h| model.index(&h.param)).collect();
    let column = |i: usize| -> Vec<f64> {
        // d prediction / d ln p_i (all the retraction's parameters are log-fitted), whitened
        let h: f64 = 1e-5;
        let mut up = o.p.clone();
        let mut dn = o.p.clone();
        up[i] *= h.exp();
        dn[i] *= (-h).exp();
        let a = model.predict(&up, t, &prep.inputs);
        let b = model.predict(&dn, t, &prep.inputs);
        let mut c: Vec<f64> = a.iter().zip(&b).map(|(x, y)| (x - y) / (2.0 * h)).collect();
        prep.normalise(&mut c, o.sigma);
        c
    };
    if fidx.iter().chain(&hidx).any(|&i| !specs[i].log) {
        return;
    }
    let jf: Vec<Vec<f64>> = fidx.iter().map(|&i| column(i)).collect();
    let k = jf.len();
    let jtj = DMatrix::from_fn(k, k, |a, b| dot(&jf[a], &jf[b]));
    let Some(inv) = crate::numeric::linalg::pseudo_inverse(&jtj, 1e-14 * jtj.norm()) else {
        return;
    };
    // the covariance of the free parameters in ln p, from the fit's sigmas and correlations
    let sd: Vec<f64> = fidx
        .iter()
        .map(|&i| o.sigma_p[i] / o.p[i].abs().max(1e-300))
        .collect();
    let n_all = k + hidx.len();
    let mut cov = DMatrix::zeros(n_all, n_all);
    for a in 0..k {
        for b in 0..k {
            cov[(a, b)] = o.corr[(a, b)] * sd[a] * sd[b];
        }
    }
    for (m, (&hi, h)) in hidx.iter().zip(held).enumerate() {
        let jh = column(hi);
        let b = DVector::from_fn(k, |a, _| dot(&jf[a], &jh));
        let g = &inv * b;
        let r2 = h.relative_sigma * h.relative_sigma;
        let row = k + m;
        for a in 0..k {
            for c in 0..k {
                cov[(a, c)] += r2 * g[a] * g[c];
            }
            cov[(a, row)] = -r2 * g[a];
            cov[(row, a)] = -r2 * g[a];
        }
        cov[(row, row)] = r2;
        o.sigma_p[hi] = h.relative_sigma * o.p[hi];
    }
    for (a, &i) in fidx.iter().enumerate() {
        if o.resolved[i] {
            o.sigma_p[i] = o.p[i].abs() * cov[(a, a)].max(0.0).sqrt();
        }
    }
    // the combinations: their variance from the data alone and with the held values
    let order: Vec<usize> = fidx.iter().chain(&hidx).copied().collect();
    for (name, c) in o.combinations.iter_mut() {
        let Some(exps) = combination_exponents(o.model.scenario, name) else {
            continue;
        };
        let g: Vec<f64> = order
            .iter()
            .map(|&i| {
                let n = &o.model.param_names()[i];
                exps.iter().filter(|(e, _)| e == n).map(|(_, x)| *x).sum()
            })
            .collect();
        let mut var_all = 0.0;
        let mut var_data = 0.0;
        for a in 0..n_all {
            for b in 0..n_all {
                var_all += g[a] * cov[(a, b)] * g[b];
                if a < k && b < k {
                    var_data += g[a] * o.corr[(a, b)] * sd[a] * sd[b] * g[b];
                }
            }
        }
        // moved by the held values beyond the data's own spread: not resolved by the data
        if c.sigma.is_some() && var_all > 1.21 * var_data + 1e-30 {
            c.sigma = None;
        }
    }
}
