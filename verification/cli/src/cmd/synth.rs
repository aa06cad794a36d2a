//! `geodesic synth`: writes a synthetic dataset (YAML + CSV + truth JSON) from a truth model
//! built from the effect catalogue, with seeded white noise.

use std::collections::BTreeMap;
use std::path::PathBuf;

use geodesic_facility::{Scenario, TipProfile};
use geodesic_fit::synth::{SynthSpec, generate, write};

use crate::error::{CliError, CmdResult};

/// Flags of `geodesic synth`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scenario: tmmf-release or rt-retraction.
    #[arg(long)]
    pub scenario: String,
    /// Truth effects, comma separated.
    #[arg(long, value_delimiter = ',', required = true)]
    pub effects: Vec<String>,
    /// Truth parameter: effect.param=VALUE (SI), repeatable; others are nominal.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub param: Vec<String>,
    /// Known constant: NAME=VALUE (m [kg], E0 [V]), repeatable.
    #[arg(long = "known", value_name = "NAME=VALUE")]
    pub known: Vec<String>,
    /// 1-sigma white noise per channel: CHANNEL=VALUE [m], repeatable.
    #[arg(long = "noise", value_name = "CHANNEL=VALUE")]
    pub noise: Vec<String>,
    /// Leave the noise figures out of the YAML (the fit must estimate them).
    #[arg(long)]
    pub no_noise_in_yaml: bool,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Sampling frequency [Hz] (default: the scenario's examples).
    #[arg(long, value_parser = crate::quantity::frequency())]
    pub fs: Option<f64>,
    /// Record before the trigger [s].
    #[arg(long, value_parser = crate::quantity::time())]
    pub pre: Option<f64>,
    /// Record after the trigger [s].
    #[arg(long, value_parser = crate::quantity::time())]
    pub post: Option<f64>,
    /// Tip profile jerk [m/s^3] (tmmf-release).
    #[arg(long, value_parser = crate::quantity::jerk())]
    pub jerk: Option<f64>,
    /// Tip profile final speed [m/s] (tmmf-release).
    #[arg(long, value_parser = crate::quantity::velocity())]
    pub v: Option<f64>,
    /// Output YAML path (CSV and truth JSON are written beside it).
    #[arg(long)]
    pub out: PathBuf,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

fn pairs(
    list: &[String],
    flag: &str,
    dim_of: impl Fn(&str) -> Option<geodesic_core::units::Dim> + Copy,
) -> Result<BTreeMap<String, f64>, CliError> {
    let mut m = BTreeMap::new();
    for s in list {
        let (k, v) = crate::quantity::pair(s, flag, dim_of)?;
        m.insert(k, v);
    }
    Ok(m)
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let scenario = Scenario::from_name(&args.scenario).ok_or_else(|| {
        CliError::bad(format!(
            "unknown scenario `{}` (tmmf-release, rt-retraction)",
            args.scenario
        ))
    })?;
    let effects: Vec<&str> = args.effects.iter().map(|s| s.trim()).collect();
    let mut spec = SynthSpec::defaults(scenario, &effects);
    spec.params = pairs(&args.param, "param", crate::quantity::param_dim)?;
    spec.known
        .extend(pairs(&args.known, "known", crate::quantity::channel_dim)?);
    let noise = pairs(&args.noise, "noise", crate::quantity::channel_dim)?;
    if !noise.is_empty() {
        spec.noise.extend(noise);
    }
    spec.noise_in_yaml = !args.no_noise_in_yaml;
    spec.seed = args.seed;
    spec.fs_hz = args.fs.unwrap_or(spec.fs_hz);
    spec.pre_s = args.pre.unwrap_or(spec.pre_s);
    spec.post_s = args.post.unwrap_or(spec.post_s);
    spec.profile = TipProfile {
        jerk_m_s3: args.jerk.unwrap_or(spec.profile.jerk_m_s3),
        v_m_s: args.v.unwrap_or(spec.profile.v_m_s),
    };
    let name = args
        .out
        .file_name()
        .map_or("synth.yaml".into(), |s| s.to_string_lossy().to_string());
    let task = crate::progress::Task::spinner(args.json, "synth: generating the record");
    let ds = generate(&spec, &name).map_err(|e| CliError::bad(e.to_string()));
    task.finish();
    let ds = ds?;
    let files = write(&ds, &spec, &args.out).map_err(|e| CliError::Io(e.to_string()))?;
    if args.json {
        let doc = serde_json::json!({
            "yaml": files[0].display().to_string(),
            "csv": files[1].display().to_string(),
            "truth": files[2].display().to_string(),
            "rows": ds.t.len(),
            "spec": spec,
        });
        println!("{doc}");
    } else {
        println!(
            "wrote {} rows: {}",
            ds.t.len(),
            files
                .iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    Ok(0)
}
