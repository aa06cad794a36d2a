//! Making a dataset ready for fitting: noise per channel, the smooth tip profile that drives
//! the TMMF model (examples README: never the raw noisy `y`), and data-driven guesses.

use std::collections::BTreeMap;

use geodesic_facility::TipProfile;
use geodesic_facility::effects::GuessContext;
use geodesic_facility::model::Inputs;
use serde::{Deserialize, Serialize};

use crate::dataset::Dataset;
use crate::numeric::lm::{LmOptions, minimize};
use crate::numeric::noise::ArNoise;
use crate::numeric::residual::noise_from_differences;

/// A dataset made ready for fitting: fitted channel, noise, inputs and data-driven guesses.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The dataset.
    pub dataset: Dataset,
    /// Name of the fitted channel.
    pub channel: &'static str,
    /// Its 1-sigma noise [SI]: of the innovations when the noise is coloured (`ar`), the
    /// figure the whitened residual is normalised by.
    pub sigma: f64,
    /// The fitted channel's coloured-noise model (`None`: white noise of `sigma`).
    pub ar: Option<crate::numeric::noise::ArNoise>,
    /// The tip channel's own coloured-noise model (`tmmf-release`; `None`: white), which its
    /// constant-jerk profile is fitted and judged whitened by ([`ProfileFit`]).
    pub tip_ar: Option<crate::numeric::noise::ArNoise>,
    /// Noise per channel [SI].
    pub noise: BTreeMap<String, f64>,
    /// Where each noise figure came from (`yaml`, `pre-trigger`, `differences`).
    pub noise_source: BTreeMap<String, String>,
    /// Inputs of the prediction (mass, tip profile, initial voltage).
    pub inputs: Inputs,
    /// Quantities the effects use for their starting points.
    pub guess: GuessContext,
    /// The smooth tip profile fitted to `y` (`tmmf-release`).
    pub profile: Option<ProfileFit>,
    /// Whether the record was screened for wild samples ([`crate::screen::screen`]).
    pub screened: bool,
    /// The samples the screen set aside (not in `dataset`), in time order.
    pub set_aside: Vec<crate::record::SetAside>,
    /// Each declared noise figure tested against the pre-trigger ([`crate::record::check_noise`]).
    pub noise_checks: Vec<crate::record::NoiseCheck>,
    /// What the screen found the record shows: gaps, irregular sampling, quantisation, heavy
    /// tails ([`crate::record::Finding`]).
    pub record_shows: Vec<crate::record::Finding>,
}

/// Fewest pre-trigger samples a noise model estimated from the residual is tested against
/// ([`Prepared::with_residual_noise`]): below, the model is taken from the residual alone.
pub const MIN_QUIET: usize = 8;

/// The tip retraction profile fitted to the measured `y` (constant jerk, then constant speed).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct ProfileFit {
    /// Jerk [m/s^3].
    pub jerk_m_s3: f64,
    /// Final speed [m/s].
    pub v_m_s: f64,
    /// Reduced chi-square of the profile against `y`.
    pub chi2_red: f64,
    /// Samples of `y` the profile was fitted to (those at `t >= 0`); not in the JSON.
    #[serde(skip)]
    pub n_samples: usize,
}

impl ProfileFit {
    /// Whether the profile describes the tip channel within its noise: `chi2_red` at most
    /// `1 + 5 sqrt(2/nu)` (`nu` = samples - 2), the bound a fitted channel is judged by
    /// ([`crate::report::is_explained`]). A tip that starts late (a trigger delay of tens of
    /// microseconds), stalls or accelerates otherwise leaves it above. `None` when the sample
    /// count is unknown (a profile read back from JSON).
    pub fn misfit(&self) -> Option<(f64, f64)> {
        if self.n_samples < 3 {
            return None;
        }
        let bound = 1.0 + 5.0 * (2.0 / (self.n_samples - 2) as f64).sqrt();
        (self.chi2_red > bound).then_some((self.chi2_red, bound))
    }
}

