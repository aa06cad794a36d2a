//! Measurement datasets (interface.md): a YAML metadata file beside a CSV file.
//!
//! Every refusal names the file and line: malformed YAML, missing file or column, unknown or
//! wrong-dimension unit, NaN or empty cells, time not strictly increasing, a channel or known
//! constant the scenario needs but lacks. Values are converted to SI with
//! `geodesic_core::units::parse_unit`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use geodesic_core::units::{Dim, parse_unit};
use geodesic_facility::Scenario;
use serde::Deserialize;
use serde_saphyr::Spanned;

use crate::error::FitError;

/// A loaded dataset, values in SI.
#[derive(Debug, Clone)]
pub struct Dataset {
    /// Path of the YAML file.
    pub yaml_path: PathBuf,
    /// The YAML file name as given on the command line (for JSON and reports).
    pub name: String,
    /// Scenario.
    pub scenario: Scenario,
    /// Free text.
    pub description: String,
    /// Sample times [s] from the trigger, strictly increasing.
    pub t: Vec<f64>,
    /// Channels, values in SI.
    pub channels: BTreeMap<String, Vec<f64>>,
    /// Channel units as written in the YAML.
    pub units: BTreeMap<String, String>,
    /// Known constants (`m` [kg], `E0` [V], ...).
    pub known: BTreeMap<String, f64>,
    /// 1-sigma white noise per channel from the YAML, in SI.
    pub noise: BTreeMap<String, f64>,
}

#[derive(Deserialize)]
struct Meta {
    scenario: Spanned<String>,
    #[serde(default)]
    description: Option<String>,
    data: Spanned<String>,
    #[serde(default)]
    time_column: Option<Spanned<String>>,
    channels: Spanned<BTreeMap<String, Spanned<String>>>,
    #[serde(default)]
    known: Option<BTreeMap<String, Spanned<f64>>>,
    #[serde(default)]
    noise: Option<BTreeMap<String, Spanned<f64>>>,
}

fn line_of<T>(s: &Spanned<T>) -> usize {
    s.referenced.line() as usize
}

/// Dimension a channel of a scenario must have, if the scenario fixes it.
fn channel_dim(name: &str) -> Option<Dim> {
    match name {
        "x" | "y" => Some(Dim::LENGTH),
        "E" => Some(Dim::VOLTAGE),
        _ => None,
    }
}

/// Reads a YAML file (size-limited) into `T`; a read or parse error is `file:line: cause`.
pub(crate) fn read_yaml<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, FitError> {
    let file = path.display().to_string();
    let text = geodesic_core::fsio::read_text(path, geodesic_core::fsio::MAX_YAML_BYTES)
        .map_err(|e| FitError::input(&file, e.line(), e.cause()))?;
    serde_saphyr::from_str(&text).map_err(|e| {
        let line = e.location().map_or(0, |l| l.line() as usize);
        let msg = e.to_string();
        let first = msg.lines().next().unwrap_or("malformed YAML").to_string();
        FitError::input(&file, line, format!("malformed YAML: {first}"))
    })
}

