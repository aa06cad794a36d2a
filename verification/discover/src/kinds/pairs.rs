//! Two terms outside the catalogue at once (issue 50, item 4): every pair of the best single
//! kinds fitted jointly with the model, ranked by BIC.
//!
//! Taking the leading single term out of the data and searching the rest again picks the wrong
//! pair when one kind can stand in for the other: on a TM moving at nearly constant speed the
//! velocity force's column (`int (x - x0)`, about `v t^2 / 2`) is nearly the `position` kind's
//! constant-force column, so an anti-restoring force with an offset led a record holding a
//! damping and a 50 Hz pickup, and the pickup, searched after it, came out at 59.9 Hz. So each
//! pair of the [`PAIR_KINDS`] best kinds is fitted as one problem: a scanned parameter of
//! either term (a frequency, a time constant, the time of a jump) is scanned again by the
//! score test with the partner's columns beside it, then both terms' coefficients and the
//! model's parameters are fitted together (one Levenberg-Marquardt run, the forces on the state
//! to first order and solved with the state, the better kept), and the scanned parameter is
//! searched again by golden section with that joint fit at each trial value. The pair's
//! `delta_bic` is `-delta chi2 + k ln N` against the model alone, `k` both terms' coefficients
//! and scanned parameters.
//!
//! The force on the position and the one on the velocity are paired whenever either is among
//! the best kinds. A pair is reported only when both terms are resolved: each coefficient has a
//! finite 1-sigma (first order, after the fit's freedom and the partner's columns) and each term
//! is strongly supported beside the other (the pair's delta BIC below the partner's alone by
//! more than 10).
//! The resolved pairs within 10 in BIC of the best are what the record cannot tell apart
//! ([`PairFit::alike`]).

use rayon::prelude::*;

use super::{
    Basis, Joint, JointEnd, KindFit, describe_offset, scan, scanned_shape, state_shape, state_text,
    term_text,
};
use crate::diagnose::DELTA_BIC_STRONG;
use crate::estimate::FitOutcome;
use crate::numeric::lm::LmOptions;
use crate::numeric::observe::Observer;
use crate::prepare::Prepared;

/// How many of the best single kinds are paired with one another (six pairs of four).
pub const PAIR_KINDS: usize = 4;

/// Two terms fitted jointly with the model ([`best_pair`]).
#[derive(Debug, Clone)]
pub struct PairFit {
    /// The two terms, each with its coefficients, their 1-sigma and its parameter from the joint
    /// fit; each one's `delta_chi2` and `delta_bic` are what it adds beside the other (the
    /// pair's against the partner's alone).
    pub terms: Vec<KindFit>,
    /// The pair's delta BIC against the model alone.
    pub delta_bic: f64,
    /// The pairs the record cannot tell apart, this one first (`"velocity + vibration"`): the
    /// joint fits within `DELTA_BIC_STRONG` (10) of this one's. Empty when it stands alone.
    pub alike: Vec<String>,
}

/// A pair's joint fit: its two terms at the end of the run, the chi-square removed from the
/// model's and the parameters counted.
struct Fitted {
    terms: Vec<KindFit>,
    delta_chi2: f64,
    k: usize,
}

impl Fitted {
    fn delta_bic(&self, ln_n: f64) -> f64 {
        -self.delta_chi2 + self.k as f64 * ln_n
    }

    fn name(&self) -> String {
        format!("{} + {}", self.terms[0].kind, self.terms[1].kind)
    }
}

/// Whether the kind has a scanned parameter (its columns are [`scanned_shape`]'s).
fn scanned(k: &KindFit) -> bool {
    k.parameter
        .as_ref()
        .is_some_and(|p| scanned_shape(&[], &k.kind, p.value).is_some())
}

/// The coefficients and parameters a kind counts in BIC.
fn count(k: &KindFit) -> usize {
    k.shape.len() + usize::from(scanned(k) || k.kind == "delay")
}

