//! Criterion benchmarks of geodesic live in `benches/benches/`; this library holds what they
//! share with the command line: the public `rt-plunger` record resampled to any length
//! ([`resample_rt_plunger`]), so that a benchmark and a `geodesic fit` run time the same
//! record (`cargo run --release -p geodesic-benches --example resample -- 1000000 DIR`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The public example `data/examples/rt-plunger` (1 021 samples at 1 MHz, 1 ms) resampled to
/// `n` samples over the same time span by linear interpolation between its samples (the
/// issue-35 record: 1 000 000 samples), written as `DIR/rt-plunger-<n>.{yaml,csv}`; returns the
/// YAML's path. The YAML is the example's with its `data` line pointing at the new CSV (same
/// scenario, channel, known voltage and noise figure). Deterministic: the same bytes for the
/// same `n`.
pub fn resample_rt_plunger(n: usize, dir: &Path) -> std::io::Result<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/examples");
    let csv = std::fs::read_to_string(root.join("rt-plunger.csv"))?;
    let yaml = std::fs::read_to_string(root.join("rt-plunger.yaml"))?;
    let mut t = Vec::new();
    let mut y = Vec::new();
    for line in csv.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let (a, b) = line
            .split_once(',')
            .ok_or_else(|| std::io::Error::other(format!("rt-plunger.csv: `{line}`")))?;
        let parse = |s: &str| {
            s.trim()
                .parse::<f64>()
                .map_err(|e| std::io::Error::other(format!("rt-plunger.csv: `{s}`: {e}")))
        };
        t.push(parse(a)?);
        y.push(parse(b)?);
    }
    if n < 2 || t.len() < 2 {
        return Err(std::io::Error::other("at least two samples"));
    }
    let (t0, t1) = (t[0], t[t.len() - 1]);
    let mut out = String::with_capacity(n * 34 + 8);
    out.push_str("t,y\n");
    let mut j = 0;
    for i in 0..n {
        let ti = t0 + (t1 - t0) * i as f64 / (n - 1) as f64;
        while j + 2 < t.len() && t[j + 1] <= ti {
            j += 1;
        }
        let w = (ti - t[j]) / (t[j + 1] - t[j]);
        let yi = y[j] + (y[j + 1] - y[j]) * w;
        let _ = writeln!(out, "{ti:.12e},{yi:.7e}");
    }
    std::fs::create_dir_all(dir)?;
    let stem = format!("rt-plunger-{n}");
    std::fs::write(dir.join(format!("{stem}.csv")), out)?;
    let yaml: String = yaml
        .lines()
        .map(|l| {
            if l.starts_with("data:") {
                format!("data: {stem}.csv\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let path = dir.join(format!("{stem}.yaml"));
    std::fs::write(&path, yaml)?;
    Ok(path)
}
