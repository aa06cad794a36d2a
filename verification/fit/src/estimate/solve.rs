//! The solution of one fit (`super::fit_model`'s stages after the search): refinement,
//! covariance, profile likelihood along each parameter, evidence.

use geodesic_facility::Model;
use nalgebra::DMatrix;
use rayon::prelude::*;

use super::problem::{Problem, Profiled};
use super::search::{canonical_forms, effort, refine, search, start_values};
use super::{FitOptions, FitOutcome, STEP_RATIO_TOLERANCE, effective_sigma};
use crate::coords::from_u;
use crate::error::FitError;
use crate::numeric::lm::{
    LmOptions, fd_steps, jacobian_columns_central, minimize_with_steps, normal_equations,
};
use crate::prepare::Prepared;

/// [`fit_model`](super::fit_model) on `prep` itself; with `refine_only`, `starts[0]` is
/// refined by the long run only (no screening, no stages).
pub(super) fn fit_model_on(
    prep: &Prepared,
    model: &Model,
    opts: &FitOptions,
    starts: &[Vec<f64>],
    refine_only: bool,
    depth: usize,
) -> Result<FitOutcome, FitError> {
    let clock = std::time::Instant::now();
    let obs = &*opts.observer;
    let debug = obs.debugging();
    // the model in every progress line: `discover` and `diagnose` fit many side by side
    let label = model.effect_names().join("+");
    let lap = |what: &str| {
        obs.debug(&|| {
            format!(
                "[{:.2} s] {what} ({} samples)",
                clock.elapsed().as_secs_f64(),
                prep.dataset.t.len()
            )
        });
        obs.progress(
            &format!(
                "fit of {label} on {} samples: {what} done ({:.1} s)",
                prep.dataset.t.len(),
                clock.elapsed().as_secs_f64()
            ),
            true,
        );
    };
    // the stages, in order: data and constraints (the noise model is the dataset's:
    // `Prepared`), start values, search, refinement, canonical forms, uncertainty (covariance,
    // Laplace evidence, profiles) and the outcome; the residual analysis and the report are
    // `crate::report`'s
    let pb = Problem::new(prep, model, opts)?;
    let long_iter = effort(model).refine_iterations;
    let starts = start_values(&pb, opts, starts);
    let first = search(&pb, &starts, refine_only);
    lap("search (screening and short runs)");
    let refined = refine(&pb, &starts, &first, long_iter, debug);
    lap("long Levenberg-Marquardt runs");
    let (si, chi2, u) = refined
        .into_iter()
        .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
        .expect("at least one start");
    let start = &starts[si];
    let (chi2, u) = canonical_forms(&pb, start, chi2, u, long_iter);
    lap("canonical forms");
    let mut c = uncertainty(&pb, opts, start, chi2, &u);
    lap("covariance");
    if opts.profile && c.n_free > 0 {
        let ctx = ProfileContext {
            pb: &pb,
            c: &c,
            start,
            u: &u,
            depth,
            debug,
            clock,
        };
        // a profile that went below the best fit shows that the refinement stopped short of
        // the optimum (a sloppy valley): refine again from the lowest point met, so that the
        // fit reported, and every comparison of models made from it, is an optimum
        match profiles(&ctx) {
            Profiles::Lower(w) => {
                let mut o =
                    fit_model_on(prep, model, opts, &[pb.full(&w, start)], true, depth + 1)?;
                o.starts = starts.len();
                return Ok(o);
            }
            Profiles::Widths(widths) => widen(&pb, &mut c, &u, &widths),
        }
        match sweep_unresolved(&ProfileContext {
            pb: &pb,
            c: &c,
            start,
            u: &u,
            depth,
            debug,
            clock,
        }) {
            Sweep::Lower(w) => {
                let mut o =
                    fit_model_on(prep, model, opts, &[pb.full(&w, start)], true, depth + 1)?;
                o.starts = starts.len();
                return Ok(o);
            }
            Sweep::Points(points) => widen_to_points(&pb, &mut c, &points),
        }
    }
    lap("profiles");
    outcome(&pb, c, starts.len())
}

/// What the covariance stage leaves for the profiles and the outcome.
struct Uncertainty {
    /// Best parameters [SI] and the model's prediction there.
    p: Vec<f64>,
    pred: Vec<f64>,
    /// Chi-square at the fit's noise `sig`, and where `sig` came from.
    chi2: f64,
    sig: f64,
    sigma_source: String,
    /// `prep.sigma / sig` (the residuals were normalised by `prep.sigma`).
    ratio: f64,
    n: usize,
    n_free: usize,
    /// Finite-difference steps of the free parameters (fit coordinates).
    steps: Vec<f64>,
    /// Covariance in the fit's coordinates (on the resolved directions when a symmetry is
    /// found), and `max(1, chi2_red)`.
    cov: DMatrix<f64>,
    inflate: f64,
    step_ratio: Vec<f64>,
    resolved: Vec<bool>,
    ns: crate::identify::NullSpace,
    half_log_det_2pi_cov: Option<f64>,
    log_prior_volume: Option<f64>,
    sigma_p: Vec<f64>,
    sigma_cov: Vec<f64>,
    corr: DMatrix<f64>,
    free_names: Vec<String>,
}