/// Estimates the noise of a channel: from the samples before the trigger when there are at
/// least 5, else from third differences of the whole record.
fn estimate_noise(t: &[f64], v: &[f64]) -> (f64, &'static str) {
    let pre: Vec<f64> = t
        .iter()
        .zip(v)
        .filter(|(t, _)| **t < 0.0)
        .map(|(_, v)| *v)
        .collect();
    if let Some(s) = noise_from_differences(&pre)
        && s > 0.0
    {
        return (s, "pre-trigger");
    }
    // third differences (divided ones on irregular time stamps): var = 20 sigma^2 for white
    // noise
    let (d3, _, _) = crate::record::third_differences(t, v);
    let var = d3.iter().map(|x| x * x).sum::<f64>() / d3.len().max(1) as f64;
    ((var / 20.0).sqrt().max(1e-30), "differences")
}

/// Least-squares slope of `v` against `t`.
fn slope(t: &[f64], v: &[f64]) -> f64 {
    let n = t.len() as f64;
    let (mt, mv) = (t.iter().sum::<f64>() / n, v.iter().sum::<f64>() / n);
    let num: f64 = t.iter().zip(v).map(|(a, b)| (a - mt) * (b - mv)).sum();
    let den: f64 = t.iter().map(|a| (a - mt).powi(2)).sum();
    if den > 0.0 { num / den } else { 0.0 }
}

/// Fits the constant-jerk-then-constant-speed profile to the tip signal `y` after the trigger,
/// its residual whitened by `ar` when the tip's noise is coloured (`sigma` then the innovation
/// sigma).
fn fit_profile(t: &[f64], y: &[f64], sigma: f64, ar: Option<&ArNoise>) -> ProfileFit {
    let post: Vec<(f64, f64)> = t
        .iter()
        .zip(y)
        .filter(|(t, _)| **t >= 0.0)
        .map(|(a, b)| (*a, *b))
        .collect();
    let (tp, yp): (Vec<f64>, Vec<f64>) = post.iter().copied().unzip();
    let k = tp.len() * 2 / 3;
    let v0 = slope(&tp[k..], &yp[k..]).abs().max(1e-6);
    let mt = tp[k..].iter().sum::<f64>() / (tp.len() - k) as f64;
    let my = yp[k..].iter().sum::<f64>() / (tp.len() - k) as f64;
    let t_int = (mt - my / v0).max(tp[tp.len() - 1] * 1e-3);
    let t1 = 1.5 * t_int;
    let j0 = 2.0 * v0 / (t1 * t1);
    let f = |u: &[f64]| {
        let p = TipProfile {
            jerk_m_s3: u[0].exp(),
            v_m_s: u[1].exp(),
        };
        let mut r: Vec<f64> = tp.iter().zip(&yp).map(|(t, y)| p.y(*t) - y).collect();
        if let Some(m) = ar {
            m.whiten(&mut r);
        }
        r.iter_mut().for_each(|v| *v /= sigma);
        r
    };
    let mut best = None::<crate::numeric::lm::LmResult>;
    for s in [1.0, 0.3, 3.0] {
        let r = minimize(
            &f,
            &[(j0 * s).ln(), v0.ln()],
            &[-30.0, -30.0],
            &[60.0, 10.0],
            &LmOptions::default(),
        );
        if best.as_ref().is_none_or(|b| r.cost < b.cost) {
            best = Some(r);
        }
    }
    let b = best.expect("one start");
    ProfileFit {
        jerk_m_s3: b.u[0].exp(),
        v_m_s: b.u[1].exp(),
        chi2_red: b.cost / (tp.len().saturating_sub(2)).max(1) as f64,
        n_samples: tp.len(),
    }
}

