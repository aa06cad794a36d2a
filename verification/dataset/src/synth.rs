//! `synth`: synthetic datasets from a truth model built from the same effect code as the fit,
//! with seeded white noise (or AR(1) coloured noise, `noise_ar`). Used by the tests that hide each effect in turn.
//!
//! With `oversample = K > 1` the truth differs from the fitted model's own evaluation: it is
//! simulated at `K` sub-samples per sample (and, for `tmmf-release`, with an RK4 step `K` times
//! smaller), and each sample is the mean of its `K` sub-samples, centred on the sample time (an
//! integrating converter) - both channels.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use geodesic_facility::model::Inputs;
use geodesic_facility::{Model, Scenario, TipProfile};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

use crate::dataset::Dataset;
use crate::error::{FitError, write_atomic};

/// What to synthesise.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct SynthSpec {
    /// Scenario.
    pub scenario: String,
    /// Truth effects.
    pub effects: Vec<String>,
    /// Parameter values overriding the nominal ones (`effect.param` -> SI).
    pub params: BTreeMap<String, f64>,
    /// Known constants (`m` [kg] for tmmf-release, `E0` [V] for rt-retraction).
    pub known: BTreeMap<String, f64>,
    /// 1-sigma white noise per channel [SI].
    pub noise: BTreeMap<String, f64>,
    /// Write the noise figures into the YAML.
    pub noise_in_yaml: bool,
    /// Coloured noise: the AR(1) coefficient per channel (`n_i = phi n_{i-1} + e_i`, the
    /// channel's `noise` its marginal 1-sigma); absent channels have white noise.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub noise_ar: BTreeMap<String, f64>,
    /// Sampling frequency [Hz].
    pub fs_hz: f64,
    /// Record before the trigger [s].
    pub pre_s: f64,
    /// Record after the trigger [s].
    pub post_s: f64,
    /// Tip profile (`tmmf-release`).
    pub profile: TipProfile,
    /// Noise seed.
    pub seed: u64,
    /// Sub-samples per sample of the truth (1: the fit's own sampling and integration step).
    #[serde(default = "one")]
    pub oversample: usize,
}

fn one() -> usize {
    1
}

impl SynthSpec {
    /// Defaults of a scenario: the public examples' sampling and noise, nominal parameters.
    pub fn defaults(scenario: Scenario, effects: &[&str]) -> SynthSpec {
        let d = scenario.synth_defaults();
        let pairs = |v: &[(&str, f64)]| -> BTreeMap<String, f64> {
            v.iter().map(|(k, x)| (k.to_string(), *x)).collect()
        };
        let (known, noise, fs, pre, post) =
            (pairs(d.known), pairs(d.noise), d.fs_hz, d.pre_s, d.post_s);
        SynthSpec {
            scenario: scenario.name().to_string(),
            effects: effects.iter().map(|s| s.to_string()).collect(),
            params: BTreeMap::new(),
            known,
            noise,
            noise_in_yaml: true,
            noise_ar: BTreeMap::new(),
            fs_hz: fs,
            pre_s: pre,
            post_s: post,
            profile: TipProfile {
                jerk_m_s3: 6000.0,
                v_m_s: 3e-3,
            },
            seed: 1,
            oversample: 1,
        }
    }
}

/// The truth parameter vector of a spec: nominal values overridden by `spec.params`.
pub(crate) fn truth_params(model: &Model, spec: &SynthSpec) -> Result<Vec<f64>, FitError> {
    let mut p = model.nominal();
    for (k, v) in &spec.params {
        let i = model.index(k).ok_or_else(|| {
            FitError::input(
                "synth",
                0,
                format!("parameter `{k}` is not in the truth model"),
            )
        })?;
        p[i] = *v;
    }
    Ok(p)
}

/// Largest number of rows `synth` writes (`(pre + post) * fs + 1`).
pub const MAX_ROWS: f64 = 10_000_000.0;
/// Largest number of truth sub-samples per sample.
pub const MAX_OVERSAMPLE: usize = 64;

