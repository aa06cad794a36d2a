//! Terms outside the catalogue: which kind of physics the residual of a fit still holds.
//!
//! For every kind of missing physics the catalogue does not hold, a shape `s(t)` (one or two
//! columns, with at most one scanned parameter) is what that physics would add to the fitted
//! channel to first order. The fit can absorb part of any shape by moving its own parameters, so
//! each shape is first projected out of the span of the fit's Jacobian at the optimum (the
//! columns `d pred / d u` of the free parameters, finite differences); the rest is regressed on
//! the residual. All of it happens on the residual and the shapes whitened and normalised as the
//! fit sees them (the dataset's noise model, the fit's noise figure), so that
//!
//! `delta chi2 = b^T G^-1 b`, `b = S_perp^T r`, `G = S_perp^T S_perp`
//!
//! is the chi-square the term would remove (the score test of adding it), and the coefficient
//! `G^-1 b` has the 1-sigma `sqrt(diag G^-1)`. A kind's `delta_bic` is
//! `-delta chi2 + k ln N` with `k` its coefficients plus its scanned parameter: negative values
//! favour the term. The kinds, in the channel `x` the fit reads (the TM for `tmmf-release`, the
//! tip for `rt-retraction`), with `t` the time since the trigger and the integrals from it:
//!
//! | kind | shape | coefficient | parameter |
//! | --- | --- | --- | --- |
//! | `position` (spring, pendulum mode) | `int int x` | `-w0^2` [1/s^2] | `f0 = w0 / 2 pi` [Hz] |
//! | `velocity` (damping) | `int int dx/dt` | `-gamma` [1/s] | `gamma` [1/s] |
//! | `delay` (timing) | `-dx/dt` (whole record) | delay [s] | delay [s] |
//! | `creep` (piezo creep, relaxation) | `ln(1 + t / tau)` | [m] | `tau` [s], scanned |
//! | `slip` (a jump of the contact point) | `H(t - t0)` | [m] | `t0` [s], scanned |
//! | `impulse` (a knock, a sudden release) | `(t - t0)+` | [m/s] | `t0` [s], scanned |
//! | `vibration` (floor, stand) | `sin, cos(2 pi f t)` (whole record) | amplitude [m] | `f` [Hz], scanned |
//!
//! Scans run on a grid and zoom in around the best point; the frequency grid covers the whole
//! band at a quarter of the record's resolution for records up to 4 096 samples, else the low
//! band (up to 64 / record length) and the periodogram's peaks.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::coords::{from_u, to_u};
use crate::estimate::FitOutcome;
use crate::numeric::lm::LmOptions;
use crate::numeric::observe::Observer;
use crate::prepare::Prepared;

mod basis;
pub mod pairs;
pub use basis::Basis;
use basis::dot;

/// A spectral peak of the residual.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct Peak {
    /// Channel.
    pub channel: String,
    /// Frequency [Hz].
    pub hz: f64,
    /// Amplitude of the equivalent sinusoid [channel unit, SI].
    pub amplitude: f64,
    /// Power over the median power of the periodogram.
    pub over_floor: f64,
}

/// Correlation of the residual with a state of the model.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct StateCorrelation {
    /// The state.
    pub state: String,
    /// Pearson correlation coefficient.
    pub r: f64,
}

/// The scanned or derived parameter of a term.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct TermParameter {
    /// Name (`f0`, `gamma`, `delay`, `tau`, `t0`, `f`).
    pub name: String,
    /// Value [unit].
    pub value: f64,
    /// Unit.
    pub unit: String,
}

/// A kind of missing physics fitted to the residual.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct KindFit {
    /// Kind (`position`, `velocity`, `delay`, `creep`, `slip`, `impulse`, `vibration`).
    pub kind: String,
    /// The state variable or time dependence it acts on.
    pub state: String,
    /// The term in words, with its parameter.
    pub term: String,
    /// Coefficient [`coefficient_unit`] (the amplitude for a vibration).
    pub coefficient: f64,
    /// Its 1-sigma.
    pub sigma: f64,
    /// Unit of the coefficient.
    pub coefficient_unit: String,
    /// The physical parameter it implies.
    pub parameter: Option<TermParameter>,
    /// Chi-square the term removes (score test, after the fit's own freedom).
    pub delta_chi2: f64,
    /// `-delta_chi2 + k ln N`: negative favours the term.
    pub delta_bic: f64,
    /// The term's raw columns [SI per unit coefficient] (not serialised).
    #[serde(skip)]
    pub shape: Vec<Vec<f64>>,
    /// Their coefficients (not serialised).
    #[serde(skip)]
    pub coefs: Vec<f64>,
    /// The shift of a `delay` term's column [s] (its delay is `coefs[0] * scan`; not serialised).
    #[serde(skip)]
    pub scan: f64,
}

/// The sine and cosine of frequency `f` [Hz] at times `t` [s]: a vibration's two columns.
///
/// Sine and cosine of each phase in one call (`sin_cos`, glibc's `sincos`: the bits of `sin`
/// and `cos` taken apart, at about half their cost; the vibration scans' grids on a long
/// record were half trigonometry).
fn sincos(t: &[f64], f: f64) -> Vec<Vec<f64>> {
    let w = std::f64::consts::TAU * f;
    let (s, c): (Vec<f64>, Vec<f64>) = t.iter().map(|t| (w * t).sin_cos()).unzip();
    vec![s, c]
}

/// Cumulative trapezoid integral of `v` over `t` from the trigger (zero before it).
fn integ(t: &[f64], v: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; v.len()];
    for i in 1..v.len() {
        if t[i - 1] >= 0.0 {
            out[i] = out[i - 1] + 0.5 * (v[i] + v[i - 1]) * (t[i] - t[i - 1]);
        } else if t[i] > 0.0 {
            // the interval holding the trigger: from t = 0
            out[i] = v[i] * t[i];
        }
    }
    out
}

/// Maximises `f` over `[lo, hi]` (in `log` space when asked): a grid of `n` points, then zooms of
/// 16 points around the best until the spacing is below `tol` (same space). Returns the best
/// point and its value.
///
/// The points of a grid are evaluated side by side on the thread pool and then compared in
/// grid order, so the result is the one of evaluating them in turn (a 400 000-sample record's
/// 256-point vibration grid had kept one core busy for 3 s while the other waited).
fn scan(
    lo: f64,
    hi: f64,
    n: usize,
    log: bool,
    tol: f64,
    f: &(dyn Fn(f64) -> f64 + Sync),
) -> (f64, f64) {
    let (mut a, mut b) = if log { (lo.ln(), hi.ln()) } else { (lo, hi) };
    let to = |z: f64| if log { z.exp() } else { z };
    let mut best = (to(a), f64::NEG_INFINITY);
    let mut m = n.max(2);
    for _ in 0..40 {
        let h = (b - a) / (m - 1) as f64;
        let mut bz = a;
        let values: Vec<f64> = (0..m)
            .into_par_iter()
            .map(|k| f(to(a + h * k as f64)))
            .collect();
        for (k, v) in values.into_iter().enumerate() {
            let z = a + h * k as f64;
            if v > best.1 {
                best = (to(z), v);
                bz = z;
            } else if best.0 == to(z) {
                bz = z;
            }
        }
        if h <= tol {
            break;
        }
        let c = if best.1.is_finite() {
            if log { best.0.ln() } else { best.0 }
        } else {
            bz
        };
        a = (c - h).max(if log { lo.ln() } else { lo });
        b = (c + h).min(if log { hi.ln() } else { hi });
        m = 16;
    }
    best
}

