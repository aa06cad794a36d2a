//! The search of a fit (`super::fit_model_on`'s stages "start values", "search", "refine" and
//! "canonical forms"): every start screened by its cost, successive halving of short
//! Levenberg-Marquardt runs on growing windows of the record, long runs from the survivors
//! (those that cannot win stopped early), and the effects' equivalent canonical forms.

use rayon::prelude::*;

use super::{FitOptions, Problem, hi_of, lo_of, to_u};
use crate::numeric::lm::{LmOptions, LmRun, minimize};

/// An equivalent canonical form is kept when its chi-square is at most this much above the
/// best (2 sigma for one degree of freedom: the two forms differ only in how they absorb noise).
const CANONICAL_TOLERANCE: f64 = 4.0;

/// Starts added to the screened ones for their cost on the whole record (windowed stages).
const SCREEN_FULL: usize = 8;

/// Number of screened starts that get a short Levenberg-Marquardt run.
const SCREEN_KEEP: usize = 32;

/// The stages, refinement iterations and stage windows of a model's fits: its scenario's
/// [`SearchHints`](geodesic_facility::scenario::SearchHints) (fixed per scenario:
/// deterministic).
pub(super) fn effort(model: &geodesic_facility::Model) -> geodesic_facility::scenario::SearchHints {
    model.scenario.search()
}

/// Stage "start values": the given starts of the right length (the problem's base when none),
/// at most `max_starts`, with the fixed values and superseded parameters imposed, duplicates
/// dropped.
pub(super) fn start_values(pb: &Problem, opts: &FitOptions, starts: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let (model, specs, names, base) = (pb.model, &pb.specs, &pb.names, &pb.base);
    let np = specs.len();
    let mut starts: Vec<Vec<f64>> = starts.iter().filter(|s| s.len() == np).cloned().collect();
    if starts.is_empty() {
        starts.push(base.clone());
    }
    if let Some(cap) = opts.max_starts {
        starts.truncate(cap.max(1));
    }
    // fixed values override every start; superseded parameters take their nominal value;
    // starts that no longer differ are dropped
    for s in &mut starts {
        for (k, v) in &opts.fixed {
            s[model.index(k).expect("checked")] = *v;
        }
        for &i in &model.superseded() {
            if !opts.fixed.contains_key(&names[i]) {
                s[i] = specs[i].nominal;
            }
        }
    }
    let mut seen: Vec<Vec<u64>> = Vec::new();
    starts.retain(|s| {
        let key: Vec<u64> = s.iter().map(|v| v.to_bits()).collect();
        if seen.contains(&key) {
            false
        } else {
            seen.push(key);
            true
        }
    });
    starts
}