/// The tip channel's residual after the trigger against the profile `p` (data - profile) and
/// its values before the trigger.
fn tip_residual(t: &[f64], y: &[f64], p: &ProfileFit) -> (Vec<f64>, Vec<f64>) {
    let tp = TipProfile {
        jerk_m_s3: p.jerk_m_s3,
        v_m_s: p.v_m_s,
    };
    let pre = t.iter().zip(y).filter(|(t, _)| **t < 0.0).map(|(_, v)| *v);
    let post = t.iter().zip(y).filter(|(t, _)| **t >= 0.0);
    (post.map(|(t, y)| y - tp.y(*t)).collect(), pre.collect())
}

/// The tip channel's own noise model (issue 50, item 3), as the fitted channel's: from its
/// pre-trigger when it has at least [`MIN_SAMPLES`](crate::numeric::noise::MIN_SAMPLES)
/// samples, else from the white profile's residual, re-estimated with the profile refitted
/// whitened until the coefficients settle ([`NOISE_ITERATIONS`] at most), each taken only when
/// the pre-trigger samples (at least [`MIN_QUIET`]) are better described by that colour than by
/// white noise or the residual's first differences show it (as in [`Prepared::with_residual_noise`]). When one is found the profile `p` is refitted whitened, and the tip's figure,
/// the innovation sigma, pooled with the differences of the whitened residual after the trigger
/// as a white tip's is (`pool_tip_noise`). A figure the YAML states is white (interface.md):
/// `None` then.
fn tip_noise(
    dataset: &Dataset,
    noise: &mut BTreeMap<String, f64>,
    noise_source: &mut BTreeMap<String, String>,
    p: &mut ProfileFit,
) -> Option<ArNoise> {
    use crate::numeric::noise::{MIN_SAMPLES, estimate};
    let ch = dataset.scenario.tip_profile_channel()?;
    if noise_source.get(ch).is_none_or(|s| s != "pre-trigger") {
        return None;
    }
    let (t, y) = (&dataset.t, dataset.channel(ch));
    let (_, pre) = tip_residual(t, y, p);
    let (mut m, src) = if pre.len() >= MIN_SAMPLES {
        (estimate(&pre)?, "pre-trigger")
    } else {
        let mut cur: Option<ArNoise> = None;
        let mut fit = *p;
        for _ in 0..NOISE_ITERATIONS {
            let (post, pre) = tip_residual(t, y, &fit);
            let Some(m) = estimate(&post) else { break };
            if pre.len() >= MIN_QUIET && m.quiet_lr(&pre) <= 0.0 && !m.differences_support(&post) {
                break;
            }
            if cur.as_ref().is_some_and(|c| c.settled(&m)) {
                break;
            }
            fit = fit_profile(t, y, m.innovation_sigma, Some(&m));
            cur = Some(m);
        }
        (cur?, "residual")
    };
    *p = fit_profile(t, y, m.innovation_sigma, Some(&m));
    let (mut post, _) = tip_residual(t, y, p);
    m.whiten(&mut post);
    if let Some(sd) = noise_from_differences(&post[m.order().min(post.len())..]) {
        let s0 = m.innovation_sigma;
        let (a, b) = (
            pre.len().saturating_sub(1) as f64,
            post.len().saturating_sub(1) as f64,
        );
        let pooled = ((a * s0 * s0 + b * sd * sd) / (a + b)).sqrt();
        if pooled > 0.0 {
            p.chi2_red *= (s0 / pooled).powi(2);
            m.marginal_sigma *= pooled / s0;
            m.innovation_sigma = pooled;
        }
    }
    noise.insert(ch.to_string(), m.marginal_sigma);
    noise_source.insert(ch.to_string(), format!("{src} AR({})", m.order()));
    Some(m)
}

/// Most re-estimates of a noise model from a residual with the fit redone whitened.
pub const NOISE_ITERATIONS: usize = 3;

