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

use crate::numeric::observe::Observer;

/// Relative change of a direction's curvature, when the difference steps are halved, above
/// which the curvature is the differences' truncation error (an exact symmetry): resolved
/// directions of the examples move by under 1 %, exact ones by 75 % or more (the Jacobian of the
/// uncertainty stage takes central differences, whose truncation error falls as the step
/// squared and its curvature as the fourth power; where rounding dominates it grows instead).
/// Forward differences, used before 2026-11-28, left a curvature term `h/2 d2r/du2` that along a
/// weakly resolved direction moved with the step too: a 1.6 Hz pendulum on a 20 ms release
/// record was called an exact symmetry of its frequency, offset and the contact parameters,
/// where central differences resolve them (f0 1.566 +- 0.129 Hz against 1.6 Hz).
pub const EXACT_TOLERANCE: f64 = 0.2;

/// Ratio of a direction's curvature with the difference steps halved to the curvature with
/// the full steps under which the curvature is a truncation error without further test
/// ([`symmetries_confirmed`]): a truncation error's curvature falls by 4 (forward differences)
/// or 16 (central) when the steps are halved; a ratio above it (including one above 1, a
/// rounding error or a rotating pair of weak directions) is tried on the model.
pub const TRUNCATION_MU: f64 = 0.3;

/// Weight (component of the unit direction in the fit's coordinates) above which a parameter
/// takes part in a symmetry.
pub const WEIGHT: f64 = 0.1;

/// A parameter a fit holds at a stated value because the record cannot tell it (issue 33),
/// with the value's own uncertainty, which is propagated to the parameters the fit moves to
/// compensate it ([`propagate_held`]).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
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

/// The parameters a fit holds when the user holds none of those its model's exact symmetries
/// move (the scenario's [`Holds`](geodesic_facility::scenario::Holds); for the retraction, docs/fitting.md: `piezo.Ca` for the
/// scaling and `piezo.R` for the electrical time `R Ca`, which the record's identifiable
/// combinations leave free), each at its nominal value (the thesis table, clamped into a user
/// bound) known to the scenario's relative sigma (the release budget's 11.5 %). Empty for a
/// scenario without holds, a model without the effect they need, or when the user fixes or
/// bounds one of the moved parameters (then the null-space check reports what is left free).
pub fn holds(
    model: &Model,
    fixed: &BTreeMap<String, f64>,
    bounds: &BTreeMap<String, (f64, f64)>,
) -> Vec<Held> {
    let Some(spec) = model.scenario.holds() else {
        return Vec::new();
    };
    if !model.has(spec.requires_effect) {
        return Vec::new();
    }
    let mut out = Vec::new();
    let specs = model.specs();
    let relative_sigma = spec.relative_sigma;
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
            relative_sigma,
            reason: format!(
                "{reason}: held at {value:e} {} (thesis table), known to {:.1} % (the release \
                 budget's spread of the mechanism parameters), propagated to the parameters \
                 that move with it",
                specs[i].unit,
                100.0 * relative_sigma
            ),
        });
    };
    // a user who holds any parameter the symmetries move chooses the holds (the null-space
    // check reports what the record leaves free then)
    if spec
        .moved
        .iter()
        .any(|n| fixed.contains_key(*n) || bounds.contains_key(*n))
    {
        return out;
    }
    for (param, reason) in spec.held {
        hold(param, reason);
    }
    out
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A direction of parameters the record does not resolve.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
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
    symmetries_confirmed(
        a,
        a_half,
        a_half_scale,
        width,
        names,
        &|_: &[f64]| true,
        &crate::numeric::observe::Silent,
    )
}