/// The best pair, by BIC, of two distinct kinds among the [`PAIR_KINDS`] best of `all` (the
/// kinds of `o`'s residual on `basis`, most supported first, their `delta_bic` the single
/// terms'; with the force on the position or the velocity when its twin is among them) whose
/// two terms are both resolved; `None` when no pair is (see the module documentation).
pub fn best_pair(
    prep: &Prepared,
    o: &FitOutcome,
    all: &[KindFit],
    basis: &Basis,
    max_iter: usize,
    obs: &dyn Observer,
) -> Option<PairFit> {
    let usable = |k: &&KindFit| !k.shape.is_empty() && k.shape.len() == k.coefs.len();
    let mut top: Vec<&KindFit> = all.iter().filter(usable).take(PAIR_KINDS).collect();
    // a force on the position brings the force on the velocity, and the other way round: on a
    // TM at nearly constant speed one stands in for the other (a damping's column is nearly a
    // constant force's), so the one the single fits put behind is paired too
    for twin in ["position", "velocity"] {
        let other = if twin == "position" {
            "velocity"
        } else {
            "position"
        };
        if top.iter().any(|k| k.kind == other) && !top.iter().any(|k| k.kind == twin) {
            top.extend(all.iter().filter(usable).find(|k| k.kind == twin));
        }
    }
    let pairs: Vec<(usize, usize)> = (0..top.len())
        .flat_map(|i| (i + 1..top.len()).map(move |j| (i, j)))
        .collect();
    let fitted: Vec<Option<Fitted>> = pairs
        .par_iter()
        .map(|&(i, j)| fit_pair(prep, o, basis, top[i], top[j], max_iter, obs))
        .collect();
    let ln_n = (o.n.max(2) as f64).ln();
    let mut fitted: Vec<Fitted> = fitted.into_iter().flatten().collect();
    fitted.sort_by(|a, b| a.delta_bic(ln_n).total_cmp(&b.delta_bic(ln_n)));
    for f in &fitted {
        obs.debug(&|| {
            format!(
                "pair {}: delta BIC {:.1}, chi2 {:.1} ({} at {:?}, {} at {:?})",
                f.name(),
                f.delta_bic(ln_n),
                o.chi2 - f.delta_chi2,
                f.terms[0].kind,
                f.terms[0].parameter.as_ref().map(|p| p.value),
                f.terms[1].kind,
                f.terms[1].parameter.as_ref().map(|p| p.value)
            )
        });
    }
    let single = |kind: &str| {
        all.iter()
            .find(|k| k.kind == kind)
            .map_or(0.0, |k| k.delta_bic.min(0.0))
    };
    // each term's figures beside the other, and whether both are resolved
    let judged: Vec<(Vec<KindFit>, f64)> = fitted
        .iter()
        .filter_map(|f| {
            let bic = f.delta_bic(ln_n);
            let mut terms = f.terms.clone();
            for (i, t) in terms.iter_mut().enumerate() {
                t.delta_bic = bic - single(&f.terms[1 - i].kind);
                t.delta_chi2 = -t.delta_bic + count(t) as f64 * ln_n;
            }
            let resolved = terms
                .iter()
                .all(|t| t.sigma.is_finite() && t.sigma > 0.0 && t.delta_bic < DELTA_BIC_STRONG);
            resolved.then_some((terms, bic))
        })
        .collect();
    let (terms, bic) = judged.first()?.clone();
    let mut alike: Vec<String> = judged
        .iter()
        .filter(|(_, b)| b - bic < -DELTA_BIC_STRONG)
        .map(|(t, _)| format!("{} + {}", t[0].kind, t[1].kind))
        .collect();
    if alike.len() < 2 {
        alike.clear();
    }
    Some(PairFit {
        terms,
        delta_bic: bic,
        alike,
    })
}

/// The scan of a scanned kind's parameter around `v` beside the partner's columns: its
/// bracket and grid (a vibration two frequency resolutions either side, a creep a factor 3, a
/// jump a tenth of the record), in log space for the creep.
fn bracket(kind: &str, v: f64, t: &[f64], dt: f64) -> (f64, f64, usize, bool, f64) {
    let (span, t_end) = (t[t.len() - 1] - t[0], t[t.len() - 1]);
    match kind {
        "vibration" => {
            let res = 1.0 / span;
            (
                (v - 2.0 * res).max(0.5 * res),
                v + 2.0 * res,
                33,
                false,
                0.01 * res,
            )
        }
        "creep" => (v / 3.0, 3.0 * v, 24, true, 0.02),
        _ => (
            (v - 0.1 * span).max(2.0 * dt),
            (v + 0.1 * span).min(t_end - 2.0 * dt),
            41,
            false,
            0.5 * dt,
        ),
    }
}