impl Dataset {
    /// Loads the YAML at `path` and its CSV.
    pub fn load(path: &Path) -> Result<Dataset, FitError> {
        let file = path.display().to_string();
        let meta: Meta = read_yaml(path)?;
        let scenario = Scenario::from_name(&meta.scenario.value).ok_or_else(|| {
            FitError::input(
                &file,
                line_of(&meta.scenario),
                format!(
                    "unknown scenario `{}` (known: tmmf-release, rt-retraction)",
                    meta.scenario.value
                ),
            )
        })?;
        // units
        let mut scales = BTreeMap::new();
        let mut units = BTreeMap::new();
        for (ch, u) in &meta.channels.value {
            let unit = parse_unit(u.value.trim())
                .map_err(|e| FitError::input(&file, line_of(u), format!("channel `{ch}`: {e}")))?;
            if let Some(d) = channel_dim(ch)
                && unit.dim != d
            {
                return Err(FitError::input(
                    &file,
                    line_of(u),
                    format!(
                        "channel `{ch}` has unit `{}` of dimension {}, expected {d}",
                        u.value, unit.dim
                    ),
                ));
            }
            scales.insert(ch.clone(), unit.scale);
            units.insert(ch.clone(), u.value.clone());
        }
        for need in scenario.required_channels() {
            if !scales.contains_key(*need) {
                return Err(FitError::input(
                    &file,
                    line_of(&meta.channels),
                    format!(
                        "scenario {} needs channel `{need}`, not declared under channels",
                        scenario.name()
                    ),
                ));
            }
        }
        let mut known = BTreeMap::new();
        for (k, v) in meta.known.iter().flatten() {
            if !v.value.is_finite() {
                return Err(FitError::input(
                    &file,
                    line_of(v),
                    format!("known `{k}` is not a finite number"),
                ));
            }
            known.insert(k.clone(), v.value);
        }
        for need in scenario.required_known() {
            if !known.contains_key(*need) {
                return Err(FitError::input(
                    &file,
                    0,
                    format!(
                        "scenario {} needs the known constant `{need}` (under known:)",
                        scenario.name()
                    ),
                ));
            }
        }
        for (k, what) in [("m", "TM mass, kg"), ("E0", "electrode voltage, V")] {
            if let Some(v) = meta.known.as_ref().and_then(|m| m.get(k))
                && v.value <= 0.0
            {
                return Err(FitError::input(
                    &file,
                    line_of(v),
                    format!("known `{k}` ({what}) must be positive, not {}", v.value),
                ));
            }
        }
        let mut noise = BTreeMap::new();
        for (ch, v) in meta.noise.iter().flatten() {
            let Some(s) = scales.get(ch) else {
                return Err(FitError::input(
                    &file,
                    line_of(v),
                    format!("noise given for undeclared channel `{ch}`"),
                ));
            };
            if !(v.value.is_finite() && v.value > 0.0) {
                return Err(FitError::input(
                    &file,
                    line_of(v),
                    format!("noise of `{ch}` must be a positive number"),
                ));
            }
            noise.insert(ch.clone(), v.value * s);
        }
        let time_col = meta
            .time_column
            .as_ref()
            .map_or("t".to_string(), |s| s.value.clone());
        let csv_path = path
            .parent()
            .unwrap_or(Path::new("."))
            .join(&meta.data.value);
        let (t, mut channels) = read_csv(&csv_path, &time_col, &scales)?;
        if t.len() < 10 {
            return Err(FitError::input(
                csv_path.display().to_string(),
                0,
                format!("only {} samples", t.len()),
            ));
        }
        if !t.iter().any(|&v| v >= 0.0) {
            return Err(FitError::input(
                csv_path.display().to_string(),
                0,
                "no sample at or after the trigger t = 0",
            ));
        }
        for (ch, s) in &scales {
            if let Some(v) = channels.get_mut(ch) {
                v.iter_mut().for_each(|x| *x *= s);
                // values near the largest float overflow once in SI (or in any sum of squares
                // downstream): a channel must stay well inside the float range
                if let Some(k) = v.iter().position(|x| x.is_nan() || x.abs() > MAX_ABS_SI) {
                    return Err(FitError::input(
                        csv_path.display().to_string(),
                        0,
                        format!(
                            "channel `{ch}` sample {} is {:e} in SI, beyond the supported magnitude {MAX_ABS_SI:e}",
                            k + 1,
                            v[k]
                        ),
                    ));
                }
            }
        }
        let name = path
            .file_name()
            .map_or(file.clone(), |n| n.to_string_lossy().to_string());
        Ok(Dataset {
            yaml_path: path.to_path_buf(),
            name,
            scenario,
            description: meta.description.unwrap_or_default(),
            t,
            channels,
            units,
            known,
            noise,
        })
    }

    /// The values of a channel [SI].
    pub fn channel(&self, name: &str) -> &[f64] {
        &self.channels[name]
    }

    /// Stem of the YAML file name (`run-017` for `run-017.yaml`).
    pub fn stem(&self) -> String {
        self.yaml_path
            .file_stem()
            .map_or("dataset".into(), |s| s.to_string_lossy().to_string())
    }
}

/// Largest magnitude of a sample in SI: squares and sums of squares of a whole record stay
/// finite (1e100^2 times a billion samples is far below the float maximum).
pub const MAX_ABS_SI: f64 = 1e100;

/// `s` cut to at most 80 characters for a one-line message.
fn short(s: &str) -> String {
    let one: String = s
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    if one.chars().count() > 80 {
        format!("{}...", one.chars().take(80).collect::<String>())
    } else {
        one
    }
}

type Columns = (Vec<f64>, BTreeMap<String, Vec<f64>>);