/// [`symmetries`], with each direction the step test flags (whose curvature is not zero and
/// does not fall with the step as a truncation error does, [`TRUNCATION_MU`]) kept as exact
/// only if `confirm(w)` says so, `w` its unit direction in the fit's coordinates. The fit passes a test made on the model itself (`estimate::solve`: the
/// chi-square at the direction's predicted 1-sigma on either side): two weak directions of
/// nearly equal curvature rotate into each other when the steps are halved, which gives a pair
/// of generalised eigenvalues `mu` and about `1/mu` (2.82 and 0.354 on a 1.6 Hz pendulum
/// record, 1.30 and 0.765 on a TMMF adhesion record) that the matrices alone cannot tell from a
/// truncation error, while the chi-square rises by about 1 along either, as a resolved
/// direction does.
pub(crate) fn symmetries_confirmed(
    a: &DMatrix<f64>,
    a_half: &DMatrix<f64>,
    a_half_scale: f64,
    width: &[f64],
    names: &[String],
    confirm: &dyn Fn(&[f64]) -> bool,
    obs: &dyn Observer,
) -> NullSpace {
    let n = a.nrows();
    let debug = obs.debugging();
    let d: Vec<f64> = (0..n).map(|k| a[(k, k)].max(1e-300).sqrt()).collect();
    let s = DMatrix::from_fn(n, n, |i, j| a[(i, j)] / (d[i] * d[j]));
    let sh = DMatrix::from_fn(n, n, |i, j| a_half[(i, j)] * a_half_scale / (d[i] * d[j]));
    let Some(eig0) = crate::numeric::linalg::sym_eigen(s.clone()) else {
        // a normal matrix that is not finite resolves nothing
        return NullSpace::nothing_resolved(n, Vec::new());
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
    found.extend(exact_directions(&s, &sh, max, &to_report, confirm, obs));
    let basis = orthonormal_basis(found.iter().map(|(v, _)| v));
    let projector = |basis: &[DVector<f64>]| {
        let mut p = DMatrix::identity(n, n);
        for b in basis {
            p -= b * b.transpose();
        }
        p
    };
    // the parameters an exact direction leaves unresolved: they have no sigma whatever the
    // rest, so their share of a direction does not make it a symmetry of the others (issue
    // 48: with a parameter on its bound and nearly no curvature, `1/d` is huge, and every
    // resolved direction that kept a trace of it looked like a symmetry along it; nine such
    // directions took the whole space, and every other parameter was reported with sigma 0)
    let mut exact_heavy = vec![false; n];
    for (v, _) in &found {
        let (w, _) = to_report(v, "exact", 1.0, None);
        for (i, wi) in w.iter().enumerate() {
            exact_heavy[i] |= wi.abs() > WEIGHT;
        }
    }
    // a direction left out of the covariance still moves the resolved parameters it touches:
    // they get its spread within the allowed box (that of a uniform over the reach, `reach /
    // sqrt(12)`), instead of the conditional sigma that would ignore it
    let mut cov = DMatrix::zeros(n, n);
    for (v, _) in &found {
        let w: Vec<f64> = (0..n).map(|i| v[i] / d[i]).collect();
        if let Some(s_box) = box_spread(&w, &exact_heavy, width, false) {
            cov += v * v.transpose() * (s_box * s_box);
        }
    }
    // near symmetries among the rest: an eigen-direction of P S P whose 1-sigma leaves the box
    let p = projector(&basis);
    let psp = &p * &s * &p;
    let Some(eig) = crate::numeric::linalg::sym_eigen((&psp + psp.transpose()) * 0.5) else {
        return NullSpace::nothing_resolved(n, found.into_iter().map(|(_, s)| s).collect());
    };
    for k in 0..n {
        let lam = eig.eigenvalues[k];
        let v = eig.eigenvectors.column(k).into_owned();
        if basis.iter().any(|b| b.dot(&v).abs() > 0.5) || lam <= max * 1e-12 {
            continue;
        }
        let sigma_scaled = 1.0 / lam.sqrt();
        // the direction in the fit's coordinates without the parameters already unresolved
        let wv: Vec<f64> = (0..n)
            .map(|i| if exact_heavy[i] { 0.0 } else { v[i] / d[i] })
            .collect();
        let norm_u = wv.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm_u.is_nan() || norm_u <= 0.0 {
            // it moves only parameters that are unresolved already
            cov += &v * v.transpose() / lam;
            continue;
        }
        let w: Vec<f64> = wv.iter().map(|x| x / norm_u).collect();
        let sigma_t = sigma_scaled * norm_u;
        let beyond = w
            .iter()
            .zip(width)
            .filter(|(wi, _)| wi.abs() > WEIGHT)
            .all(|(wi, wd)| (wi * sigma_t).abs() > *wd);
        if debug {
            obs.debug(&|| {
                format!(
                    "null-space: near test sigma_t {sigma_t:.3e} beyond {beyond}: {:?}",
                    w.iter()
                        .zip(width)
                        .enumerate()
                        .filter(|(_, (wi, _))| wi.abs() > 0.01)
                        .map(|(i, (wi, wd))| format!("{} {wi:.3} (width {wd:.3e})", names[i]))
                        .collect::<Vec<_>>()
                )
            });
        }
        if beyond {
            let sym = Symmetry {
                kind: "near".to_string(),
                direction: w
                    .iter()
                    .enumerate()
                    .filter(|(_, x)| x.abs() > 0.01)
                    .map(|(i, x)| (names[i].clone(), *x))
                    .collect(),
                step_ratio: 1.0,
                sigma: Some(sigma_t),
            };
            let spread = box_spread(&wv, &exact_heavy, width, true)
                .map_or(sigma_scaled, |s| s.min(sigma_scaled));
            cov += &v * v.transpose() * (spread * spread);
            found.push((v.clone(), sym));
        } else {
            cov += &v * v.transpose() / lam;
        }
    }
    let (symmetries, null, resolved) = report_directions(found, &exact_heavy, &d, &to_report);
    let cov = DMatrix::from_fn(n, n, |i, j| cov[(i, j)] / (d[i] * d[j]));
    NullSpace {
        symmetries,
        resolved,
        cov,
        null,
    }
}

impl NullSpace {
    /// Nothing resolved among `n` free parameters (a decomposition failed), with the
    /// `symmetries` found so far.
    fn nothing_resolved(n: usize, symmetries: Vec<Symmetry>) -> NullSpace {
        NullSpace {
            symmetries,
            resolved: vec![false; n],
            cov: DMatrix::from_element(n, n, f64::NAN),
            null: Vec::new(),
        }
    }
}

/// A direction of the scaled space to its unit vector in the fit's coordinates and its report
/// (kind, curvature ratio, sigma).
type ToReport<'a> = dyn Fn(&DVector<f64>, &str, f64, Option<f64>) -> (Vec<f64>, Symmetry) + 'a;

/// Cosine above which two unresolved directions are one in the report.
const DUPLICATE_COS: f64 = 0.99995;

/// The spread (1-sigma, in `w`'s length units) of a uniform distribution over the reach of the
/// direction `w` (fit coordinates, not normalised) inside the allowed box: the shortest range
/// `width_i / |w_i|` among its parameters with a weight above [`WEIGHT`] (of the unit
/// direction), over `sqrt(12)`; with `skip_heavy` false, `heavy` parameters count too. `None`
/// when no such parameter has a finite range.
fn box_spread(w: &[f64], heavy: &[bool], width: &[f64], skip_heavy: bool) -> Option<f64> {
    let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !(norm > 0.0 && norm.is_finite()) {
        return None;
    }
    let reach = w
        .iter()
        .zip(width)
        .zip(heavy)
        .filter(|((wi, _), h)| (wi.abs() / norm) > WEIGHT && !(skip_heavy && **h))
        .map(|((wi, wd), _)| wd / wi.abs())
        .filter(|r| r.is_finite())
        .fold(f64::INFINITY, f64::min);
    reach.is_finite().then(|| reach / 12f64.sqrt())
}

/// The report of the unresolved directions `found` (scaled space; `d` the scaling): each
/// direction once ([`DUPLICATE_COS`]), in the fit's coordinates (a near one without the
/// parameters an exact one leaves unresolved, `exact_heavy`), the unit directions, and which
/// free parameters stay resolved (no weight above [`WEIGHT`] in any).
fn report_directions(
    found: Vec<(DVector<f64>, Symmetry)>,
    exact_heavy: &[bool],
    d: &[f64],
    to_report: &ToReport<'_>,
) -> (Vec<Symmetry>, Vec<Vec<f64>>, Vec<bool>) {
    let n = d.len();
    let mut symmetries: Vec<Symmetry> = Vec::new();
    let mut null: Vec<Vec<f64>> = Vec::new();
    let mut resolved = vec![true; n];
    for (v, sym) in found {
        // the reported direction (for a near one, without the parameters already unresolved)
        let w: Vec<f64> = if sym.kind == "exact" {
            to_report(&v, &sym.kind, sym.step_ratio, None).0
        } else {
            let wv: Vec<f64> = (0..n)
                .map(|i| if exact_heavy[i] { 0.0 } else { v[i] / d[i] })
                .collect();
            let norm = wv.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-300);
            wv.iter().map(|x| x / norm).collect()
        };
        for (i, wi) in w.iter().enumerate() {
            if wi.abs() > WEIGHT {
                resolved[i] = false;
            }
        }
        // one entry per direction: a direction within 0.01 rad of one already listed adds
        // nothing to the report (its parameters are unresolved either way)
        let duplicate = null.iter().any(|o: &Vec<f64>| {
            o.iter().zip(&w).map(|(a, b)| a * b).sum::<f64>().abs() > DUPLICATE_COS
        });
        null.push(w);
        if !duplicate {
            symmetries.push(sym);
        }
    }
    (symmetries, null, resolved)
}