/// A tip figure estimated from a few hundred pre-trigger samples is uncertain by several
/// percent (11 % low on a record of issue 50, whose tip check then refused the right effect):
/// pooled with the differences of the profile `p`'s residual after the trigger, as the fitted
/// channel's figure is pooled with its fit's residual (`crate::estimate::effective_sigma`);
/// the profile's chi2_red is rescaled to it. A declared figure is left as it is.
fn pool_tip_noise(
    dataset: &Dataset,
    noise: &mut BTreeMap<String, f64>,
    noise_source: &mut BTreeMap<String, String>,
    p: &mut ProfileFit,
) {
    let Some(ch) = dataset.scenario.tip_profile_channel() else {
        return;
    };
    if noise_source.get(ch).is_none_or(|s| s != "pre-trigger") {
        return;
    }
    let tp = TipProfile {
        jerk_m_s3: p.jerk_m_s3,
        v_m_s: p.v_m_s,
    };
    let post: Vec<f64> = dataset
        .t
        .iter()
        .zip(dataset.channel(ch))
        .filter(|(t, _)| **t >= 0.0)
        .map(|(t, y)| y - tp.y(*t))
        .collect();
    let n_pre = dataset.t.iter().filter(|t| **t < 0.0).count();
    let Some(sd) = noise_from_differences(&post) else {
        return;
    };
    let s0 = noise[ch];
    let (a, b) = (
        n_pre.saturating_sub(1) as f64,
        post.len().saturating_sub(1) as f64,
    );
    let pooled = ((a * s0 * s0 + b * sd * sd) / (a + b)).sqrt();
    if pooled > 0.0 {
        p.chi2_red *= (s0 / pooled).powi(2);
        noise.insert(ch.to_string(), pooled);
        noise_source.insert(ch.to_string(), "pre-trigger+residual-differences".into());
    }
}