/// Whether the direction `w` (a unit vector in the fit's coordinates) that the step test
/// flagged without the signature of a truncation error is flat, tried on the model itself
/// (`crate::identify::symmetries_confirmed`). The normal matrix `a` (`J^T J` at the reported
/// noise) predicts a chi-square rise of 1 at `s = 1 / sqrt(w^T a w)`; the residuals are
/// evaluated at `u +- s w` (shortened to stay inside `[lo, hi]`), and the direction is flat when
/// the rise on both sides stays under [`FLAT_RISE`]. A direction the data resolve rises by about
/// 1 there, or more where the differences understate its curvature; two weak directions of
/// nearly equal curvature that rotate into each other when the steps are halved are flagged by
/// the matrices and resolved here. `r0` are the residuals at `u` (normalised by the
/// preparation's noise; `ratio` rescales them to the reported one).
#[allow(clippy::too_many_arguments)]
fn flat_along<F: crate::numeric::lm::Residuals + ?Sized>(
    f: &F,
    u: &[f64],
    lo: &[f64],
    hi: &[f64],
    r0: &[f64],
    ratio: f64,
    a: &DMatrix<f64>,
    w: &[f64],
    obs: &dyn crate::numeric::observe::Observer,
) -> bool {
    let n = u.len();
    let curvature: f64 = (0..n)
        .map(|i| (0..n).map(|j| w[i] * a[(i, j)] * w[j]).sum::<f64>())
        .sum();
    if !(curvature > 0.0 && curvature.is_finite()) {
        return true;
    }
    let reach = |sign: f64| -> f64 {
        let mut s = 1.0 / curvature.sqrt();
        for k in 0..n {
            let d = sign * w[k];
            if d > 0.0 {
                s = s.min((hi[k] - u[k]) / d);
            } else if d < 0.0 {
                s = s.min((lo[k] - u[k]) / d);
            }
        }
        sign * s.max(0.0)
    };
    let points: Vec<Vec<f64>> = [reach(1.0), reach(-1.0)]
        .iter()
        .map(|s| u.iter().zip(w).map(|(x, d)| x + s * d).collect())
        .collect();
    let chi2 = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>() * ratio * ratio;
    let base = chi2(r0);
    let rise: Vec<f64> = f
        .eval_many(&points)
        .iter()
        .map(|r| chi2(r) - base)
        .collect();
    if obs.debugging() {
        obs.debug(&|| format!("null-space: along the direction, chi-square rise at +-s {rise:?}"));
    }
    // a rise that is not a number refutes nothing
    rise.iter().all(|r| r.is_nan() || *r < FLAT_RISE)
}

/// Chi-square rise at a direction's predicted 1-sigma under which it is flat ([`flat_along`]):
/// a quarter of the rise of 1 that a resolved direction shows.
const FLAT_RISE: f64 = 0.25;

