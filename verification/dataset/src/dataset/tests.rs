use super::*;

fn write(dir: &Path, yaml: &str, csv: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("d.csv"), csv).unwrap();
    let p = dir.join("d.yaml");
    std::fs::write(&p, yaml).unwrap();
    p
}

const YAML: &str =
    "scenario: rt-retraction\ndata: d.csv\ntime_column: t\nchannels:\n  y: nm\nknown:\n  E0: 120\n";

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

fn err_of_strict(yaml: &str, csv: &str) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let p = write(tmp.path(), yaml, csv);
    Dataset::load_with(&p, LoadOptions { strict: true })
        .unwrap_err()
        .to_string()
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
    let e = err_of_strict(YAML, &csv_rows_with(20, Some((3, "1e-6,"))));
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
        let e = err_of_strict(YAML, &csv_rows_with(30, Some((row, &bad))));
        let at = format!("d.csv:{}:", row + 2);
        proptest::prop_assert!(e.contains(&at), "{} does not name {}", e, at);
    }
}

/// The public example `tmmf-adhesion` (YAML text, CSV text).
fn example() -> (String, String) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/examples");
    (
        std::fs::read_to_string(dir.join("tmmf-adhesion.yaml")).unwrap(),
        std::fs::read_to_string(dir.join("tmmf-adhesion.csv")).unwrap(),
    )
}

/// A decimal number's text with its exponent shifted by `k` (the value times 10^k, written
/// as a lab would: `-6.32e-10` m is `-0.632` nm).
fn shifted(text: &str, k: i32) -> String {
    let (m, e) = text.split_once('e').unwrap();
    let e: i32 = e.parse().unwrap();
    let v: f64 = format!("{m}e{}", e + k).parse().unwrap();
    format!("{v}")
}

/// The example as a lab delivers it: time in ms, x and y in nm under their own headers, in
/// another column order, with an extra column and comment lines.
fn lab_variant() -> (String, String) {
    let (yaml, csv) = example();
    let yaml = yaml.replace("time_column: t\nchannels:\n  x: m\n  y: m\n", "time_column: Time [ms]\ntime_unit: ms\nchannels:\n  x: {column: \"TM displacement [nm]\", unit: nm}\n  y:\n    column: tip (nm)\n    unit: nm\n")
        .replace("  x: 8.000000e-10\n  y: 3.000000e-09\n", "  x: 0.8\n  y: 3.0\n");
    let mut out = String::from("# TMMF release, intermediate TM mock-up\n# exported 2026-11-27\n");
    out += "tip (nm),Time [ms],temperature [K],TM displacement [nm]\n";
    for (i, l) in csv.lines().skip(1).enumerate() {
        let c: Vec<&str> = l.split(',').collect();
        if i == 100 {
            out += "# the operator noted a door closing here\n";
        }
        out += &format!(
            "{},{},293.1,{}\n",
            shifted(c[2], 9),
            shifted(c[0], 3),
            shifted(c[1], 9)
        );
    }
    (yaml, out)
}

#[test]
fn a_lab_style_record_loads_to_the_bits_of_the_plain_record() {
    let (yaml, csv) = example();
    let tmp = tempfile::tempdir().unwrap();
    let plain = Dataset::load(&write(
        &tmp.path().join("plain"),
        &yaml.replace("tmmf-adhesion.csv", "d.csv"),
        &csv,
    ))
    .unwrap();
    let (ly, lc) = lab_variant();
    assert!(ly.contains("time_unit: ms") && lc.contains("# exported"));
    let lab = Dataset::load(&write(
        &tmp.path().join("lab"),
        &ly.replace("tmmf-adhesion.csv", "d.csv"),
        &lc,
    ))
    .unwrap();
    assert_eq!(lab.t.len(), plain.t.len());
    // the same bits, not merely close: ms and nm shift the decimal exponent as written
    assert!(
        lab.t
            .iter()
            .zip(&plain.t)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    );
    for ch in ["x", "y"] {
        let (a, b) = (lab.channel(ch), plain.channel(ch));
        let bad = a
            .iter()
            .zip(b)
            .position(|(a, b)| a.to_bits() != b.to_bits());
        assert!(
            bad.is_none(),
            "{ch}: sample {bad:?}: {:?} vs {:?}",
            bad.map(|i| a[i]),
            bad.map(|i| b[i])
        );
    }
    assert_eq!(lab.noise["x"].to_bits(), plain.noise["x"].to_bits());
    assert_eq!(lab.rows.comments, 3);
    assert!(lab.rows.warnings.is_empty(), "{:?}", lab.rows.warnings);
    // lines: the first sample is on line 4 (two comments and the header before it), and the
    // comment before the 101st row moves the rest by one
    assert_eq!(lab.line_of(0), Some(4));
    assert_eq!(lab.line_of(100), Some(105));
}

