//! What a fit's data resolve (issue 33, item 5): symmetries of a model found from its Jacobian's
//! null space, the retraction's scale held by a stated value, and the combinations of
//! parameters a record identifies.
//!
//! * **Null-space check** ([`symmetries`]): the normal matrix `J^T J` of the whitened residual
//!   (unit diagonal) is diagonalised; a direction whose curvature changes by more than
//!   [`EXACT_TOLERANCE`] when the finite-difference steps are halved is made by the differences'
//!   truncation error, not by the data: an exact (or numerically exact) symmetry of the model.
//!   A direction whose 1-sigma reaches beyond the parameters' allowed ranges is a near symmetry:
//!   the record does not resolve it within the prior. Both are reported with their weights on
//!   the parameters (`symmetries` in the fit object), and a parameter with a weight above
//!   [`WEIGHT`] in one of them gets no finite sigma (`resolved: false`).
//! * **The retraction's exact scaling** (docs/fitting.md, "Sigmas the data do not resolve"):
//!   `m, b, k, Ca, T, Mg, Kg` times `s` and `R` over `s` leave the record unchanged. Unless the
//!   user holds one of them (`--fix`), the fit holds `piezo.Ca` at its nominal value (the thesis
//!   table) and says so (`held_scale`): the other parameters are then reported on that scale,
//!   their sigmas widened by the scale's own uncertainty, the release budget's 11.5 % per
//!   mechanism parameter (models/release/budget.yaml, physics.md s.3).
//! * **Identifiable combinations** ([`combinations`]): products of powers of parameters that
//!   the scaling leaves unchanged (the static stroke `T E0 / k`, the electrical time `R Ca`, the
//!   tip's natural frequency `sqrt(k / m)`, ...), each with its sigma from the covariance on the
//!   resolved directions when its log-gradient has no weight on an unresolved direction.

use std::collections::BTreeMap;

use geodesic_facility::{Model, Scenario};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// Relative change of a direction's curvature, when the difference steps are halved, above
/// which the curvature is the differences' truncation error (an exact symmetry): resolved
/// directions of the examples move by under 1 %, exact ones by 75 % (the curvature of a
/// truncation error falls as the step squared).
pub const EXACT_TOLERANCE: f64 = 0.2;

/// Weight (component of the unit direction in the fit's coordinates) above which a parameter
/// takes part in a symmetry.
pub const WEIGHT: f64 = 0.1;

/// The relative 1-sigma of the retraction's scale when the fit holds it (the release budget's
/// spread of every mechanism parameter, models/release/budget.yaml).
pub const SCALE_RELATIVE_SIGMA: f64 = 0.115;

/// The retraction's parameters that the exact scaling multiplies by `s` (with `piezo.R`
/// divided by `s`).
pub const SCALED: [&str; 8] = [
    "piezo.R",
    "piezo.m",
    "piezo.Ca",
    "piezo.k",
    "piezo.b",
    "piezo.T",
    "plunger_compliance.Mg",
    "plunger_compliance.Kg",
];

/// The parameter held to fix the retraction's scale.
pub const SCALE_PARAM: &str = "piezo.Ca";

/// A parameter a fit holds at a stated value because the record cannot tell it (issue 33),
/// with the value's own uncertainty, which is propagated to the parameters the fit moves to
/// compensate it ([`propagate_held`]).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Held {
    /// The parameter held.
    pub param: String,
    /// Its value [SI].
    pub value: f64,
    /// Its relative 1-sigma, folded into the sigma of every parameter and combination that
    /// moves with it.
    pub relative_sigma: f64,
    /// Why, and where the value comes from.
    pub reason: String,
}