/// Refuses a spec whose dataset the loader would refuse, or that cannot be generated: the same
/// checks as [`Dataset::load`] (positive known constants, positive noise of declared channels)
/// plus finite, bounded sampling, a finite positive tip profile and physical parameter values.
pub fn validate(spec: &SynthSpec, scenario: Scenario, model: &Model) -> Result<(), FitError> {
    let bad = |c: String| Err(FitError::input("synth", 0, c));
    for (name, v) in [
        ("fs", spec.fs_hz),
        ("pre", spec.pre_s),
        ("post", spec.post_s),
    ] {
        if !v.is_finite() {
            return bad(format!("--{name} {v}: must be finite"));
        }
    }
    if !(spec.fs_hz > 0.0 && spec.pre_s >= 0.0 && spec.post_s > 0.0) {
        return bad("sampling must be positive (--fs > 0, --pre >= 0, --post > 0)".into());
    }
    let rows = (spec.pre_s + spec.post_s) * spec.fs_hz + 1.0;
    if rows.is_nan() || rows > MAX_ROWS {
        return bad(format!(
            "--fs {} over {} s gives {rows:.3e} rows, more than the maximum {MAX_ROWS:e}",
            spec.fs_hz,
            spec.pre_s + spec.post_s
        ));
    }
    if spec.oversample == 0 || spec.oversample > MAX_OVERSAMPLE {
        return bad(format!(
            "oversample {} must be 1..={MAX_OVERSAMPLE}",
            spec.oversample
        ));
    }
    for (name, v) in [("jerk", spec.profile.jerk_m_s3), ("v", spec.profile.v_m_s)] {
        if !(v.is_finite() && v > 0.0) {
            return bad(format!("--{name} {v}: must be finite and positive"));
        }
    }
    let specs = model.specs();
    for (k, v) in &spec.params {
        if let Some(i) = model.index(k) {
            crate::coords::check_value(&specs[i], k, *v)
                .map_err(|c| FitError::input("synth", 0, format!("--param {k}={v}: {c}")))?;
        }
    }
    for (k, v) in &spec.known {
        if !v.is_finite() {
            return bad(format!("--known {k}={v}: must be finite"));
        }
        // a constant some scenario needs is a physical magnitude: positive
        let needed = geodesic_facility::scenario::registry()
            .iter()
            .any(|s| s.required_known().contains(&k.as_str()));
        if needed && *v <= 0.0 {
            return bad(format!("--known {k}={v}: must be positive"));
        }
    }
    let channels = synthesised_channels(scenario);
    for (ch, v) in &spec.noise {
        if !channels.contains(&ch.as_str()) {
            return bad(format!(
                "--noise {ch}: not a channel of {} (channels: {})",
                scenario.name(),
                channels.join(", ")
            ));
        }
        let ok = if spec.noise_in_yaml {
            *v > 0.0
        } else {
            *v >= 0.0
        };
        if !(v.is_finite() && ok) {
            return bad(format!("--noise {ch}={v}: must be a positive number"));
        }
    }
    for (ch, phi) in &spec.noise_ar {
        if !channels.contains(&ch.as_str()) {
            return bad(format!(
                "--noise-ar {ch}: not a channel of {} (channels: {})",
                scenario.name(),
                channels.join(", ")
            ));
        }
        if !(phi.is_finite() && phi.abs() < 1.0) {
            return bad(format!(
                "--noise-ar {ch}={phi}: an AR(1) coefficient must lie in (-1, 1)"
            ));
        }
    }
    Ok(())
}

/// The channels a synthetic record of `scenario` carries: the fitted one, then the measured
/// inputs ([`ScenarioSpec::synth_inputs`](geodesic_facility::ScenarioSpec::synth_inputs)).
fn synthesised_channels(scenario: Scenario) -> Vec<&'static str> {
    let mut channels = vec![scenario.fitted_channel()];
    for ch in scenario.required_channels() {
        if !channels.contains(ch) {
            channels.push(ch);
        }
    }
    channels
}

