//! The least-squares problem of one fit: free parameters, their bounds in the fit's
//! coordinates, and the whitened, normalised residual over a window of the record.

use geodesic_facility::{Model, ParamSpec};
use rayon::prelude::*;

use super::FitOptions;
use crate::coords::{check_bound, check_value, from_u};
use crate::error::FitError;
use crate::numeric::lm::Residuals;
use crate::prepare::Prepared;

/// The least-squares problem of one fit (stage "data and constraints"): the model, which
/// parameters are free, their bounds in the fit's coordinates (log for the log-fitted ones),
/// and the whitened, normalised residual ([`Prepared::normalise`]).
pub(super) struct Problem<'a> {
    pub(super) prep: &'a Prepared,
    pub(super) model: &'a Model,
    pub(super) specs: Vec<ParamSpec>,
    pub(super) names: Vec<String>,
    /// Values of the parameters that are not free (and the default start).
    pub(super) base: Vec<f64>,
    /// Which parameters are free.
    pub(super) free: Vec<bool>,
    /// Indices of the free parameters.
    pub(super) fidx: Vec<usize>,
    /// Bounds of the free parameters in the fit's coordinates.
    pub(super) lo: Vec<f64>,
    pub(super) hi: Vec<f64>,
    pub(super) t: &'a [f64],
    pub(super) data: &'a [f64],
    pub(super) sigma: f64,
    /// The observer of the fit's options (progress and debug lines).
    pub(super) obs: &'a dyn crate::numeric::observe::Observer,
}

impl<'a> Problem<'a> {
    /// Checks the options against the model and sets up the free parameters and their bounds
    /// (a user bound replaces the built-in range).
    pub(super) fn new(
        prep: &'a Prepared,
        model: &'a Model,
        opts: &'a FitOptions,
    ) -> Result<Self, FitError> {
        let specs = model.specs();
        let names = model.param_names();
        let np = specs.len();
        for k in opts.fixed.keys().chain(opts.bounds.keys()) {
            if !names.contains(k) {
                return Err(FitError::input(
                    &prep.dataset.name,
                    0,
                    format!(
                        "parameter `{k}` is not in the model (parameters: {})",
                        names.join(", ")
                    ),
                ));
            }
        }
        for (k, v) in &opts.fixed {
            let i = model.index(k).expect("checked");
            check_value(&specs[i], k, *v).map_err(|c| {
                FitError::input(&prep.dataset.name, 0, format!("--fix {k}={v}: {c}"))
            })?;
        }
        for (k, (bl, bh)) in &opts.bounds {
            let i = model.index(k).expect("checked");
            check_bound(&specs[i], *bl, *bh).map_err(|c| {
                FitError::input(&prep.dataset.name, 0, format!("--bound {k}={bl}:{bh}: {c}"))
            })?;
        }
        let superseded = model.superseded();
        let mut free = vec![true; np];
        for i in superseded {
            free[i] = false;
        }
        let mut base = model.nominal();
        for (k, v) in &opts.fixed {
            let i = model.index(k).expect("checked");
            free[i] = false;
            base[i] = *v;
        }
        let fidx: Vec<usize> = (0..np).filter(|i| free[*i]).collect();
        let mut lo = Vec::new();
        let mut hi = Vec::new();
        for &i in &fidx {
            // a user bound replaces the built-in range of that parameter (wider or narrower)
            let (l, h) = opts
                .bounds
                .get(&names[i])
                .copied()
                .unwrap_or((specs[i].lower, specs[i].upper));
            let (ul, uh) = if specs[i].log {
                (l.max(1e-300).ln(), h.ln())
            } else {
                (l / specs[i].scale, h / specs[i].scale)
            };
            lo.push(ul);
            hi.push(uh);
        }
        Ok(Problem {
            prep,
            model,
            specs,
            names,
            base,
            free,
            fidx,
            lo,
            hi,
            t: &prep.dataset.t,
            data: prep.data(),
            sigma: prep.sigma,
            obs: &*opts.observer,
        })
    }

    /// The full parameter vector of free values `u` (fit coordinates) over `start`.
    pub(super) fn full(&self, u: &[f64], start: &[f64]) -> Vec<f64> {
        let mut p = start.to_vec();
        for (k, &i) in self.fidx.iter().enumerate() {
            p[i] = from_u(&self.specs[i], u[k]);
        }
        p
    }

    /// Residuals over the first `n_use` samples (a time window, for continuation), whitened by
    /// the noise model when it is coloured and normalised by the noise.
    pub(super) fn resid_n(&self, u: &[f64], start: &[f64], n_use: usize) -> Vec<f64> {
        let p = self.full(u, start);
        // the prediction's buffer becomes the residual: one allocation per evaluation
        let mut r = self.model.predict(&p, &self.t[..n_use], &self.prep.inputs);
        for (m, d) in r.iter_mut().zip(self.data) {
            *m -= d;
        }
        self.prep.normalise(&mut r, self.sigma);
        r
    }

    /// Residuals over the whole record.
    pub(super) fn resid(&self, u: &[f64], start: &[f64]) -> Vec<f64> {
        self.resid_n(u, start, self.t.len())
    }