/// Every kind fitted to the residual of `o`, most supported first (see the module
/// documentation). `peaks` are the periodogram's (frequencies the vibration scan also tries).
pub fn kinds<'a>(prep: &'a Prepared, o: &FitOutcome, peaks: &[Peak]) -> (Vec<KindFit>, Basis<'a>) {
    let basis = Basis::new(prep, o);
    (kinds_of(&basis, prep, o, peaks), basis)
}

/// [`kinds`] on the basis of `o` already made ([`Basis::new`]`(prep, o)`: its Jacobian is most
/// of the cost on a long record, issue 33 item 6), the same bits.
pub(crate) fn kinds_of(
    basis: &Basis,
    prep: &Prepared,
    o: &FitOutcome,
    peaks: &[Peak],
) -> Vec<KindFit> {
    let t = &prep.dataset.t;
    let n = t.len();
    if n < 16 {
        return Vec::new();
    }
    let mut dts: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    dts.sort_by(f64::total_cmp);
    let mut s = KindScan {
        basis,
        t,
        ch: prep.channel,
        x: &o.pred,
        ln_n: (o.n.max(2) as f64).ln(),
        dt: dts[dts.len() / 2],
        span: t[n - 1] - t[0],
        t_end: t[n - 1],
        out: Vec::new(),
    };
    s.state_kinds();
    // the scans are independent and read-only: side by side on the thread pool (the kinds
    // of a 400 000-sample record took 10 to 15 s on one core, issue 33 item 6), each kind
    // then pushed in the order of the sequential scan, so the same bits whatever the thread
    // count
    let scanned = s.t_end > 4.0 * s.dt;
    let (delay_best, (scanned_best, vibration_best)) = rayon::join(
        || s.delay_scan(),
        || {
            rayon::join(
                || {
                    if scanned {
                        s.scanned_scan()
                    } else {
                        Vec::new()
                    }
                },
                || s.vibration_scan(peaks),
            )
        },
    );
    let delay_d = s.delay(delay_best);
    s.scanned_kinds(scanned_best);
    s.vibration(vibration_best);
    s.finish(delay_d)
}

/// A kind with a scanned parameter ([`KindScan::scanned_specs`]): its name, the state its
/// words name, its coefficient's unit, the parameter scanned and its scan (from `lo` to `hi`
/// [s] on `grid` points, in log space when `log`, zoomed until the spacing is below `tol`).
struct ScannedSpec {
    kind: &'static str,
    state: &'static str,
    unit: &'static str,
    name: &'static str,
    lo: f64,
    hi: f64,
    grid: usize,
    log: bool,
    tol: f64,
}

/// The scan of every kind over a residual ([`kinds_of`]): the basis of the fit, the record's
/// time axis and sampling, and the kinds fitted so far.
struct KindScan<'s, 'b> {
    basis: &'s Basis<'b>,
    /// Time since the trigger [s].
    t: &'s [f64],
    /// The fitted channel.
    ch: &'s str,
    /// The model's prediction of it [SI].
    x: &'s [f64],
    /// ln N, N the samples the fit counts.
    ln_n: f64,
    /// The median sampling step [s].
    dt: f64,
    /// The record's length [s].
    span: f64,
    /// Its last time [s].
    t_end: f64,
    out: Vec<KindFit>,
}

impl KindScan<'_, '_> {
    /// Scores the kind of columns `cols` (`scanned`: with a scanned parameter) and keeps it
    /// when the score test is defined; `describe` gives its term and parameter from its
    /// coefficient [`unit`].
    fn push(
        &mut self,
        kind: &str,
        state: String,
        cols: Vec<Vec<f64>>,
        scanned: bool,
        unit: &str,
        describe: &dyn Fn(f64) -> (String, Option<TermParameter>),
    ) {
        let k = cols.len() + usize::from(scanned);
        let shape = cols.clone();
        let Some((c, s, d)) = self.basis.score(cols) else {
            return;
        };
        let coefs = c.clone();
        let (coef, sig) = if c.len() == 2 && kind != "position" {
            let a = c[0].hypot(c[1]);
            let sa = if a > 0.0 {
                ((c[0] * s[0]).powi(2) + (c[1] * s[1]).powi(2)).sqrt() / a
            } else {
                s[0]
            };
            (a, sa)
        } else {
            (c[0], s[0])
        };
        let (term, parameter) = describe(coef);
        self.out.push(KindFit {
            kind: kind.into(),
            state,
            term,
            coefficient: coef,
            sigma: sig,
            coefficient_unit: unit.into(),
            parameter,
            delta_chi2: d,
            delta_bic: -d + k as f64 * self.ln_n,
            shape,
            coefs,
            scan: 0.0,
        });
    }

    /// Forces proportional to the position (spring, pendulum) and to the velocity (damping).
    fn state_kinds(&mut self) {
        let ch = self.ch;
        for (kind, state, unit) in [
            ("position", format!("{ch} (position)"), "1/s^2"),
            ("velocity", format!("d{ch}/dt (velocity)"), "1/s"),
        ] {
            let cols = state_shape(self.t, kind, self.x, 0.0).expect("a state kind");
            self.push(kind, state, cols, false, unit, &|c| state_text(kind, ch, c));
        }
    }

    /// The scan of [`Self::delay`]: the best shift (signed) and its score over both signs.
    fn delay_scan(&self) -> (f64, f64) {
        let (t, x, dt, basis) = (self.t, self.x, self.dt, self.basis);
        let per_sign: Vec<(f64, f64)> = [1.0, -1.0]
            .into_par_iter()
            .map(|sign| {
                let b = scan(
                    0.2 * dt,
                    (0.05 * self.span).max(0.4 * dt),
                    24,
                    true,
                    0.01,
                    &|d| {
                        let cols = state_shape(t, "delay", x, sign * d).expect("a state kind");
                        basis.score(cols).map_or(f64::NEG_INFINITY, |s| s.2)
                    },
                );
                (sign * b.0, b.1)
            })
            .collect();
        let mut shift_best = (0.0, f64::NEG_INFINITY);
        for b in per_sign {
            if b.1 > shift_best.1 {
                shift_best = b;
            }
        }
        shift_best
    }