#[test]
fn a_missing_value_is_skipped_with_a_warning_or_refused_under_strict() {
    let (yaml, csv) = example();
    let yaml = yaml.replace("tmmf-adhesion.csv", "d.csv");
    let mut rows: Vec<String> = csv.lines().map(String::from).collect();
    // row 500 (line 501) loses its x, row 900 (line 901) is cut short after t
    let c: Vec<String> = rows[500].split(',').map(String::from).collect();
    rows[500] = format!("{},,{}", c[0], c[2]);
    rows[900] = rows[900].split(',').next().unwrap().to_string();
    let csv = rows.join("\n") + "\n";
    let tmp = tempfile::tempdir().unwrap();
    let p = write(tmp.path(), &yaml, &csv);
    let d = Dataset::load(&p).unwrap();
    assert_eq!(d.t.len(), 1801 - 2);
    assert_eq!(
        d.rows.skipped,
        vec![
            Skipped {
                line: 501,
                column: "x".into()
            },
            Skipped {
                line: 901,
                column: "x".into()
            }
        ]
    );
    let w = d.rows.warnings.join("\n");
    assert!(
        w.contains("d.csv:501:") && w.contains("2 rows skipped") && w.contains("--strict"),
        "{w}"
    );
    let e = Dataset::load_with(&p, LoadOptions { strict: true })
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("d.csv:501:") && e.contains("without --strict"),
        "{e}"
    );
    assert!(!e.contains('\n'));
}

#[test]
fn unknown_keys_are_refused_with_line_and_the_nearest_key() {
    let (yaml, csv) = example();
    let yaml = yaml.replace("tmmf-adhesion.csv", "d.csv");
    let cases = [
        (yaml.replace("noise:", "noize:"), "d.yaml:10:", "`noise`"),
        (
            yaml.replace("time_column: t", "time_colum: t"),
            "d.yaml:4:",
            "`time_column`",
        ),
        (
            yaml.replace("  x: m\n", "  x: {colum: x, unit: m}\n"),
            "d.yaml:6:",
            "`column`",
        ),
        (yaml.replace("  m: 8.9", "  mass: 8.9"), "d.yaml:9:", "`m`"),
        (yaml.replace("  x: 8.0", "  X: 8.0"), "d.yaml:11:", "`x`"),
        (yaml.replace("  x: m\n", "  X: m\n"), "d.yaml:6:", "`x`"),
        (
            yaml.replace("scenario: tmmf-release", "scenario: tmmf-relase"),
            "d.yaml:1:",
            "`tmmf-release`",
        ),
    ];
    for (y, at, near) in cases {
        let e = err_of(&y, &csv, "");
        assert!(
            e.contains(at) && e.contains(&format!("did you mean {near}")),
            "{e}"
        );
        assert!(!e.contains('\n') && e.len() < 400, "{e}");
    }
    // no near key: the list of valid keys and what to do
    let e = err_of(&yaml.replace("noise:", "operator: me\nnoise:"), &csv, "");
    assert!(
        e.contains("d.yaml:10:") && e.contains("remove it") && e.contains("time_unit"),
        "{e}"
    );
}

