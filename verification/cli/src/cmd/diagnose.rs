//! `geodesic diagnose DATASET.yaml --effects a,b`: fits the model, then every candidate effect
//! of the scenario it lacks, ranks them by delta BIC and names the missing one (interface.md).
//! Arguments -> [`geodesic_discover::session::Session::diagnose`] -> print.

use geodesic_fit::summary::summary;

use crate::error::{CliError, CmdResult};
use crate::fitting::{FitProgress, fits_dir, open, warn};

/// Flags of `geodesic diagnose`: the same as `geodesic fit` (the model to start from).
pub use crate::fitting::FitArgs as Args;

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let fits = fits_dir(&args)?;
    let opts = args.model.options()?;
    let effects = args.model.effects();
    let session = open(&args.dataset, args.strict, &effects, opts)?;
    let task = FitProgress::start(
        args.json,
        &format!(
            "diagnose: {} samples, model {} and each candidate effect it lacks",
            session.prepared().dataset.t.len(),
            effects.join("+")
        ),
        "diagnose: ",
    );
    // wild samples set aside before any decision (the same prepared record for the outputs)
    let report = session
        .with_observer(task.observer())
        .with_outputs(fits)
        .diagnose()
        .map_err(crate::error::from_fit);
    task.finish();
    let report = report?;
    warn(&report.fit);
    if args.json {
        println!("{}", serde_json::to_string(&report).map_err(CliError::io)?);
    } else {
        print!("{}", summary(&report.fit));
        println!("candidates (best first):");
        for c in &report.candidates {
            let rms: Vec<String> = c.rms.iter().map(|(k, v)| format!("{k} {v:.3e}")).collect();
            println!(
                "  {:<24} delta_bic {:>12}  -2 delta ln Z {:>12}  chi2_red {:>10}  rms {}",
                c.effect,
                geodesic_fit::outliers::fmt_sig(c.delta_bic),
                c.delta_evidence
                    .map_or("-".to_string(), geodesic_fit::outliers::fmt_sig),
                geodesic_fit::outliers::fmt_sig(c.chi2_red),
                rms.join(", ")
            );
        }
        match &report.missing {
            Some(m) => println!("missing: {m}"),
            None => println!(
                "missing: none (no candidate improves BIC by more than {})",
                -report.delta_bic_threshold
            ),
        }
        println!(
            "explained: {} ({})",
            report.explained, report.explained_reason
        );
        for f in &report.record_shows {
            println!("the record shows: {}", f.text);
        }
        if !report.evidence_note.is_empty() {
            println!("evidence: {}", report.evidence_note);
        }
        if let Some(d) = &report.design {
            println!(
                "{} and {} are close (delta BIC gap {:.1}): what to measure next",
                d.first, d.second, d.observed_gap
            );
            println!(
                "  change                samples   expected delta BIC if {} true / if {} true",
                d.first, d.second
            );
            for o in &d.options {
                println!(
                    "  {:<20} {:>8}   {:>12.1} / {:<12.1}",
                    o.change, o.samples, o.if_first_true, o.if_second_true
                );
            }
            println!("  best: {}", d.best);
        }
        if report.missing.is_some() && !report.explained {
            println!(
                "  the named effect improves the fit but does not explain it: run `geodesic discover` \
                 to add effects round after round and describe what is left"
            );
        }
    }
    Ok(0)
}