impl Prepared {
    /// Prepares a dataset: noise per channel, tip profile (`tmmf-release`), guesses.
    pub fn new(dataset: Dataset) -> Prepared {
        let scenario = dataset.scenario;
        let channel = scenario.fitted_channel();
        let mut noise = BTreeMap::new();
        let mut noise_source = BTreeMap::new();
        let mut noise_checks = Vec::new();
        for (ch, v) in &dataset.channels {
            if let Some(s) = dataset.noise.get(ch) {
                // the declared figure tested against the pre-trigger (issue 50): a mismatch
                // beyond sampling is reported and the record's figure used
                let pre: Vec<f64> = dataset
                    .t
                    .iter()
                    .zip(v)
                    .filter(|(t, _)| **t < 0.0)
                    .map(|(_, v)| *v)
                    .collect();
                // (then estimated as when the YAML states none: the pre-trigger's figure pooled
                // with the residual's differences, which hundreds of samples after the trigger
                // pin down where the pre-trigger alone leaves 8 % of doubt)
                let check = crate::record::check_noise(ch, *s, &pre).or_else(|| {
                    (pre.len() < crate::record::MIN_PRE_TRIGGER)
                        .then(|| crate::record::check_noise_differences(ch, *s, &dataset.t, v))
                        .flatten()
                });
                let (used, src) = match &check {
                    Some(c) if c.mismatch => estimate_noise(&dataset.t, v),
                    _ => (*s, "yaml"),
                };
                noise.insert(ch.clone(), used);
                noise_source.insert(ch.clone(), src.to_string());
                noise_checks.extend(check.map(|mut c| {
                    c.used = used;
                    c
                }));
            } else {
                let (s, src) = estimate_noise(&dataset.t, v);
                noise.insert(ch.clone(), s);
                noise_source.insert(ch.clone(), src.to_string());
            }
        }
        let mut sigma = noise[channel];
        // coloured noise: only judged from the pre-trigger samples, and only when the YAML
        // states no noise figure (interface.md: a stated figure is white noise)
        let mut ar = None;
        if noise_source.get(channel).map(String::as_str) == Some("pre-trigger") {
            let pre: Vec<f64> = dataset
                .t
                .iter()
                .zip(dataset.channel(channel))
                .filter(|(t, _)| **t < 0.0)
                .map(|(_, v)| *v)
                .collect();
            if let Some(m) = crate::numeric::noise::estimate(&pre) {
                sigma = m.innovation_sigma;
                noise.insert(channel.to_string(), m.marginal_sigma);
                noise_source.insert(
                    channel.to_string(),
                    format!("pre-trigger AR({})", m.order()),
                );
                ar = Some(m);
            }
        }
        let m_kg = dataset.known.get("m").copied().unwrap_or(0.0);
        let e0_v = dataset.known.get("E0").copied().unwrap_or(120.0);
        let mut profile = scenario
            .tip_profile_channel()
            .map(|ch| fit_profile(&dataset.t, dataset.channel(ch), noise[ch], None));
        let mut tip_ar = None;
        if let Some(p) = profile.as_mut() {
            tip_ar = tip_noise(&dataset, &mut noise, &mut noise_source, p);
            if tip_ar.is_none() {
                pool_tip_noise(&dataset, &mut noise, &mut noise_source, p);
            }
        }
        let inputs = Inputs {
            m_kg,
            profile: profile.map_or(
                TipProfile {
                    jerk_m_s3: 6000.0,
                    v_m_s: 3e-3,
                },
                |p| TipProfile {
                    jerk_m_s3: p.jerk_m_s3,
                    v_m_s: p.v_m_s,
                },
            ),
            e0_v,
        };
        // data-driven guesses from the fitted channel
        let (t, x) = (&dataset.t, dataset.channel(channel));
        let i0 = t.iter().position(|v| *v >= 0.0).unwrap_or(0);
        let n = t.len();
        let k = i0 + (n - i0) * 2 / 3;
        let late = slope(&t[k..], &x[k..]);
        let (mt, mx) = (
            t[k..].iter().sum::<f64>() / (n - k) as f64,
            x[k..].iter().sum::<f64>() / (n - k) as f64,
        );
        // the late line crosses zero at t0; a quarter-period spring catapult ends at 2.75 t0
        let t0 = if late.abs() > 0.0 {
            mt - mx / late
        } else {
            0.0
        };
        let catapult_s = if t0 > 0.0 {
            t0 / (1.0 - 2.0 / std::f64::consts::PI)
        } else {
            0.0
        };
        let span = x.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - x.iter().cloned().fold(f64::INFINITY, f64::min);
        let guess = GuessContext {
            m_kg,
            late_velocity_m_s: late,
            catapult_s,
            span_m: span,
            duration_s: t[n - 1].max(0.0),
            e0_v,
            k_needle_n_m: 0.0,
        };
        Prepared {
            dataset,
            channel,
            sigma,
            ar,
            tip_ar,
            noise,
            noise_source,
            inputs,
            guess,
            profile,
            screened: false,
            set_aside: Vec::new(),
            noise_checks,
            record_shows: Vec::new(),
        }
    }

