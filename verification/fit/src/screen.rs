//! The record screened before any decision (issue 50): wild samples set aside on every channel
//! (the record's figures and findings: `crate::record`).
//!
//! **Outliers never decide** ([`screen`]). The loader excludes samples 20 robust sigma off
//! their neighbours (`crate::dataset::wild_samples`); spikes of 10 to 20 sigma stay in the
//! record, and a few of them (0.5 % of the samples) raise chi-square enough to turn the right
//! catalogue effect into "physics outside the catalogue". `discover` and `diagnose` therefore
//! first fit the baseline model and set aside every sample that lies [`SET_ASIDE_SIGMA`] robust
//! sigma and [`SET_ASIDE_SPREAD`] neighbour spreads off its neighbours: on the fitted channel
//! its residual against that fit, on the tip channel (`tmmf-release`) its residual against the
//! fitted tip profile, on any other channel its value. A missing effect bends the residual over
//! many samples, which the neighbours' median follows: it is never set aside. The record is
//! prepared again without those rows (noise figures, tip profile, guesses), the baseline
//! refitted, and the search repeated once; every decision is then taken on the cleaned record,
//! and the reports list each sample set aside by its CSV line. `discover` looks again with its
//! last model ([`again`]).

use crate::dataset::{Dataset, local_deviation_at, robust_scale};
use crate::error::FitError;
use crate::estimate::FitOptions;
use crate::prepare::Prepared;
use crate::record::{
    Finding, SetAside, quantisation_finding, sampling_findings, set_aside_text, tails_finding,
};
pub use crate::record::{SET_ASIDE_SIGMA, SET_ASIDE_SPREAD};

/// Indices of `resid` (at times `t` [s]) that lie [`SET_ASIDE_SIGMA`] robust sigma (floored at
/// a thousandth of `noise`) and [`SET_ASIDE_SPREAD`] spreads off their neighbours
/// ([`local_deviation_at`]), with the deviation and its robust sigma.
fn wild_in(t: &[f64], resid: &[f64], noise: f64) -> Vec<(usize, f64, f64)> {
    let dev = local_deviation_at(t, resid);
    if dev.is_empty() {
        return Vec::new();
    }
    let s = robust_scale(&dev).max(1e-3 * noise);
    dev.iter()
        .enumerate()
        .filter(|(_, (d, spread))| {
            d.abs() > SET_ASIDE_SIGMA * s && d.abs() > SET_ASIDE_SPREAD * spread
        })
        .map(|(i, (d, _))| (i, *d, if s > 0.0 { d.abs() / s } else { f64::INFINITY }))
        .collect()
}

/// Each channel of `prep` with its residual: the fitted channel's against the fit `pred`, the
/// tip channel's against its profile, any other's its value; and what it was taken against.
fn residuals(prep: &Prepared, pred: &[f64]) -> Vec<(String, Vec<f64>, &'static str)> {
    let ds = &prep.dataset;
    let profile_ch = ds.scenario.tip_profile_channel();
    let mut out = Vec::new();
    for (ch, v) in &ds.channels {
        let (resid, against): (Vec<f64>, &str) = if ch == prep.channel {
            (v.iter().zip(pred).map(|(d, m)| d - m).collect(), "model")
        } else if Some(ch.as_str()) == profile_ch
            && let Some(p) = prep.profile
        {
            let tp = geodesic_facility::TipProfile {
                jerk_m_s3: p.jerk_m_s3,
                v_m_s: p.v_m_s,
            };
            (
                ds.t.iter().zip(v).map(|(t, y)| y - tp.y(*t)).collect(),
                "tip profile",
            )
        } else {
            (v.clone(), "value")
        };
        out.push((ch.clone(), resid, against));
    }
    out
}

/// The samples of `prep` to set aside, the fitted channel's judged against the fit `pred`.
fn find(prep: &Prepared, pred: &[f64]) -> Vec<(usize, SetAside)> {
    let ds = &prep.dataset;
    let mut out = Vec::new();
    for (ch, resid, against) in residuals(prep, pred) {
        let v = ds.channel(&ch);
        let noise = prep.noise.get(&ch).copied().unwrap_or(0.0);
        for (i, d, z) in wild_in(&ds.t, &resid, noise) {
            out.push((
                i,
                SetAside {
                    channel: ch.clone(),
                    line: ds.line_of(i),
                    t: ds.t[i],
                    value: v[i],
                    deviation: d,
                    robust_sigma: z,
                    against: against.to_string(),
                },
            ));
        }
    }
    out
}

/// `ds` without the rows `drop` (sorted indices).
fn without(ds: &Dataset, drop: &[usize]) -> Dataset {
    let mut out = ds.clone();
    let keep = |v: &mut Vec<f64>| {
        let mut k = 0;
        v.retain(|_| {
            k += 1;
            drop.binary_search(&(k - 1)).is_err()
        });
    };
    keep(&mut out.t);
    for v in out.channels.values_mut() {
        keep(v);
    }
    if out.rows.lines.len() == ds.t.len() {
        let mut k = 0;
        out.rows.lines.retain(|_| {
            k += 1;
            drop.binary_search(&(k - 1)).is_err()
        });
    }
    out
}

