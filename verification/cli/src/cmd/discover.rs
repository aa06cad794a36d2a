//! `geodesic discover DATASET.yaml --effects BASELINE`: the discovery loop (issue 13,
//! interface.md): round after round, diagnose, add the effect the evidence supports, refit, test
//! removing earlier additions; stop when the residual is noise or nothing is justified; then say
//! whether the model explains the data and describe what is left. Thin: the loop is in
//! `geodesic_fit::discover`.

use crate::cmd::fit::{effect_list, fits_under, load, options, outputs, summary, warn};
use crate::error::{CliError, CmdResult};
use geodesic_fit::discover::{DiscoverOptions, discover};
use std::path::PathBuf;

/// Flags of `geodesic discover`.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  geodesic discover data/examples/tmmf-adhesion.yaml --effects needle_contact,tip_contact\n  geodesic discover data/examples/rt-plunger.yaml --effects piezo --json\n\
Each round's fit goes into the fit history (geodesic history) and its plot into DIR/fits/.\n\
explained: true when the final residual is consistent with the noise (chi2_red within\n\
1 + 5 sqrt(2/nu) and a white residual); otherwise no catalogue effect is named and the\n\
residual is described (windows, spectral peaks, correlations with the model's states, terms)."
)]
pub struct Args {
    /// Dataset YAML.
    pub dataset: PathBuf,
    /// The baseline model's effects, comma separated.
    #[arg(long, value_delimiter = ',', required = true)]
    pub effects: Vec<String>,
    /// Most rounds that add an effect.
    #[arg(long, default_value_t = 4)]
    pub max_rounds: usize,
    /// Hold a parameter fixed: effect.param=VALUE (SI or with a unit), repeatable.
    #[arg(long = "fix", value_name = "NAME=VALUE")]
    pub fix: Vec<String>,
    /// Bound a parameter: effect.param=LO:HI, repeatable.
    #[arg(long = "bound", value_name = "NAME=LO:HI")]
    pub bound: Vec<String>,
    /// Reports folder: plots and the history go into DIR/fits/.
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
    /// Refuse a record with a missing value (an empty cell) or a wild sample instead of
    /// skipping that row with a warning.
    #[arg(long)]
    pub strict: bool,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
    /// Write a new effect NAME (snake_case) from the leading term outside the catalogue into
    /// the catalogue: its file under models/facility/src/effects/, its registration, its hiding
    /// test and guard-list entry (run from the repository's root; rebuild, then discover again).
    #[arg(long, value_name = "NAME")]
    pub scaffold: Option<String>,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    // --scaffold: the name and the repository checked before any computation
    if let Some(name) = &args.scaffold {
        scaffold_preflight(name)?;
    }
    let fits = fits_under(&args.reports, None)?;
    let fit = options(&args.fix, &args.bound)?;
    let prep = load(&args.dataset, args.strict)?;
    let effects = effect_list(&args.effects);
    let mut task = crate::progress::Task::spinner(
        args.json,
        &format!(
            "discover: {} samples from {}",
            prep.dataset.t.len(),
            effects.join("+")
        ),
    );
    let opts = DiscoverOptions {
        fit,
        max_rounds: args.max_rounds,
    };
    geodesic_fit::progress::set_hook(task.fit_hook());
    let r = discover(&prep, &effects, &opts, |m| {
        task.set_label(&format!("discover: {m}"))
    })
    .map_err(|e| CliError::bad(e.to_string()));
    geodesic_fit::progress::set_hook(None);
    task.finish();
    let (mut report, last, all) = r?;
    // every round's fit into the history and its plot, in order
    for o in &all {
        let mut fr = geodesic_fit::FitReport::new(&prep, o);
        outputs(&prep, &o.pred, &mut fr, &fits)?;
    }
    let mut fr = report.final_fit.clone();
    geodesic_fit::outliers::flag_user_bounds(&mut fr, &opts.fit.bounds);
    warn(&fr);
    let svg = geodesic_fit::plot::fit_svg(&prep, &last.pred, &fr)
        .map_err(|e| CliError::Io(e.to_string()))?;
    let path = fits.join(format!("{}.discover.svg", prep.dataset.stem()));
    geodesic_fit::plot::write_svg(&path, &svg).map_err(|e| CliError::Io(e.to_string()))?;
    fr.svg = Some(path.display().to_string());
    report.final_fit = fr;
    let scaffolded = match &args.scaffold {
        Some(name) => Some(scaffold(name, &args.dataset, &prep, &report)?),
        None => None,
    };
    if args.json {
        let mut v = serde_json::to_value(&report).map_err(|e| CliError::Io(e.to_string()))?;
        if let (Some(s), Some(obj)) = (&scaffolded, v.as_object_mut()) {
            obj.insert("scaffold".into(), s.json.clone());
        }
        println!(
            "{}",
            serde_json::to_string(&v).map_err(|e| CliError::Io(e.to_string()))?
        );
        return Ok(0);
    }
    println!(
        "round  model                                        chi2_red    delta_bic   margin  added / removed"
    );
    for (k, r) in report.rounds.iter().enumerate() {
        let fmt = |v: Option<f64>| v.map_or("-".to_string(), geodesic_fit::outliers::fmt_sig);
        println!(
            "{k:>5}  {:<44} {:>9} {:>12} {:>8}  {}{}",
            r.effects.join("+"),
            geodesic_fit::outliers::fmt_sig(r.chi2_red),
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
    print!("{}", summary(&report.final_fit));
    println!("explained: {} ({})", report.explained, report.reason);
    for i in &report.improves {
        println!(
            "  {} improves the fit (delta BIC {:.1}, chi2_red {:.3}) but does not explain it",
            i.effect, i.delta_bic, i.chi2_red
        );
    }
    let d = &report.residual;
    for w in &d.windows {
        println!(
            "  window {} {:.4e}..{:.4e} s ({}): peak {:.3e} ({} sigma)",
            w.failure.channel,
            w.failure.t_start,
            w.failure.t_end,
            w.phase,
            w.failure.peak,
            geodesic_fit::outliers::fmt_sig(w.failure.peak_sigma)
        );
    }
    for p in &d.peaks {
        println!(
            "  peak {} {:.4e} Hz, amplitude {:.3e}, {} x the floor",
            p.channel,
            p.hz,
            p.amplitude,
            geodesic_fit::outliers::fmt_sig(p.over_floor)
        );
    }
    for c in d.correlations.iter().take(3) {
        println!("  correlation with {}: r = {:+.3}", c.state, c.r);
    }
    if let Some(l) = &d.leading {
        println!("  {l}");
    }
    for t in &d.terms {
        println!(
            "  term [{}] {}: {:+.3e} +- {:.2e} {} (delta BIC {})",
            t.kind,
            t.term,
            t.coefficient,
            t.sigma,
            t.coefficient_unit,
            geodesic_fit::outliers::fmt_sig(t.delta_bic)
        );
    }
    if let Some(a) = &d.indistinguishable.first() {
        println!(
            "  indistinguishable on this record: {} (joint fits within 10 in BIC of {a}'s)",
            d.indistinguishable.join(", ")
        );
    }
    for t in &report.thresholds {
        let assumes: Vec<String> = t
            .assumes
            .iter()
            .map(|(k, v)| format!("{k} = {v:.3e}"))
            .collect();
        println!(
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
            println!(
                "    threshold along the other parameter: {}",
                pts.join("; ")
            );
        }
    }
    if let Some(s) = &scaffolded {
        print!("{}", s.text);
    }
    Ok(0)
}

/// What `--scaffold` wrote: lines for the terminal and the `scaffold` object of `--json`.
struct Scaffolded {
    text: String,
    json: serde_json::Value,
}

/// `--scaffold NAME` before any computation: the name (snake_case, not in the catalogue, no
/// file of that name) and the working directory (the repository's root).
fn scaffold_preflight(name: &str) -> Result<(), CliError> {
    use geodesic_fit::scaffold;
    let root = std::path::Path::new(".");
    scaffold::check_root(root).map_err(CliError::bad)?;
    scaffold::check_name(name, Some(&root.join(scaffold::EFFECTS_DIR))).map_err(CliError::bad)
}

/// `--scaffold NAME` after the discovery: the effect from the leading term outside the
/// catalogue, every file written or none (issue 36).
fn scaffold(
    name: &str,
    dataset: &std::path::Path,
    prep: &geodesic_fit::fit::Prepared,
    report: &geodesic_fit::discover::DiscoverReport,
) -> Result<Scaffolded, CliError> {
    use geodesic_fit::scaffold::{self, Conditions, Scaffold, lit};
    let root = std::path::Path::new(".");
    let bad = |e: String| CliError::bad(format!("--scaffold {name}: {e}"));
    if report.explained {
        return Err(bad(format!(
            "{} is explained by the catalogue ({}): no term outside the catalogue to scaffold",
            dataset.display(),
            report.reason
        )));
    }
    let Some(lead) = report.residual.terms.first() else {
        return Err(bad(format!(
            "discover found no term outside the catalogue in {}: nothing to scaffold",
            dataset.display()
        )));
    };
    let ds = &prep.dataset;
    let t = &ds.t;
    let mut dts: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    dts.sort_by(f64::total_cmp);
    let dt = dts.get(dts.len() / 2).copied().unwrap_or(1e-5);
    let post_s = t.last().copied().unwrap_or(0.0).max(dt);
    // the hiding test's record: the record's sampling, at most 20 000 samples after the trigger
    let fs_hz = (1.0 / dt).min(20_000.0 / post_s);
    let channel = ds.scenario.fitted_channel();
    let noise = report
        .final_fit
        .noise
        .get(channel)
        .or_else(|| ds.noise.get(channel))
        .copied()
        .filter(|v| v.is_finite() && *v > 0.0)
        .unwrap_or(1e-9);
    // the scenario's first known constant (the TM mass, the initial voltage), as loaded
    let known = ds
        .scenario
        .required_known()
        .first()
        .map_or(("", 0.0), |&k| (k, ds.known.get(k).copied().unwrap_or(0.0)));
    let conditions = Conditions {
        fs_hz,
        post_s,
        known,
        noise,
        jerk_m_s3: prep.inputs.profile.jerk_m_s3,
        v_m_s: prep.inputs.profile.v_m_s,
    };
    let record = dataset.display().to_string();
    let s = Scaffold::from_term(
        name,
        ds.scenario,
        lead,
        &record,
        &report.residual.indistinguishable,
        &scaffold::today(),
        conditions,
    )
    .map_err(bad)?;
    let mut edits = s.edits(root).map_err(bad)?;
    for (_, text) in edits.iter_mut() {
        *text = scaffold::rustfmt(text, root).map_err(bad)?;
    }
    scaffold::write_all(&edits).map_err(|e| CliError::Io(format!("--scaffold {name}: {e}")))?;
    let files: Vec<String> = edits
        .iter()
        .map(|(p, _)| p.strip_prefix(root).unwrap_or(p).display().to_string())
        .collect();
    let mut text = format!(
        "scaffold: wrote the effect `{name}` ({}: {}) from the leading term [{}] (delta BIC {:.1}):\n",
        s.scenario.name(),
        s.law(),
        s.kind,
        s.delta_bic
    );
    for p in &s.params {
        text.push_str(&format!(
            "  {name}.{} = {} {} (range {} .. {})\n",
            p.name,
            lit(p.nominal),
            p.unit,
            lit(p.lower),
            lit(p.upper)
        ));
    }
    for f in &files {
        text.push_str(&format!("  wrote {f}\n"));
    }
    let baseline = report
        .rounds
        .first()
        .map(|r| r.effects.join(","))
        .unwrap_or_default();
    text.push_str(&format!(
        "next: cargo build --release -p geodesic; geodesic discover {record} --effects {baseline}; cargo test --release -p geodesic-fit --test hide_each hidden_{name}\n"
    ));
    let params: serde_json::Map<String, serde_json::Value> = s
        .params
        .iter()
        .map(|p| {
            (
                format!("{name}.{}", p.name),
                serde_json::json!({"value": p.nominal, "unit": p.unit, "lower": p.lower, "upper": p.upper}),
            )
        })
        .collect();
    let json = serde_json::json!({
        "name": name,
        "kind": s.kind,
        "scenario": s.scenario.name(),
        "delta_bic": s.delta_bic,
        "params": params,
        "files": files,
    });
    Ok(Scaffolded { text, json })
}