    /// The exact Jacobian of [`Problem::resid_n`] at `u` (the model's forward sensitivities,
    /// [`Model::tangents`], through the parameters' coordinates and the noise
    /// model's normalisation, both linear in the residuals), if the model has one.
    pub(super) fn jacobian_n(
        &self,
        u: &[f64],
        start: &[f64],
        n_use: usize,
    ) -> Option<Vec<Vec<f64>>> {
        let p = self.full(u, start);
        let tangents = self
            .model
            .tangents(&p, &self.fidx, &self.t[..n_use], &self.prep.inputs)?;
        Some(
            tangents
                .into_iter()
                .zip(&self.fidx)
                .map(|(mut col, &i)| {
                    // d p / d u: p = exp(u) (log) or u * scale
                    let dp_du = if self.specs[i].log {
                        p[i]
                    } else {
                        self.specs[i].scale
                    };
                    for v in col.iter_mut() {
                        *v *= dp_du;
                    }
                    self.prep.normalise(&mut col, self.sigma);
                    col
                })
                .collect(),
        )
    }

    /// [`Problem::resid_n`] at each point of `us`, the same bits: in groups of the model's
    /// [`Model::lanes`] (evaluated together in one thread), the groups spread over threads.
    pub(super) fn resid_many(&self, us: &[Vec<f64>], start: &[f64], n_use: usize) -> Vec<Vec<f64>> {
        let lanes = self.model.lanes();
        if lanes <= 1 || us.len() <= 1 {
            return us
                .par_iter()
                .map(|u| self.resid_n(u, start, n_use))
                .collect();
        }
        let ps: Vec<Vec<f64>> = us.iter().map(|u| self.full(u, start)).collect();
        self.resid_of_many(&ps, n_use)
    }

    /// The residuals over the first `n_use` samples at each full parameter vector of `ps`
    /// (each the bits of [`Problem::resid_n`] at it), in groups of the model's lanes, the
    /// groups spread over threads.
    pub(super) fn resid_of_many(&self, ps: &[Vec<f64>], n_use: usize) -> Vec<Vec<f64>> {
        self.model
            .predict_in_lanes(ps, &self.t[..n_use], &self.prep.inputs)
            .into_iter()
            .map(|mut r| {
                for (m, d) in r.iter_mut().zip(self.data) {
                    *m -= d;
                }
                self.prep.normalise(&mut r, self.sigma);
                r
            })
            .collect()
    }

    /// The residuals over `start` on the first `n_use` samples, as a [`Residuals`] whose sets
    /// of points the model evaluates together.
    pub(super) fn window<'p>(&'p self, start: &'p [f64], n_use: usize) -> Window<'p, 'a> {
        Window {
            pb: self,
            start,
            n_use,
        }
    }
}

/// A profile point's residuals: the free parameters but the `k`-th, which is held at `uk`.
pub(super) struct Profiled<'p, 'a> {
    pub(super) window: Window<'p, 'a>,
    pub(super) k: usize,
    pub(super) uk: f64,
}

impl Profiled<'_, '_> {
    pub(super) fn with_held(&self, v: &[f64]) -> Vec<f64> {
        let mut w = v.to_vec();
        w.insert(self.k, self.uk);
        w
    }
}

impl Residuals for Profiled<'_, '_> {
    fn eval(&self, v: &[f64]) -> Vec<f64> {
        self.window.eval(&self.with_held(v))
    }
    fn eval_many(&self, vs: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let ws: Vec<Vec<f64>> = vs.iter().map(|v| self.with_held(v)).collect();
        self.window.eval_many(&ws)
    }
    fn has_jacobian(&self) -> bool {
        self.window.has_jacobian()
    }
    fn jacobian(&self, v: &[f64]) -> Option<Vec<Vec<f64>>> {
        // the window's columns but the held parameter's
        let mut cols = self.window.jacobian(&self.with_held(v))?;
        cols.remove(self.k);
        Some(cols)
    }
}

/// [`Problem::window`].
pub(super) struct Window<'p, 'a> {
    pub(super) pb: &'p Problem<'a>,
    pub(super) start: &'p [f64],
    pub(super) n_use: usize,
}

impl Residuals for Window<'_, '_> {
    fn eval(&self, u: &[f64]) -> Vec<f64> {
        self.pb.resid_n(u, self.start, self.n_use)
    }
    fn eval_many(&self, us: &[Vec<f64>]) -> Vec<Vec<f64>> {
        self.pb.resid_many(us, self.start, self.n_use)
    }
    fn has_jacobian(&self) -> bool {
        self.pb.model.has_tangents(self.pb.fidx.len())
    }
    fn jacobian(&self, u: &[f64]) -> Option<Vec<Vec<f64>>> {
        self.pb.jacobian_n(u, self.start, self.n_use)
    }
}

pub(super) fn lo_of(lo: &[f64], i: usize, fidx: &[usize]) -> f64 {
    fidx.iter()
        .position(|&f| f == i)
        .map_or(f64::NEG_INFINITY, |k| lo[k])
}

pub(super) fn hi_of(hi: &[f64], i: usize, fidx: &[usize]) -> f64 {
    fidx.iter()
        .position(|&f| f == i)
        .map_or(f64::INFINITY, |k| hi[k])
}