/// Stage "search": screen every start by its cost and run the successive-halving stages of
/// short Levenberg-Marquardt runs (on early windows of the record, then the whole); with
/// `refine_only`, the first start alone, clamped to the bounds. Returns (start, cost, u) of
/// the points to refine.
pub(super) fn search(
    pb: &Problem,
    starts: &[Vec<f64>],
    refine_only: bool,
) -> Vec<(usize, f64, Vec<f64>)> {
    let (specs, fidx, lo, hi) = (&pb.specs, &pb.fidx, &pb.lo, &pb.hi);
    let model = pb.model;
    let t = pb.t;
    let full = |u: &[f64], start: &[f64]| pb.full(u, start);
    let hints = effort(model);
    let (stages, windows, also_full) = (hints.stages, hints.windows, hints.stages_on_whole_record);
    let debug = pb.obs.debugging();
    // sample count of a window: the pre-trigger samples plus a fraction of the record after
    let i0 = t.iter().position(|v| *v >= 0.0).unwrap_or(0);
    let n_window = |frac: f64| -> usize {
        let post = t.len() - i0;
        (i0 + ((post as f64 * frac).ceil() as usize).max(20)).min(t.len())
    };
    if refine_only {
        // the search was made on the reduced record: refine its result only
        let u0: Vec<f64> = fidx
            .iter()
            .map(|&i| to_u(&specs[i], starts[0][i]).clamp(lo_of(lo, i, fidx), hi_of(hi, i, fidx)))
            .collect();
        vec![(0, f64::INFINITY, u0)]
    } else {
        // screen every start by its cost, run a short LM from the best few distinct ones
        // each start at its clamped values, all evaluated as one set (the model's lanes)
        let clamped: Vec<Vec<f64>> = starts
            .iter()
            .map(|s| {
                let u0: Vec<f64> = fidx
                    .iter()
                    .map(|&i| to_u(&specs[i], s[i]).clamp(lo_of(lo, i, fidx), hi_of(hi, i, fidx)))
                    .collect();
                full(&u0, s)
            })
            .collect();
        let cost = |r: Vec<f64>| -> f64 {
            let c: f64 = r.iter().map(|v| v * v).sum();
            if c.is_finite() { c } else { f64::INFINITY }
        };
        let screened: Vec<(usize, f64)> = pb
            .resid_of_many(&clamped, n_window(windows[0]))
            .into_iter()
            .map(cost)
            .enumerate()
            .collect();
        let mut sorted = screened;
        sorted.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        let mut order = keep_screened(model, starts, &sorted);
        // the cost of every start on the whole record (only needed when the stages are windowed)
        let full_costs: Vec<(usize, f64)> = if windows[0] < 1.0 {
            pb.resid_of_many(&clamped, t.len())
                .into_iter()
                .map(cost)
                .enumerate()
                .collect()
        } else {
            Vec::new()
        };
        // a windowed screen judges starts on the early record only: the best few on the whole
        // record join them
        let mut by_full = full_costs.clone();
        by_full.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        for &(si, c) in by_full.iter().take(SCREEN_FULL) {
            if !order.iter().any(|&(sj, _)| sj == si) {
                order.push((si, c));
            }
        }
        // successive halving: a few iterations from every kept start, more from the best ones
        let initial = |list: &[(usize, f64)]| -> Vec<(usize, f64, Vec<f64>)> {
            list.iter()
                .map(|&(si, c)| {
                    let u0: Vec<f64> = fidx
                        .iter()
                        .map(|&i| to_u(&specs[i], starts[si][i]))
                        .collect();
                    (si, c, u0)
                })
                .collect()
        };
        let run_stages = |first: Vec<(usize, f64, Vec<f64>)>, windows: [f64; 2]| {
            run_stages(pb, starts, &stages, &n_window, first, windows, debug)
        };
        let mut first = run_stages(initial(&order), windows);
        if windows[0] < 1.0 && also_full {
            // and the same stages on the whole record from the starts that fit it best
            let mut top: Vec<(usize, f64)> = Vec::new();
            for &(si, c) in &by_full {
                if top.len() >= SCREEN_KEEP {
                    break;
                }
                top.push((si, c));
            }
            first.extend(run_stages(initial(&top), [1.0, 1.0]));
        }
        // the start that fits the whole record best also gets a full run (with a windowed screen
        // it may have been dropped; e.g. a candidate at its null values, i.e. the baseline)
        if windows[0] < 1.0
            && let Some(&(si, c)) = full_costs
                .iter()
                .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
        {
            if pb.obs.debugging() {
                pb.obs.debug(&|| {
                    format!("best full-record start {si} {:?}: cost {c:.2}", &starts[si])
                });
            }
            // from its own values, not from where the windowed stages moved it
            let u0: Vec<f64> = fidx
                .iter()
                .map(|&i| {
                    to_u(&specs[i], starts[si][i]).clamp(lo_of(lo, i, fidx), hi_of(hi, i, fidx))
                })
                .collect();
            first.push((si, c, u0));
        }
        first
    }
}

/// The screened starts (`sorted`: (start, cost), best first) kept for the stages: the best
/// start for each distinct starting value of the first effect's parameters (the base of the
/// model, whose basins differ most), best first, so that one basin cannot fill every slot;
/// then the next best overall, up to [`SCREEN_KEEP`].
fn keep_screened(
    model: &geodesic_facility::Model,
    starts: &[Vec<f64>],
    sorted: &[(usize, f64)],
) -> Vec<(usize, f64)> {
    // keep the best start for each distinct starting value of the first effect's parameters
    // (the base of the model, whose basins differ most), best first, so that one basin cannot
    // fill every slot
    let first_len = model.range(0).len();
    let mut order: Vec<(usize, f64)> = Vec::new();
    for &(si, c) in sorted {
        if order.len() >= SCREEN_KEEP {
            break;
        }
        let key = &starts[si][..first_len];
        if !order.iter().any(|&(sj, _)| &starts[sj][..first_len] == key) {
            order.push((si, c));
        }
    }
    // then fill up with the next best overall
    for &(si, c) in sorted {
        if order.len() >= SCREEN_KEEP {
            break;
        }
        if !order.iter().any(|&(sj, _)| sj == si) {
            order.push((si, c));
        }
    }
    order
}

