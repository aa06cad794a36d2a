//! Fit history per dataset: every fit appends one JSON line (`<stem>.history.jsonl` under the
//! output directory), so the error can be watched falling as the model grows.

use std::io::Write;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::FitError;
use crate::fit::FitReport;

/// One fit of a dataset.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
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
                    format!("v{} (same effects)", self.version)
                } else {
                    format!("v{} {}", self.version, d.join(" "))
                }
            }
        }
    }
}

/// Path of the history file of a dataset stem.
pub fn path_for(out_dir: &Path, stem: &str) -> PathBuf {
    out_dir.join(format!("{stem}.history.jsonl"))
}

/// Reads a history (empty when the file does not exist).
pub fn read(path: &Path) -> Result<Vec<Entry>, FitError> {
    if !path.exists() {
        return Ok(Vec::new());
    }
    let text = geodesic_core::fsio::read_text(path, geodesic_core::fsio::MAX_CSV_BYTES)
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

/// Appends the fit to the history of its dataset; returns the entry.
pub fn append(out_dir: &Path, stem: &str, r: &FitReport) -> Result<Entry, FitError> {
    let path = path_for(out_dir, stem);
    let prev = read(&path)?;
    let vals: Vec<f64> = r.rms.values().copied().collect();
    let rms = (vals.iter().map(|v| v * v).sum::<f64>() / vals.len().max(1) as f64).sqrt();
    let noise: Vec<f64> = r
        .rms
        .keys()
        .filter_map(|ch| r.noise.get(ch).copied())
        .collect();
    let noise_rms = (noise.len() == vals.len() && !noise.is_empty())
        .then(|| (noise.iter().map(|v| v * v).sum::<f64>() / noise.len() as f64).sqrt());
    let e = Entry {
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
    use crate::fit::{FitOptions, FitReport, Prepared, fit};
    use crate::synth::{SynthSpec, generate};
    use geodesic_facility::Scenario;

    #[test]
    fn a_non_utf8_history_is_an_error_naming_the_file() {
        let dir =
            std::env::temp_dir().join(format!("geodesic-history-utf8-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = path_for(&dir, "h");
        std::fs::write(&p, b"{\"version\":1}\n\xff\xfe\n").unwrap();
        let e = read(&p).unwrap_err().to_string();
        assert!(
            e.contains("h.history.jsonl:2:") && e.contains("UTF-8"),
            "{e}"
        );
        assert!(read(&path_for(&dir, "none")).unwrap().is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn appends_versions_and_plots_them() {
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
        assert!(h[1].rms < h[0].rms / 3.0, "{} vs {}", h[1].rms, h[0].rms);
        assert!(table(&h).contains("piezo,voltage_ramp"));
        let svg = crate::plot::history_svg(&h).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("</svg>"));
        let o = fit(&prep, &["piezo"], &FitOptions::default()).unwrap();
        let r = FitReport::new(&prep, &o);
        let fsvg = crate::plot::fit_svg(&prep, &o.pred, &r).unwrap();
        assert!(!r.failures.is_empty());
        assert!(
            fsvg.to_uppercase().contains("#FFC8C8"),
            "failure windows are shaded"
        );
        assert!(
            fsvg.contains("failure window") && fsvg.contains("noise band"),
            "every shaded band is in a legend"
        );
    }
}