#[test]
fn every_refusal_names_file_line_and_the_fix() {
    let (yaml, csv) = example();
    let yaml = yaml.replace("tmmf-adhesion.csv", "d.csv");
    let header = |h: &str| csv.replacen("t,x,y", h, 1);
    let cases: Vec<(String, String, &str, &str)> = vec![
        // a renamed column without its mapping
        (
            yaml.clone(),
            header("t,TM displacement [nm],y"),
            "d.csv:1:",
            "unit: ...}`",
        ),
        // the header in a comment line
        (
            yaml.clone(),
            format!(
                "# t,x,y\n{}",
                csv.lines().skip(1).collect::<Vec<_>>().join("\n")
            ),
            "d.csv:2:",
            "remove its `#`",
        ),
        // semicolons where the YAML says commas (without `delimiter:` they are detected)
        (
            yaml.replace("time_column: t\n", "time_column: t\ndelimiter: \",\"\n"),
            csv.replace(',', ";"),
            "d.csv:1:",
            "delimiter: \";\"",
        ),
        // a time unit that is not a time
        (
            yaml.replace("time_column: t", "time_column: t\ntime_unit: nm"),
            csv.clone(),
            "d.yaml:5:",
            "ms",
        ),
        // a channel of the wrong dimension
        (
            yaml.replace("  x: m\n", "  x: V\n"),
            csv.clone(),
            "d.yaml:6:",
            "nm",
        ),
        // a channel missing
        (
            yaml.replace("  x: m\n", ""),
            csv.clone(),
            "d.yaml:",
            "column: \"HEADER\"",
        ),
        // time in ms read as s: no sample is at t >= 0 after... (here: time not increasing)
        (
            yaml.clone(),
            csv.replacen("-9.950000000e-04", "-2.0e-03", 1),
            "d.csv:3:",
            "sort the rows",
        ),
        // a NaN
        (
            yaml.clone(),
            csv.replacen("-1.6277004e-09", "NaN", 1),
            "d.csv:3:",
            "leave the cell empty",
        ),
        // the data file missing
        (
            yaml.replace("d.csv", "none.csv"),
            csv.clone(),
            "d.yaml:3:",
            "relative to the YAML",
        ),
    ];
    for (y, c, at, fix) in cases {
        let e = err_of(&y, &c, "");
        assert!(
            e.contains(at) && e.contains(fix),
            "expected {at} and {fix:?} in: {e}"
        );
        assert!(!e.contains('\n'), "{e}");
    }
}

#[test]
fn a_wild_sample_is_excluded_named_by_line_or_refused_under_strict() {
    let (yaml, csv) = example();
    let yaml = yaml.replace("tmmf-adhesion.csv", "d.csv");
    let mut rows: Vec<String> = csv.lines().map(String::from).collect();
    let c: Vec<String> = rows[700].split(',').map(String::from).collect();
    rows[700] = format!("{},1e30,{}", c[0], c[2]);
    let tmp = tempfile::tempdir().unwrap();
    let p = write(tmp.path(), &yaml, &(rows.join("\n") + "\n"));
    let d = Dataset::load(&p).unwrap();
    assert_eq!(d.t.len(), 1800);
    assert_eq!(d.rows.wild.len(), 1);
    assert_eq!(d.rows.wild[0].line, 701);
    assert_eq!(d.rows.wild[0].channel, "x");
    assert!(d.rows.warnings[0].contains("d.csv:701:") && d.rows.warnings[0].contains("wild"));
    let e = Dataset::load_with(&p, LoadOptions { strict: true })
        .unwrap_err()
        .to_string();
    assert!(e.contains("d.csv:701:") && e.contains("wild sample"), "{e}");
    // the plain example has none
    let p = write(&tmp.path().join("plain"), &yaml, &csv);
    assert!(Dataset::load(&p).unwrap().rows.wild.is_empty());
}

use crate::noise::gauss;