/// The successive-halving stages (`stages`, on the windows `windows` of the record, sample
/// counts from `n_window`) of short Levenberg-Marquardt runs from `first` ((start, cost, u)),
/// the best `keep` of each stage going on; returns the survivors, best first.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn run_stages(
    pb: &Problem,
    starts: &[Vec<f64>],
    stages: &[(usize, usize); 2],
    n_window: &dyn Fn(f64) -> usize,
    mut first: Vec<(usize, f64, Vec<f64>)>,
    windows: [f64; 2],
    debug: bool,
) -> Vec<(usize, f64, Vec<f64>)> {
    let (lo, hi) = (&pb.lo, &pb.hi);
    let full = |u: &[f64], start: &[f64]| pb.full(u, start);
    for (&(iters, keep), &frac) in stages.iter().zip(&windows) {
        let n_use = n_window(frac);
        let opts_stage = LmOptions {
            max_iter: iters,
            observer: pb.obs,
            ..LmOptions::default()
        };
        let t0 = std::time::Instant::now();
        let nfirst = first.len();
        first = if iters > STAGE_ROUND {
            // in rounds, the runs that cannot reach the `keep` best stopped (the same survivors)
            in_rounds(
                pb,
                starts,
                &first,
                &opts_stage,
                n_use,
                keep,
                STAGE_ROUND,
                debug,
            )
        } else {
            first
                .par_iter()
                .map(|(si, _, u)| {
                    let r = minimize(&pb.window(&starts[*si], n_use), u, lo, hi, &opts_stage);
                    (*si, r.cost, r.u)
                })
                .collect()
        };
        first.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        if debug {
            pb.obs.debug(&|| {
                format!(
                    "stage {iters} (window {frac}): {nfirst} runs in {:.3} s",
                    t0.elapsed().as_secs_f64()
                )
            });
        }
        if debug {
            for (si, c, u) in &first {
                let p = full(u, &starts[*si]);
                pb.obs.debug(&|| {
                    format!(
                        "stage {iters} (window {frac}): start {si} {:?} -> cost {c:.2} at {p:?}",
                        &starts[*si]
                    )
                });
            }
        }
        first.truncate(keep);
    }
    first
}

/// Iterations of a round of [`refine`]: between rounds, the runs that cannot catch up with
/// the best are stopped.
const ROUND: usize = 20;

/// Iterations of a round of a successive-halving stage longer than one round ([`run_stages`]):
/// between rounds, the runs that cannot reach the stage's survivors are stopped.
const STAGE_ROUND: usize = 10;

/// How much faster than over its last round a run is assumed to keep descending when
/// [`in_rounds`] judges whether it can still reach the runs kept.
const CATCH_UP_FACTOR: f64 = 4.0;

/// Stage "refine": a long Levenberg-Marquardt run (`long_iter` iterations, ftol 1e-9) from each
/// searched point on the whole record; returns (start, cost, u) of each ([`in_rounds`], the
/// lowest kept: a third of the refinement was the crawl of runs that could not win,
/// FAC-FIT-QUAL's fits, 2026-11-26).
pub(super) fn refine(
    pb: &Problem,
    starts: &[Vec<f64>],
    first: &[(usize, f64, Vec<f64>)],
    long_iter: usize,
    debug: bool,
) -> Vec<(usize, f64, Vec<f64>)> {
    let opts = LmOptions {
        max_iter: long_iter,
        ftol: 1e-9,
        observer: pb.obs,
        ..LmOptions::default()
    };
    in_rounds(pb, starts, first, &opts, pb.t.len(), 1, ROUND, debug)
}