/// Stage "uncertainty": the noise figure, the covariance from the Jacobian (and from half the
/// steps, the step test), the null space, the Laplace evidence's ingredients, the sigmas and
/// correlations at the best fit `u` over `start`.
fn uncertainty(
    pb: &Problem,
    opts: &FitOptions,
    start: &[f64],
    chi2: f64,
    u: &[f64],
) -> Uncertainty {
    let prep = pb.prep;
    let model = pb.model;
    let (specs, fidx, lo, hi) = (&pb.specs, &pb.fidx, &pb.lo, &pb.hi);
    let np = specs.len();
    let (data, t) = (pb.data, pb.t);
    let p = pb.full(u, start);
    let pred = model.predict(&p, t, &prep.inputs);
    let n = data.len();
    let n_free = fidx.len();
    let r0 = pb.resid(u, start);
    let f = pb.window(start, t.len());
    let steps = fd_steps(&f, u, &r0, lo, hi, LmOptions::default().fd_step);
    let cols = jacobian_columns_central(&f, u, &r0, lo, hi, &steps);
    let (jtj, _) = normal_equations(&cols, &r0);
    drop(cols);
    // the same from differences over half the steps: in a direction the data do not constrain
    // the curvature is the differences' own truncation error, and the sigma grows like 1/step
    let half: Vec<f64> = steps.iter().map(|h| h / 2.0).collect();
    let (jtj_half, _) = normal_equations(&jacobian_columns_central(&f, u, &r0, lo, hi, &half), &r0);
    let raw: Vec<f64> = data.iter().zip(&pred).map(|(d, m)| d - m).collect();
    let (sig, sigma_source) = match opts.sigma {
        Some(s) => match (&opts.sigma_source, &prep.ar) {
            // a figure passed on with its source (discover's round 0) says it as it was
            (Some(src), _) => (s, src.clone()),
            // the whitening stays the dataset's: say so
            (None, Some(m)) => (
                s,
                format!("given, whitened by pre-trigger AR({})", m.order()),
            ),
            (None, None) => (s, "given".to_string()),
        },
        None => effective_sigma(prep, &raw),
    };
    // the residuals were normalised by prep.sigma: rescale chi-square and covariance
    let ratio = prep.sigma / sig;
    let chi2 = chi2 * ratio * ratio;
    let a = jtj * (ratio * ratio);
    let cov = invert_spd(&a);
    // (`cov` is the inverse of `J^T J` times ratio^2, `cov_half` of the plain one)
    let cov_half = invert_spd(&jtj_half);
    let mut step_ratio = vec![1.0; np];
    for (k, &i) in fidx.iter().enumerate() {
        step_ratio[i] = (cov_half[(k, k)] / (cov[(k, k)] * ratio * ratio)).sqrt();
    }
    // the Jacobian's null space: exact and near symmetries of the model on this record
    // (crate::identify); the covariance then lives on the resolved directions only
    let widths: Vec<f64> = lo.iter().zip(hi).map(|(l, h)| h - l).collect();
    let free_names: Vec<String> = fidx.iter().map(|&i| pb.names[i].clone()).collect();
    let confirm = |w: &[f64]| flat_along(&f, u, lo, hi, &r0, ratio, &a, w, pb.obs);
    let ns = crate::identify::symmetries_confirmed(
        &a,
        &jtj_half,
        ratio * ratio,
        &widths,
        &free_names,
        &confirm,
        pb.obs,
    );
    let exact_symmetry = ns.symmetries.iter().any(|s| s.kind == "exact");
    let cov = if ns.symmetries.is_empty() {
        cov
    } else {
        ns.cov.clone()
    };
    let mut resolved = vec![true; np];
    for (k, &i) in fidx.iter().enumerate() {
        let r = step_ratio[i];
        resolved[i] = ns.resolved[k] && !(r.is_nan() || (r - 1.0).abs() > STEP_RATIO_TOLERANCE);
    }
    // Laplace evidence ingredients (FitOutcome::log_evidence): on the identifiable space, so
    // undefined while an exact symmetry is left (its flat direction is not integrated)
    let half_log_det_2pi_cov = log_det_spd(&a)
        .filter(|_| !exact_symmetry)
        .map(|ld| 0.5 * (n_free as f64 * (2.0 * std::f64::consts::PI).ln() - ld));
    let log_prior_volume = lo
        .iter()
        .zip(hi)
        .map(|(l, h)| h - l)
        .try_fold(0.0, |acc, w| {
            (w.is_finite() && w > 0.0).then(|| acc + w.ln())
        });
    let chi2_red = chi2 / (n.saturating_sub(n_free)).max(1) as f64;
    let inflate = chi2_red.max(1.0);
    let mut sigma_p = vec![0.0; np];
    let mut sigma_cov = vec![0.0; np];
    let mut corr = DMatrix::zeros(n_free, n_free);
    for (k, &i) in fidx.iter().enumerate() {
        let su = cov[(k, k)].max(0.0).sqrt();
        sigma_cov[i] = if specs[i].log {
            p[i] * su
        } else {
            specs[i].scale * su
        };
        sigma_p[i] = sigma_cov[i] * inflate.sqrt();
        for l in 0..n_free {
            let d = (cov[(k, k)] * cov[(l, l)]).sqrt();
            corr[(k, l)] = if d > 0.0 { cov[(k, l)] / d } else { 0.0 };
        }
    }
    Uncertainty {
        p,
        pred,
        chi2,
        sig,
        sigma_source,
        ratio,
        n,
        n_free,
        steps,
        cov,
        inflate,
        step_ratio,
        resolved,
        ns,
        half_log_det_2pi_cov,
        log_prior_volume,
        sigma_p,
        sigma_cov,
        corr,
        free_names,
    }
}

/// What the profiles read.
struct ProfileContext<'p, 'a> {
    pb: &'p Problem<'a>,
    c: &'p Uncertainty,
    start: &'p [f64],
    u: &'p [f64],
    depth: usize,
    debug: bool,
    clock: std::time::Instant,
}

/// The profiles' answer.
enum Profiles {
    /// Each free parameter's reach up and down (fit coordinates).
    Widths(Vec<[f64; 2]>),
    /// A point below the best fit (free parameters, fit coordinates) to refine from.
    Lower(Vec<f64>),
}