/// The exact directions of the scaled normal matrix `s` (maximum eigenvalue `max`), with
/// `sh` the same from differences over half the steps: those of the generalised problem
/// `S_half w = mu S w` with `mu` off 1 by more than [`EXACT_TOLERANCE`] that `confirm` (or a
/// curvature under [`TRUNCATION_MU`], or none) keeps, each with its report (`to_report`).
fn exact_directions(
    s: &DMatrix<f64>,
    sh: &DMatrix<f64>,
    max: f64,
    to_report: &ToReport<'_>,
    confirm: &dyn Fn(&[f64]) -> bool,
    obs: &dyn Observer,
) -> Vec<(DVector<f64>, Symmetry)> {
    let debug = obs.debugging();
    let n = s.nrows();
    let mut found = Vec::new();
    // the generalised problem on a regularised S (a zero column would break its Cholesky)
    let reg = max.max(1e-300) * 1e-13;
    let sr = s + DMatrix::identity(n, n) * reg;
    let shr = sh + DMatrix::identity(n, n) * reg;
    if let Some(ch) = sr.clone().cholesky() {
        let l = ch.l();
        if let Some(li) = l.clone().try_inverse() {
            let m = &li * &shr * li.transpose();
            let m = (&m + m.transpose()) * 0.5;
            let eig = crate::numeric::linalg::sym_eigen(m);
            for k in 0..eig.as_ref().map_or(0, |e| e.eigenvalues.len()) {
                let eig = eig.as_ref().expect("decomposed");
                let mu = eig.eigenvalues[k];
                let y = eig.eigenvectors.column(k).into_owned();
                let v = li.transpose() * y;
                let curv = (v.transpose() * s * &v)[(0, 0)];
                let flat = curv <= max * 1e-12 * v.norm_squared();
                if debug {
                    obs.debug(&|| {
                        format!(
                            "null-space: half/full curvature {mu:.4}, relative curvature {:.3e}",
                            curv / (max * v.norm_squared()).max(1e-300)
                        )
                    });
                }
                if flat || (mu - 1.0).abs() > EXACT_TOLERANCE {
                    let v = v.normalize();
                    let (w, sym) = to_report(&v, "exact", mu, None);
                    // a curvature that falls with the step is a truncation error (by 4 for
                    // forward differences, 16 for central ones): exact without more ado
                    if flat || mu < TRUNCATION_MU || confirm(&w) {
                        found.push((v.clone(), sym));
                    } else if debug {
                        obs.debug(&|| {
                            "null-space: refuted: the chi-square rises along the direction".into()
                        });
                    }
                }
            }
        }
    }
    found
}

