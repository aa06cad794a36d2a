//! Amplitude spectral density of a time series and its judgement against a spectral
//! requirement (issue 16, item 3).
//!
//! **Estimator.** Welch's averaged periodogram (Hann window, segments overlapping by a stated
//! fraction, the equivalent degrees of freedom and the 95 % band): `geodesic_numeric::spectral`,
//! which knows no unit, file or requirement; this module reads the series and judges the
//! estimate.
//!
//! **Judgement.** Over the bins inside the requirement's band, the ratio `ASD(f) / L(f)` with
//! `L(f) = level x shape(f)`; the value reported is `max ratio x level` (margin `1 - max ratio`),
//! with the frequency where it occurs, and the same ratio for the upper 95 % bound of the ASD
//! (a conservative margin) beside it.

use crate::error::FitError;
use geodesic_core::spectrum::Spectrum;
use geodesic_core::units::{Dim, parse_unit};
use serde::{Deserialize, Serialize};
use serde_saphyr::Spanned;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The estimator (Welch's averaged periodogram), from `geodesic_numeric::spectral`: a caller
/// reads a [`Series`], estimates its ASD and [`judge`]s it, all through this module.
pub use geodesic_numeric::spectral::{Asd, WelchOptions, default_nperseg, welch};

/// A uniformly sampled series, values in SI.
#[derive(Debug, Clone)]
pub struct Series {
    /// The YAML file.
    pub path: PathBuf,
    /// Free text.
    pub description: String,
    /// Channel name.
    pub channel: String,
    /// The channel's unit as written.
    pub unit: String,
    /// Dimension of the values.
    pub dim: Dim,
    /// Sample interval [s].
    pub dt_s: f64,
    /// Values in SI.
    pub values: Vec<f64>,
    /// What the series is: a measurement, a simulation, or synthetic (`origin:`; unstated when
    /// the file does not say).
    pub origin: SeriesOrigin,
    /// Where it comes from (`provenance:`: facility, instrument, date, run; or the model and
    /// its inputs for a simulation); required for a measurement.
    pub provenance: Option<String>,
}

/// What a series declares itself to be (`origin:` in its YAML).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum SeriesOrigin {
    /// Measured data, with its provenance: evidence on basis `measurement`.
    Measurement,
    /// The output of a simulation, with its provenance: evidence on basis `model`.
    Simulation,
    /// Made up for an example or a test: an illustration, never a verdict.
    Synthetic,
    /// The file does not say: an illustration, never a verdict.
    Unstated,
}