/// Stage "profiles": the profile likelihood of each free parameter, both sides in parallel.
/// Moves each free parameter away from the best fit, refits the others and widens its 1-sigma
/// to where chi-square has risen by max(1, chi2_red); only ever widens the covariance figure
/// (banana-shaped valleys, examples README pitfall).
///
/// The sides advance in waves, one profile point each per wave, in parallel (sixteen tasks
/// for eight parameters: two cores stay busy). A wave that meets a point below the best fit
/// ends the stage there: the fit is refined from the lowest point the wave met and profiled
/// again, so the farther points of this round, which would be measured from the old best,
/// are not computed (on a million-sample retraction record that was a quarter of the
/// profiles' time, issue 35). Which point is chosen depends on the waves alone, not on the
/// threads' timing.
fn profiles(ctx: &ProfileContext) -> Profiles {
    let n_free = ctx.c.n_free;
    let mut sides: Vec<Side> = (0..2 * n_free)
        .map(|ks| Side::new(ctx, ks / 2, ks % 2))
        .collect();
    let n_profiled = sides.iter().filter(|s| !s.done).count();
    let mut n_done = 0;
    loop {
        let before = sides.iter().filter(|s| !s.done).count();
        if before == 0 {
            break;
        }
        sides
            .par_iter_mut()
            .filter(|s| !s.done)
            .for_each(|s| s.advance(ctx));
        n_done += before - sides.iter().filter(|s| !s.done).count();
        ctx.pb.obs.progress(
            &{
                format!(
                    "profiles of {}: {n_done} of {n_profiled} sides done ({:.1} s)",
                    ctx.pb.model.effect_names().join("+"),
                    ctx.clock.elapsed().as_secs_f64()
                )
            },
            true,
        );
        // the lowest point met below the best fit (the first in parameter and side order
        // among equals)
        let mut lowest: Option<&(f64, Vec<f64>)> = None;
        for c in sides.iter().filter_map(|s| s.lowest.as_ref()) {
            if lowest.is_none_or(|b| c.0 < b.0) {
                lowest = Some(c);
            }
        }
        if let Some((c, w)) = lowest
            && ctx.depth < PROFILE_RESTARTS
        {
            if ctx.debug {
                let r2 = ctx.c.ratio * ctx.c.ratio;
                ctx.pb.obs.debug(&|| {
                    format!(
                        "a profile met chi-square {:.3} below the best fit: refining from there",
                        (ctx.c.chi2 / r2 - c) * r2
                    )
                });
            }
            return Profiles::Lower(w.clone());
        }
    }
    Profiles::Widths(sides.chunks(2).map(|c| [c[0].out, c[1].out]).collect())
}

/// Whether the `k`-th free parameter (parameter `i`) is profiled: not along a symmetry (the
/// profile would walk along it), with a finite, positive covariance sigma.
fn is_profiled(c: &Uncertainty, i: usize, k: usize) -> bool {
    let su = (c.cov[(k, k)].max(0.0) * c.inflate).sqrt();
    su.is_finite() && su > 0.0 && c.resolved[i]
}

/// Iterations of one profile point's refit of the other parameters.
const PROFILE_ITERATIONS: usize = 60;

/// Iterations of one profile point's refit for a model the record rejects outright (chi2_red
/// above [`CHI2_RED_ASTRONOMICAL`](super::CHI2_RED_ASTRONOMICAL): its report
/// says the model misses most of the record, and its sigmas are inflated by at least 100).
/// Such a refit crawls along the wrong model's valley on a finite-difference gradient that is
/// mostly truncation error: on the million-sample `rt-plunger` fitted with `piezo` alone, the
/// Gauss-Newton step predicted a fall of 2e8 in chi-square where the cost fell by 1e3, and
/// every side that used more than 20 iterations ended above the target rise after 20 as after
/// 60 (its width the covariance sigma either way), at three times the time (issue 35). A model
/// that describes its record keeps [`PROFILE_ITERATIONS`]: its refits converge (1 to 5
/// iterations on the million-sample record with `piezo,plunger_compliance`), or crawl for a
/// reason a cut could hide (up to 60 on a light plunger's 1 021-sample record, whose
/// widths then change).
const PROFILE_ITERATIONS_REJECTED: usize = 20;

/// One side (`side` 0 up, 1 down) of the profile of the `k`-th free parameter, advanced a
/// point at a time ([`Side::advance`]).
struct Side {
    k: usize,
    side: usize,
    /// Its reach so far (fit coordinates): the covariance sigma, widened by the points.
    out: f64,
    /// The lowest point met below the best fit (by more than 0.01 in chi-square): cost and
    /// free parameters.
    lowest: Option<(f64, Vec<f64>)>,
    /// Whether the side has ended (or is not profiled).
    done: bool,
    /// The other free parameters, their bounds and difference steps.
    others: Vec<usize>,
    /// Where the others' optimum moves per unit of `u_k`, to first order: the regression
    /// slope of the covariance, `cov(j, k) / cov(k, k)`. Each point starts from the previous
    /// one moved along it, next to its optimum, so the refit of the others takes a few
    /// iterations instead of a crawl along the valley.
    slope: Vec<f64>,
    step: f64,
    v0: Vec<f64>,
    uk_prev: f64,
    doublings: usize,
}