/// `k` at the scanned value `v`: its columns and parameter.
fn at(k: &KindFit, v: f64, t: &[f64]) -> KindFit {
    let mut k = k.clone();
    k.shape = scanned_shape(t, &k.kind, v).expect("a scanned kind");
    if let Some(p) = k.parameter.as_mut() {
        p.value = v;
    }
    k
}

/// The coefficients of both terms (`a`'s columns then `b`'s) by the score test on `basis`,
/// with their 1-sigma; `None` when the columns are dependent.
fn score_pair(basis: &Basis, a: &KindFit, b: &KindFit) -> Option<(Vec<f64>, Vec<f64>, f64)> {
    let cols: Vec<Vec<f64>> = a.shape.iter().chain(&b.shape).cloned().collect();
    basis.score(cols)
}

/// The pair `a`, `b` fitted jointly with the model (see the module documentation); `None`
/// when their columns are dependent on the record.
fn fit_pair(
    prep: &Prepared,
    o: &FitOutcome,
    basis: &Basis,
    a: &KindFit,
    b: &KindFit,
    max_iter: usize,
    obs: &dyn Observer,
) -> Option<Fitted> {
    let t = &prep.dataset.t;
    let n = t.len();
    let span = t[n - 1] - t[0];
    let dt = span / (n.max(2) - 1) as f64;
    let mut terms = vec![a.clone(), b.clone()];
    // each scanned parameter scanned again beside the partner's columns
    for i in 0..2 {
        if !scanned(&terms[i]) {
            continue;
        }
        let v0 = terms[i].parameter.as_ref().map_or(0.0, |p| p.value);
        let (lo, hi, m, log, tol) = bracket(&terms[i].kind, v0, t, dt);
        if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
            continue;
        }
        let partner = terms[1 - i].clone();
        let me = terms[i].clone();
        let (v, _) = scan(lo, hi, m, log, tol, &|v| {
            score_pair(basis, &partner, &at(&me, v, t)).map_or(f64::NEG_INFINITY, |s| s.2)
        });
        terms[i] = at(&me, v, t);
    }
    let (mut c, _, _) = score_pair(basis, &terms[0], &terms[1])?;
    let na = terms[0].shape.len();
    terms[1].coefs = c.split_off(na);
    terms[0].coefs = c;
    let solved = terms
        .iter()
        .any(|k| matches!(k.kind.as_str(), "position" | "velocity"));
    let modes: &[bool] = if solved { &[false, true] } else { &[false] };
    let (mut best, mut mode) = (None::<JointEnd>, false);
    for &m in modes {
        let end = joint_pair(prep, o, &terms, &o.p, max_iter, m, obs);
        if best.as_ref().is_none_or(|b| end.0 > b.0) {
            (best, mode) = (Some(end), m);
        }
    }
    let (mut d, coefs, p) = best?;
    set_coefs(&mut terms, coefs);
    // a scanned parameter searched again with the joint fit at each trial value
    for i in 0..2 {
        if !scanned(&terms[i]) {
            continue;
        }
        let v0 = terms[i].parameter.as_ref().map_or(0.0, |p| p.value);
        let (log, half) = match terms[i].kind.as_str() {
            "vibration" => (false, 0.25 / span),
            "creep" => (true, 1.5f64.ln()),
            _ => (false, 2.0 * dt),
        };
        let z0 = if log { v0.ln() } else { v0 };
        let trial = |z: f64| -> (f64, Vec<KindFit>) {
            let v = if log { z.exp() } else { z };
            let mut ts = terms.clone();
            ts[i] = at(&ts[i], v, t);
            if let Some((mut c, _, _)) = score_pair(basis, &ts[0], &ts[1]) {
                ts[1].coefs = c.split_off(na);
                ts[0].coefs = c;
            }
            let (d, c, _) = joint_pair(prep, o, &ts, &p, max_iter, mode, obs);
            set_coefs(&mut ts, c);
            (d, ts)
        };
        let (zb, db, tb) = golden(z0 - half, z0 + half, &trial);
        if db > d {
            d = db;
            terms = tb;
            let v = if log { zb.exp() } else { zb };
            if let Some(p) = terms[i].parameter.as_mut() {
                p.value = v;
            }
        }
    }
    let (_, sig, _) = score_pair(basis, &terms[0], &terms[1])?;
    let (sa, sb) = sig.split_at(na);
    describe(&mut terms[0], sa, prep.channel);
    describe(&mut terms[1], sb, prep.channel);
    let k = count(&terms[0]) + count(&terms[1]);
    Some(Fitted {
        terms,
        delta_chi2: d,
        k,
    })
}