/// Generates the dataset in memory (its `yaml_path` is `name`).
pub fn generate(spec: &SynthSpec, name: &str) -> Result<Dataset, FitError> {
    let scenario = Scenario::from_name(&spec.scenario).ok_or_else(|| {
        FitError::input("synth", 0, format!("unknown scenario `{}`", spec.scenario))
    })?;
    let effects: Vec<&str> = spec.effects.iter().map(String::as_str).collect();
    let model =
        Model::new(scenario, &effects).map_err(|e| FitError::input("synth", 0, e.to_string()))?;
    let p = truth_params(&model, spec)?;
    validate(spec, scenario, &model)?;
    let n_pre = (spec.pre_s * spec.fs_hz).round() as i64;
    let n_post = (spec.post_s * spec.fs_hz).round() as i64;
    let t: Vec<f64> = (-n_pre..=n_post).map(|i| i as f64 / spec.fs_hz).collect();
    let inputs = Inputs {
        m_kg: spec.known.get("m").copied().unwrap_or(0.089),
        profile: spec.profile,
        e0_v: spec.known.get("E0").copied().unwrap_or(120.0),
    };
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(spec.seed);
    let unit = Normal::new(0.0, 1.0).expect("unit normal");
    let mut channels = BTreeMap::new();
    let k = spec.oversample.max(1);
    // sub-sample times, centred on each sample time; their means are the samples
    let fine: Vec<f64> = t
        .iter()
        .flat_map(|&ti| (0..k).map(move |j| ti + ((j as f64 + 0.5) / k as f64 - 0.5) / spec.fs_hz))
        .collect();
    let mean_of = |v: Vec<f64>| -> Vec<f64> {
        v.chunks(k)
            .map(|c| c.iter().sum::<f64>() / k as f64)
            .collect()
    };
    let truth = if k == 1 {
        model.predict(&p, &t, &inputs)
    } else {
        model.predict_subsampled(&p, &fine, &inputs, k)
    };
    let fitted = scenario.fitted_channel();
    let mut add = |ch: &str, clean: Vec<f64>| {
        let s = spec.noise.get(ch).copied().unwrap_or(0.0);
        let noisy = match spec.noise_ar.get(ch) {
            // AR(1) of marginal sigma s, started in its stationary distribution
            Some(&phi) => {
                let e = s * (1.0 - phi * phi).sqrt();
                let mut n = s * unit.sample(&mut rng);
                clean
                    .into_iter()
                    .map(|v| {
                        let out = v + n;
                        n = phi * n + e * unit.sample(&mut rng);
                        out
                    })
                    .collect::<Vec<f64>>()
            }
            None => clean
                .into_iter()
                .map(|v| v + s * unit.sample(&mut rng))
                .collect::<Vec<f64>>(),
        };
        channels.insert(ch.to_string(), noisy);
    };
    add(fitted, truth);
    for (ch, v) in scenario.synth_inputs(&spec.profile, &fine) {
        add(ch, mean_of(v));
    }
    let units = channels
        .keys()
        .map(|c| (c.clone(), "m".to_string()))
        .collect();
    for (ch, v) in &channels {
        if let Some(k) = v
            .iter()
            .position(|x| x.is_nan() || x.abs() > crate::dataset::MAX_ABS_SI)
        {
            return Err(FitError::input(
                "synth",
                0,
                format!(
                    "the truth model gives {:e} on channel `{ch}` at t = {:e} s (non-finite or beyond {:e})",
                    v[k],
                    t[k],
                    crate::dataset::MAX_ABS_SI
                ),
            ));
        }
    }
    let noise = if spec.noise_in_yaml {
        spec.noise.clone()
    } else {
        BTreeMap::new()
    };
    Ok(Dataset {
        yaml_path: PathBuf::from(name),
        name: name.to_string(),
        scenario,
        description: format!("synthetic: {} (seed {})", spec.effects.join(","), spec.seed),
        t,
        channels,
        units,
        known: spec.known.clone(),
        noise,
        rows: Default::default(),
    })
}

/// The JSON document of `geodesic synth --json` (docs/spec/interface.md). Fields are declared
/// in byte order of their keys, the order the document has always printed.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct SynthDoc {
    /// The CSV written (the record's samples).
    pub csv: String,
    /// Samples (rows) in the record.
    pub rows: usize,
    /// The spec synthesised (units as in [`SynthSpec`]). Printed with its keys in byte order,
    /// as the document always has; the truth file holds the same spec in declaration order.
    #[serde(serialize_with = "keys_in_byte_order")]
    pub spec: SynthSpec,
    /// The truth JSON written (the spec).
    pub truth: String,
    /// The record's YAML written.
    pub yaml: String,
}