    /// A shift of the time axis by d: x(t - d) - x(t), |d| scanned from a fifth of a sample to a
    /// twentieth of the record, both signs; the delay is the coefficient times d (a coefficient
    /// of 1 for a pure shift, and any product for a shift small enough to be linear). Returns
    /// the shift scanned, when the kind was scored.
    fn delay(&mut self, shift_best: (f64, f64)) -> Option<f64> {
        let (t, x, ch) = (self.t, self.x, self.ch);
        if !shift_best.1.is_finite() {
            return None;
        }
        let d = shift_best.0;
        let cols = state_shape(t, "delay", x, d).expect("a state kind");
        self.push(
            "delay",
            "time (a shift of the time axis)".into(),
            cols,
            true,
            "s",
            &|c| state_text("delay", ch, c * d),
        );
        Some(d)
    }

    /// The scanned kinds: creep over a log grid of tau; a step in position and in velocity over
    /// t0.
    fn scanned_specs(&self) -> [ScannedSpec; 3] {
        let (dt, post) = (self.dt, self.t_end);
        let spec = |kind, state, unit, name, lo, hi, grid, log, tol| ScannedSpec {
            kind,
            state,
            unit,
            name,
            lo,
            hi,
            grid,
            log,
            tol,
        };
        [
            spec(
                "creep",
                "time since the trigger (logarithmic)",
                "m",
                "tau",
                dt,
                3.0 * post,
                24,
                true,
                0.02,
            ),
            spec(
                "slip",
                "time since the trigger (a jump)",
                "m",
                "t0",
                2.0 * dt,
                post - 2.0 * dt,
                200,
                false,
                0.5 * dt,
            ),
            spec(
                "impulse",
                "time since the trigger (a velocity jump)",
                "m/s",
                "t0",
                2.0 * dt,
                post - 2.0 * dt,
                200,
                false,
                0.5 * dt,
            ),
        ]
    }

    /// The scans of [`Self::scanned_kinds`], side by side: each kind's best parameter.
    fn scanned_scan(&self) -> Vec<f64> {
        let (t, basis) = (self.t, self.basis);
        self.scanned_specs()
            .into_par_iter()
            .map(|k| {
                let cols = |v: f64| scanned_shape(t, k.kind, v).expect("a scanned kind");
                scan(k.lo, k.hi, k.grid, k.log, k.tol, &|v| {
                    basis.score(cols(v)).map_or(f64::NEG_INFINITY, |s| s.2)
                })
                .0
            })
            .collect()
    }

    /// Creep, slip and impulse at their scanned parameters `best` (none when not scanned).
    fn scanned_kinds(&mut self, best: Vec<f64>) {
        let t = self.t;
        for (k, v) in self.scanned_specs().into_iter().zip(best) {
            let cols = scanned_shape(t, k.kind, v).expect("a scanned kind");
            self.push(k.kind, k.state.into(), cols, true, k.unit, &|c| {
                (
                    term_text(k.kind, c, v),
                    Some(TermParameter {
                        name: k.name.into(),
                        value: v,
                        unit: "s".into(),
                    }),
                )
            });
        }
    }

    /// The scan of [`Self::vibration`]: over the whole band for records up to 4 096 samples,
    /// else the low band and around the periodogram's first three `peaks`, the bands side by
    /// side; the best frequency and its score.
    fn vibration_scan(&self, peaks: &[Peak]) -> (f64, f64) {
        let (t, dt, basis) = (self.t, self.dt, self.basis);
        let score_f = |f: f64| basis.score(sincos(t, f)).map_or(f64::NEG_INFINITY, |s| s.2);
        let res = 1.0 / self.span;
        let nyq = 0.5 / dt;
        let mut bands: Vec<(f64, f64, usize)> = Vec::new();
        if t.len() <= 4096 {
            bands.push((0.5 * res, nyq, (4.0 * (nyq - 0.5 * res) / res) as usize + 2));
        } else {
            bands.push((0.5 * res, 64.0 * res, 256));
            for p in peaks.iter().take(3) {
                bands.push((p.hz - 2.0 * res, p.hz + 2.0 * res, 17));
            }
        }
        let found: Vec<Option<(f64, f64)>> = bands
            .into_par_iter()
            .map(|(lo, hi, m)| {
                let hi = hi.min(0.98 * nyq);
                (hi > lo).then(|| scan(lo, hi, m, false, 0.01 * res, &score_f))
            })
            .collect();
        let mut best = (0.0, f64::NEG_INFINITY);
        for b in found.into_iter().flatten() {
            if b.1 > best.1 {
                best = b;
            }
        }
        best
    }

    /// A vibration over the whole record at the frequency `best` scanned (none when its score
    /// is not finite).
    fn vibration(&mut self, best: (f64, f64)) {
        let t = self.t;
        if best.1.is_finite() {
            let f = best.0;
            self.push(
                "vibration",
                "time (periodic)".into(),
                sincos(t, f),
                true,
                "m",
                &|c| {
                    (
                        term_text("vibration", c, f),
                        Some(TermParameter {
                            name: "f".into(),
                            value: f,
                            unit: "Hz".into(),
                        }),
                    )
                },
            );
        }
    }

    /// The kinds, the delay's coefficient in seconds (`delay_d`, the shift scanned), each
    /// described with its offset, most supported first.
    fn finish(self, delay_d: Option<f64>) -> Vec<KindFit> {
        let mut out = self.out;
        if let Some(d) = delay_d
            && let Some(k) = out.iter_mut().find(|k| k.kind == "delay")
        {
            k.scan = d;
            k.coefficient *= d;
            k.sigma *= d.abs();
        }
        for k in out.iter_mut() {
            describe_offset(k, self.ch);
        }
        out.sort_by(|a, b| a.delta_bic.total_cmp(&b.delta_bic));
        out
    }
}