/// The joint coefficients `c` (`terms[0]`'s then `terms[1]`'s) put into the terms.
fn set_coefs(terms: &mut [KindFit], mut c: Vec<f64>) {
    let rest = c.split_off(terms[0].shape.len().min(c.len()));
    terms[0].coefs = c;
    terms[1].coefs = rest;
}

/// Golden section of `f`'s first value over `[a, b]` (six steps): the best point, its value
/// and what `f` gave there (the refinement of a single term's scanned parameter uses it too).
pub(super) fn golden<T: Clone>(a: f64, b: f64, f: &dyn Fn(f64) -> (f64, T)) -> (f64, f64, T) {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (a, b);
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut kc) = f(c);
    let (mut fd, mut kd) = f(d);
    for _ in 0..6 {
        if fc > fd {
            b = d;
            (d, fd, kd) = (c, fc, kc.clone());
            c = b - g * (b - a);
            (fc, kc) = f(c);
        } else {
            a = c;
            (c, fc, kc) = (d, fd, kd.clone());
            d = a + g * (b - a);
            (fd, kd) = f(d);
        }
    }
    if fc > fd { (c, fc, kc) } else { (d, fd, kd) }
}

/// The two `terms` fitted jointly with the model from its parameters `from` (the forces on the
/// state to first order or `solved` with the state): the chi-square removed from `o.chi2`, the
/// coefficients and the model's parameters.
fn joint_pair(
    prep: &Prepared,
    o: &FitOutcome,
    terms: &[KindFit],
    from: &[f64],
    max_iter: usize,
    solved: bool,
    obs: &dyn Observer,
) -> JointEnd {
    let joint = Joint::new(prep, o, terms.iter().collect(), from);
    let opts = LmOptions {
        max_iter,
        observer: obs,
        ..LmOptions::default()
    };
    let r = crate::numeric::lm::minimize(
        &|u: &[f64]| joint.residual(u, solved),
        &joint.u0,
        &joint.lo,
        &joint.hi,
        &opts,
    );
    let coefs = (0..joint.w.len())
        .map(|j| r.u[joint.nm + j] * joint.sc[j])
        .collect();
    (o.chi2 - r.cost, coefs, joint.params(&r.u))
}

/// A term's coefficient, 1-sigma (`sig`, its columns'), words and parameter from its joint
/// coefficients, as [`super::KindScan::push`] and the refinement give them.
fn describe(k: &mut KindFit, sig: &[f64], ch: &str) {
    let c = &k.coefs;
    let (coef, s) = if c.len() == 2 && k.kind != "position" {
        let a = c[0].hypot(c[1]);
        let sa = if a > 0.0 {
            ((c[0] * sig[0]).powi(2) + (c[1] * sig[1]).powi(2)).sqrt() / a
        } else {
            sig[0]
        };
        (a, sa)
    } else {
        (c[0], sig[0])
    };
    if state_shape(&[], &k.kind, &[], 0.0).is_some() {
        let coef = if k.kind == "delay" {
            coef * k.scan
        } else {
            coef
        };
        let (term, parameter) = state_text(&k.kind, ch, coef);
        k.coefficient = coef;
        k.sigma = if k.kind == "delay" {
            s * k.scan.abs()
        } else {
            s
        };
        k.term = term;
        k.parameter = parameter;
        describe_offset(k, ch);
    } else if let Some(v) = k.parameter.as_ref().map(|p| p.value) {
        k.coefficient = coef;
        k.sigma = s;
        k.term = term_text(&k.kind, coef, v);
    }
}