impl SynthDoc {
    /// The document of `ds` synthesised from `spec` and written as `files` ([`write`]: YAML,
    /// CSV, truth).
    pub fn new(ds: &Dataset, spec: &SynthSpec, files: &[PathBuf]) -> SynthDoc {
        let name = |i: usize| {
            files
                .get(i)
                .map(|f| f.display().to_string())
                .unwrap_or_default()
        };
        SynthDoc {
            csv: name(1),
            rows: ds.t.len(),
            spec: spec.clone(),
            truth: name(2),
            yaml: name(0),
        }
    }
}

/// Serialises `v` with the keys of every object in byte order (through a `serde_json::Value`,
/// whose maps are sorted): a struct's own order is its declaration order.
fn keys_in_byte_order<T: Serialize, S: serde::Serializer>(v: &T, s: S) -> Result<S::Ok, S::Error> {
    serde_json::to_value(v)
        .map_err(serde::ser::Error::custom)?
        .serialize(s)
}

/// The JSON document of `geodesic synth --campaign N --json`, in byte order of its keys.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
pub struct SynthCampaignDoc {
    /// The campaign file written (`DIR/campaign.yaml`, the list of releases).
    pub campaign: String,
    /// Releases written.
    pub releases: usize,
    /// The campaign's truth written (`DIR/truth.json`, [`CampaignTruth`]).
    pub truth: String,
}

/// Writes `ds` as `yaml_path` + CSV beside it (+ `.truth.json` with the spec), each atomically.
pub fn write(ds: &Dataset, spec: &SynthSpec, yaml_path: &Path) -> Result<Vec<PathBuf>, FitError> {
    let stem = yaml_path
        .file_stem()
        .map_or("synth".into(), |s| s.to_string_lossy().to_string());
    let dir = yaml_path.parent().unwrap_or(Path::new(""));
    let csv_name = format!("{stem}.csv");
    let chans: Vec<&String> = ds.channels.keys().collect();
    let mut csv = String::from("t");
    for c in &chans {
        csv += &format!(",{c}");
    }
    csv.push('\n');
    for (i, t) in ds.t.iter().enumerate() {
        csv += &format!("{t:.9e}");
        for c in &chans {
            csv += &format!(",{:.9e}", ds.channels[*c][i]);
        }
        csv.push('\n');
    }
    let mut y = format!(
        "scenario: {}\ndescription: {}\ndata: {csv_name}\ntime_column: t\nchannels:\n",
        ds.scenario.name(),
        serde_json::to_string(&ds.description).unwrap_or_default()
    );
    for c in &chans {
        y += &format!("  {c}: {}\n", ds.units[*c]);
    }
    y += "known:\n";
    for (k, v) in &ds.known {
        y += &format!("  {k}: {v:e}\n");
    }
    if !ds.noise.is_empty() {
        y += "noise:\n";
        for (k, v) in &ds.noise {
            y += &format!("  {k}: {v:e}\n");
        }
    }
    let csv_path = dir.join(&csv_name);
    let truth_path = dir.join(format!("{stem}.truth.json"));
    write_atomic(&csv_path, csv.as_bytes())?;
    write_atomic(yaml_path, y.as_bytes())?;
    let truth = serde_json::to_string_pretty(spec)
        .map_err(|e| FitError::input("synth", 0, e.to_string()))?;
    write_atomic(&truth_path, truth.as_bytes())?;
    // what was written must load: otherwise remove it and refuse
    if let Err(e) = Dataset::load(yaml_path) {
        for f in [yaml_path, csv_path.as_path(), truth_path.as_path()] {
            let _ = std::fs::remove_file(f);
        }
        return Err(FitError::input(
            "synth",
            0,
            format!("the dataset written would not load back: {e}"),
        ));
    }
    Ok(vec![yaml_path.to_path_buf(), csv_path, truth_path])
}

/// A population to draw a synthetic campaign from (normal, truncated positive).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct TruePopulation {
    /// Mean of A1 [N/m].
    pub a1_mean: f64,
    /// Spread of A1 [N/m].
    pub a1_sd: f64,
    /// Mean of lambda [m].
    pub lambda_mean: f64,
    /// Spread of lambda [m].
    pub lambda_sd: f64,
    /// Correlation of A1 and lambda.
    pub rho: f64,
}

