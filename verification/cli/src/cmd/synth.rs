//! `geodesic synth`: writes a synthetic dataset (YAML + CSV + truth JSON) from a truth model
//! built from the effect catalogue, with seeded white noise.

use std::collections::BTreeMap;
use std::path::PathBuf;

use geodesic_dataset::synth::{SynthSpec, generate, write};
use geodesic_facility::{Scenario, TipProfile};

use crate::error::{CliError, CmdResult};

/// Flags of `geodesic synth`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scenario: tmmf-release or rt-retraction.
    #[arg(long, required_unless_present = "campaign")]
    pub scenario: Option<String>,
    /// Truth effects, comma separated.
    #[arg(long, value_delimiter = ',', required_unless_present = "campaign")]
    pub effects: Vec<String>,
    /// Write a campaign of N TMMF releases (needle_contact, tip_contact, tip_adhesion) into the
    /// folder --out, A1 and lambda drawn from a known population (--a1, --lambda, --rho), the
    /// preload, tip speed and noise varying; writes campaign.yaml and truth.json there.
    #[arg(long, value_name = "N")]
    pub campaign: Option<usize>,
    /// Campaign population of A1: MEAN:SD [N/m].
    #[arg(long, value_name = "MEAN:SD")]
    pub a1: Option<String>,
    /// Campaign population of lambda: MEAN:SD [m].
    #[arg(long, value_name = "MEAN:SD")]
    pub lambda: Option<String>,
    /// Campaign population correlation of A1 and lambda.
    #[arg(long, allow_hyphen_values = true)]
    pub rho: Option<f64>,
    /// Truth parameter: effect.param=VALUE (SI), repeatable; others are nominal.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub param: Vec<String>,
    /// Known constant: NAME=VALUE (m [kg], E0 [V]), repeatable.
    #[arg(long = "known", value_name = "NAME=VALUE")]
    pub known: Vec<String>,
    /// 1-sigma white noise per channel: CHANNEL=VALUE [m], repeatable.
    #[arg(long = "noise", value_name = "CHANNEL=VALUE")]
    pub noise: Vec<String>,
    /// Coloured noise: AR(1) coefficient per channel, CHANNEL=PHI with |PHI| < 1 (the channel's
    /// --noise is then the noise's own 1-sigma), repeatable. Use with --no-noise-in-yaml: a
    /// YAML noise figure states white noise.
    #[arg(long = "noise-ar", value_name = "CHANNEL=PHI")]
    pub noise_ar: Vec<String>,
    /// Leave the noise figures out of the YAML (the fit must estimate them).
    #[arg(long)]
    pub no_noise_in_yaml: bool,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Sampling frequency [Hz] (default: the scenario's examples).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::positive(crate::quantity::frequency(), "a sampling frequency"))]
    pub fs: Option<f64>,
    /// Record before the trigger [s].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::non_negative(crate::quantity::time(), "the record before the trigger"))]
    pub pre: Option<f64>,
    /// Record after the trigger [s].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::positive(crate::quantity::time(), "the record after the trigger"))]
    pub post: Option<f64>,
    /// Tip profile jerk [m/s^3] (tmmf-release).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::positive(crate::quantity::jerk(), "the tip profile's jerk"))]
    pub jerk: Option<f64>,
    /// Tip profile final speed [m/s] (tmmf-release).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::positive(crate::quantity::velocity(), "the tip profile's final speed"))]
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
    if let Some(n) = args.campaign {
        return campaign(&args, n);
    }
    let scenario_name = args.scenario.clone().unwrap_or_default();
    let scenario = Scenario::from_name(&scenario_name).ok_or_else(|| {
        CliError::usage(format!(
            "--scenario {scenario_name}: unknown scenario (tmmf-release, rt-retraction)"
        ))
    })?;
    let effects: Vec<&str> = args.effects.iter().map(|s| s.trim()).collect();
    // the flag named with what it names wrongly
    let known: Vec<&str> = geodesic_facility::effects::catalogue()
        .iter()
        .filter(|e| e.scenario() == scenario)
        .map(|e| e.name())
        .collect();
    if let Some(bad) = effects.iter().find(|e| !known.contains(e)) {
        return Err(CliError::unknown_effect(format!(
            "--effects {bad}: unknown effect for {} (known: {})",
            scenario.name(),
            known.join(", ")
        )));
    }
    let mut spec = SynthSpec::defaults(scenario, &effects);
    spec.params = pairs(&args.param, "param", crate::quantity::param_dim)?;
    spec.known
        .extend(pairs(&args.known, "known", crate::quantity::channel_dim)?);
    let noise = pairs(&args.noise, "noise", crate::quantity::channel_dim)?;
    if !noise.is_empty() {
        spec.noise.extend(noise);
    }
    spec.noise_in_yaml = !args.no_noise_in_yaml;
    spec.noise_ar = pairs(&args.noise_ar, "noise-ar", |_| {
        Some(geodesic_core::units::Dim::DIMENSIONLESS)
    })?;
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
    crate::preflight::out_file_in_new_dir("--out", &args.out)?;
    let task = crate::progress::Task::spinner(args.json, "synth: generating the record");
    let ds = generate(&spec, &name).map_err(crate::error::from_fit);
    task.finish();
    let ds = ds?;
    let files = write(&ds, &spec, &args.out).map_err(CliError::io)?;
    if args.json {
        let doc =
            serde_json::to_string(&geodesic_dataset::synth::SynthDoc::new(&ds, &spec, &files))
                .map_err(CliError::io)?;
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

fn mean_sd(flag: &str, v: &Option<String>, default: (f64, f64)) -> Result<(f64, f64), CliError> {
    let Some(v) = v else { return Ok(default) };
    let bad = || {
        CliError::usage(format!(
            "--{flag} {v}: expected MEAN:SD, two finite numbers in SI, SD >= 0"
        ))
    };
    let (a, b) = v.split_once(':').ok_or_else(bad)?;
    let (m, s): (f64, f64) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if !(m.is_finite() && s.is_finite() && m > 0.0 && s >= 0.0) {
        return Err(bad());
    }
    Ok((m, s))
}

/// `synth --campaign N --out DIR`: N TMMF releases from a known adhesion population.
fn campaign(args: &Args, n: usize) -> CmdResult {
    use geodesic_dataset::synth::{CampaignTruth, ReleaseTruth, TruePopulation, draw_release};
    if n == 0 || n > 10_000 {
        return Err(CliError::usage(format!(
            "--campaign {n}: between 1 and 10 000 releases"
        )));
    }
    if args
        .scenario
        .as_deref()
        .is_some_and(|s| s != "tmmf-release")
    {
        return Err(CliError::usage(
            "--campaign writes tmmf-release campaigns (a campaign of TMMF releases)",
        ));
    }
    let d = TruePopulation::default();
    let (a1_mean, a1_sd) = mean_sd("a1", &args.a1, (d.a1_mean, d.a1_sd))?;
    let (lambda_mean, lambda_sd) = mean_sd("lambda", &args.lambda, (d.lambda_mean, d.lambda_sd))?;
    let rho = args.rho.unwrap_or(0.0);
    if !(rho.is_finite() && (-1.0..=1.0).contains(&rho)) {
        return Err(CliError::usage(format!(
            "--rho {rho}: a correlation in [-1, 1]"
        )));
    }
    let pop = TruePopulation {
        a1_mean,
        a1_sd,
        lambda_mean,
        lambda_sd,
        rho,
    };
    let dir = &args.out;
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::usage(format!(
            "--out {}: with --campaign, a folder",
            dir.display()
        )));
    }
    std::fs::create_dir_all(dir).map_err(|e| CliError::io_at(dir, e))?;
    let effects = ["needle_contact", "tip_contact", "tip_adhesion"];
    let task = crate::progress::Task::counter(args.json, "synth: campaign releases", n as u64);
    let mut names = Vec::new();
    let mut truth = Vec::new();
    for i in 0..n {
        let (a1, lambda, f_pre, v, noise) = draw_release(&pop, args.seed, i as u64);
        let mut spec = SynthSpec::defaults(Scenario::TmmfRelease, &effects);
        spec.params.insert("tip_adhesion.A1".into(), a1);
        spec.params.insert("tip_adhesion.lambda".into(), lambda);
        spec.params.insert("needle_contact.F_pre".into(), f_pre);
        spec.noise.insert("x".into(), noise);
        spec.seed = args.seed.wrapping_mul(1_000_003).wrapping_add(i as u64);
        spec.fs_hz = args.fs.unwrap_or(1e5);
        spec.pre_s = args.pre.unwrap_or(5e-4);
        spec.post_s = args.post.unwrap_or(4e-3);
        spec.profile = TipProfile {
            jerk_m_s3: args.jerk.unwrap_or(spec.profile.jerk_m_s3),
            v_m_s: v,
        };
        let name = format!("release-{:03}.yaml", i + 1);
        let ds = generate(&spec, &name).map_err(crate::error::from_fit)?;
        write(&ds, &spec, &dir.join(&name)).map_err(CliError::io)?;
        truth.push(ReleaseTruth {
            file: name.clone(),
            f_pre_n: f_pre,
            noise_x_m: noise,
            a1_n_m: a1,
            lambda_m: lambda,
            tip_speed_m_s: v,
        });
        names.push(name);
        task.inc(1);
    }
    task.finish();
    let list = format!(
        "description: synthetic TMMF campaign of {n} releases (geodesic synth --campaign, seed {})\nreleases:\n{}",
        args.seed,
        names
            .iter()
            .map(|n| format!("  - {n}\n"))
            .collect::<String>()
    );
    geodesic_util::output::write_atomic(&dir.join("campaign.yaml"), list.as_bytes())?;
    let doc = CampaignTruth {
        population: pop,
        releases: truth,
        seed: args.seed,
    };
    let text = serde_json::to_string_pretty(&doc).map_err(CliError::io)?;
    geodesic_util::output::write_atomic(&dir.join("truth.json"), text.as_bytes())?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string(&geodesic_dataset::synth::SynthCampaignDoc {
                campaign: dir.join("campaign.yaml").display().to_string(),
                releases: n,
                truth: dir.join("truth.json").display().to_string(),
            })
            .map_err(CliError::io)?
        );
    } else {
        println!(
            "wrote {n} releases, campaign.yaml and truth.json into {}",
            dir.display()
        );
    }
    Ok(0)
}