impl Side {
    fn new(ctx: &ProfileContext, k: usize, side: usize) -> Side {
        let (c, u) = (ctx.c, ctx.u);
        let (cov, inflate, n_free) = (&c.cov, c.inflate, c.n_free);
        let su = (cov[(k, k)].max(0.0) * inflate).sqrt();
        let others: Vec<usize> = (0..n_free).filter(|&j| j != k).collect();
        let slope: Vec<f64> = others
            .iter()
            .map(|&j| {
                let s = cov[(j, k)] / cov[(k, k)];
                if s.is_finite() { s } else { 0.0 }
            })
            .collect();
        let v0: Vec<f64> = others.iter().map(|&j| u[j]).collect();
        Side {
            k,
            side,
            out: su,
            lowest: None,
            done: !is_profiled(c, ctx.pb.fidx[k], k),
            others,
            slope,
            step: su,
            v0,
            uk_prev: u[k],
            doublings: 0,
        }
    }

    /// The next point of the side: `u_k` moved by the step, the others refitted; ends the
    /// side when chi-square has risen by the target, a bound is met, the doublings are used
    /// or a point below the best fit is met.
    fn advance(&mut self, ctx: &ProfileContext) {
        let (pb, c, u, start) = (ctx.pb, ctx.c, ctx.u, ctx.start);
        let (lo, hi, t) = (&pb.lo, &pb.hi, pb.t);
        let k = self.k;
        let target = c.inflate;
        let r2 = c.ratio * c.ratio;
        let cost_best = c.chi2 / r2;
        let sgn = if self.side == 0 { 1.0 } else { -1.0 };
        let lo2: Vec<f64> = self.others.iter().map(|&j| lo[j]).collect();
        let hi2: Vec<f64> = self.others.iter().map(|&j| hi[j]).collect();
        let steps2: Vec<f64> = self.others.iter().map(|&j| c.steps[j]).collect();
        let uk = (u[k] + sgn * self.step).clamp(lo[k], hi[k]);
        let at_bound = uk != u[k] + sgn * self.step;
        for (i, v) in self.v0.iter_mut().enumerate() {
            *v = (*v + self.slope[i] * (uk - self.uk_prev)).clamp(lo2[i], hi2[i]);
        }
        self.uk_prev = uk;
        let f = Profiled {
            window: pb.window(start, t.len()),
            k,
            uk,
        };
        // chi-square to 1 % of `target`, the rise the profile compares it with: one unit for
        // a model that fits (chi2_red <= 1: as before), chi2_red units for one that does not,
        // whose sigmas are inflated by sqrt(chi2_red). Refining a wrong model's profile point
        // to 1 % of a unit of a chi-square of 1e10 made a million-sample record's profiles
        // crawl for 60 iterations each (issue 35) without moving its width beyond that 1 %.
        let opts_p = LmOptions {
            max_iter: if target > super::CHI2_RED_ASTRONOMICAL {
                PROFILE_ITERATIONS_REJECTED
            } else {
                PROFILE_ITERATIONS
            },
            atol: 0.01 * target / r2,
            observer: ctx.pb.obs,
            ..LmOptions::default()
        };
        let r = minimize_with_steps(&f, &self.v0, &lo2, &hi2, &opts_p, Some(&steps2));
        if ctx.debug {
            ctx.pb.obs.debug(&|| {
                format!(
                    "profile {k} side {}: {} iterations, dchi2 {:.3}",
                    self.side,
                    r.iterations,
                    (r.cost - cost_best) * r2
                )
            });
        }
        ctx.pb.obs.progress(
            &{
                format!(
                    "profile of {} ({}): {} iterations, delta chi2 {:.4e} (target {:.4e})",
                    c.free_names[k],
                    if self.side == 0 { "up" } else { "down" },
                    r.iterations,
                    (r.cost - cost_best) * r2,
                    target
                )
            },
            false,
        );
        self.doublings += 1;
        if r.cost < cost_best - 0.01 / r2 && self.lowest.as_ref().is_none_or(|(c, _)| r.cost < *c) {
            let mut w = r.u.clone();
            w.insert(k, uk);
            self.lowest = Some((r.cost, w));
            // the fit is refined from here and profiled again: this side stops
            if ctx.depth < PROFILE_RESTARTS {
                self.done = true;
                return;
            }
        }
        let dchi = ((r.cost - cost_best) * r2).max(0.0);
        let reach = (uk - u[k]).abs();
        if dchi >= target {
            self.out = self.out.max(reach * (target / dchi).sqrt());
            self.done = true;
            return;
        }
        self.out = self.out.max(reach);
        if at_bound || self.doublings >= PROFILE_DOUBLINGS {
            self.done = true;
            return;
        }
        self.v0 = r.u;
        self.step *= 2.0;
    }
}