/// The model refitted, from `o`'s optimum and from its default starts, to the data less the
/// term `kind` at its score-test coefficients (what the term would be if the model had not
/// absorbed part of it): the start of [`joint_lm`]. Returns the parameters.
pub(crate) fn refit_without(
    prep: &Prepared,
    o: &FitOutcome,
    kind: &KindFit,
    opts: &crate::estimate::FitOptions,
) -> Result<Vec<f64>, crate::FitError> {
    let mut fo = opts.clone();
    fo.profile = false;
    fo.sigma = Some(o.sigma);
    let mut less = prep.clone();
    let ch = less
        .dataset
        .channels
        .get_mut(prep.channel)
        .expect("the fitted channel");
    if kind.kind == "delay" {
        // the model's time axis shifted by the delay (exact: the data are not interpolated),
        // the delay the one of a scan of the fit's own model over shifts of both signs from a
        // fifth of a sample to a twentieth of the record, the score test's beside it
        let t = &prep.dataset.t;
        let n = t.len();
        let dt = (t[n - 1] - t[0]) / (n.max(2) - 1) as f64;
        let span = t[n - 1] - t[0];
        let mut data = prep.data().to_vec();
        prep.normalise(&mut data, o.sigma);
        let cost = |d: f64| -> f64 {
            let shifted: Vec<f64> = t.iter().map(|ti| ti - d).collect();
            let mut v = o.model.predict(&o.p, &shifted, &prep.inputs);
            prep.normalise(&mut v, o.sigma);
            v.iter().zip(&data).map(|(a, b)| (a - b) * (a - b)).sum()
        };
        let (mut best_d, mut best_c) = (kind.coefficient, cost(kind.coefficient));
        let (a, b) = ((0.2 * dt).ln(), (0.05 * span).max(0.4 * dt).ln());
        for sign in [1.0, -1.0] {
            for j in 0..48 {
                let d = sign * (a + (b - a) * j as f64 / 47.0).exp();
                let c = cost(d);
                if c < best_c {
                    (best_d, best_c) = (d, c);
                }
            }
        }
        less.dataset.t = t.iter().map(|ti| ti - best_d).collect();
    } else {
        for (j, col) in kind.shape.iter().enumerate() {
            for (v, s) in ch.iter_mut().zip(col) {
                *v -= kind.coefs[j] * s;
            }
        }
    }
    let mut starts = vec![o.p.clone()];
    starts.extend(crate::estimate::default_starts(
        &o.model,
        &prep.guess,
        opts.max_starts.unwrap_or(16).min(16),
    ));
    Ok(crate::estimate::fit_model(&less, &o.model, &fo, &starts)?.p)
}

/// The term `kind` fitted jointly with the model: one local Levenberg-Marquardt run over the
/// model's free parameters (from `from`) and the term's coefficients (from `kind.coefs`), at
/// most `max_iter` Jacobians. Returns the chi-square removed from `o.chi2` (at `o.sigma`), the
/// coefficients and the model's parameters where the run ended.
pub(crate) fn joint_lm(
    prep: &Prepared,
    o: &FitOutcome,
    kind: &KindFit,
    from: &[f64],
    max_iter: usize,
    obs: &dyn Observer,
) -> JointEnd {
    let first = joint_lm_as(prep, o, kind, from, max_iter, false, obs);
    if !matches!(kind.kind.as_str(), "position" | "velocity") {
        return first;
    }
    // a force on the state to first order (the response to the model's own state) and solved
    // with the state it changes: the one that fits better stands (a strong damping is far from
    // first order; a perturbation added to first order is not a solution of the equation)
    let solved = joint_lm_as(prep, o, kind, from, max_iter, true, obs);
    if solved.0 > first.0 { solved } else { first }
}