impl Default for TruePopulation {
    /// Near the public example's adhesion (A1 1.3e5 N/m, lambda 6e-7 m), a 25 % and 15 % spread.
    fn default() -> Self {
        TruePopulation {
            a1_mean: 1.0e5,
            a1_sd: 2.5e4,
            lambda_mean: 6.0e-7,
            lambda_sd: 0.9e-7,
            rho: 0.0,
        }
    }
}

/// The truth of a synthetic campaign, `DIR/truth.json` of `geodesic synth --campaign N`: the
/// population drawn from and each release's drawn values. Fields are declared in byte order of
/// their keys, the order the file has always had.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct CampaignTruth {
    /// The population the releases were drawn from.
    pub population: TruePopulation,
    /// Each release, in campaign order.
    pub releases: Vec<ReleaseTruth>,
    /// The campaign's seed (`--seed`).
    pub seed: u64,
}

/// One release of [`CampaignTruth`] ([`draw_release`]), in byte order of its keys.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct ReleaseTruth {
    /// The release's YAML, in the campaign's folder (`release-001.yaml`).
    pub file: String,
    /// Needle preload [N].
    #[serde(rename = "needle_contact.F_pre")]
    pub f_pre_n: f64,
    /// 1-sigma white noise of channel x [m].
    pub noise_x_m: f64,
    /// Adhesion strength A1 [N/m].
    #[serde(rename = "tip_adhesion.A1")]
    pub a1_n_m: f64,
    /// Adhesion length lambda [m].
    #[serde(rename = "tip_adhesion.lambda")]
    pub lambda_m: f64,
    /// Tip retraction speed [m/s].
    pub tip_speed_m_s: f64,
}