/// An orthonormal basis of the span of `vectors` (Gram-Schmidt, twice per vector; a vector
/// within 1e-6 of the span so far adds nothing).
fn orthonormal_basis<'a>(vectors: impl Iterator<Item = &'a DVector<f64>>) -> Vec<DVector<f64>> {
    let mut basis: Vec<DVector<f64>> = Vec::new();
    for v in vectors {
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
    basis
}

/// A combination of parameters that the retraction's scaling leaves unchanged.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
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

/// The exponents of the combination `name` of `scenario`.
pub(crate) fn combination_exponents(scenario: Scenario, name: &str) -> Option<Vec<(String, f64)>> {
    scenario
        .combinations(&BTreeMap::new())
        .into_iter()
        .find(|c| c.name == name)
        .map(|c| {
            c.exponents
                .into_iter()
                .map(|(n, e)| (n.to_string(), e))
                .collect()
        })
}

/// The identifiable combinations of a fit (its scenario's, empty for most): `p` the
/// parameters, `free` which are free, `fidx` their indices, `ns` the null-space analysis (its
/// covariance in the fit's coordinates, all log for these parameters), `inflate` the factor on
/// variances (chi2_red when above 1), `known` the record's known constants.
pub fn combinations(
    model: &Model,
    p: &[f64],
    fidx: &[usize],
    ns: &NullSpace,
    inflate: f64,
    known: &BTreeMap<String, f64>,
) -> BTreeMap<String, Combination> {
    let mut out = BTreeMap::new();
    let specs = model.specs();
    for spec in model.scenario.combinations(known) {
        let (name, unit, formula, c, exps) = (
            spec.name,
            spec.unit,
            spec.formula,
            spec.constant,
            spec.exponents,
        );
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

    /// Two weak directions of nearly equal curvature that rotate into each other when the
    /// steps are halved give `mu` and about `1/mu`: flagged by the matrices, kept as exact only
    /// when the model confirms it (the fit's test: the chi-square along the direction).
    #[test]
    fn a_rotating_pair_is_exact_only_if_the_model_confirms_it() {
        let names = vec!["a".to_string(), "b".to_string(), "c".to_string()];
        let (e1, e2) = (1e-6, 3e-6);
        let (c, s) = (0.8f64.cos(), 0.8f64.sin());
        // the weak pair's eigenvectors turn by 0.8 rad between the full and the half steps
        let pair = |c: f64, s: f64| {
            let r = DMatrix::from_row_slice(2, 2, &[c, -s, s, c]);
            let d = DMatrix::from_row_slice(2, 2, &[e1, 0.0, 0.0, e2]);
            &r * d * r.transpose()
        };
        let embed = |m: DMatrix<f64>| {
            let mut a = DMatrix::zeros(3, 3);
            a.view_mut((0, 0), (2, 2)).copy_from(&m);
            a[(2, 2)] = 1.0;
            a
        };
        let full = embed(pair(1.0, 0.0));
        let half = embed(pair(c, s));
        let wide = [f64::INFINITY; 3];
        let flagged = symmetries(&full, &half, 1.0, &wide, &names);
        assert!(
            flagged.symmetries.iter().any(|s| s.kind == "exact"),
            "the matrices alone flag the pair: {:?}",
            flagged.symmetries
        );
        let refuted = symmetries_confirmed(
            &full,
            &half,
            1.0,
            &wide,
            &names,
            &|_: &[f64]| false,
            &crate::numeric::observe::Silent,
        );
        assert!(
            refuted.symmetries.iter().all(|s| s.kind != "exact"),
            "{:?}",
            refuted.symmetries
        );
        assert_eq!(refuted.resolved, vec![true, true, true]);
        assert!(
            (refuted.cov[(0, 0)] * e1 - 1.0).abs() < 1e-6,
            "{}",
            refuted.cov
        );
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