/// Widens each free parameter's sigma to its profile's reach (`widths`, up and down in the
/// fit's coordinates) where that is wider.
fn widen(pb: &Problem, c: &mut Uncertainty, u: &[f64], widths: &[[f64; 2]]) {
    let (specs, fidx) = (&pb.specs, &pb.fidx);
    let (p, sigma_p) = (&c.p, &mut c.sigma_p);
    for (k, &i) in fidx.iter().enumerate() {
        let up = (from_u(&specs[i], u[k] + widths[k][0]) - p[i]).abs();
        let down = (p[i] - from_u(&specs[i], u[k] - widths[k][1])).abs();
        let prof = up.max(down);
        if prof.is_finite() && prof > sigma_p[i] {
            sigma_p[i] = prof;
        }
    }
}

/// Fractions of an unresolved parameter's allowed range (fit coordinates) at which
/// [`sweep_unresolved`] holds it.
const SWEEP_FRACTIONS: [f64; 5] = [0.1, 0.3, 0.5, 0.7, 0.9];

/// What the sweep of the unresolved parameters found.
enum Sweep {
    /// The points (free parameters, fit coordinates) within the profiles' chi-square rise of
    /// the best fit: equally good solutions.
    Points(Vec<Vec<f64>>),
    /// A point below the best fit to refine from.
    Lower(Vec<f64>),
}

/// Stage "unresolved sweep" (issue 48): each free parameter the data do not resolve is held at
/// points across its allowed range ([`SWEEP_FRACTIONS`]) and the others refitted from the best
/// fit. The covariance and the profiles are local: a parameter pinned on a bound where the
/// model stops depending on it (a damping at its lower bound, in log coordinates) has no
/// gradient there, so the profile of a resolved parameter never moves it, and the sigmas of
/// the parameters that trade with it far from the bound were missed. On the independent
/// `needle-body-3` record the preload was 0.29889 +- 0.00029 N (truth 0.3, 3.9 sigma) with
/// both dampings at 1e-4 N s/m; held at `F_pre` = 0.3 the chi-square rises by 0.63 only,
/// with `c_tm` at 9.8 N s/m. The points whose chi-square stays within the profiles' rise
/// (`max(1, chi2_red)`) are equally good solutions, and the resolved parameters' sigmas are
/// widened to reach them ([`widen_to_points`]). Runs with the profiles (`fit`), not in the
/// searches of `diagnose` and `discover`.
fn sweep_unresolved(ctx: &ProfileContext) -> Sweep {
    let (pb, c) = (ctx.pb, ctx.c);
    let (lo, hi) = (&pb.lo, &pb.hi);
    let ks: Vec<usize> = (0..c.n_free)
        .filter(|&k| !c.resolved[pb.fidx[k]] && lo[k].is_finite() && hi[k].is_finite())
        .collect();
    let r2 = c.ratio * c.ratio;
    let cost_best = c.chi2 / r2;
    let target = c.inflate;
    let swept: Vec<Vec<(f64, f64, Vec<f64>)>> = ks.par_iter().map(|&k| sweep_one(ctx, k)).collect();
    let mut all: Vec<(f64, Vec<f64>)> = Vec::new();
    for (k, pts) in ks.iter().zip(swept) {
        for (uk, cost, w) in pts {
            if ctx.debug {
                pb.obs.debug(&|| {
                    format!(
                        "sweep of {} at u {uk:.4}: delta chi2 {:.3}",
                        c.free_names[*k],
                        (cost - cost_best) * r2
                    )
                });
            }
            all.push((cost, w));
        }
    }
    // the lowest point below the best fit, by more than the profiles' margin (the first in
    // parameter and point order among equals): the refinement stopped short of the optimum
    let mut lowest: Option<&(f64, Vec<f64>)> = None;
    for pt in all.iter().filter(|(cost, _)| *cost < cost_best - 0.01 / r2) {
        if lowest.is_none_or(|b| pt.0 < b.0) {
            lowest = Some(pt);
        }
    }
    if let Some((_, w)) = lowest
        && ctx.depth < PROFILE_RESTARTS
    {
        return Sweep::Lower(w.clone());
    }
    Sweep::Points(
        all.into_iter()
            .filter(|(cost, _)| ((cost - cost_best) * r2) < target)
            .map(|(_, w)| w)
            .collect(),
    )
}

/// Bisections of the interval between the last equally good point of a sweep and the first
/// one beyond the rise ([`sweep_one`]): the edge to 1/16 of a grid interval.
const SWEEP_BISECTIONS: usize = 4;