    /// A reduced copy of a record longer than `max_n` samples, for the search of a fit (screening
    /// and first stages of [`crate::estimate::fit_model`]): about `max_n / 8` pre-trigger samples
    /// (evenly thinned, the last one kept), the first `max_n / 2` samples after the trigger, where
    /// the contact dynamics and the ringing are, all kept, and the rest of the record evenly
    /// thinned to the remaining budget. Noise figures, inputs, guesses and profile are those of
    /// the whole record. `None` when the record has at most `max_n` samples.
    pub fn reduced(&self, max_n: usize) -> Option<Prepared> {
        let t = &self.dataset.t;
        let n = t.len();
        if n <= max_n || max_n < 16 {
            return None;
        }
        let i0 = t.iter().position(|v| *v >= 0.0).unwrap_or(n);
        let (b_pre, b_head) = (max_n / 8, max_n / 2);
        let b_tail = max_n - b_pre - b_head;
        let mut idx: Vec<usize> = Vec::with_capacity(max_n + 2);
        // pre-trigger: evenly thinned, ending on the last sample before the trigger
        if i0 > 0 {
            let stride = i0.div_ceil(b_pre).max(1);
            let mut i = (i0 - 1) % stride;
            while i < i0 {
                idx.push(i);
                i += stride;
            }
        }
        let head_end = (i0 + b_head).min(n);
        idx.extend(i0..head_end);
        if head_end < n {
            let stride = (n - head_end).div_ceil(b_tail).max(1);
            let mut i = head_end + stride - 1;
            while i < n {
                idx.push(i);
                i += stride;
            }
            if idx.last() != Some(&(n - 1)) {
                idx.push(n - 1);
            }
        }
        let pick = |v: &[f64]| idx.iter().map(|&i| v[i]).collect::<Vec<f64>>();
        let mut dataset = self.dataset.clone();
        dataset.t = pick(t);
        for v in dataset.channels.values_mut() {
            *v = pick(v);
        }
        // thinned samples are not evenly spaced: the search uses the white approximation at the
        // noise's own sigma; the refinement on the whole record is whitened
        Some(Prepared {
            dataset,
            channel: self.channel,
            sigma: self.ar.as_ref().map_or(self.sigma, |m| m.marginal_sigma),
            ar: None,
            tip_ar: self.tip_ar.clone(),
            noise: self.noise.clone(),
            noise_source: self.noise_source.clone(),
            inputs: self.inputs,
            guess: self.guess,
            profile: self.profile,
            screened: self.screened,
            set_aside: self.set_aside.clone(),
            noise_checks: self.noise_checks.clone(),
            record_shows: self.record_shows.clone(),
        })
    }

    /// The record with the fitted channel's coloured-noise model estimated from `resid` (data -
    /// model of the current fit, the whole record), iterated with the fit by the caller (issue
    /// 50, item 3). Two cases, the figure never one the YAML states (interface.md: white):
    ///
    /// * the pre-trigger gave a model (`pre-trigger AR(p)`, or one from the residual before):
    ///   the residual's, estimated from ten times the samples, replaces it unless it is the same
    ///   ([`ArNoise::settled`](crate::numeric::noise::ArNoise::settled)) or the pre-trigger
    ///   samples reject it against their own model (twice the log-likelihood ratio above the
    ///   chi-square 1 % point of its order): a few hundred samples of an AR(1) 0.98 give 0.94,
    ///   whose whitening leaves enough low-frequency power to support a drift;
    /// * the pre-trigger is shorter than the noise estimator needs
    ///   ([`MIN_SAMPLES`](crate::numeric::noise::MIN_SAMPLES)) or absent: the residual's model is
    ///   taken when the pre-trigger samples (at least [`MIN_QUIET`]) are better described by its
    ///   colour than by white noise (a positive log-likelihood ratio,
    ///   [`ArNoise::quiet_lr`](crate::numeric::noise::ArNoise::quiet_lr)): the TM is at rest
    ///   there, so a colour only the residual after the trigger shows is a misfit of the model,
    ///   not the noise. (20 white quiet samples pass under a coefficient 0.95 only when their
    ///   lag-1 correlation exceeds 0.47, about 2 % of the time; a 1 % test would miss half the
    ///   AR(1) 0.95 records of 20 pre-trigger samples.) Twenty samples can also look white
    ///   by chance: the model is then still taken when the residual's first differences show
    ///   its colour ([`ArNoise::differences_support`](crate::numeric::noise::ArNoise::differences_support)),
    ///   which a smooth misfit cannot lend them;
    ///
    /// `None` when the residual is white (Ljung-Box at 1 %) or the model is refused; otherwise
    /// the channel's `noise_source` becomes `residual AR(p)`.
    pub fn with_residual_noise(&self, resid: &[f64]) -> Option<Prepared> {
        use crate::numeric::noise::{MIN_SAMPLES, chi2_sf, estimate};
        let src = self
            .noise_source
            .get(self.channel)
            .map_or("yaml", String::as_str);
        if src == "yaml" {
            return None;
        }
        let t = &self.dataset.t;
        let quiet: Vec<f64> = t
            .iter()
            .zip(resid)
            .filter(|(t, _)| **t < 0.0)
            .map(|(_, r)| *r)
            .collect();
        let m = match &self.ar {
            Some(cur) => {
                let m = estimate(resid)?;
                let worse = cur.quiet_lr(&quiet) - m.quiet_lr(&quiet);
                if cur.settled(&m) || chi2_sf(worse, m.order() as f64) < 0.01 {
                    return None;
                }
                m
            }
            None if quiet.len() < MIN_SAMPLES => {
                let m = estimate(resid)?;
                if quiet.len() >= MIN_QUIET
                    && m.quiet_lr(&quiet) <= 0.0
                    && !m.differences_support(resid)
                {
                    return None;
                }
                m
            }
            None => return None,
        };
        let mut out = self.clone();
        out.sigma = m.innovation_sigma;
        out.noise.insert(self.channel.to_string(), m.marginal_sigma);
        out.noise_source.insert(
            self.channel.to_string(),
            format!("residual AR({})", m.order()),
        );
        out.ar = Some(m);
        Some(out)
    }