/// The parameters the retraction's fit holds when the user holds none of its mechanism
/// parameters (the model's two exact symmetries, docs/fitting.md): `piezo.Ca` for the scaling
/// and `piezo.R` for the electrical time `R Ca` (which the record's identifiable combinations
/// leave free), each at its nominal value (the thesis table, clamped into a user bound) known
/// to the release budget's 11.5 %. Empty for other scenarios, or when the user fixes or bounds
/// one of [`SCALED`] (then the null-space check reports what is left free).
pub fn holds(
    model: &Model,
    fixed: &BTreeMap<String, f64>,
    bounds: &BTreeMap<String, (f64, f64)>,
) -> Vec<Held> {
    if model.scenario != Scenario::RtRetraction || !model.has("piezo") {
        return Vec::new();
    }
    let mut out = Vec::new();
    let specs = model.specs();
    let mut hold = |param: &str, reason: &str| {
        let Some(i) = model.index(param) else { return };
        let mut value = specs[i].nominal;
        if let Some(&(lo, hi)) = bounds.get(param)
            && lo <= hi
        {
            value = value.clamp(lo, hi);
        }
        out.push(Held {
            param: param.to_string(),
            value,
            relative_sigma: SCALE_RELATIVE_SIGMA,
            reason: format!(
                "{reason}: held at {value:e} {} (thesis table), known to {:.1} % (the release \
                 budget's spread of the mechanism parameters), propagated to the parameters \
                 that move with it",
                specs[i].unit,
                100.0 * SCALE_RELATIVE_SIGMA
            ),
        });
    };
    // a user who holds any mechanism parameter chooses the holds (the null-space check
    // reports what the record leaves free then)
    if SCALED
        .iter()
        .any(|n| fixed.contains_key(*n) || bounds.contains_key(*n))
    {
        return out;
    }
    hold(
        SCALE_PARAM,
        "the retraction is unchanged when m, b, k, Ca, T, Mg, Kg are multiplied by s and R \
         divided by it (its scale)",
    );
    {
        hold(
            "piezo.R",
            "the record fixes the poles and the stroke, not the electrical time R Ca apart from \
             the mechanics (a second exact symmetry)",
        );
    }
    out
}

