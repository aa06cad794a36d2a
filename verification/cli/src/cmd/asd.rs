//! `geodesic asd SERIES.yaml --requirement ID`: the amplitude spectral density of a time series
//! judged against a spectral requirement (issue 16, item 3), without running `verify`. Thin:
//! the estimator is `geodesic_fit::spectral`, the judgement `geodesic_checks::spectral`.
//! Exit 0 when the series meets the curve over the band, 1 when it does not, 2 on bad input.

use crate::error::{CliError, CmdResult};
use geodesic_fit::spectral::{self, Series, WelchOptions};
use geodesic_util::output::write_atomic;
use std::path::PathBuf;

/// Flags of `geodesic asd`.
#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:
  geodesic asd series.yaml --requirement ID --requirements missions/NAME/requirements --json
SERIES.yaml: `data` (CSV beside it), `time_column` (default t, seconds, uniformly sampled),
`channel` (the CSV column) and its `unit`; see docs/spectra.md.")]
pub struct Args {
    /// The series YAML.
    #[arg(value_name = "SERIES.yaml")]
    pub series: PathBuf,
    /// The spectral requirement to judge against.
    #[arg(long, value_name = "ID")]
    pub requirement: String,
    /// Directory of requirement YAML files [default: ./requirements if present, else the
    /// built-in set].
    #[arg(long, value_name = "DIR")]
    pub requirements: Option<PathBuf>,
    /// Samples per Welch segment [default: the power of two >= 4 fs / f_min of the band].
    #[arg(long, value_name = "N")]
    pub segment: Option<usize>,
    /// Overlap of the segments as a fraction.
    #[arg(long, default_value_t = 0.5)]
    pub overlap: f64,
    /// Also write the log-log plot (ASD, 95 % band, limit over the band) to FILE.svg.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let (reqs, _, _) = crate::missions::load_requirements(args.requirements.as_ref())?;
    let req = reqs.get(args.requirement.trim()).ok_or_else(|| {
        CliError::usage(format!(
            "--requirement {}: no such requirement is loaded",
            args.requirement
        ))
    })?;
    let (Some(lim), Some(spec)) = (&req.limit, &req.spectrum) else {
        return Err(CliError::usage(format!(
            "--requirement {}: not a spectral requirement (no `spectrum` under its limit)",
            req.id
        )));
    };
    if let Some(p) = &args.plot {
        geodesic_util::output::check_target(p)
            .map_err(|e| CliError::usage(format!("--plot {e}")))?;
    }
    let series = Series::load(&args.series).map_err(crate::error::from_fit)?;
    if series.dim != lim.dim {
        return Err(CliError::conflict(format!(
            "{}: the series is in `{}` ({}), {} bounds a {}",
            args.series.display(),
            series.unit,
            series.dim,
            req.id,
            lim.dim
        )));
    }
    let fs = 1.0 / series.dt_s;
    let n = args
        .segment
        .unwrap_or_else(|| spectral::default_nperseg(series.values.len(), fs, spec.band_hz[0]));
    let asd = spectral::welch(
        &series.values,
        fs,
        WelchOptions {
            nperseg: n,
            overlap: args.overlap,
        },
    )
    .map_err(|e| {
        CliError::invalid(format!("{}: {e}", args.series.display())).in_file(&args.series, 0)
    })?;
    let j = spectral::judge(&asd, spec, lim.value.value).map_err(|e| {
        CliError::invalid(format!("{}: {e}", args.series.display())).in_file(&args.series, 0)
    })?;
    if asd.segments < 4 {
        eprintln!(
            "geodesic: warning: {} segment(s) only ({:.1} dof per bin): each ASD bin scatters by about {:.0} %; a longer series gives a firmer verdict",
            asd.segments,
            asd.dof,
            100.0 * (1.0 / (2.0 * asd.dof)).sqrt()
        );
    }
    let scale = lim.unit.scale;
    let met = lim.op.holds(j.worst_ratio, 1.0);
    let per = |v: &[f64]| v.iter().map(|v| v / scale).collect::<Vec<_>>();
    let doc = spectral::AsdDoc {
        asd: per(&asd.asd),
        asd_at_worst: j.worst_asd / scale,
        asd_hi95: per(&asd.hi95),
        asd_lo95: per(&asd.lo95),
        band_hz: spec.band_hz,
        bins_judged: j.bins,
        dof_per_bin: asd.dof,
        f_hz: asd.f_hz.clone(),
        judged_hz: j.judged_hz,
        limit: lim.text.to_string(),
        limit_at_worst: j.worst_limit / scale,
        margin: 1.0 - j.worst_ratio,
        met,
        nperseg: asd.options.nperseg,
        overlap: asd.options.overlap,
        requirement: req.id.as_str().to_string(),
        sample_rate_hz: fs,
        samples: series.values.len(),
        segments: asd.segments,
        series: args.series.display().to_string(),
        shape: spec.shape_text.to_string(),
        unit: lim.unit.symbol.to_string(),
        value_referred_to_level: j.worst_ratio * lim.value.value / scale,
        window: asd.window.to_string(),
        worst_frequency_hz: j.worst_f_hz,
        worst_frequency_upper95_hz: j.worst_f_hi95_hz,
        worst_ratio: j.worst_ratio,
        worst_ratio_upper95: j.worst_ratio_hi95,
    };
    if let Some(p) = &args.plot {
        let svg = geodesic_checks::spectral::asd_svg(req, &asd).map_err(CliError::io)?;
        write_atomic(p, svg.as_bytes())?;
    }
    if args.json {
        let text = serde_json::to_string_pretty(&doc).map_err(CliError::io)?;
        println!("{text}");
    } else {
        println!(
            "{}: {} samples at {:.4e} Hz, Welch Hann {} x {} samples ({:.0} % overlap, {:.1} dof per bin)",
            args.series.display(),
            series.values.len(),
            fs,
            asd.segments,
            asd.options.nperseg,
            asd.options.overlap * 100.0,
            asd.dof
        );
        println!(
            "{} {} x ({}) over {}: {} bins judged ({:.4e} .. {:.4e} Hz)",
            req.id,
            lim.text,
            spec.shape_text,
            spec.band_text,
            j.bins,
            j.judged_hz[0],
            j.judged_hz[1]
        );
        println!(
            "worst ratio ASD / limit {:.4} at {:.4e} Hz ({:.4e} against {:.4e} {}), margin {:.1} %; upper 95 % bound: {:.4} at {:.4e} Hz",
            j.worst_ratio,
            j.worst_f_hz,
            j.worst_asd / scale,
            j.worst_limit / scale,
            lim.unit.symbol,
            100.0 * (1.0 - j.worst_ratio),
            j.worst_ratio_hi95,
            j.worst_f_hi95_hz
        );
        println!("{}", if met { "met" } else { "NOT MET" });
    }
    Ok(if met { 0 } else { 1 })
}