impl SeriesOrigin {
    /// As written in YAML (`unstated` when absent).
    pub fn as_str(self) -> &'static str {
        match self {
            SeriesOrigin::Measurement => "measurement",
            SeriesOrigin::Simulation => "simulation",
            SeriesOrigin::Synthetic => "synthetic",
            SeriesOrigin::Unstated => "unstated",
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SeriesMeta {
    #[serde(default)]
    description: Option<String>,
    #[serde(default)]
    origin: Option<Spanned<String>>,
    #[serde(default)]
    provenance: Option<Spanned<String>>,
    data: Spanned<String>,
    #[serde(default)]
    time_column: Option<Spanned<String>>,
    channel: Spanned<String>,
    unit: Spanned<String>,
}

/// Relative tolerance on the sample interval for a series to count as uniformly sampled [-].
pub const UNIFORM_TOL: f64 = 1e-6;

impl Series {
    /// Loads a series YAML (`data`, `time_column` [default `t`, seconds], `channel`, `unit`,
    /// optional `origin: measurement | simulation | synthetic` with `provenance`, which a
    /// measurement or a simulation must give) and its CSV.
    pub fn load(path: &Path) -> Result<Series, FitError> {
        let file = path.display().to_string();
        let meta: SeriesMeta = crate::dataset::read_yaml(path)?;
        let line = |s: &Spanned<String>| s.referenced.line() as usize;
        let origin = match &meta.origin {
            None => SeriesOrigin::Unstated,
            Some(o) => match o.value.trim() {
                "measurement" => SeriesOrigin::Measurement,
                "simulation" => SeriesOrigin::Simulation,
                "synthetic" => SeriesOrigin::Synthetic,
                other => {
                    return Err(FitError::input(
                        &file,
                        line(o),
                        format!(
                            "origin `{}`: write measurement, simulation or synthetic",
                            geodesic_util::text::clip(other, 40)
                        ),
                    ));
                }
            },
        };
        let provenance = meta
            .provenance
            .as_ref()
            .map(|p| p.value.trim().to_string())
            .filter(|p| !p.is_empty());
        if matches!(origin, SeriesOrigin::Measurement | SeriesOrigin::Simulation)
            && provenance.is_none()
        {
            return Err(FitError::input(
                &file,
                meta.origin.as_ref().map_or(0, line),
                format!(
                    "origin {}: state its `provenance` (facility, instrument, date and run of a measurement; the model and its inputs of a simulation)",
                    origin.as_str()
                ),
            ));
        }
        let unit = parse_unit(meta.unit.value.trim())
            .map_err(|e| FitError::input(&file, line(&meta.unit), format!("unit: {e}")))?;
        let time_col = meta
            .time_column
            .as_ref()
            .map_or("t".to_string(), |s| s.value.clone());
        let csv_path = path
            .parent()
            .unwrap_or(Path::new("."))
            .join(&meta.data.value);
        let mut scales = BTreeMap::new();
        scales.insert(meta.channel.value.clone(), unit.scale);
        let (t, mut ch) = crate::dataset::read_csv_columns(&csv_path, &time_col, &scales)?;
        let csv = csv_path.display().to_string();
        if t.len() < 16 {
            return Err(FitError::input(
                &csv,
                0,
                format!("only {} samples (at least 16 for a spectrum)", t.len()),
            ));
        }
        let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
        if let Some(k) = t
            .windows(2)
            .position(|w| ((w[1] - w[0]) - dt).abs() > UNIFORM_TOL * dt)
        {
            return Err(FitError::input(
                &csv,
                k + 3,
                format!(
                    "sampling is not uniform (interval {:e} s where the mean is {dt:e} s); resample the series first",
                    t[k + 1] - t[k]
                ),
            ));
        }
        let mut values = ch.remove(&meta.channel.value).unwrap_or_default();
        values.iter_mut().for_each(|v| *v *= unit.scale);
        Ok(Series {
            path: path.to_path_buf(),
            description: meta.description.unwrap_or_default(),
            channel: meta.channel.value.clone(),
            unit: meta.unit.value.clone(),
            dim: unit.dim,
            dt_s: dt,
            values,
            origin,
            provenance,
        })
    }
}

/// The judgement of an ASD against a spectral limit.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct Judgement {
    /// Worst `ASD / L` over the band [-].
    pub worst_ratio: f64,
    /// Frequency of the worst ratio [Hz].
    pub worst_f_hz: f64,
    /// ASD there [SI / sqrt(Hz)].
    pub worst_asd: f64,
    /// The limit there [SI / sqrt(Hz)].
    pub worst_limit: f64,
    /// Worst ratio of the upper 95 % bound of the ASD [-].
    pub worst_ratio_hi95: f64,
    /// Frequency of that ratio [Hz].
    pub worst_f_hi95_hz: f64,
    /// Worst ratio of the lower 95 % bound of the ASD [-]: above 1, the ASD exceeds the
    /// limit at that bin beyond what the estimate's scatter explains.
    pub worst_ratio_lo95: f64,
    /// Bins judged.
    pub bins: usize,
    /// Lowest and highest frequencies judged [Hz].
    pub judged_hz: [f64; 2],
}

/// The JSON document of `geodesic asd` (interface.md): a series' amplitude spectral density
/// judged against a spectral requirement. Fields are declared in byte order of their keys, the
/// order the document has always printed. "the unit" below is `unit`, the requirement's
/// limit unit (an ASD unit, per sqrt(Hz)).
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct AsdDoc {
    /// The ASD per frequency bin, in the unit.
    pub asd: Vec<f64>,
    /// The ASD at the worst bin, in the unit.
    pub asd_at_worst: f64,
    /// Upper bound of the 95 % interval of each bin's ASD, in the unit.
    pub asd_hi95: Vec<f64>,
    /// Lower bound of the 95 % interval of each bin's ASD, in the unit.
    pub asd_lo95: Vec<f64>,
    /// The requirement's band [Hz]: low, high.
    pub band_hz: [f64; 2],
    /// Frequency bins judged in the band.
    pub bins_judged: usize,
    /// Degrees of freedom per ASD bin (dimensionless).
    pub dof_per_bin: f64,
    /// Frequency of each bin [Hz].
    pub f_hz: Vec<f64>,
    /// The frequency range judged [Hz]: low, high.
    pub judged_hz: [f64; 2],
    /// The requirement's limit, as written.
    pub limit: String,
    /// The limit's shape at the worst bin, in the unit.
    pub limit_at_worst: f64,
    /// 1 - worst_ratio (dimensionless; negative when the limit is exceeded).
    pub margin: f64,
    /// Whether the requirement is met.
    pub met: bool,
    /// Samples per Welch segment.
    pub nperseg: usize,
    /// Overlap of the Welch segments (fraction, dimensionless).
    pub overlap: f64,
    /// The requirement's ID.
    pub requirement: String,
    /// Sample rate of the series [Hz].
    pub sample_rate_hz: f64,
    /// Samples in the series.
    pub samples: usize,
    /// Welch segments averaged.
    pub segments: usize,
    /// The series file, as given on the command line.
    pub series: String,
    /// The limit's spectral shape, as written.
    pub shape: String,
    /// Symbol of the unit.
    pub unit: String,
    /// The worst ratio referred to the limit's level, in the unit.
    pub value_referred_to_level: f64,
    /// The Welch window's name.
    pub window: String,
    /// Frequency of the worst bin [Hz].
    pub worst_frequency_hz: f64,
    /// Frequency of the worst bin of the upper 95 % bound [Hz].
    pub worst_frequency_upper95_hz: f64,
    /// Worst ratio of ASD to limit over the judged bins (dimensionless).
    pub worst_ratio: f64,
    /// Worst ratio of the upper 95 % ASD bound to the limit (dimensionless).
    pub worst_ratio_upper95: f64,
}

/// Judges `asd` against `level x shape(f)` over the spectrum's band (bins from 1 up).
pub fn judge(asd: &Asd, spectrum: &Spectrum, level_si: f64) -> Result<Judgement, String> {
    let nyq = asd.fs_hz / 2.0;
    if nyq < spectrum.band_hz[1] {
        return Err(format!(
            "the series is sampled at {:.4e} Hz: its Nyquist frequency {:.4e} Hz is below the band's top {:.4e} Hz",
            asd.fs_hz, nyq, spectrum.band_hz[1]
        ));
    }
    let df = asd.fs_hz / asd.options.nperseg as f64;
    if df > spectrum.band_hz[0] {
        return Err(format!(
            "segments of {} samples resolve {df:.4e} Hz, coarser than the band's bottom {:.4e} Hz: the band would not be judged where it starts; use segments of at least {:.0} s (the series must be at least as long)",
            asd.options.nperseg,
            spectrum.band_hz[0],
            1.0 / spectrum.band_hz[0]
        ));
    }
    let mut best: Option<Judgement> = None;
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    let mut bins = 0;
    for j in 1..asd.f_hz.len() {
        let f = asd.f_hz[j];
        if !spectrum.in_band(f) {
            continue;
        }
        bins += 1;
        lo = lo.min(f);
        hi = hi.max(f);
        let l = level_si * spectrum.shape(f);
        let r = asd.asd[j] / l;
        let rh = asd.hi95[j] / l;
        let rl = asd.lo95[j] / l;
        let b = best.get_or_insert(Judgement {
            worst_ratio: r,
            worst_f_hz: f,
            worst_asd: asd.asd[j],
            worst_limit: l,
            worst_ratio_hi95: rh,
            worst_f_hi95_hz: f,
            worst_ratio_lo95: rl,
            bins: 0,
            judged_hz: [f, f],
        });
        if r > b.worst_ratio {
            b.worst_ratio = r;
            b.worst_f_hz = f;
            b.worst_asd = asd.asd[j];
            b.worst_limit = l;
        }
        b.worst_ratio_lo95 = b.worst_ratio_lo95.max(rl);
        if rh > b.worst_ratio_hi95 {
            b.worst_ratio_hi95 = rh;
            b.worst_f_hi95_hz = f;
        }
    }
    let mut j = best.ok_or_else(|| {
        format!(
            "no frequency bin inside the band {:.4e}..{:.4e} Hz (bin width {df:.4e} Hz): the series or its segments are too short; a segment of at least {:.0} s is needed",
            spectrum.band_hz[0],
            spectrum.band_hz[1],
            4.0 / spectrum.band_hz[0]
        )
    })?;
    j.bins = bins;
    j.judged_hz = [lo, hi];
    Ok(j)
}
#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    /// AR(1) noise `x_n = a x_{n-1} + e_n`: one-sided PSD `2 s^2 / fs / |1 - a exp(-i w)|^2`.
    fn ar1(n: usize, a: f64, s: f64, seed: u64) -> Vec<f64> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let nd = Normal::new(0.0, s).unwrap();
        let mut x = 0.0;
        (0..n)
            .map(|_| {
                x = a * x + nd.sample(&mut rng);
                x
            })
            .collect()
    }

    #[test]
    fn judgement_finds_the_worst_frequency() {
        // white noise, flat ASD A; limit level L0 (1 + (f / 3 mHz)^2): worst at the band's bottom
        let (fs, sd) = (1.0, 1e-13);
        let x = ar1(200_000, 0.0, sd, 5);
        let spec = Spectrum::parse("1 mHz .. 30 mHz", "1 + (f / 3 mHz)^2").unwrap();
        let n = default_nperseg(x.len(), fs, spec.band_hz[0]);
        assert_eq!(n, 4096);
        let est = welch(
            &x,
            fs,
            WelchOptions {
                nperseg: n,
                overlap: 0.5,
            },
        )
        .unwrap();
        let flat = (2.0 * sd * sd / fs).sqrt();
        let level = 3.0 * flat;
        let j = judge(&est, &spec, level).unwrap();
        assert!(j.worst_f_hz < 4e-3, "{}", j.worst_f_hz);
        // the ratio is the ASD over the limit at the worst bin: about 1/3 / (1 + (f/3mHz)^2)
        let expect = j.worst_asd / (level * spec.shape(j.worst_f_hz));
        assert!((j.worst_ratio - expect).abs() < 1e-12);
        assert!(
            j.worst_ratio > 0.2 && j.worst_ratio < 0.5,
            "{}",
            j.worst_ratio
        );
        assert!(j.worst_ratio_hi95 > j.worst_ratio);
        assert!(j.worst_ratio_lo95 < j.worst_ratio);
        // too slowly sampled or too short: a clear refusal
        let slow = welch(
            &x,
            0.02,
            WelchOptions {
                nperseg: 1024,
                overlap: 0.5,
            },
        )
        .unwrap();
        assert!(judge(&slow, &spec, level).unwrap_err().contains("Nyquist"));
        let short = welch(
            &x[..512],
            fs,
            WelchOptions {
                nperseg: 256,
                overlap: 0.5,
            },
        )
        .unwrap();
        assert!(
            judge(&short, &spec, level)
                .unwrap_err()
                .contains("coarser than the band's bottom")
        );
    }
}