/// Folds the held values' uncertainties into a fit: for each held parameter `h`, the free
/// parameters' optimum moves by `G_h = (J^T J)^-1 J^T J_h` per unit of `ln h` (the regression
/// of its whitened Jacobian column on the free ones, central differences at the optimum), so
/// the covariance of the free parameters gains `r_h^2 G_h G_h^T` and `h` itself has the
/// relative sigma `r_h`. The parameters' sigmas, and the combinations' (with
/// [`combinations`]), include it; a combination that the held values move is not resolved by
/// the data and gets no sigma.
pub fn propagate_held(prep: &crate::fit::Prepared, o: &mut crate::fit::FitOutcome, held: &[Held]) {
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
    let Some(inv) = crate::linalg::pseudo_inverse(&jtj, 1e-14 * jtj.norm()) else {
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
        let Some(exps) = combination_exponents(name) else {
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

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A direction of parameters the record does not resolve.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Symmetry {
    /// `exact` (the curvature is the differences' truncation error) or `near` (its 1-sigma
    /// reaches beyond the parameters' ranges).
    pub kind: String,
    /// The unit direction's weights on the free parameters (fit coordinates: `ln p` for the
    /// log-fitted ones), those above 0.01.
    pub direction: BTreeMap<String, f64>,
    /// Curvature with the difference steps halved over the curvature reported.
    pub step_ratio: f64,
    /// The direction's 1-sigma in the fit's coordinates (infinite for an exact symmetry: absent
    /// in JSON).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
}

/// The null-space analysis of a fit.
#[derive(Debug, Clone)]
pub struct NullSpace {
    /// The unresolved directions.
    pub symmetries: Vec<Symmetry>,
    /// Per free parameter (free order), whether it is resolved.
    pub resolved: Vec<bool>,
    /// The covariance of the free parameters on the resolved directions (the pseudo-inverse of
    /// `a` without the unresolved ones), in the fit's coordinates.
    pub cov: DMatrix<f64>,
    /// The unresolved directions in the fit's coordinates (unit vectors, free order).
    pub null: Vec<Vec<f64>>,
}

/// Finds the unresolved directions of the normal matrix `a` (`J^T J` at the reported noise),
/// with `a_half * a_half_scale` the same from differences over half the steps and `width`
/// each free parameter's allowed range in the fit's coordinates (infinite when unbounded).
///
/// In the scaled space (unit diagonal), the truncation-made directions are those of the
/// generalised eigenproblem `S_half w = mu S w` with `mu` off 1 by more than
/// [`EXACT_TOLERANCE`] (the curvature a direction loses or gains when the steps are halved;
/// plain eigenvectors of `S` are not enough: an exact direction mixed with a weak resolved
/// one can keep its Rayleigh quotient while the inverse moves by 4), plus the directions of
/// zero curvature. On what is left, an eigen-direction whose 1-sigma leaves the allowed box
/// along every parameter it moves is a near symmetry. The covariance is the pseudo-inverse of
/// `S` on the complement of those directions.
pub fn symmetries(
    a: &DMatrix<f64>,
    a_half: &DMatrix<f64>,
    a_half_scale: f64,
    width: &[f64],
    names: &[String],
) -> NullSpace {
    let n = a.nrows();
    let debug = std::env::var("GEODESIC_FIT_DEBUG").is_ok();
    let d: Vec<f64> = (0..n).map(|k| a[(k, k)].max(1e-300).sqrt()).collect();
    let s = DMatrix::from_fn(n, n, |i, j| a[(i, j)] / (d[i] * d[j]));
    let sh = DMatrix::from_fn(n, n, |i, j| a_half[(i, j)] * a_half_scale / (d[i] * d[j]));
    let Some(eig0) = crate::linalg::sym_eigen(s.clone()) else {
        // a normal matrix that is not finite resolves nothing
        return NullSpace {
            symmetries: Vec::new(),
            resolved: vec![false; n],
            cov: DMatrix::from_element(n, n, f64::NAN),
            null: Vec::new(),
        };
    };
    let max = eig0.eigenvalues.iter().cloned().fold(0.0, f64::max);
    // unresolved directions found so far (scaled space), with their report
    let mut found: Vec<(DVector<f64>, Symmetry)> = Vec::new();
    let to_report = |v: &DVector<f64>, kind: &str, ratio: f64, sigma: Option<f64>| {
        // the direction in the fit's coordinates, u = D^-1 v, as a unit vector
        let mut w: Vec<f64> = (0..n).map(|i| v[i] / d[i]).collect();
        let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-300);
        w.iter_mut().for_each(|x| *x /= norm);
        let sym = Symmetry {
            kind: kind.to_string(),
            direction: w
                .iter()
                .enumerate()
                .filter(|(_, x)| x.abs() > 0.01)
                .map(|(i, x)| (names[i].clone(), *x))
                .collect(),
            step_ratio: if ratio.is_finite() { ratio } else { 0.0 },
            sigma: sigma.map(|s| s / norm),
        };
        (w, sym)
    };
    // the generalised problem on a regularised S (a zero column would break its Cholesky)
    let reg = max.max(1e-300) * 1e-13;
    let sr = &s + DMatrix::identity(n, n) * reg;
    let shr = &sh + DMatrix::identity(n, n) * reg;
    if let Some(ch) = sr.clone().cholesky() {
        let l = ch.l();
        if let Some(li) = l.clone().try_inverse() {
            let m = &li * &shr * li.transpose();
            let m = (&m + m.transpose()) * 0.5;
            let eig = crate::linalg::sym_eigen(m);
            for k in 0..eig.as_ref().map_or(0, |e| e.eigenvalues.len()) {
                let eig = eig.as_ref().expect("decomposed");
                let mu = eig.eigenvalues[k];
                let y = eig.eigenvectors.column(k).into_owned();
                let v = li.transpose() * y;
                let curv = (v.transpose() * &s * &v)[(0, 0)];
                let flat = curv <= max * 1e-12 * v.norm_squared();
                if debug {
                    eprintln!(
                        "null-space: half/full curvature {mu:.4}, relative curvature {:.3e}",
                        curv / (max * v.norm_squared()).max(1e-300)
                    );
                }
                if flat || (mu - 1.0).abs() > EXACT_TOLERANCE {
                    let v = v.normalize();
                    found.push((v.clone(), to_report(&v, "exact", mu, None).1));
                }
            }
        }
    }
    // an orthonormal basis of the exact directions
    let mut basis: Vec<DVector<f64>> = Vec::new();
    for (v, _) in &found {
        let mut x = v.clone();
        for _ in 0..2 {
            for b in &basis {
                let c = b.dot(&x);
                x -= b * c;
            }
        }
        if x.norm() > 1e-6 {
            basis.push(x.normalize());
        }
    }
    let projector = |basis: &[DVector<f64>]| {
        let mut p = DMatrix::identity(n, n);
        for b in basis {
            p -= b * b.transpose();
        }
        p
    };
    // near symmetries among the rest: an eigen-direction of P S P whose 1-sigma leaves the box
    let p = projector(&basis);
    let psp = &p * &s * &p;
    let Some(eig) = crate::linalg::sym_eigen((&psp + psp.transpose()) * 0.5) else {
        return NullSpace {
            symmetries: found.into_iter().map(|(_, s)| s).collect(),
            resolved: vec![false; n],
            cov: DMatrix::from_element(n, n, f64::NAN),
            null: Vec::new(),
        };
    };
    let mut cov = DMatrix::zeros(n, n);
    for k in 0..n {
        let lam = eig.eigenvalues[k];
        let v = eig.eigenvectors.column(k).into_owned();
        if basis.iter().any(|b| b.dot(&v).abs() > 0.5) || lam <= max * 1e-12 {
            continue;
        }
        let sigma_scaled = 1.0 / lam.sqrt();
        let (w, _) = to_report(&v, "near", 1.0, None);
        let norm_u: f64 = (0..n).map(|i| (v[i] / d[i]).powi(2)).sum::<f64>().sqrt();
        let sigma_t = sigma_scaled * norm_u;
        let beyond = w
            .iter()
            .zip(width)
            .filter(|(wi, _)| wi.abs() > WEIGHT)
            .all(|(wi, wd)| (wi * sigma_t).abs() > *wd);
        if beyond {
            let mut sym = to_report(&v, "near", 1.0, None).1;
            sym.sigma = Some(sigma_t);
            found.push((v.clone(), sym));
        } else {
            cov += &v * v.transpose() / lam;
        }
    }
    let mut symmetries = Vec::new();
    let mut null = Vec::new();
    let mut resolved = vec![true; n];
    for (v, sym) in found {
        let (w, _) = to_report(&v, &sym.kind, sym.step_ratio, None);
        for (i, wi) in w.iter().enumerate() {
            if wi.abs() > WEIGHT {
                resolved[i] = false;
            }
        }
        null.push(w);
        symmetries.push(sym);
    }
    let cov = DMatrix::from_fn(n, n, |i, j| cov[(i, j)] / (d[i] * d[j]));
    NullSpace {
        symmetries,
        resolved,
        cov,
        null,
    }
}

/// A combination of parameters that the retraction's scaling leaves unchanged.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Combination {
    /// Value [unit].
    pub value: f64,
    /// 1-sigma [unit] (covariance on the resolved directions, inflated by chi2_red when above
    /// 1); absent when the combination lies along an unresolved direction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
    /// Unit.
    pub unit: String,
    /// Its definition.
    pub formula: String,
}

/// The retraction's identifiable combinations: (name, unit, formula, constant factor, exponents
/// of the parameters). Each exponent vector sums to zero over the scaled parameters with `R`
/// counted negative, so that the scaling leaves it unchanged.
#[allow(clippy::type_complexity)]
fn retraction_combinations(
    e0: f64,
) -> Vec<(
    &'static str,
    &'static str,
    &'static str,
    f64,
    Vec<(&'static str, f64)>,
)> {
    vec![
        (
            "d0",
            "m",
            "T E0 / k (static stroke)",
            e0,
            vec![("piezo.T", 1.0), ("piezo.k", -1.0)],
        ),
        (
            "tau_e",
            "s",
            "R Ca (electrical time)",
            1.0,
            vec![("piezo.R", 1.0), ("piezo.Ca", 1.0)],
        ),
        (
            "w_tip",
            "rad/s",
            "sqrt(k / m) (tip on the stack)",
            1.0,
            vec![("piezo.k", 0.5), ("piezo.m", -0.5)],
        ),
        (
            "b_over_m",
            "1/s",
            "b / m (damping rate)",
            1.0,
            vec![("piezo.b", 1.0), ("piezo.m", -1.0)],
        ),
        (
            "kappa",
            "1",
            "T^2 / (Ca k) (electromechanical coupling)",
            1.0,
            vec![("piezo.T", 2.0), ("piezo.Ca", -1.0), ("piezo.k", -1.0)],
        ),
        (
            "mass_ratio",
            "1",
            "Mg / m",
            1.0,
            vec![("plunger_compliance.Mg", 1.0), ("piezo.m", -1.0)],
        ),
        (
            "stiffness_ratio",
            "1",
            "Kg / k",
            1.0,
            vec![("plunger_compliance.Kg", 1.0), ("piezo.k", -1.0)],
        ),
        (
            "em",
            "V/s",
            "em (voltage slope)",
            1.0,
            vec![("voltage_ramp.em", 1.0)],
        ),
    ]
}

/// The exponents of a named retraction combination.
fn combination_exponents(name: &str) -> Option<Vec<(String, f64)>> {
    retraction_combinations(1.0)
        .into_iter()
        .find(|c| c.0 == name)
        .map(|c| c.4.into_iter().map(|(n, e)| (n.to_string(), e)).collect())
}

/// The identifiable combinations of a retraction fit (empty for other scenarios): `p` the
/// parameters, `free` which are free, `fidx` their indices, `ns` the null-space analysis (its
/// covariance in the fit's coordinates, all log for these parameters), `inflate` the factor on
/// variances (chi2_red when above 1), `e0` the initial voltage [V].
pub fn combinations(
    model: &Model,
    p: &[f64],
    fidx: &[usize],
    ns: &NullSpace,
    inflate: f64,
    e0: f64,
) -> BTreeMap<String, Combination> {
    let mut out = BTreeMap::new();
    if model.scenario != Scenario::RtRetraction {
        return out;
    }
    let specs = model.specs();
    for (name, unit, formula, c, exps) in retraction_combinations(e0) {
        let idx: Option<Vec<(usize, f64)>> = exps
            .iter()
            .map(|(n, e)| model.index(n).map(|i| (i, *e)))
            .collect();
        let Some(idx) = idx else { continue };
        if idx.iter().any(|(i, _)| !specs[*i].log) {
            continue;
        }
        let value = c * idx.iter().map(|(i, e)| p[*i].powf(*e)).product::<f64>();
        // gradient of ln(value) in the free parameters' coordinates (ln p)
        let g: Vec<f64> = fidx
            .iter()
            .map(|f| idx.iter().filter(|(i, _)| i == f).map(|(_, e)| *e).sum())
            .collect();
        let gn = g.iter().map(|x| x * x).sum::<f64>().sqrt();
        let along = ns.null.iter().any(|w| {
            g.iter().zip(w).map(|(a, b)| a * b).sum::<f64>().abs() > WEIGHT * gn.max(1e-300)
        });
        let sigma = if along {
            None
        } else {
            let mut var = 0.0;
            for (a, ga) in g.iter().enumerate() {
                for (b, gb) in g.iter().enumerate() {
                    var += ga * ns.cov[(a, b)] * gb;
                }
            }
            let s = value.abs() * (var.max(0.0) * inflate).sqrt();
            s.is_finite().then_some(s)
        };
        out.insert(
            name.to_string(),
            Combination {
                value,
                sigma,
                unit: unit.to_string(),
                formula: formula.to_string(),
            },
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A normal matrix with an exact symmetry (two columns equal but for the differences'
    /// truncation error, which halves with the step) and a resolved direction: the symmetry is
    /// found with its weights, the parameters it moves are unresolved, and the covariance on
    /// the resolved direction is the inverse curvature there.
    #[test]
    fn an_exact_symmetry_is_found_from_the_step_test() {
        let names = vec!["a".to_string(), "b".to_string(), "c".to_string()];
        // J columns: a = x, b = x + h e, c = z (orthogonal): J^T J in the basis
        let h = 1e-4;
        let build = |h: f64| {
            DMatrix::from_row_slice(3, 3, &[1.0, 1.0, 0.0, 1.0, 1.0 + h * h, 0.0, 0.0, 0.0, 4.0])
        };
        let ns = symmetries(&build(h), &build(h / 2.0), 1.0, &[f64::INFINITY; 3], &names);
        assert_eq!(ns.symmetries.len(), 1, "{:?}", ns.symmetries);
        let s = &ns.symmetries[0];
        assert_eq!(s.kind, "exact");
        assert!(
            (s.direction["a"].abs() - 0.5f64.sqrt()).abs() < 1e-3,
            "{s:?}"
        );
        assert!(s.direction["a"] * s.direction["b"] < 0.0);
        assert!(!s.direction.contains_key("c"));
        assert_eq!(ns.resolved, vec![false, false, true]);
        assert!((ns.cov[(2, 2)] - 0.25).abs() < 1e-12);
        // a resolved pair with a moderate correlation is left alone
        let ok = DMatrix::from_row_slice(2, 2, &[1.0, 0.5, 0.5, 1.0]);
        let ns = symmetries(&ok, &ok, 1.0, &[f64::INFINITY; 2], &names[..2]);
        assert!(ns.symmetries.is_empty() && ns.resolved == vec![true, true]);
    }

    /// A direction resolved by the differences but whose 1-sigma reaches beyond the
    /// parameters' ranges is a near symmetry.
    #[test]
    fn a_direction_wider_than_the_prior_is_a_near_symmetry() {
        let names = vec!["a".to_string(), "b".to_string()];
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 0.999_999, 0.999_999, 1.0]);
        let ns = symmetries(&a, &a, 1.0, &[1.0, 1.0], &names);
        assert_eq!(ns.symmetries.len(), 1);
        assert_eq!(ns.symmetries[0].kind, "near");
        assert!(ns.symmetries[0].sigma.is_some_and(|s| s > 100.0));
    }
}
