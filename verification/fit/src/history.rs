//! Fit history per dataset (`<stem>.history.jsonl` under the output directory, one JSON line a
//! row), so the error can be watched falling as the model grows: **one row per model version**.
//! A model version is a set of effects with its number of free parameters (a `--fix` makes
//! another); a fit of a version already in the history replaces that row, keeping its number
//! and place (the latest fit of each version is what the table and plot show), a new version
//! is appended. So `fit` after `diagnose` of the same model, or `verify` run twice, add no row.
//! Histories written before, with a row per fit, read as one row per version.

use std::io::Write;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::FitError;
use crate::report::FitReport;

/// One fit of a dataset.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct Entry {
    /// 1-based version number (order of the fits).
    pub version: usize,
    /// Dataset YAML file name.
    pub dataset: String,
    /// The model's effects.
    pub effects: Vec<String>,
    /// Free parameters.
    pub n_free: usize,
    /// Total RMS over the fitted channels [SI].
    pub rms: f64,
    /// Reduced chi-square.
    pub chi2_red: f64,
    /// BIC.
    pub bic: f64,
    /// RMS of the measurement noise over the fitted channels [SI]: the floor the residual RMS
    /// falls to when the model is complete (absent in histories written before it was kept).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_rms: Option<f64>,
}

impl Entry {
    /// The version's name as the history plot and table write it: `v1 base` for the first
    /// model, then the effects added (`+name`) and removed (`-name`) against the version before.
    pub fn name(&self, previous: Option<&Entry>) -> String {
        match previous {
            None => format!("v{} base", self.version),
            Some(p) => {
                let mut d: Vec<String> = self
                    .effects
                    .iter()
                    .filter(|e| !p.effects.contains(e))
                    .map(|e| format!("+{e}"))
                    .collect();
                d.extend(
                    p.effects
                        .iter()
                        .filter(|e| !self.effects.contains(e))
                        .map(|e| format!("-{e}")),
                );
                if d.is_empty() {
                    // the same effects: another number of free parameters (`--fix`)
                    format!("v{} ({} free)", self.version, self.n_free)
                } else {
                    format!("v{} {}", self.version, d.join(" "))
                }
            }
        }
    }
}

/// The JSON document of `geodesic history --json` (interface.md). Fields are declared in byte
/// order of their keys, the order the document has always printed.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct HistoryDoc {
    /// The dataset's stem.
    pub dataset: String,
    /// The history's entries, oldest first.
    pub entries: Vec<EntryDoc>,
    /// The history file (JSON lines).
    pub history: String,
    /// The history plot written.
    pub svg: String,
}

/// An [`Entry`] as `geodesic history --json` prints it: the same fields, declared in byte
/// order of their keys (the history file keeps [`Entry`]'s own order).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct EntryDoc {
    /// BIC (dimensionless).
    pub bic: f64,
    /// Reduced chi-square (dimensionless).
    pub chi2_red: f64,
    /// Dataset YAML file name.
    pub dataset: String,
    /// The model's effects.
    pub effects: Vec<String>,
    /// Free parameters.
    pub n_free: usize,
    /// RMS of the measurement noise over the fitted channels [SI]; absent when not kept.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_rms: Option<f64>,
    /// Total RMS over the fitted channels [SI].
    pub rms: f64,
    /// 1-based version number (order of the fits).
    pub version: usize,
}

impl From<Entry> for EntryDoc {
    fn from(e: Entry) -> EntryDoc {
        EntryDoc {
            bic: e.bic,
            chi2_red: e.chi2_red,
            dataset: e.dataset,
            effects: e.effects,
            n_free: e.n_free,
            noise_rms: e.noise_rms,
            rms: e.rms,
            version: e.version,
        }
    }
}

/// Path of the history file of a dataset stem.
pub fn path_for(out_dir: &Path, stem: &str) -> PathBuf {
    out_dir.join(format!("{stem}.history.jsonl"))
}

/// The model version of an entry: its effects as a set, and its free parameters.
fn version_key(e: &Entry) -> (Vec<String>, usize) {
    let mut k = e.effects.clone();
    k.sort();
    k.dedup();
    (k, e.n_free)
}

