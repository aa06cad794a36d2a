//! The discover report as text (what `geodesic discover` prints without `--json`): the ledger,
//! the final fit's summary, the verdict, what the residual still holds and the detection
//! thresholds.

use std::fmt::Write;

use super::{Description, DiscoverReport, Threshold};
use crate::outliers::fmt_sig;

/// The report as the terminal shows it, one line per round, finding and threshold.
pub fn text(report: &DiscoverReport) -> String {
    let mut s = ledger(report);
    s += &crate::summary::summary(&report.final_fit);
    let _ = writeln!(s, "explained: {} ({})", report.explained, report.reason);
    for f in &report.record_shows {
        let _ = writeln!(s, "the record shows: {}", f.text);
    }
    for r in &report.refused {
        let _ = writeln!(
            s,
            "  {} refused at round {} (delta BIC {:.1}): {}",
            r.effect, r.round, r.delta_bic, r.why
        );
    }
    for i in &report.improves {
        let _ = writeln!(
            s,
            "  {} improves the fit (delta BIC {:.1}, chi2_red {:.3}) but does not explain it",
            i.effect, i.delta_bic, i.chi2_red
        );
    }
    s += &residual(&report.residual);
    for t in &report.thresholds {
        s += &threshold(t);
    }
    s
}

/// The ledger: one row a round.
fn ledger(report: &DiscoverReport) -> String {
    let mut s = String::from(
        "round  model                                        chi2_red    delta_bic   margin  added / removed\n",
    );
    for (k, r) in report.rounds.iter().enumerate() {
        let fmt = |v: Option<f64>| v.map_or("-".to_string(), fmt_sig);
        let _ = writeln!(
            s,
            "{k:>5}  {:<44} {:>9} {:>12} {:>8}  {}{}",
            r.effects.join("+"),
            fmt_sig(r.chi2_red),
            fmt(r.delta_bic),
            fmt(r.margin),
            r.added.as_deref().unwrap_or("-"),
            if r.removed.is_empty() {
                String::new()
            } else {
                format!(" / removed {}", r.removed.join(", "))
            }
        );
    }
    s
}

/// What the residual still holds: windows, peaks, the three strongest correlations, the
/// leading term's sentence, the terms and what the record cannot tell apart.
fn residual(d: &Description) -> String {
    let mut s = String::new();
    for w in &d.windows {
        let _ = writeln!(
            s,
            "  window {} {:.4e}..{:.4e} s ({}): peak {:.3e} ({} sigma)",
            w.failure.channel,
            w.failure.t_start,
            w.failure.t_end,
            w.phase,
            w.failure.peak,
            fmt_sig(w.failure.peak_sigma)
        );
    }
    for p in &d.peaks {
        let _ = writeln!(
            s,
            "  peak {} {:.4e} Hz, amplitude {:.3e}, {} x the floor",
            p.channel,
            p.hz,
            p.amplitude,
            fmt_sig(p.over_floor)
        );
    }
    for c in d.correlations.iter().take(3) {
        let _ = writeln!(s, "  correlation with {}: r = {:+.3}", c.state, c.r);
    }
    if let Some(l) = &d.leading {
        let _ = writeln!(s, "  {l}");
    }
    for t in &d.terms {
        let _ = writeln!(
            s,
            "  term [{}] {}: {:+.3e} +- {:.2e} {} (delta BIC {})",
            t.kind,
            t.term,
            t.coefficient,
            t.sigma,
            t.coefficient_unit,
            fmt_sig(t.delta_bic)
        );
    }
    if let Some(a) = &d.indistinguishable.first() {
        let _ = writeln!(
            s,
            "  indistinguishable on this record: {} (joint fits within 10 in BIC of {a}'s)",
            d.indistinguishable.join(", ")
        );
    }
    for (i, t) in d.separate_terms.iter().enumerate() {
        let _ = writeln!(
            s,
            "  unknown term {} of {}: [{}] {} (delta BIC {})",
            i + 1,
            d.separate_terms.len(),
            t.kind,
            t.term,
            fmt_sig(t.delta_bic)
        );
    }
    if let Some(a) = d.separate_indistinguishable.first() {
        let _ = writeln!(
            s,
            "  pairs indistinguishable on this record: {} (joint fits within 10 in BIC of {a}'s)",
            d.separate_indistinguishable.join(", ")
        );
    }
    s
}

/// A detection threshold, with the values it assumes and its curve along the other parameter.
fn threshold(t: &Threshold) -> String {
    let mut s = String::new();
    let assumes: Vec<String> = t
        .assumes
        .iter()
        .map(|(k, v)| format!("{k} = {v:.3e}"))
        .collect();
    let _ = writeln!(
        s,
        "  {} not detected: {} would be seen above {:.3e} {}{}",
        t.effect,
        t.parameter,
        t.detectable_above,
        t.unit,
        if assumes.is_empty() {
            String::new()
        } else {
            format!(" (assuming {})", assumes.join(", "))
        }
    );
    if !t.curve.is_empty() {
        let pts: Vec<String> = t
            .curve
            .iter()
            .map(|c| {
                let (k, v) = c.at.iter().next().expect("one parameter");
                format!("{k} {v:.2e}: {:.2e}", c.detectable_above)
            })
            .collect();
        let _ = writeln!(
            s,
            "    threshold along the other parameter: {}",
            pts.join("; ")
        );
    }
    s
}