/// Reads the time column and the named channels (scaled by nothing: values as written) of a
/// CSV, with the dataset format's checks (finite numbers, strictly increasing time, file and
/// line in every error); used by the spectral series reader too.
pub(crate) fn read_csv_columns(
    path: &Path,
    time_col: &str,
    channels: &BTreeMap<String, f64>,
) -> Result<Columns, FitError> {
    read_csv(path, time_col, channels)
}

fn read_csv(
    path: &Path,
    time_col: &str,
    channels: &BTreeMap<String, f64>,
) -> Result<Columns, FitError> {
    let file = path.display().to_string();
    let text = geodesic_core::fsio::read_text(path, geodesic_core::fsio::MAX_CSV_BYTES)
        .map_err(|e| FitError::input(&file, e.line(), format!("data file: {}", e.cause())))?;
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = rdr
        .headers()
        .map_err(|e| FitError::input(&file, 1, format!("bad header: {e}")))?
        .clone();
    let col = |name: &str| -> Result<usize, FitError> {
        headers.iter().position(|h| h == name).ok_or_else(|| {
            FitError::input(
                &file,
                1,
                format!(
                    "no column `{name}` in the header ({})",
                    geodesic_core::text::clip(&headers.iter().collect::<Vec<_>>().join(","), 200)
                ),
            )
        })
    };
    let it = col(time_col)?;
    let idx: Vec<(String, usize)> = channels
        .keys()
        .map(|c| col(c).map(|i| (c.clone(), i)))
        .collect::<Result<_, _>>()?;
    let mut t = Vec::new();
    let mut out: BTreeMap<String, Vec<f64>> =
        channels.keys().map(|c| (c.clone(), Vec::new())).collect();
    for rec in rdr.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line() as usize);
            FitError::input(
                &file,
                line,
                format!("malformed CSV row: {}", short(&e.to_string())),
            )
        })?;
        let line = rec.position().map_or(0, |p| p.line() as usize);
        let cell = |i: usize, name: &str| -> Result<f64, FitError> {
            let s = rec.get(i).unwrap_or("");
            if s.is_empty() {
                return Err(FitError::input(
                    &file,
                    line,
                    format!("empty cell in column `{name}`"),
                ));
            }
            let v: f64 = s.parse().map_err(|_| {
                FitError::input(
                    &file,
                    line,
                    if s.starts_with('"') {
                        format!(
                            "`{}` in column `{name}` is not a number (unbalanced quote?)",
                            short(s)
                        )
                    } else {
                        format!("`{}` in column `{name}` is not a number", short(s))
                    },
                )
            })?;
            if !v.is_finite() {
                return Err(FitError::input(
                    &file,
                    line,
                    format!("`{}` in column `{name}` is not a finite number", short(s)),
                ));
            }
            Ok(v)
        };
        let tv = cell(it, time_col)?;
        if let Some(&prev) = t.last()
            && tv <= prev
        {
            return Err(FitError::input(
                &file,
                line,
                format!("time not strictly increasing ({tv} after {prev})"),
            ));
        }
        t.push(tv);
        for (c, i) in &idx {
            let v = cell(*i, c)?;
            out.get_mut(c).expect("channel").push(v);
        }
    }
    Ok((t, out))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, yaml: &str, csv: &str) -> PathBuf {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join("d.csv"), csv).unwrap();
        let p = dir.join("d.yaml");
        std::fs::write(&p, yaml).unwrap();
        p
    }

    const YAML: &str = "scenario: rt-retraction\ndata: d.csv\ntime_column: t\nchannels:\n  y: nm\nknown:\n  E0: 120\n";

    /// `n` data rows `t,y` with t in us from -2 us; row `k` (0-based, CSV line `k + 2`)
    /// replaced by `bad` when given.
    fn csv_rows_with(n: usize, bad: Option<(usize, &str)>) -> String {
        let mut s = String::from("t,y\n");
        for i in 0..n {
            match bad {
                Some((k, row)) if k == i => s += row,
                _ => s += &format!("{}e-6,{}", i as i64 - 2, i),
            }
            s.push('\n');
        }
        s
    }

    fn csv_rows(n: usize) -> String {
        csv_rows_with(n, None)
    }

    fn err_of(yaml: &str, csv: &str, _tag: &str) -> String {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().to_path_buf();
        let p = write(&dir, yaml, csv);
        Dataset::load(&p).unwrap_err().to_string()
    }

    #[test]
    fn loads_and_converts_units() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().to_path_buf();
        let p = write(&dir, YAML, &csv_rows(20));
        let d = Dataset::load(&p).unwrap();
        assert_eq!(d.t.len(), 20);
        assert!((d.channel("y")[3] - 3e-9).abs() < 1e-20);
    }

    #[test]
    fn refuses_bad_input_with_file_and_line() {
        let e = err_of(&YAML.replace("y: nm", "y: furlong"), &csv_rows(20), "unit");
        assert!(e.contains("d.yaml:5:") && e.contains("furlong"), "{e}");
        let e = err_of(YAML, &csv_rows_with(20, Some((3, "1e-6,NaN"))), "nan");
        assert!(e.contains("d.csv:5:") && e.contains("NaN"), "{e}");
        let e = err_of(YAML, &csv_rows_with(20, Some((3, "1e-6,"))), "empty");
        assert!(e.contains("d.csv:5:") && e.contains("empty"), "{e}");
        let e = err_of(YAML, &csv_rows_with(20, Some((3, "-5e-6,3"))), "time");
        assert!(e.contains("d.csv:5:") && e.contains("increasing"), "{e}");
        let e = err_of(&YAML.replace("d.csv", "none.csv"), "", "missing");
        assert!(e.contains("none.csv") && e.contains("cannot read"), "{e}");
        let e = err_of(&YAML.replace("  y: nm", "  E: V"), &csv_rows(20), "chan");
        assert!(e.contains("needs channel `y`"), "{e}");
        let e = err_of(&YAML.replace("y: nm", "y: V"), &csv_rows(20), "dim");
        assert!(e.contains("dimension"), "{e}");
        let e = err_of(
            &YAML.replace("channels:", "channels: ["),
            &csv_rows(20),
            "yaml",
        );
        assert!(e.contains("d.yaml:") && e.contains("malformed YAML"), "{e}");
        let e = err_of(YAML, &csv_rows(20).replace("t,y", "t,z"), "col");
        assert!(e.contains("d.csv:1:") && e.contains("no column `y`"), "{e}");
        let e = err_of(
            &YAML.replace("  E0: 120\n", "  Q: 1\n"),
            &csv_rows(20),
            "known",
        );
        assert!(e.contains("`E0`"), "{e}");
    }

    #[test]
    fn refuses_non_regular_overflowing_quoted_and_unphysical_input() {
        #[cfg(unix)]
        {
            let e = Dataset::load(Path::new("/dev/zero"))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("/dev/zero") && e.contains("not a regular file"),
                "{e}"
            );
        }
        let e = err_of(YAML, &csv_rows_with(20, Some((3, "1e-6,1e300"))), "huge");
        assert!(e.contains("d.csv") && e.contains("magnitude"), "{e}");
        let mut q = csv_rows_with(20, Some((3, "1e-6,\"4")));
        q += &"x".repeat(5000);
        let e = err_of(YAML, &q, "quote");
        assert!(
            e.contains("d.csv:5:") && e.len() < 300 && !e.contains('\n'),
            "{e}"
        );
        let e = err_of(&YAML.replace("E0: 120", "E0: 0"), &csv_rows(20), "e0");
        assert!(e.contains("d.yaml:7:") && e.contains("`E0`"), "{e}");
        let e = err_of(&YAML.replace("E0: 120", "E0: -5"), &csv_rows(20), "e0neg");
        assert!(e.contains("positive"), "{e}");
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config::with_cases(24))]
        /// Whatever row is bad and however, the refusal names the CSV file and that row's line.
        #[test]
        fn a_bad_row_is_reported_at_its_line(row in 0usize..30, kind in 0usize..4) {
            let bad = match kind {
                0 => format!("{}e-6,NaN", row as i64 - 2),
                1 => format!("{}e-6,", row as i64 - 2),
                2 => format!("{}e-6,inf", row as i64 - 2),
                _ => "-1e-3,0".to_string(),
            };
            // a time going back is only detectable after the first row
            let row = if kind == 3 { row.max(1) } else { row };
            let e = err_of(YAML, &csv_rows_with(30, Some((row, &bad))), &format!("prop{row}-{kind}"));
            let at = format!("d.csv:{}:", row + 2);
            proptest::prop_assert!(e.contains(&at), "{} does not name {}", e, at);
        }
    }
}