#[test]
fn wild_samples_are_glitches_not_signals() {
    let n = 20_000;
    let noise = gauss(n, 3);
    // signals far above the noise that stay within their neighbours' envelope: a sinusoid of
    // 1e6 sigma sampled 6 times a period, a step of 1e6 sigma, a ramp, a kink
    let signals: Vec<Vec<f64>> = vec![
        (0..n)
            .map(|i| 1e6 * (i as f64 * std::f64::consts::TAU / 6.0).sin())
            .collect(),
        (0..n).map(|i| if i < n / 2 { 0.0 } else { 1e6 }).collect(),
        (0..n).map(|i| 1e3 * i as f64).collect(),
        (0..n)
            .map(|i| 50.0 * (i as f64 - n as f64 / 2.0).abs())
            .collect(),
    ];
    for (k, s) in signals.iter().enumerate() {
        let v: Vec<f64> = s.iter().zip(&noise).map(|(a, b)| a + b).collect();
        assert!(wild_samples(&v, 0.0).is_empty(), "signal {k}");
        // glitches of one to four adjacent samples: found, and nothing else
        let mut g = v.clone();
        let mut want = Vec::new();
        for (start, len) in [(1000, 1), (5000, 2), (9000, 3), (12000, 4), (19_998, 2)] {
            for (i, x) in g.iter_mut().enumerate().skip(start).take(len) {
                *x -= 1e9 * (1.0 + (i % 3) as f64);
                want.push(i);
            }
        }
        let w: Vec<usize> = wild_samples(&g, 0.0).iter().map(|x| x.0).collect();
        assert_eq!(w, want, "signal {k}");
    }
    // quantised data: a flicker of one step is not wild
    let q: Vec<f64> = noise.iter().map(|x| (0.2 * x).round()).collect();
    assert!(wild_samples(&q, 0.0).is_empty());
    // pure noise over many seeds: never a false alarm
    for seed in 0..20 {
        assert!(wild_samples(&gauss(5000, 100 + seed), 0.0).is_empty());
    }
}

#[test]
fn the_committed_lab_fixture_loads_to_the_bits_of_the_example() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/examples");
    let plain = Dataset::load(&dir.join("tmmf-adhesion.yaml")).unwrap();
    let lab = Dataset::load(&dir.join("lab/tmmf-adhesion-lab.yaml")).unwrap();
    assert_eq!(lab.t.len(), plain.t.len());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&lab.t), bits(&plain.t));
    for ch in ["x", "y"] {
        assert_eq!(bits(lab.channel(ch)), bits(plain.channel(ch)), "{ch}");
        assert_eq!(lab.noise[ch].to_bits(), plain.noise[ch].to_bits(), "{ch}");
    }
    assert_eq!(lab.known, plain.known);
    assert!(lab.rows.warnings.is_empty() && lab.rows.wild.is_empty());
}

/// On jittered stamps (sd 10 % of a 1 us step) a steep smooth signal (a 200 Hz swing of 50 um,
/// 0.063 m/s at its fastest) with 1 nm of noise: the neighbours' median by index reads the
/// signal between uneven stamps as deviations of many robust sigma, the deviations at the
/// stamps do not; a 12-sigma spike still stands out; a regular grid gets the index's figures
/// bit for bit.
#[test]
fn local_deviations_follow_jittered_stamps() {
    let n = 3000;
    let (g, j) = (gauss(n, 31), gauss(n, 32));
    let t: Vec<f64> = (0..n).map(|i| (i as f64 + 0.1 * j[i]) * 1e-6).collect();
    let swing = |t: f64| 5e-5 * (1.0 - (2.0 * std::f64::consts::PI * 200.0 * t).cos());
    let mut v: Vec<f64> = t
        .iter()
        .zip(&g)
        .map(|(t, e)| swing(*t) + 1e-9 * e)
        .collect();
    let worst = |dev: &[(f64, f64)]| {
        let s = robust_scale(dev);
        dev.iter().map(|(d, _)| d.abs() / s).fold(0.0, f64::max)
    };
    let by_index = worst(&local_deviation(&v));
    let at_stamps = worst(&local_deviation_at(&t, &v));
    assert!(by_index > 8.0 && at_stamps < 6.0, "{by_index} {at_stamps}");
    v[1500] += 12e-9;
    let dev = local_deviation_at(&t, &v);
    let s = robust_scale(&dev);
    assert!(dev[1500].0 / s > 9.0, "{}", dev[1500].0 / s);
    let grid: Vec<f64> = (0..n).map(|i| i as f64 * 1e-6).collect();
    let a = local_deviation(&v);
    let b = local_deviation_at(&grid, &v);
    assert!(
        a.iter()
            .zip(&b)
            .all(|(x, y)| x.0.to_bits() == y.0.to_bits() && x.1.to_bits() == y.1.to_bits())
    );
}