/// Screens `prep` against the model `baseline` (see the module documentation): returns the
/// record with the samples set aside removed, prepared again, and marked screened (the same
/// record, marked, when nothing is set aside). A record already screened is returned as it is.
pub fn screen(
    prep: Prepared,
    baseline: &[&str],
    opts: &FitOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<Prepared, FitError> {
    if prep.screened {
        return Ok(prep);
    }
    let mut prep = prep;
    let mut set_aside: Vec<SetAside> = Vec::new();
    // what the record shows of its sampling and quantisation, before anything is removed
    let mut shows = sampling_findings(&prep.dataset.t);
    for (ch, v) in &prep.dataset.channels {
        let noise = prep.noise.get(ch).copied().unwrap_or(0.0);
        shows.extend(quantisation_finding(ch, v, noise));
    }
    let mut tails: Vec<Finding> = Vec::new();
    // twice at most: the second search on the residual of the baseline refitted without the
    // first one's samples
    for pass in 0..2 {
        progress(&format!(
            "screening the record for wild samples ({} fit)",
            if pass == 0 { "baseline" } else { "cleaned" }
        ));
        let o = crate::estimate::fit(&prep, baseline, opts)?;
        tails = tails_against(&prep, &o);
        let found = find(&prep, &o.pred);
        if found.is_empty() {
            break;
        }
        let mut drop: Vec<usize> = found.iter().map(|(i, _)| *i).collect();
        drop.sort_unstable();
        drop.dedup();
        let ds = without(&prep.dataset, &drop);
        set_aside.extend(found.into_iter().map(|(_, s)| s));
        prep = Prepared::new(ds);
    }
    set_aside.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.channel.cmp(&b.channel)));
    prep.screened = true;
    prep.set_aside = set_aside;
    shows.extend(tails);
    prep.record_shows = shows;
    Ok(prep)
}

/// The record `prep` (screened) without the samples that the fit `pred` shows wild too, or
/// `None` when it shows none: the loop's last model describes what the baseline did not, and
/// a spike inside the baseline's misfit stands out of its residual.
pub fn again(prep: &Prepared, pred: &[f64]) -> Option<Prepared> {
    let found = find(prep, pred);
    if found.is_empty() {
        return None;
    }
    let mut drop: Vec<usize> = found.iter().map(|(i, _)| *i).collect();
    drop.sort_unstable();
    drop.dedup();
    let mut out = Prepared::new(without(&prep.dataset, &drop));
    out.set_aside = prep.set_aside.clone();
    out.set_aside.extend(found.into_iter().map(|(_, s)| s));
    out.set_aside
        .sort_by(|a, b| a.t.total_cmp(&b.t).then(a.channel.cmp(&b.channel)));
    out.screened = true;
    out.record_shows = prep.record_shows.clone();
    Some(out)
}

/// The heavy-tail findings of `prep`'s channels against the fit `o`: the fitted channel's only
/// when `o` describes it (chi2_red at most 2; a model's misfit is no tail of the noise), the tip
/// channel's against its profile, any other's on its values.
fn tails_against(prep: &Prepared, o: &crate::estimate::FitOutcome) -> Vec<Finding> {
    let fits = o.chi2_red() <= 2.0;
    residuals(prep, &o.pred)
        .iter()
        .filter(|(ch, _, _)| fits || ch != prep.channel)
        .filter_map(|(ch, r, _)| {
            tails_finding(
                ch,
                &prep.dataset.t,
                r,
                prep.noise.get(ch).copied().unwrap_or(0.0),
            )
        })
        .collect()
}

/// `prep` with its findings judged against the fit `o` ([`shows_against`]) when `o` reveals
/// heavy tails on the fitted channel that `prep` does not know of (the baseline's misfit hid
/// them: the fitted channel's tails are judged only against a fit that describes it); `None`
/// otherwise.
pub fn tails_revealed(prep: &Prepared, o: &crate::estimate::FitOutcome) -> Option<Prepared> {
    let on_fitted =
        |f: &Finding| f.kind == "heavy tails" && f.channel.as_deref() == Some(prep.channel);
    if prep.record_shows.iter().any(on_fitted) {
        return None;
    }
    let shows = shows_against(prep, o);
    if !shows.iter().any(on_fitted) {
        return None;
    }
    let mut out = prep.clone();
    out.record_shows = shows;
    Some(out)
}

/// `prep`'s findings with the heavy tails judged against the fit `o` instead (the loop's last
/// model: the baseline's misfit hides the fitted channel's tails or passes for them).
pub fn shows_against(prep: &Prepared, o: &crate::estimate::FitOutcome) -> Vec<Finding> {
    let mut out: Vec<Finding> = prep
        .record_shows
        .iter()
        .filter(|f| f.kind != "heavy tails")
        .cloned()
        .collect();
    out.extend(tails_against(prep, o));
    out
}

/// `reason` followed by what the screen did to the record: the samples set aside and the
/// declared noise figures the pre-trigger disproved.
pub fn with_record_notes(reason: &str, prep: &Prepared) -> String {
    let mut out = reason.to_string();
    let aside = set_aside_text(&prep.set_aside);
    if !aside.is_empty() {
        out += "; ";
        out += &aside;
    }
    for c in prep.noise_checks.iter().filter(|c| c.mismatch) {
        out += "; ";
        out += &c.note;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    use geodesic_dataset::noise::gauss;

    #[test]
    fn spikes_are_found_and_a_step_or_a_kink_is_not() {
        let mut r: Vec<f64> = gauss(2000, 3);
        // a step of 30 sigma and a kink: a missing effect, not wild samples
        for (i, v) in r.iter_mut().enumerate() {
            if i >= 700 {
                *v += 30.0;
            }
            if i >= 1200 {
                *v += 0.5 * (i - 1200) as f64;
            }
        }
        assert!(wild_in(&[], &r, 1.0).is_empty());
        for (i, a) in [(300, 12.0), (900, -15.0), (1500, 10.0)] {
            r[i] += a;
        }
        let found: Vec<usize> = wild_in(&[], &r, 1.0).iter().map(|w| w.0).collect();
        assert_eq!(found, vec![300, 900, 1500]);
    }
}