/// One entry per model version, in the order of each version's first fit, each the latest fit
/// of its version, numbered from 1.
pub fn versions(raw: Vec<Entry>) -> Vec<Entry> {
    let mut out: Vec<Entry> = Vec::with_capacity(raw.len());
    for e in raw {
        match out.iter().position(|o| version_key(o) == version_key(&e)) {
            Some(i) => out[i] = e,
            None => out.push(e),
        }
    }
    for (i, e) in out.iter_mut().enumerate() {
        e.version = i + 1;
    }
    out
}

/// Reads a history, one entry per model version ([`versions`]); empty when the file does not
/// exist.
pub fn read(path: &Path) -> Result<Vec<Entry>, FitError> {
    read_rows(path).map(versions)
}

/// Every row of a history file as written.
fn read_rows(path: &Path) -> Result<Vec<Entry>, FitError> {
    if !path.exists() {
        return Ok(Vec::new());
    }
    let text = geodesic_util::fsio::read_text(path, geodesic_util::fsio::MAX_CSV_BYTES)
        .map_err(|e| FitError::input(path.display().to_string(), e.line(), e.cause()))?;
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            serde_json::from_str(l).map_err(|e| {
                FitError::input(
                    path.display().to_string(),
                    i + 1,
                    format!("bad history line: {e}"),
                )
            })
        })
        .collect()
}

/// Records the fit in the history of its dataset: replaces the row of its model version, or
/// appends a row for a new version; returns the entry.
pub fn append(out_dir: &Path, stem: &str, r: &FitReport) -> Result<Entry, FitError> {
    let path = path_for(out_dir, stem);
    let rows = read_rows(&path)?;
    let n_rows = rows.len();
    let mut prev = versions(rows);
    let vals: Vec<f64> = r.rms.values().copied().collect();
    let rms = (vals.iter().map(|v| v * v).sum::<f64>() / vals.len().max(1) as f64).sqrt();
    let noise: Vec<f64> = r
        .rms
        .keys()
        .filter_map(|ch| r.noise.get(ch).copied())
        .collect();
    let noise_rms = (noise.len() == vals.len() && !noise.is_empty())
        .then(|| (noise.iter().map(|v| v * v).sum::<f64>() / noise.len() as f64).sqrt());
    let mut e = Entry {
        version: prev.len() + 1,
        dataset: r.dataset.clone(),
        effects: r.effects.clone(),
        n_free: r.n_free,
        rms,
        chi2_red: r.chi2_red,
        bic: r.bic,
        noise_rms,
    };
    let werr = |x: std::io::Error| FitError::Write {
        path: path.display().to_string(),
        cause: x.to_string(),
    };
    std::fs::create_dir_all(out_dir).map_err(werr)?;
    let same = prev.iter().position(|p| version_key(p) == version_key(&e));
    if same.is_some() || n_rows != prev.len() {
        // a version already there (or a history of an older tool with a row per fit): the
        // history is written again whole, one row per version (atomically: never half)
        match same {
            Some(i) => {
                e.version = prev[i].version;
                prev[i] = e.clone();
            }
            None => prev.push(e.clone()),
        }
        let mut text = String::new();
        for p in &prev {
            text += &serde_json::to_string(p)
                .map_err(|x| FitError::input("history", 0, x.to_string()))?;
            text.push('\n');
        }
        crate::error::write_atomic(&path, text.as_bytes())?;
        return Ok(e);
    }
    let line =
        serde_json::to_string(&e).map_err(|x| FitError::input("history", 0, x.to_string()))? + "\n";
    if path.is_symlink() {
        // a link into a `verify` report set: never append through it (that would change a
        // committed set); the history becomes a file of its own
        let mut bytes = std::fs::read(&path).map_err(werr)?;
        bytes.extend_from_slice(line.as_bytes());
        crate::error::write_atomic(&path, &bytes)?;
        return Ok(e);
    }
    // one write of one line in append mode: a line is added whole
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&path)
        .map_err(werr)?;
    f.write_all(line.as_bytes()).map_err(werr)?;
    Ok(e)
}