/// Levenberg-Marquardt runs (`opts`, on the first `n_use` samples) from each point of `first`
/// ((start, cost, u)), of which the `keep` lowest are wanted; returns (start, cost, u) of each.
///
/// The runs advance side by side in rounds of `round` iterations (the iterates of
/// uninterrupted runs: [`LmRun`]). After each round a run above the `keep`-th lowest cost met
/// so far stops when, descending [`CATCH_UP_FACTOR`] times faster than it did over that round
/// for every iteration it has left, it would still end above it (by 1 % and one unit): it
/// cannot be among the runs kept. The runs kept, the `keep` lowest, are the same, with the
/// same bits, as without the rounds, unless a stopped run would have overtaken one of them by
/// descending faster than that (costs only fall, so the `keep`-th lowest at the end is at most
/// the one judged against). A stopped run is returned at the cost where it stopped.
#[allow(clippy::too_many_arguments)]
fn in_rounds(
    pb: &Problem,
    starts: &[Vec<f64>],
    first: &[(usize, f64, Vec<f64>)],
    opts: &LmOptions,
    n_use: usize,
    keep: usize,
    round: usize,
    debug: bool,
) -> Vec<(usize, f64, Vec<f64>)> {
    let (lo, hi) = (&pb.lo, &pb.hi);
    // (start, run, cost at the start of the round, still advancing)
    let mut runs: Vec<(usize, LmRun, f64, bool)> = first
        .par_iter()
        .map(|(si, _, u)| {
            let run = LmRun::new(&pb.window(&starts[*si], n_use), u, lo, hi, opts, None);
            let c = run.cost();
            (*si, run, c, true)
        })
        .collect();
    let mut done = 0;
    while done < opts.max_iter && runs.iter().any(|r| r.3) {
        done = (done + round).min(opts.max_iter);
        runs.par_iter_mut().filter(|r| r.3).for_each(|r| {
            r.2 = r.1.cost();
            r.1.advance(&pb.window(&starts[r.0], n_use), lo, hi, opts, done);
        });
        // the keep-th lowest cost met so far (infinite while fewer runs)
        let mut costs: Vec<f64> = runs.iter().map(|r| r.1.cost()).collect();
        costs.sort_by(f64::total_cmp);
        let bar = costs.get(keep.max(1) - 1).copied().unwrap_or(f64::INFINITY);
        let left = (opts.max_iter - done) as f64;
        for r in runs.iter_mut().filter(|r| r.3) {
            if r.1.finished() {
                r.3 = false;
                continue;
            }
            let rate = (r.2 - r.1.cost()).max(0.0) / round as f64;
            let reach = r.1.cost() - CATCH_UP_FACTOR * rate * left;
            if reach > bar * 1.01 + 1.0 {
                r.3 = false;
                if debug {
                    pb.obs.debug(&|| format!(
                        "run from start {} ({} iterations at most) stopped after {} iterations at cost {:.3} (bar {bar:.3})",
                        r.0,
                        opts.max_iter,
                        r.1.iterations(),
                        r.1.cost()
                    ));
                }
            }
        }
    }
    runs.into_iter()
        .map(|(si, run, _, _)| {
            if debug {
                pb.obs.debug(&|| {
                    format!(
                        "run from start {si} ({} iterations at most): {} iterations, cost {:.3}",
                        opts.max_iter,
                        run.iterations(),
                        run.cost()
                    )
                });
            }
            let r = run.result();
            (si, r.cost, r.u)
        })
        .collect()
}

/// Stage "canonical forms": an effect may re-express its fitted values equivalently (same
/// number of parameters); the alternative is refitted and kept when it fits as well (within
/// [`CANONICAL_TOLERANCE`] in chi-square). Returns the kept (cost, u).
pub(super) fn canonical_forms(
    pb: &Problem,
    start: &[f64],
    chi2: f64,
    u: Vec<f64>,
    long_iter: usize,
) -> (f64, Vec<f64>) {
    let (specs, fidx, lo, hi) = (&pb.specs, &pb.fidx, &pb.lo, &pb.hi);
    let model = pb.model;
    let full = |u: &[f64], start: &[f64]| pb.full(u, start);
    // canonical forms: an effect may re-express its fitted values equivalently (same number of
    // parameters); the alternative is refitted and kept when it fits as well (within 1 in chi2)
    let (mut chi2, mut u) = (chi2, u);
    for _ in 0..3 {
        let p = full(&u, start);
        let mut changed = false;
        for (ei, e) in model.effects.iter().enumerate() {
            for alt in e.hints().alternatives(&p[model.range(ei)]) {
                let mut pa = p.clone();
                pa[model.range(ei)].copy_from_slice(&alt);
                let ua: Vec<f64> = fidx
                    .iter()
                    .map(|&i| to_u(&specs[i], pa[i]).clamp(lo_of(lo, i, fidx), hi_of(hi, i, fidx)))
                    .collect();
                let long = LmOptions {
                    max_iter: long_iter,
                    ftol: 1e-9,
                    observer: pb.obs,
                    ..LmOptions::default()
                };
                let r = minimize(&pb.window(start, pb.t.len()), &ua, lo, hi, &long);
                if pb.obs.debugging() {
                    pb.obs.debug(&|| {
                        format!(
                            "alternative of {}: {alt:?} -> cost {:.2} (best {chi2:.2})",
                            e.name(),
                            r.cost
                        )
                    });
                }
                if r.cost <= chi2 + CANONICAL_TOLERANCE {
                    chi2 = r.cost.min(chi2);
                    u = r.u;
                    changed = true;
                    break;
                }
            }
            if changed {
                break;
            }
        }
        if !changed {
            break;
        }
    }
    (chi2, u)
}