/// Draws release `i` of a synthetic campaign: (A1, lambda, preload F_pre [N], tip speed [m/s],
/// noise [m]).
pub fn draw_release(pop: &TruePopulation, seed: u64, i: u64) -> (f64, f64, f64, f64, f64) {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(i);
    use rand::RngExt;
    let mut g = || {
        // Box-Muller from two uniforms (the stream is fixed: no distribution-crate state)
        let (u1, u2): (f64, f64) = (rng.random_range(1e-12..1.0), rng.random_range(0.0..1.0));
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    };
    let (z1, z2) = (g(), g());
    let z2 = pop.rho * z1 + (1.0 - pop.rho * pop.rho).max(0.0).sqrt() * z2;
    let a1 = (pop.a1_mean + pop.a1_sd * z1).max(0.05 * pop.a1_mean);
    let lambda = (pop.lambda_mean + pop.lambda_sd * z2).max(0.05 * pop.lambda_mean);
    let f_pre = 7e-3 * (1.0 + 0.2 * g()).clamp(0.5, 1.5);
    let v = 3e-3 * (1.0 + 0.15 * g()).clamp(0.5, 1.5);
    let noise = 8e-10 * (1.0 + 0.3 * g().abs());
    (a1, lambda, f_pre, v, noise)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn campaign_truth_prints_its_keys_in_byte_order_and_reads_back() {
        let pop = TruePopulation::default();
        let (a1, lambda, f_pre, v, noise) = draw_release(&pop, 5, 0);
        let truth = CampaignTruth {
            population: pop,
            releases: vec![ReleaseTruth {
                file: "release-001.yaml".into(),
                f_pre_n: f_pre,
                noise_x_m: noise,
                a1_n_m: a1,
                lambda_m: lambda,
                tip_speed_m_s: v,
            }],
            seed: 5,
        };
        let printed = serde_json::to_string_pretty(&truth).unwrap();
        let sorted = serde_json::to_string_pretty(&serde_json::to_value(&truth).unwrap()).unwrap();
        assert_eq!(printed, sorted);
        for key in [
            "needle_contact.F_pre",
            "noise_x_m",
            "tip_adhesion.A1",
            "tip_adhesion.lambda",
            "tip_speed_m_s",
        ] {
            assert!(printed.contains(&format!("\"{key}\"")), "{key}");
        }
        assert_eq!(
            serde_json::from_str::<CampaignTruth>(&printed).unwrap(),
            truth
        );
    }

    #[test]
    fn synth_doc_prints_its_keys_in_byte_order_and_reads_back() {
        let mut spec = SynthSpec::defaults(Scenario::TmmfRelease, &["needle_contact"]);
        spec.noise_ar.insert("x".into(), 0.5);
        spec.params.insert("needle_contact.F_pre".into(), 6e-3);
        let doc = SynthDoc {
            csv: "s.csv".into(),
            rows: 3,
            spec: spec.clone(),
            truth: "s.truth.json".into(),
            yaml: "s.yaml".into(),
        };
        let printed = serde_json::to_string(&doc).unwrap();
        // every object's keys sorted, the spec's included (noise_ar before noise_in_yaml)
        assert_eq!(printed, serde_json::to_value(&doc).unwrap().to_string());
        assert!(printed.contains(r#""spec":{"effects":["needle_contact"],"fs_hz""#));
        assert!(printed.contains(r#""noise_ar":{"x":0.5},"noise_in_yaml":true"#));
        // the truth file keeps the spec's declaration order
        assert!(
            serde_json::to_string(&spec)
                .unwrap()
                .starts_with(r#"{"scenario""#)
        );
        assert_eq!(serde_json::from_str::<SynthDoc>(&printed).unwrap(), doc);
        let camp = SynthCampaignDoc {
            campaign: "c/campaign.yaml".into(),
            releases: 2,
            truth: "c/truth.json".into(),
        };
        let printed = serde_json::to_string(&camp).unwrap();
        assert_eq!(printed, serde_json::to_value(&camp).unwrap().to_string());
        assert_eq!(
            serde_json::from_str::<SynthCampaignDoc>(&printed).unwrap(),
            camp
        );
    }

    #[test]
    fn refuses_specs_the_loader_would_refuse() {
        let base = SynthSpec::defaults(Scenario::TmmfRelease, &["needle_contact", "tip_contact"]);
        let cases: Vec<(SynthSpec, &str)> = vec![
            (
                SynthSpec {
                    fs_hz: 1e12,
                    ..base.clone()
                },
                "--fs",
            ),
            (
                SynthSpec {
                    fs_hz: f64::INFINITY,
                    ..base.clone()
                },
                "--fs",
            ),
            (
                SynthSpec {
                    noise: [("x".to_string(), -1e-9)].into(),
                    ..base.clone()
                },
                "--noise x",
            ),
            (
                SynthSpec {
                    noise: [("q".to_string(), 1e-9)].into(),
                    ..base.clone()
                },
                "--noise q",
            ),
            (
                SynthSpec {
                    known: [("m".to_string(), -0.089)].into(),
                    ..base.clone()
                },
                "--known m",
            ),
            (
                SynthSpec {
                    profile: TipProfile {
                        jerk_m_s3: f64::NAN,
                        v_m_s: 3e-3,
                    },
                    ..base.clone()
                },
                "--jerk",
            ),
            (
                SynthSpec {
                    params: [("needle_contact.k_nd".to_string(), -1.0)].into(),
                    ..base.clone()
                },
                "needle_contact.k_nd",
            ),
        ];
        for (spec, want) in cases {
            let e = generate(&spec, "s.yaml").unwrap_err().to_string();
            assert!(e.contains(want), "{want}: {e}");
        }
    }

    #[test]
    fn written_datasets_load_back_identically_and_are_deterministic() {
        let mut spec = SynthSpec::defaults(
            Scenario::TmmfRelease,
            &["needle_contact", "tip_contact", "drift"],
        );
        spec.params.insert("drift.p0".into(), 2e-9);
        spec.post_s = 1e-3;
        let a = generate(&spec, "s.yaml").unwrap();
        let b = generate(&spec, "s.yaml").unwrap();
        assert_eq!(a.channels, b.channels);
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().to_path_buf();
        let files = write(&a, &spec, &dir.join("s.yaml")).unwrap();
        let back = Dataset::load(&files[0]).unwrap();
        assert_eq!(back.t.len(), a.t.len());
        for (x, y) in back.channel("x").iter().zip(a.channel("x")) {
            assert!((x - y).abs() <= 1e-9 * y.abs() + 1e-20);
        }
        assert_eq!(back.noise, a.noise);
        // pre-trigger x carries the drift offset p0
        assert!((a.channel("x")[..50].iter().sum::<f64>() / 50.0 - 2e-9).abs() < 5e-10);
        assert!(
            truth_params(
                &Model::new(Scenario::TmmfRelease, &["needle_contact", "tip_contact"]).unwrap(),
                &spec
            )
            .is_err()
        );
    }
}