/// Plain-text table of a history.
pub fn table(entries: &[Entry]) -> String {
    let mut s = format!(
        "{:>3}  {:>12}  {:>10}  {:>12}  {:>3}  effects\n",
        "ver", "rms", "chi2_red", "bic", "k"
    );
    for e in entries {
        s += &format!(
            "{:>3}  {:>12.4e}  {:>10.4}  {:>12.1}  {:>3}  {}\n",
            e.version,
            e.rms,
            e.chi2_red,
            e.bic,
            e.n_free,
            e.effects.join(",")
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimate::{FitOptions, fit};
    use crate::prepare::Prepared;
    use crate::report::FitReport;
    use crate::synth::{SynthSpec, generate};
    use geodesic_facility::Scenario;

    #[test]
    fn a_non_utf8_history_is_an_error_naming_the_file() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let p = path_for(dir, "h");
        std::fs::write(&p, b"{\"version\":1}\n\xff\xfe\n").unwrap();
        let e = read(&p).unwrap_err().to_string();
        assert!(
            e.contains("h.history.jsonl:2:") && e.contains("UTF-8"),
            "{e}"
        );
        assert!(read(&path_for(dir, "none")).unwrap().is_empty());
    }

    #[test]
    fn a_history_of_an_older_tool_reads_and_heals_to_one_row_per_version() {
        let e = |effects: &[&str], n_free, rms| Entry {
            version: 0,
            dataset: "d.yaml".into(),
            effects: effects.iter().map(|s| s.to_string()).collect(),
            n_free,
            rms,
            chi2_red: rms,
            bic: rms,
            noise_rms: None,
        };
        // base, base again (a diagnose), +b, base again, base with the effects reordered
        let raw = vec![
            e(&["a"], 2, 9.0),
            e(&["a"], 2, 8.0),
            e(&["a", "b"], 3, 1.0),
            e(&["a"], 2, 7.0),
        ];
        let v = versions(raw.clone());
        assert_eq!(v.len(), 2);
        assert_eq!(
            (v[0].version, v[0].rms),
            (1, 7.0),
            "the latest fit, first place"
        );
        assert_eq!((v[1].version, v[1].effects.len()), (2, 2));
        let mut r = raw;
        r.push(e(&["b", "a"], 3, 0.5));
        assert_eq!(versions(r)[1].rms, 0.5, "a set of effects, in any order");
    }

    #[test]
    fn appends_versions() {
        let mut spec = SynthSpec::defaults(Scenario::RtRetraction, &["piezo", "voltage_ramp"]);
        spec.post_s = 2e-4;
        let prep = Prepared::new(generate(&spec, "h.yaml").unwrap());
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().to_path_buf();
        for effects in [vec!["piezo"], vec!["piezo", "voltage_ramp"]] {
            let o = fit(&prep, &effects, &FitOptions::default()).unwrap();
            append(&dir, "h", &FitReport::new(&prep, &o)).unwrap();
        }
        let h = read(&path_for(&dir, "h")).unwrap();
        assert_eq!(h.iter().map(|e| e.version).collect::<Vec<_>>(), vec![1, 2]);
        // the base model fitted again (diagnose after fit, verify run twice): its row is
        // replaced, no row added; a --fix makes another version
        let o = fit(&prep, &["piezo"], &FitOptions::default()).unwrap();
        let again = append(&dir, "h", &FitReport::new(&prep, &o)).unwrap();
        assert_eq!(again.version, 1);
        let text = std::fs::read_to_string(path_for(&dir, "h")).unwrap();
        assert_eq!(text.lines().count(), 2, "{text}");
        let fixed = FitOptions {
            fixed: [("piezo.R".to_string(), 371.2)].into(),
            ..FitOptions::default()
        };
        let o = fit(&prep, &["piezo"], &fixed).unwrap();
        assert_eq!(
            append(&dir, "h", &FitReport::new(&prep, &o))
                .unwrap()
                .version,
            3
        );
        let h3 = read(&path_for(&dir, "h")).unwrap();
        assert_eq!(h3[2].name(Some(&h3[1])), "v3 -voltage_ramp");
        assert_eq!(
            h3[2].name(Some(&h3[0])),
            format!("v3 ({} free)", h3[2].n_free)
        );
        assert!(h[1].rms < h[0].rms / 3.0, "{} vs {}", h[1].rms, h[0].rms);
        assert!(table(&h).contains("piezo,voltage_ramp"));
    }
}