/// [`joint_lm`] with the state kinds' term to first order or `solved` with the state.
fn joint_lm_as(
    prep: &Prepared,
    o: &FitOutcome,
    kind: &KindFit,
    from: &[f64],
    max_iter: usize,
    solved: bool,
    obs: &dyn Observer,
) -> JointEnd {
    let joint = Joint::new(prep, o, vec![kind], from);
    let opts = LmOptions {
        max_iter,
        observer: obs,
        ..LmOptions::default()
    };
    if kind.kind == "delay" && kind.scan != 0.0 {
        return joint.delay(&opts);
    }
    let r = crate::numeric::lm::minimize(
        &JointResiduals {
            joint: &joint,
            solved,
        },
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

/// A joint fit's end ([`joint_lm`]): the chi-square removed from the model's, the term's
/// coefficients and the model's parameters.
pub type JointEnd = (f64, Vec<f64>, Vec<f64>);

/// [`Joint::residual`] as the fit's residuals, several points (a Jacobian's columns) predicted
/// side by side in the model's lanes ([`Model::predict_many`](geodesic_facility::Model)):
/// the same bits as one at a time, a third of the time on a jittered retraction record, where
/// a lane alone is latency-bound.
struct JointResiduals<'a, 'b> {
    joint: &'b Joint<'a>,
    solved: bool,
}

impl crate::numeric::lm::Residuals for JointResiduals<'_, '_> {
    fn eval(&self, u: &[f64]) -> Vec<f64> {
        self.joint.residual(u, self.solved)
    }

    fn eval_many(&self, us: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let j = self.joint;
        let ps: Vec<Vec<f64>> = us.iter().map(|u| j.params(u)).collect();
        let raws =
            j.o.model
                .predict_in_lanes(&ps, &j.prep.dataset.t, &j.prep.inputs);
        raws.into_par_iter()
            .zip(us.par_iter())
            .map(|(raw, u)| j.residual_of(raw, u, self.solved))
            .collect()
    }
}

/// The joint problem of [`joint_lm_as`] (and of [`pairs`]): the model's free parameters (in
/// the fit's coordinates) followed by the terms' coefficients (each in units of the change that
/// moves chi-square by about one), the data and the terms' columns normalised at `o.sigma`.
struct Joint<'a> {
    prep: &'a Prepared,
    o: &'a FitOutcome,
    /// The first term (the only one but in [`pairs`]).
    kind: &'a KindFit,
    /// Every term, and where each one's columns end in `w`.
    terms: Vec<&'a KindFit>,
    ends: Vec<usize>,
    /// The model's parameters the free ones are put into.
    from: &'a [f64],
    /// The model's parameters' specifications.
    specs: Vec<geodesic_facility::ParamSpec>,
    /// Indices of the model's free parameters.
    fidx: Vec<usize>,
    /// Their count: the term's coefficients start at `nm` in `u`.
    nm: usize,
    /// The term's columns, normalised.
    w: Vec<Vec<f64>>,
    /// Each coefficient's scale.
    sc: Vec<f64>,
    /// The data, normalised.
    data: Vec<f64>,
    /// The start, lower and upper bounds of `u`.
    u0: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl<'a> Joint<'a> {
    fn new(
        prep: &'a Prepared,
        o: &'a FitOutcome,
        terms: Vec<&'a KindFit>,
        from: &'a [f64],
    ) -> Self {
        let sigma = o.sigma;
        let specs = o.model.specs();
        let fidx: Vec<usize> = (0..specs.len()).filter(|&i| o.free[i]).collect();
        let kind = terms[0];
        let ends: Vec<usize> = terms
            .iter()
            .scan(0, |e, k| {
                *e += k.shape.len();
                Some(*e)
            })
            .collect();
        let w: Vec<Vec<f64>> = terms
            .iter()
            .flat_map(|k| &k.shape)
            .map(|c| {
                let mut c = c.clone();
                prep.normalise(&mut c, sigma);
                c
            })
            .collect();
        // each coefficient in units of the change that moves chi-square by about one
        let sc: Vec<f64> = w
            .iter()
            .map(|c| 1.0 / dot(c, c).sqrt().max(1e-300))
            .collect();
        let mut data = prep.data().to_vec();
        prep.normalise(&mut data, sigma);
        let nm = fidx.len();
        let mut u0: Vec<f64> = fidx.iter().map(|&i| to_u(&specs[i], from[i])).collect();
        let mut lo: Vec<f64> = fidx
            .iter()
            .map(|&i| to_u(&specs[i], specs[i].lower))
            .collect();
        let mut hi: Vec<f64> = fidx
            .iter()
            .map(|&i| to_u(&specs[i], specs[i].upper))
            .collect();
        for (j, c) in terms.iter().flat_map(|k| &k.coefs).enumerate() {
            u0.push(if c.is_finite() { c / sc[j] } else { 0.0 });
            lo.push(f64::NEG_INFINITY);
            hi.push(f64::INFINITY);
        }
        Joint {
            prep,
            o,
            kind,
            terms,
            ends,
            from,
            specs,
            fidx,
            nm,
            w,
            sc,
            data,
            u0,
            lo,
            hi,
        }
    }

    /// The model's parameters with the free ones at `u`'s first `nm`.
    fn params(&self, u: &[f64]) -> Vec<f64> {
        let mut p = self.from.to_vec();
        for (k, &i) in self.fidx.iter().enumerate() {
            p[i] = from_u(&self.specs[i], u[k]);
        }
        p
    }

    /// The normalised residual (model plus term minus data) at `u`, the term to first order
    /// or `solved` with the state it changes.
    fn residual(&self, u: &[f64], solved: bool) -> Vec<f64> {
        let (prep, t) = (self.prep, &self.prep.dataset.t);
        let raw = self.o.model.predict(&self.params(u), t, &prep.inputs);
        self.residual_of(raw, u, solved)
    }

    /// [`Joint::residual`] from the model's prediction `raw` at `u`.
    fn residual_of(&self, raw: Vec<f64>, u: &[f64], solved: bool) -> Vec<f64> {
        let (prep, sigma, t) = (self.prep, self.o.sigma, &self.prep.dataset.t);
        let cs: Vec<f64> = (0..self.w.len())
            .map(|j| u[self.nm + j] * self.sc[j])
            .collect();
        if solved {
            return self.residual_solved(raw, &cs);
        }
        // to first order: a term on the model's own state follows the model as it moves
        let moving: Vec<Option<Vec<Vec<f64>>>> = self
            .terms
            .iter()
            .map(|k| {
                state_shape(t, &k.kind, &raw, k.scan).map(|mut cols| {
                    for s in cols.iter_mut() {
                        prep.normalise(s, sigma);
                    }
                    cols
                })
            })
            .collect();
        let mut v = raw;
        prep.normalise(&mut v, sigma);
        for (j, col) in self.w.iter().enumerate() {
            let c = cs[j];
            let (i, start) = self.term_of(j);
            let moving = moving[i].as_ref().and_then(|m| m.get(j - start));
            let col = moving.unwrap_or(col);
            for (vi, ci) in v.iter_mut().zip(col) {
                *vi += c * ci;
            }
        }
        for (vi, d) in v.iter_mut().zip(&self.data) {
            *vi -= d;
        }
        v
    }

    /// The index of the term column `j` of `w` belongs to, and where its columns start.
    fn term_of(&self, j: usize) -> (usize, usize) {
        let i = self.ends.iter().position(|&e| j < e).unwrap_or(0);
        (i, if i == 0 { 0 } else { self.ends[i - 1] })
    }

    /// [`Joint::residual`] of a force on the state (position, velocity) acting on the state it
    /// changes: the term's displacement solves x_add = sum_j c_j K_j(x_model + x_add), a
    /// Volterra equation (double or single integrals from the trigger) solved by its Neumann
    /// series. A damping of 100 1/s over 9 ms (gamma t = 0.9) is far from first order. Of
    /// several terms, those on the state are solved together and the others (a vibration or a
    /// step of the reading) added to the reading.
    fn residual_solved(&self, raw: Vec<f64>, cs: &[f64]) -> Vec<f64> {
        let (prep, sigma, t) = (self.prep, self.o.sigma, &self.prep.dataset.t);
        let n = raw.len();
        let on_state = |k: &KindFit| matches!(k.kind.as_str(), "position" | "velocity");
        let mut xa = vec![0.0; n];
        for _ in 0..12 {
            let tot: Vec<f64> = raw.iter().zip(&xa).map(|(a, b)| a + b).collect();
            let mut cols: Vec<Vec<f64>> = Vec::new();
            let mut cc: Vec<f64> = Vec::new();
            for (i, k) in self.terms.iter().enumerate().filter(|(_, k)| on_state(k)) {
                let start = if i == 0 { 0 } else { self.ends[i - 1] };
                cols.extend(state_shape(t, &k.kind, &tot, 0.0).expect("a state kind"));
                cc.extend_from_slice(&cs[start..self.ends[i]]);
            }
            let next: Vec<f64> = (0..n)
                .map(|i| cols.iter().zip(&cc).map(|(col, c)| c * col[i]).sum())
                .collect();
            let change = next
                .iter()
                .zip(&xa)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            xa = next;
            if change < 1e-4 * sigma {
                break;
            }
        }
        let mut v: Vec<f64> = raw.iter().zip(&xa).map(|(a, b)| a + b).collect();
        prep.normalise(&mut v, sigma);
        for (j, col) in self.w.iter().enumerate() {
            if !on_state(self.terms[self.term_of(j).0]) {
                for (vi, ci) in v.iter_mut().zip(col) {
                    *vi += cs[j] * ci;
                }
            }
        }
        for (vi, d) in v.iter_mut().zip(&self.data) {
            *vi -= d;
        }
        v
    }

    /// A pure shift: the model delayed by d, d fitted with the model's parameters (in units of
    /// the median sampling step). Returns the chi-square removed and the coefficient (the
    /// shift over the scanned one).
    fn delay(&self, opts: &LmOptions) -> JointEnd {
        let (prep, o, nm, t) = (self.prep, self.o, self.nm, &self.prep.dataset.t);
        let sd = (t[t.len() - 1] - t[0]) / (t.len().max(2) - 1) as f64;
        let g = |u: &[f64]| {
            let p = self.params(u);
            // the model evaluated at the shifted times (not interpolated between samples: a
            // 73 kHz ringing sampled at 1 MHz is off by tens of nm between them)
            let d = u[nm] * sd;
            let shifted: Vec<f64> = t.iter().map(|&ti| ti - d).collect();
            let mut v = o.model.predict(&p, &shifted, &prep.inputs);
            prep.normalise(&mut v, o.sigma);
            for (vi, x) in v.iter_mut().zip(&self.data) {
                *vi -= x;
            }
            v
        };
        // the shift's start: the score test's, and a scan of the shift over both signs from a
        // fifth of a sample to a twentieth of the record with the model where the fit left it
        // (a ringing record has a chi-square with a minimum per period in the shift: a local
        // run from a poor start stops in the wrong one)
        let span = t[t.len() - 1] - t[0];
        let cost = |u: &[f64]| g(u).iter().map(|v| v * v).sum::<f64>();
        let mut best_u = self.u0[..nm].to_vec();
        best_u.push(self.kind.coefficient / sd);
        let mut best_c = cost(&best_u);
        let (a, b) = ((0.2 * sd).ln(), (0.05 * span).max(0.4 * sd).ln());
        for sign in [1.0, -1.0] {
            for j in 0..48 {
                let d = sign * (a + (b - a) * j as f64 / 47.0).exp();
                let mut u = self.u0[..nm].to_vec();
                u.push(d / sd);
                let c = cost(&u);
                if c < best_c {
                    (best_c, best_u) = (c, u);
                }
            }
        }
        let r =
            crate::numeric::lm::minimize(&g, &best_u, &self.lo[..nm + 1], &self.hi[..nm + 1], opts);
        opts.observer.debug(&|| {
            format!(
                "delay joint fit: start {:e} s cost {best_c:.1}, end {:e} s cost {:.1} (model alone {:.1})",
                best_u[nm] * sd,
                r.u[nm] * sd,
                r.cost,
                o.chi2
            )
        });
        (
            o.chi2 - r.cost,
            vec![r.u[nm] * sd / self.kind.scan],
            self.params(&r.u),
        )
    }
}

/// The columns of a kind on the model's state (`position`, `velocity`, `delay` by `d` [s]) for
/// the model's prediction `x`; `None` for the other kinds. A restoring force acts about an
/// equilibrium that need not be the TM's rest position (a pendulum whose free equilibrium is
/// offset, issue 33): `-w0^2 (x - x_eq)` has the response to `x` and the response to a
/// constant force, `t^2 / 2` after the trigger, as its two columns.
fn state_shape(t: &[f64], kind: &str, x: &[f64], d: f64) -> Option<Vec<Vec<f64>>> {
    let n = x.len();
    match kind {
        "position" => Some(vec![
            integ(t, &integ(t, x)),
            integ(t, &integ(t, &vec![1.0; n])),
        ]),
        "velocity" => {
            let i0 = t
                .iter()
                .position(|&t| t >= 0.0)
                .unwrap_or(0)
                .min(n.saturating_sub(1));
            let x0 = x.get(i0).copied().unwrap_or(0.0);
            let xr: Vec<f64> = x.iter().map(|v| v - x0).collect();
            Some(vec![integ(t, &xr)])
        }
        "delay" => Some(vec![shifted(t, x, d)]),
        _ => None,
    }
}

/// `x(t - d) - x(t)` at every time of `t`, `x(t - d)` by [`interp`]. The times are
/// increasing (the dataset's check), so each interval is found by walking on from the last one
/// instead of a binary search per sample (the same interval: the binary search remains where
/// the times do not increase); on a 400 000-sample record the searches of the delay scan's 49
/// shifts were 4 % of `discover`.
fn shifted(t: &[f64], x: &[f64], d: f64) -> Vec<f64> {
    let n = t.len();
    let mut j = 0;
    let mut last = f64::NEG_INFINITY;
    t.iter()
        .zip(x)
        .map(|(&ti, &xi)| {
            let at = ti - d;
            if at >= last {
                while j < n && t[j] <= at {
                    j += 1;
                }
            } else {
                j = t.partition_point(|&v| v <= at);
            }
            last = at;
            interp_in(x, t, j, at) - xi
        })
        .collect()
}

/// `x` at time `at` by linear interpolation over `t` (held at the ends): the reference of
/// [`shifted`]'s walk.
#[cfg(test)]
fn interp(t: &[f64], x: &[f64], at: f64) -> f64 {
    if t.is_empty() {
        return 0.0;
    }
    interp_in(x, t, t.partition_point(|&v| v <= at), at)
}

/// [`interp`] in the interval `j` (the number of times at or before `at`).
fn interp_in(x: &[f64], t: &[f64], j: usize, at: f64) -> f64 {
    let n = t.len();
    if j == 0 {
        x[0]
    } else if j >= n {
        x[n - 1]
    } else {
        let a = (at - t[j - 1]) / (t[j] - t[j - 1]);
        x[j - 1] + a * (x[j] - x[j - 1])
    }
}

/// The words and the physical parameter of a kind on the model's state with coefficient `c`.
fn state_text(kind: &str, ch: &str, c: f64) -> (String, Option<TermParameter>) {
    let par = |name: &str, value: f64, unit: &str| {
        Some(TermParameter {
            name: name.into(),
            value,
            unit: unit.into(),
        })
    };
    match kind {
        "position" if c < 0.0 => {
            let f0 = (-c).sqrt() / std::f64::consts::TAU;
            (
                format!(
                    "{ch} (position): a restoring force -w0^2 {ch}, a spring or pendulum mode at {f0:.4} Hz"
                ),
                par("f0", f0, "Hz"),
            )
        }
        "position" => {
            let g = c.sqrt();
            (
                format!(
                    "{ch} (position): an anti-restoring force +g^2 {ch} (negative stiffness), g = {g:.4e} 1/s"
                ),
                par("g", g, "1/s"),
            )
        }
        "velocity" => (
            format!(
                "d{ch}/dt (velocity): a damping force -gamma d{ch}/dt, gamma = {:.4e} 1/s",
                -c
            ),
            par("gamma", -c, "1/s"),
        ),
        _ => (
            format!("delay: the model shifted in time by {c:.4e} s (a trigger or timing delay)"),
            par("delay", c, "s"),
        ),
    }
}

/// The columns of a scanned kind at its parameter `value` (`creep`: tau [s]; `slip`, `impulse`:
/// t0 [s]; `vibration`: f [Hz]); `None` for the kinds without a scanned parameter.
fn scanned_shape(t: &[f64], kind: &str, value: f64) -> Option<Vec<Vec<f64>>> {
    match kind {
        "creep" => Some(vec![
            t.iter()
                .map(|&t| if t > 0.0 { (t / value).ln_1p() } else { 0.0 })
                .collect(),
        ]),
        "slip" => Some(vec![
            t.iter()
                .map(|&t| if t >= value { 1.0 } else { 0.0 })
                .collect(),
        ]),
        "impulse" => Some(vec![t.iter().map(|&t| (t - value).max(0.0)).collect()]),
        "vibration" => Some(sincos(t, value)),
        _ => None,
    }
}

/// The leading term of `o`'s residual refined by a joint fit ([`joint_fit`]): its coefficients
/// fitted jointly with the model, and for a scanned kind its parameter (a frequency, a time
/// constant, the time of a jump) searched again with the model refitted at each trial value
/// (golden section over a bracket of a quarter of the record's frequency resolution, two
/// samples, or a factor 1.5), so that it is not biased by what the model absorbed. Returns the
/// term, with `delta_chi2` and `delta_bic` those of the joint fit against `o`.
pub fn refined_leading(
    prep: &Prepared,
    o: &FitOutcome,
    peaks: &[Peak],
    opts: &crate::estimate::FitOptions,
    max_iter: usize,
) -> Result<Option<KindFit>, crate::FitError> {
    Ok(refined_terms(prep, o, peaks, opts, max_iter)?
        .into_iter()
        .next())
}

/// A joint fit's start (the model refitted without the term) and its result ([`joint_lm`]).
type JointFit = (Vec<f64>, JointEnd);

/// The terms [`refined_leading`] fits jointly with the model (the three best by the score
/// test, and the delay), each with the delta BIC of its joint fit, most supported first: the
/// leader refined as [`refined_leading`] says, the others at their scanned values. Terms whose
/// joint fits come within `DELTA_BIC_STRONG` (10) of the leader's are indistinguishable on the
/// record (`crate::discover::Description::indistinguishable`).
pub fn refined_terms(
    prep: &Prepared,
    o: &FitOutcome,
    peaks: &[Peak],
    opts: &crate::estimate::FitOptions,
    max_iter: usize,
) -> Result<Vec<KindFit>, crate::FitError> {
    let (all, basis) = kinds(prep, o, peaks);
    refined_terms_of(prep, o, &all, &basis, opts, max_iter)
}

/// [`refined_terms`] from the kinds `all` that [`kinds_of`] found on `basis` (the basis of
/// `o`), without making them again: the same bits.
pub(crate) fn refined_terms_of(
    prep: &Prepared,
    o: &FitOutcome,
    all: &[KindFit],
    basis: &Basis,
    opts: &crate::estimate::FitOptions,
    max_iter: usize,
) -> Result<Vec<KindFit>, crate::FitError> {
    let mut done: Vec<KindFit> = Vec::new();
    // the three best by the score test, and the delay (a pure shift, which the model can
    // absorb nonlinearly far beyond what the score test sees), each fitted jointly: the best
    // joint fit leads
    let mut best: Option<(KindFit, Vec<f64>, f64)> = None;
    let tried: Vec<KindFit> = all
        .iter()
        .enumerate()
        .filter(|(i, k)| *i < 3 || k.kind == "delay")
        .map(|(_, k)| k.clone())
        .collect();
    // the joint fits are independent of one another: side by side on the thread pool (issue
    // 33, item 6), collected in the score test's order, so the choice below is the same
    let joint: Vec<Result<JointFit, crate::FitError>> = tried
        .par_iter()
        .map(|k| {
            let from = refit_without(prep, o, k, opts)?;
            let dc = joint_lm(prep, o, k, &from, max_iter, &*opts.observer);
            Ok((from, dc))
        })
        .collect();
    let joint = joint.into_iter().collect::<Result<Vec<JointFit>, _>>()?;
    let joint = restart_close(prep, o, &tried, joint, max_iter, &*opts.observer);
    for (mut k, j) in tried.into_iter().zip(joint) {
        let penalty = k.delta_bic + k.delta_chi2;
        let (from, (d, c, _)) = j;
        if d > k.delta_chi2 {
            k.coefs = c;
            k.delta_chi2 = d;
            k.delta_bic = -d + penalty;
            if state_shape(&[], &k.kind, &[], 0.0).is_some() {
                let c = if k.kind == "delay" {
                    k.coefs[0] * k.scan
                } else {
                    k.coefs[0]
                };
                let (term, parameter) = state_text(&k.kind, prep.channel, c);
                k.coefficient = c;
                k.term = term;
                k.parameter = parameter;
                describe_offset(&mut k, prep.channel);
            }
        }
        done.push(k.clone());
        if best.as_ref().is_none_or(|b| k.delta_bic < b.0.delta_bic) {
            best = Some((k, from, penalty));
        }
    }
    let Some((mut lead, from, penalty)) = best else {
        return Ok(Vec::new());
    };
    let finish = |lead: KindFit, mut done: Vec<KindFit>| -> Vec<KindFit> {
        done.retain(|k| k.kind != lead.kind);
        done.sort_by(|a, b| a.delta_bic.total_cmp(&b.delta_bic));
        done.insert(0, lead);
        done
    };
    let t = &prep.dataset.t;
    let Some(par) = lead.parameter.clone() else {
        return Ok(finish(lead, done));
    };
    if scanned_shape(t, &lead.kind, par.value).is_none() || t.len() < 2 {
        return Ok(finish(lead, done));
    }
    let span = t[t.len() - 1] - t[0];
    let dt = span / (t.len() - 1) as f64;
    // the search runs on z: value = z (linear) or exp(z) (tau)
    let (log, half) = match lead.kind.as_str() {
        "vibration" => (false, 0.25 / span),
        "creep" => (true, 1.5f64.ln()),
        _ => (false, 2.0 * dt),
    };
    let z0 = if log { par.value.ln() } else { par.value };
    let trial = |z: f64| -> (f64, KindFit) {
        let v = if log { z.exp() } else { z };
        let mut k = lead.clone();
        k.shape = scanned_shape(t, &k.kind, v).expect("scanned");
        // the coefficients' start: the score test's (after the fit's own freedom)
        if let Some((c, _, _)) = basis.score(k.shape.clone()) {
            k.coefs = c;
        }
        let (d, c, _) = joint_lm(prep, o, &k, &from, max_iter, &*opts.observer);
        k.coefs = c;
        (d, k)
    };
    let (zb, db, mut kb) = pairs::golden(z0 - half, z0 + half, &trial);
    if db > lead.delta_chi2 {
        let v = if log { zb.exp() } else { zb };
        let a = kb.coefs.iter().map(|c| c * c).sum::<f64>().sqrt();
        let coef = if kb.coefs.len() == 2 { a } else { kb.coefs[0] };
        let p = TermParameter {
            value: v,
            ..par.clone()
        };
        kb.term = term_text(&kb.kind, coef, v);
        kb.coefficient = coef;
        kb.parameter = Some(p);
        kb.delta_chi2 = db;
        kb.delta_bic = -db + penalty;
        lead = kb;
    }
    Ok(finish(lead, done))
}

/// Fraction of the best joint fit's removed chi-square above which another kind's joint fit is
/// run again from the best one's model parameters ([`restart_close`]).
pub const RESTART_CLOSE: f64 = 0.95;

/// The joint fits `joint` of the kinds `tried`, each kind whose fit removed at least
/// [`RESTART_CLOSE`] of the best's run again from the model parameters where the best one ended
/// (its coefficients from the score test), the better of its two runs kept with its start.
///
/// A joint fit is a local run from the model refitted without the term. On a wrong model the
/// baseline's valley is flat (a parameter pair along an exact symmetry, another at a bound), and
/// where a kind's run starts in it decides where it stops: on the independent `tmmf-damping`
/// record the damping's joint fit stopped 28 above the chi-square it reaches from the anti-restoring
/// force's end point (1 991.5 against 1 963.4, the scaffolded damping effect's own 1 963), which
/// put the anti-restoring force ahead by 21 in BIC. The order of close kinds must not be decided
/// by their starts: every close kind gets the best start any of them found.
fn restart_close(
    prep: &Prepared,
    o: &FitOutcome,
    tried: &[KindFit],
    joint: Vec<JointFit>,
    max_iter: usize,
    obs: &dyn Observer,
) -> Vec<JointFit> {
    let Some(best) = (0..joint.len()).max_by(|&a, &b| joint[a].1.0.total_cmp(&joint[b].1.0)) else {
        return joint;
    };
    let (best_d, best_p) = (joint[best].1.0, joint[best].1.2.clone());
    let again: Vec<Option<JointEnd>> = tried
        .par_iter()
        .enumerate()
        .map(|(i, k)| {
            let d = joint[i].1.0;
            (i != best && best_d > 0.0 && d >= RESTART_CLOSE * best_d)
                .then(|| joint_lm(prep, o, k, &best_p, max_iter, obs))
        })
        .collect();
    joint
        .into_iter()
        .zip(again)
        .map(|((from, first), again)| match again {
            Some(a) if a.0 > first.0 => {
                obs.debug(&|| {
                    format!(
                        "joint fit restarted from the best kind's end: removed {:.1} (was {:.1})",
                        a.0, first.0
                    )
                });
                (best_p.clone(), a)
            }
            _ => (from, first),
        })
        .collect()
}

/// A `position` term's equilibrium: `-w0^2 (x - x_eq)` has the coefficients `-w0^2` and
/// `w0^2 x_eq` [m/s^2]; when the equilibrium is off the rest position by more than its 1-sigma,
/// the words say so.
fn describe_offset(k: &mut KindFit, ch: &str) {
    if k.kind != "position" || k.coefs.len() != 2 || k.coefs[0] >= 0.0 {
        return;
    }
    let x_eq = -k.coefs[1] / k.coefs[0];
    if x_eq.is_finite() {
        k.term = format!("{}, about an equilibrium {ch} = {x_eq:.4e} m", k.term);
    }
}

/// The words of a scanned kind's term with coefficient `c` and parameter `v`.
fn term_text(kind: &str, c: f64, v: f64) -> String {
    match kind {
        "creep" => {
            format!("creep: {c:.4e} m x ln(1 + t / {v:.4e} s) (piezo creep or a relaxation)")
        }
        "slip" => {
            format!("slip: a step of {c:.4e} m at t = {v:.4e} s (a slip of the contact point)")
        }
        "impulse" => format!(
            "impulse: a velocity step of {c:.4e} m/s at t = {v:.4e} s (a knock or a sudden release)"
        ),
        _ => format!(
            "sin(2 pi {v:.4e} Hz t + phi): a vibration of {c:.3e} m (floor, stand or structure)"
        ),
    }
}

/// Correlation of the residual with the response to a force proportional to each state (double
/// integral from the trigger, projected out of the fit's span), strongest first.
pub(crate) fn state_correlations(
    basis: &Basis<'_>,
    states: &[(String, Vec<f64>)],
) -> Vec<StateCorrelation> {
    let t = &basis.prep.dataset.t;
    let mut out: Vec<StateCorrelation> = states
        .iter()
        .map(|(name, s)| StateCorrelation {
            state: name.clone(),
            r: basis.correlation(integ(t, &integ(t, s))),
        })
        .collect();
    out.sort_by(|a, b| b.r.abs().total_cmp(&a.r.abs()));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vibration's columns (sine and cosine in one call) are the bits of `sin` and `cos`
    /// taken apart, from millihertz to the Nyquist frequency of a megahertz record, over two
    /// seconds: the scans' results do not depend on how the library pairs them.
    /// The delay shape's walk finds the interval a binary search finds, for shifts of both
    /// signs, beyond either end of the record, on uneven times with repeated stamps, and on
    /// times that do not increase (where it searches again).
    #[test]
    fn shifted_is_the_bits_of_interpolating_each_sample() {
        let uneven: Vec<f64> = (0..3000)
            .map(|i| -1e-3 + i as f64 * 5e-6 + 2e-6 * ((i * 7919 % 13) as f64 / 13.0))
            .collect();
        let mut repeated = uneven.clone();
        repeated[100] = repeated[99];
        let mut backwards = uneven.clone();
        backwards.swap(1500, 1700);
        let x: Vec<f64> = (0..3000).map(|i| (i as f64 * 0.01).sin() * 1e-6).collect();
        for t in [&uneven, &repeated, &backwards] {
            for d in [0.0, 7.3e-6, -7.3e-6, 1e-3, -4e-3, 0.1, -0.1, f64::NAN] {
                let fast = shifted(t, &x, d);
                for ((&ti, &xi), f) in t.iter().zip(&x).zip(&fast) {
                    let want = interp(t, &x, ti - d) - xi;
                    assert!(f.to_bits() == want.to_bits(), "d {d} at {ti}: {f} {want}");
                }
            }
        }
    }

    #[test]
    fn sincos_columns_are_the_bits_of_sin_and_cos() {
        let t: Vec<f64> = (-1000..200_000).map(|i| i as f64 * 1e-5).collect();
        for f in [1e-3, 0.7, 13.0, 1234.5, 9.9e4, 5e5] {
            let cols = sincos(&t, f);
            let w = std::f64::consts::TAU * f;
            let s: Vec<f64> = t.iter().map(|t| (w * t).sin()).collect();
            let c: Vec<f64> = t.iter().map(|t| (w * t).cos()).collect();
            for (col, want) in cols.iter().zip([&s, &c]) {
                assert_eq!(col.len(), want.len());
                assert!(
                    col.iter()
                        .zip(want)
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "{f}"
                );
            }
        }
    }

    #[test]
    fn the_scan_finds_a_maximum_between_grid_points() {
        let (x, v) = scan(0.0, 10.0, 11, false, 1e-6, &|x| -(x - 3.3).powi(2));
        assert!((x - 3.3).abs() < 1e-5, "{x}");
        assert!(v > -1e-9);
        let (x, _) = scan(1e-6, 1.0, 12, true, 1e-6, &|x| {
            -(x.ln() - 0.01f64.ln()).powi(2)
        });
        assert!((x / 0.01 - 1.0).abs() < 1e-4, "{x}");
    }

    #[test]
    fn the_integral_starts_at_the_trigger() {
        let t = [-2.0, -1.0, 0.0, 1.0, 2.0];
        let one = [1.0; 5];
        assert_eq!(integ(&t, &one), vec![0.0, 0.0, 0.0, 1.0, 2.0]);
        let t = [-0.5, 0.5, 1.5];
        assert_eq!(integ(&t, &[1.0; 3]), vec![0.0, 0.5, 1.5]);
    }
}