/// The sweep of the `k`-th free parameter ([`sweep_unresolved`]): the grid across its range,
/// then on each side of the best fit the edge of the equally good points bisected between the
/// last grid point within the rise and the first beyond it. Each point: `u_k`, its cost and the
/// free parameters (fit coordinates).
fn sweep_one(ctx: &ProfileContext, k: usize) -> Vec<(f64, f64, Vec<f64>)> {
    let (pb, c, u, start) = (ctx.pb, ctx.c, ctx.u, ctx.start);
    let (lo, hi, t) = (&pb.lo, &pb.hi, pb.t);
    let r2 = c.ratio * c.ratio;
    let cost_best = c.chi2 / r2;
    let target = c.inflate;
    let others: Vec<usize> = (0..c.n_free).filter(|&j| j != k).collect();
    let lo2: Vec<f64> = others.iter().map(|&j| lo[j]).collect();
    let hi2: Vec<f64> = others.iter().map(|&j| hi[j]).collect();
    let steps2: Vec<f64> = others.iter().map(|&j| c.steps[j]).collect();
    let opts_p = LmOptions {
        max_iter: PROFILE_ITERATIONS,
        atol: 0.01 * target / r2,
        observer: pb.obs,
        ..LmOptions::default()
    };
    // the others refitted with u_k held, from the free parameters `from`
    let point = |uk: f64, from: &[f64]| -> (f64, f64, Vec<f64>) {
        let v0: Vec<f64> = others.iter().map(|&j| from[j]).collect();
        let f = Profiled {
            window: pb.window(start, t.len()),
            k,
            uk,
        };
        let r = minimize_with_steps(&f, &v0, &lo2, &hi2, &opts_p, Some(&steps2));
        let mut w = r.u;
        w.insert(k, uk);
        (uk, r.cost, w)
    };
    let within = |cost: f64| (cost - cost_best) * r2 < target;
    let mut grid: Vec<(f64, f64, Vec<f64>)> = SWEEP_FRACTIONS
        .par_iter()
        .map(|f| point(lo[k] + f * (hi[k] - lo[k]), u))
        .collect();
    grid.push((u[k], cost_best, u.to_vec()));
    grid.sort_by(|a, b| a.0.total_cmp(&b.0));
    let ib = grid
        .iter()
        .position(|g| g.0 == u[k] && g.1 == cost_best)
        .expect("the best fit is on the grid");
    let mut edges = Vec::new();
    for dir in [1isize, -1] {
        // the last point within the rise, walking away from the best fit, and the next one
        let mut i = ib as isize;
        while (0..grid.len() as isize).contains(&(i + dir)) && within(grid[(i + dir) as usize].1) {
            i += dir;
        }
        let j = i + dir;
        if (0..grid.len() as isize).contains(&j) {
            let (mut a, mut b) = (grid[i as usize].clone(), grid[j as usize].0);
            for _ in 0..SWEEP_BISECTIONS {
                let m = point(0.5 * (a.0 + b), &a.2);
                if within(m.1) {
                    edges.push(m.clone());
                    a = m;
                } else {
                    b = m.0;
                }
            }
        }
    }
    grid.remove(ib);
    grid.extend(edges);
    grid
}

/// Widens each resolved free parameter's sigma to reach its value at each of `points` (free
/// parameters, fit coordinates: equally good solutions, [`sweep_unresolved`]).
fn widen_to_points(pb: &Problem, c: &mut Uncertainty, points: &[Vec<f64>]) {
    let (specs, fidx) = (&pb.specs, &pb.fidx);
    for w in points {
        for (k, &i) in fidx.iter().enumerate() {
            if !c.resolved[i] {
                continue;
            }
            let d = (from_u(&specs[i], w[k]) - c.p[i]).abs();
            if d.is_finite() && d > c.sigma_p[i] {
                c.sigma_p[i] = d;
            }
        }
    }
}

