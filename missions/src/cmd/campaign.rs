//! `geodesic campaign DIR|CAMPAIGN.yaml --effects E`: fits every release of a campaign in
//! parallel, tabulates P_x, F_peak and dt as a campaign report does, and estimates the adhesion
//! population with the measurement errors deconvolved (issue 14; interface.md). A command of
//! LISA Pathfinder (the campaign's adhesion population feeds its release budget). Thin: the
//! work is in `geodesic_campaign`.

use crate::error::{CliError, CmdResult};
use geodesic_verify::progress;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Flags of `geodesic campaign`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A folder of release datasets (every YAML with `scenario:`) or a campaign YAML with
    /// `releases: [file, ...]`.
    #[arg(value_name = "DIR_OR_LIST")]
    pub campaign: PathBuf,
    /// Effects of the model, comma separated (e.g. needle_contact,tip_contact; `geodesic
    /// effects` lists them).
    #[arg(long, value_delimiter = ',', required = true)]
    pub effects: Vec<String>,
    /// Hold a parameter fixed: effect.param=VALUE (SI or with a unit), repeatable.
    #[arg(long = "fix", value_name = "NAME=VALUE")]
    pub fix: Vec<String>,
    /// Bound a parameter: effect.param=LO:HI (SI or with a unit), repeatable.
    #[arg(long = "bound", value_name = "NAME=LO:HI")]
    pub bound: Vec<String>,
    /// Seed of the bootstrap of the A1-lambda correlation's interval.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Reports folder, as for `verify`: the campaign's page (campaign.md, campaign.json,
    /// histograms.svg, adhesion.svg) goes into DIR/campaign/, written as a whole set.
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
    /// Not a flag of this command (`--out` names one output file everywhere in geodesic).
    #[arg(long, hide = true)]
    pub out: Option<PathBuf>,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let opts = options(&args.fix, &args.bound)?;
    if let Some(o) = &args.out {
        return Err(CliError::usage(format!(
            "--out {}: in geodesic --out names one output file; the campaign's page goes under \
             --reports DIR (into DIR/campaign/)",
            o.display()
        )));
    }
    let page_dir = args.reports.join("campaign");
    // a bad reports folder fails now, not after the fits
    let staging = geodesic_report::write::Staging::new(&page_dir)
        .map_err(|e| CliError::usage(format!("--reports: {e}")))?;
    let files = geodesic_campaign::list(&args.campaign)
        .map_err(|e| CliError::unreadable(e.to_string()).in_file(&args.campaign, 0))?;
    let effects: Vec<&str> = args
        .effects
        .iter()
        .map(|s| s.trim())
        .filter(|s| !s.is_empty())
        .collect();
    let task = progress::Task::counter(args.json, "campaign: releases fitted", files.len() as u64);
    let r = geodesic_campaign::run(&files, &effects, &opts, args.seed, &|| task.inc(1));
    task.finish();
    let json = serde_json::to_string(&r).map_err(CliError::io)?;
    let mut plots = vec!["histograms.svg"];
    let io = |e: geodesic_fit::FitError| CliError::io(e);
    staging
        .write(
            "histograms.svg",
            geodesic_campaign::page::histograms_svg(&r)
                .map_err(io)?
                .as_bytes(),
        )
        .map_err(CliError::io)?;
    if let Some(svg) = geodesic_campaign::page::adhesion_svg(&r).map_err(io)? {
        staging
            .write("adhesion.svg", svg.as_bytes())
            .map_err(CliError::io)?;
        plots.push("adhesion.svg");
    }
    let md = geodesic_campaign::page::markdown(
        &r,
        &args.campaign.display().to_string(),
        &effects,
        &plots,
    );
    for (name, bytes) in [
        ("campaign.md", md.as_bytes()),
        ("campaign.json", json.as_bytes()),
    ] {
        staging.write(name, bytes).map_err(CliError::io)?;
    }
    staging.commit().map_err(CliError::io)?;
    for f in &r.failed {
        eprintln!(
            "geodesic: {}: not fitted: {}",
            f.file,
            geodesic_util::text::one_line(&f.cause)
        );
    }
    if args.json {
        println!("{json}");
    } else {
        println!(
            "{} releases fitted, {} failed ({})",
            r.releases.len(),
            r.failed.len(),
            args.campaign.display()
        );
        println!(
            "quantity        source    mean         sd           sd of mean   min          max"
        );
        for (q, m) in &r.table {
            for (src, s) in m {
                match s {
                    Some(s) => println!(
                        "{q:<15} {src:<8} {:>12.4e} {:>12.4e} {:>12.4e} {:>12.4e} {:>12.4e}",
                        s.mean, s.sd, s.sd_mean, s.min, s.max
                    ),
                    None => println!(
                        "{q:<15} {src:<8} (not derived from the data: see docs/fitting.md)"
                    ),
                }
            }
        }
        if let Some(obj) = r.population.as_object() {
            for (k, v) in obj {
                if k == "correlation" {
                    match (
                        v.get(geodesic_campaign::PAIR).and_then(|x| x.as_f64()),
                        r.correlation_ci95.get(geodesic_campaign::PAIR),
                    ) {
                        (Some(x), Some([lo, hi])) => println!(
                            "population correlation A1-lambda: {x:+.3} (95 % bootstrap [{lo:+.3}, {hi:+.3}])"
                        ),
                        (Some(x), None) => println!("population correlation A1-lambda: {x:+.3}"),
                        _ => println!("population correlation A1-lambda: not estimated"),
                    }
                } else {
                    println!(
                        "population {k}: mean {:.4e} +- {:.2e}, sd {:.4e} +- {:.2e} ({} releases)",
                        v["mean"].as_f64().unwrap_or(f64::NAN),
                        v["mean_sigma"].as_f64().unwrap_or(f64::NAN),
                        v["sd"].as_f64().unwrap_or(f64::NAN),
                        v["sd_sigma"].as_f64().unwrap_or(f64::NAN),
                        v["n"]
                    );
                }
            }
        }
        println!(
            "campaign page: {} (campaign.md, campaign.json, {})",
            page_dir.display(),
            plots.join(", ")
        );
    }
    Ok(if r.failed.is_empty() { 0 } else { 2 })
}

/// The fit options of `--fix` and `--bound`, each value SI or with the unit of its parameter in
/// the effect catalogue (as the framework's fit commands read them).
fn options(fix: &[String], bound: &[String]) -> Result<geodesic_fit::FitOptions, CliError> {
    use geodesic_discover::session::param_dim;
    use geodesic_verify::quantity::pair;
    let mut fixed = BTreeMap::new();
    for f in fix {
        let (k, v) = pair(f, "fix", param_dim)?;
        fixed.insert(k, v);
    }
    let mut bounds = BTreeMap::new();
    for b in bound {
        let (k, r) = geodesic_verify::quantity::bound(b, param_dim)?;
        bounds.insert(k, r);
    }
    Ok(geodesic_fit::FitOptions {
        fixed,
        bounds,
        max_starts: None,
        profile: false,
        sigma: None,
        sigma_source: None,
        observer: Default::default(),
    })
}