    /// The fitted channel's data [SI].
    pub fn data(&self) -> &[f64] {
        self.dataset.channel(self.channel)
    }

    /// 1-sigma of the noise itself [SI] (the band a raw residual is judged against).
    pub fn marginal_sigma(&self) -> f64 {
        self.ar.as_ref().map_or(self.sigma, |m| m.marginal_sigma)
    }

    /// The residual `raw` (model - data or data - model) whitened by the noise model and
    /// normalised by `sigma`, in place.
    pub fn normalise(&self, raw: &mut [f64], sigma: f64) {
        if let Some(m) = &self.ar {
            m.whiten(raw);
        }
        for v in raw.iter_mut() {
            *v /= sigma;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::{SynthSpec, generate};
    use geodesic_facility::Scenario;

    /// Issue 50, item 3: the tip channel gets its own noise model from its pre-trigger, and its
    /// constant-jerk profile is fitted and judged whitened: a TMMF record with AR(1) 0.9 noise on
    /// the tip passes the tip check (it failed it at chi2_red 6.7 judged white); a white tip has
    /// no model, as before.
    #[test]
    fn a_coloured_tip_is_judged_whitened() {
        let mut spec =
            SynthSpec::defaults(Scenario::TmmfRelease, &["needle_contact", "tip_contact"]);
        spec.noise_ar.insert("y".into(), 0.9);
        spec.noise_in_yaml = false;
        spec.seed = 3;
        let prep = Prepared::new(generate(&spec, "tip.yaml").expect("synth"));
        let m = prep.tip_ar.as_ref().expect("the tip's own model");
        assert!((m.coefficients[0] - 0.9).abs() < 0.1, "{m:?}");
        assert_eq!(prep.noise_source["y"], "pre-trigger AR(1)");
        let p = prep.profile.expect("profile");
        assert!(
            p.misfit().is_none(),
            "whitened tip profile: chi2_red {}",
            p.chi2_red
        );
        // the same record judged white, as before (the figure of the pre-trigger's differences),
        // fails the check
        let (t, y) = (&prep.dataset.t, prep.dataset.channel("y"));
        let white = fit_profile(t, y, estimate_noise(t, y).0, None);
        assert!(
            white.misfit().is_some(),
            "white: chi2_red {}",
            white.chi2_red
        );
        spec.noise_ar.clear();
        let prep = Prepared::new(generate(&spec, "tip.yaml").expect("synth"));
        assert!(prep.tip_ar.is_none() && prep.profile.unwrap().misfit().is_none());
    }
}