/// Stage "outcome": sigmas of parameters the data do not constrain bounded by their range,
/// the finiteness check, the identifiable combinations.
fn outcome(pb: &Problem, c: Uncertainty, n_starts: usize) -> Result<FitOutcome, FitError> {
    let (prep, model) = (pb.prep, pb.model);
    let (specs, fidx, lo, hi) = (&pb.specs, &pb.fidx, &pb.lo, &pb.hi);
    let Uncertainty {
        p,
        pred,
        chi2,
        sig,
        sigma_source,
        n,
        n_free,
        inflate,
        step_ratio,
        mut resolved,
        ns,
        half_log_det_2pi_cov,
        log_prior_volume,
        mut sigma_p,
        mut sigma_cov,
        corr,
        ..
    } = c;
    // a parameter the data do not constrain (its Jacobian column is zero: an effect pinned at
    // values where it vanishes) has an infinite variance; its uncertainty is then its allowed
    // range, which is what the report states, instead of failing the fit (a candidate or a
    // baseline that lands there is a legitimate, if poor, optimum)
    for (k, &i) in fidx.iter().enumerate() {
        let range = from_u(&specs[i], hi[k]) - from_u(&specs[i], lo[k]);
        for s in [&mut sigma_p, &mut sigma_cov] {
            if !ns.resolved[k] {
                // along a symmetry: no sigma from the covariance on the resolved directions
                s[i] = f64::INFINITY;
            }
            if range.is_finite() && (s[i].is_nan() || s[i] > range) {
                s[i] = range;
            }
        }
        // a sigma that fills the whole allowed range, or one that is not positive, is no
        // measurement of the parameter: it is reported unresolved, never as `+- range` or
        // `+- 0` (issue 48)
        if (range.is_finite() && sigma_p[i] >= range) || sigma_p[i].is_nan() || sigma_p[i] <= 0.0 {
            resolved[i] = false;
        }
    }
    let finite = chi2.is_finite()
        && sig.is_finite()
        && sig > 0.0
        && p.iter().all(|v| v.is_finite())
        && pred.iter().all(|v| v.is_finite())
        && sigma_p
            .iter()
            .zip(&resolved)
            .all(|(v, r)| v.is_finite() || !r);
    if !finite {
        return Err(FitError::input(
            &prep.dataset.name,
            0,
            format!(
                "the fit of {} gave non-finite values (chi-square {chi2:e}, noise {sig:e}); \
                 the data or the constraints overflow the model's arithmetic",
                model
                    .effects
                    .iter()
                    .map(|e| e.name())
                    .collect::<Vec<_>>()
                    .join("+")
            ),
        ));
    }
    let combinations =
        crate::identify::combinations(model, &p, fidx, &ns, inflate, &prep.dataset.known);
    Ok(FitOutcome {
        model: model.clone(),
        p,
        free: pb.free.clone(),
        sigma_p,
        sigma_cov,
        corr,
        pred,
        chi2,
        n,
        n_free,
        starts: n_starts,
        sigma: sig,
        sigma_source,
        half_log_det_2pi_cov,
        log_prior_volume,
        step_ratio,
        combinations,
        resolved,
        symmetries: ns.symmetries,
        held: Vec::new(),
    })
}

/// `ln det a` of a symmetric positive-definite matrix (scaled to unit diagonal, then its
/// eigenvalues); `None` when it is singular to the precision of [`invert_spd`]'s cut.
fn log_det_spd(a: &DMatrix<f64>) -> Option<f64> {
    let n = a.nrows();
    if n == 0 {
        return Some(0.0);
    }
    let d: Vec<f64> = (0..n).map(|k| a[(k, k)].max(1e-300).sqrt()).collect();
    let s = DMatrix::from_fn(n, n, |i, j| a[(i, j)] / (d[i] * d[j]));
    let eig = crate::numeric::linalg::sym_eigen(s)?;
    let max = eig.eigenvalues.iter().cloned().fold(0.0, f64::max);
    let mut ld = d.iter().map(|v| 2.0 * v.ln()).sum::<f64>();
    for &lam in eig.eigenvalues.iter() {
        if !(lam > max * 1e-15 && lam > 0.0) {
            return None;
        }
        ld += lam.ln();
    }
    ld.is_finite().then_some(ld)
}

/// Most refinements restarted from a point a profile found below the best fit.
const PROFILE_RESTARTS: usize = 2;

/// Doublings of the profile step (up to 16 covariance sigmas).
const PROFILE_DOUBLINGS: usize = 5;

/// Inverse of a symmetric positive semi-definite matrix; a singular direction gets an infinite
/// variance rather than the pseudo-inverse's optimistic zero.
fn invert_spd(a: &DMatrix<f64>) -> DMatrix<f64> {
    let n = a.nrows();
    if n == 0 {
        return DMatrix::zeros(0, 0);
    }
    // scale to unit diagonal for conditioning
    let d: Vec<f64> = (0..n).map(|k| a[(k, k)].max(1e-300).sqrt()).collect();
    let s = DMatrix::from_fn(n, n, |i, j| a[(i, j)] / (d[i] * d[j]));
    let Some(eig) = crate::numeric::linalg::sym_eigen(s.clone()) else {
        // not finite: no covariance (every sigma unresolved)
        return DMatrix::from_element(n, n, f64::NAN);
    };
    let max = eig.eigenvalues.iter().cloned().fold(0.0, f64::max);
    let mut inv = DMatrix::zeros(n, n);
    for k in 0..n {
        let lam = eig.eigenvalues[k];
        let li = if lam > max * 1e-15 && lam > 0.0 {
            1.0 / lam
        } else {
            1e30
        };
        let v = eig.eigenvectors.column(k);
        inv += v * v.transpose() * li;
    }
    DMatrix::from_fn(n, n, |i, j| inv[(i, j)] / (d[i] * d[j]))
}
