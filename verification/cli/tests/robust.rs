//! The rule of the house, end to end: bad input exits 2 with one line on standard error naming
//! the file (and line) or the flag and the cause; no panic, no hang, no NaN reported as success.
//! One test per class of input; every test works in its own scratch directory.

mod common;
use common::{geodesic, scratch};

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs and asserts exit 2 with one stderr line containing every `want`.
fn refused(args: &[&str], cwd: &Path, want: &[&str]) -> String {
    let o = geodesic(args, cwd);
    let e = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{args:?}: {e}");
    for w in want {
        assert!(e.contains(w), "{args:?}: `{w}` not in {e}");
    }
    assert!(!e.contains("panicked"), "{e}");
    e
}

/// A small rt-retraction dataset written by `synth` into `dir`.
fn dataset(dir: &Path) -> PathBuf {
    let p = dir.join("d.yaml");
    let o = geodesic(
        &[
            "synth",
            "--scenario",
            "rt-retraction",
            "--effects",
            "piezo,voltage_ramp",
            "--post",
            "2e-4",
            "--out",
            p.to_str().unwrap(),
        ],
        dir,
    );
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    p
}

#[test]
fn class1_a_bound_outside_the_built_in_range_replaces_it() {
    let d = scratch("class1");
    let ds = dataset(&d);
    let ds = ds.to_str().unwrap();
    // piezo.R is built in as [1, 1e5] ohm: a bound wholly above it used to panic in clamp
    let o = geodesic(
        &[
            "fit",
            ds,
            "--effects",
            "piezo,voltage_ramp",
            "--bound",
            "piezo.R=2e5:4e5",
            "--json",
        ],
        &d,
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let r = v["params"]["piezo.R"]["value"].as_f64().unwrap();
    assert!((2e5 * 0.999..=4e5 * 1.001).contains(&r), "{r}");
    for bad in [
        "piezo.R=5:1",
        "piezo.R=NaN:1",
        "piezo.R=1:inf",
        "piezo.R=3:3",
    ] {
        refused(
            &["fit", ds, "--effects", "piezo", "--bound", bad],
            &d,
            &["--bound"],
        );
    }
    refused(
        &["fit", ds, "--effects", "piezo", "--bound", "piezo.R=-5:10"],
        &d,
        &["--bound", "piezo.R"],
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn class2_huge_counts_are_refused_naming_the_flag() {
    let d = scratch("class2");
    refused(
        &["montecarlo", "--n", "100000000000"],
        &d,
        &["--n", "10000000"],
    );
    refused(
        &["montecarlo", "--n", "10", "--threads", "1000000"],
        &d,
        &["--threads", "1024"],
    );
    refused(
        &["montecarlo", "--n", "10", "--threads", "0"],
        &d,
        &["--threads"],
    );
    refused(&["charge", "--n", "100000000000"], &d, &["--n"]);
    refused(
        &["verify", "--mc-n", "100000000000"],
        &d,
        &["--mc-n", "between 1 and 10000000"],
    );
    for fs in ["1e12", "inf"] {
        refused(
            &[
                "synth",
                "--scenario",
                "rt-retraction",
                "--effects",
                "piezo",
                "--fs",
                fs,
                "--out",
                "e.yaml",
            ],
            &d,
            &["--fs"],
        );
    }
    refused(
        &[
            "montecarlo",
            "--n",
            "3",
            "--shard",
            "1/5",
            "--out",
            "p.json",
        ],
        &d,
        &["--shard", "empty"],
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Writes shards 1/2 and 2/2 of a 9-draw run; returns their paths.
fn parts(d: &Path) -> [String; 2] {
    let mk = |i: usize| {
        let p = d.join(format!("p{i}.json")).display().to_string();
        let o = geodesic(
            &[
                "montecarlo",
                "--n",
                "9",
                "--shard",
                &format!("{i}/2"),
                "--out",
                &p,
                "--json",
            ],
            d,
        );
        assert_eq!(o.status.code(), Some(0), "{o:?}");
        p
    };
    [mk(1), mk(2)]
}

#[test]
fn class3_garbage_is_never_reported_as_success() {
    let d = scratch("class3");
    let ds = dataset(&d);
    let ds = ds.to_str().unwrap();
    for fix in ["piezo.R=NaN", "piezo.R=inf", "piezo.R=-300"] {
        refused(
            &["fit", ds, "--effects", "piezo", "--fix", fix],
            &d,
            &["--fix", "piezo.R"],
        );
    }
    refused(
        &["charge", "--neutralise-e", "NaN"],
        &d,
        &["--neutralise-e"],
    );
    // a dataset whose values overflow downstream
    let csv = std::fs::read_to_string(d.join("d.csv")).unwrap();
    let mut lines: Vec<String> = csv.lines().map(String::from).collect();
    let t = lines[5].split(',').next().unwrap().to_string();
    lines[5] = format!("{t},1e300");
    std::fs::write(d.join("d.csv"), lines.join("\n") + "\n").unwrap();
    refused(&["fit", ds, "--effects", "piezo"], &d, &["d.csv"]);
    // E0 = 0 or negative for rt-retraction
    let yaml = std::fs::read_to_string(ds).unwrap();
    std::fs::write(d.join("z.yaml"), yaml.replace("E0: 1.2e2", "E0: 0")).unwrap();
    assert_ne!(yaml, yaml.replace("E0: 1.2e2", "E0: 0"));
    refused(
        &["fit", "z.yaml", "--effects", "piezo"],
        &d,
        &["z.yaml", "E0"],
    );
    // a quartic sum that overflows is not captured and stays a finite number
    let o = geodesic(&["capture", "--vz", "1e308", "--json"], &d);
    assert_eq!(o.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["captured"], false);
    assert!(v["quartic_sum"].as_f64().unwrap().is_finite());
    // and its text says so in one short line (it printed the sum's 309 digits)
    let o = geodesic(&["capture", "--vz", "1e308"], &d);
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    let first = out.lines().next().unwrap_or_default();
    assert!(
        first.len() < 60 && first.ends_with("NOT captured"),
        "{first}"
    );
    assert!(!String::from_utf8_lossy(&o.stdout).contains("null"));
    // merge parts: a flipped exponent bit, a NaN velocity, an empty or huge shard count
    let [p1, p2] = parts(&d);
    let edit = |name: &str, f: &dyn Fn(&mut serde_json::Value)| -> String {
        let mut v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&p2).unwrap()).unwrap();
        f(&mut v);
        let p = d.join(name).display().to_string();
        std::fs::write(&p, v.to_string()).unwrap();
        p
    };
    let flipped = edit("flip.json", &|v| {
        let b = v["v_m_s"][0].as_u64().unwrap() ^ (1 << 60);
        v["v_m_s"][0] = b.into();
    });
    refused(&["merge", &p1, &flipped], &d, &["flip.json", "checksum"]);
    let nan = edit("nan.json", &|v| {
        v["v_m_s"][0] = f64::NAN.to_bits().into();
        v.as_object_mut().unwrap().remove("sha256");
    });
    refused(&["merge", &p1, &nan], &d, &["nan.json"]);
    let huge = edit("huge.json", &|v| {
        v["shard"] = serde_json::json!([2, 1u64 << 62]);
    });
    let e = refused(&["merge", &p1, &huge], &d, &["huge.json"]);
    assert!(!e.contains("Some("), "{e}");
    let o = geodesic(&["merge", &p1, &p2, "--json"], &d);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn class4_non_regular_files_are_refused_without_hanging() {
    let d = scratch("class4");
    refused(
        &["fit", "/dev/zero", "--effects", "piezo"],
        &d,
        &["/dev/zero", "not a regular file"],
    );
    refused(
        &["montecarlo", "--budget", "/dev/zero"],
        &d,
        &["/dev/zero", "not a regular file"],
    );
    refused(
        &["verify", "--requirements", "/dev/zero"],
        &d,
        &["/dev/zero"],
    );
    let fifo = d.join("fifo.yaml");
    let ok = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    if ok {
        refused(
            &["fit", fifo.to_str().unwrap(), "--effects", "piezo"],
            &d,
            &["fifo.yaml", "FIFO"],
        );
    }
    // an extreme budget value is refused at load time, naming file, line and field
    let budget = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/release/budget.yaml"),
    )
    .unwrap();
    std::fs::write(
        d.join("b.yaml"),
        budget.replacen("max: 1.5e5", "max: 1.0e30", 1),
    )
    .unwrap();
    refused(
        &["montecarlo", "--n", "10", "--budget", "b.yaml"],
        &d,
        &["b.yaml:", "A1_n_m"],
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn class5_bad_structure_is_refused() {
    let d = scratch("class5");
    let req = d.join("requirements");
    std::fs::create_dir_all(&req).unwrap();
    std::fs::write(req.join("a.yaml"), "family: x\nrequirements: []\n").unwrap();
    refused(
        &["verify", "--requirements", "requirements"],
        &d,
        &["no requirements"],
    );
    for (args, want) in [
        (vec!["--noise", "y=-1e-9"], "--noise"),
        (vec!["--noise", "q=1e-9"], "--noise q"),
        (vec!["--known", "E0=-5"], "--known E0"),
        (vec!["--param", "piezo.R=-3"], "piezo.R"),
    ] {
        let mut a = vec![
            "synth",
            "--scenario",
            "rt-retraction",
            "--effects",
            "piezo",
            "--out",
            "s.yaml",
        ];
        a.extend(args);
        refused(&a, &d, &[want]);
    }
    refused(
        &[
            "synth",
            "--scenario",
            "tmmf-release",
            "--effects",
            "needle_contact,tip_contact",
            "--jerk",
            "NaN",
            "--out",
            "s.yaml",
        ],
        &d,
        &["--jerk"],
    );
    assert!(!d.join("s.yaml").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn class6_causes_hit_their_target() {
    let d = scratch("class6");
    // clap usage errors are one line, exit 2
    refused(&["montecarlo", "--bogus"], &d, &["usage", "--bogus"]);
    refused(&["montecarlo", "--n", "x"], &d, &["usage"]);
    // an unbalanced CSV quote gives a short cause
    let ds = dataset(&d);
    let csv = std::fs::read_to_string(d.join("d.csv")).unwrap();
    let mut lines: Vec<String> = csv.lines().map(String::from).collect();
    let t = lines[3].split(',').next().unwrap().to_string();
    lines[3] = format!("{t},\"4");
    std::fs::write(d.join("d.csv"), lines.join("\n") + "\n").unwrap();
    let e = refused(
        &["fit", ds.to_str().unwrap(), "--effects", "piezo"],
        &d,
        &["d.csv:4:"],
    );
    assert!(e.len() < 300, "{e}");
    // a non-UTF-8 fit history is an error naming the file, and nothing is appended to it
    std::fs::create_dir_all(d.join("reports/fits")).unwrap();
    let h = d.join("reports/fits/d.history.jsonl");
    std::fs::write(&h, b"\xff\xfe\n").unwrap();
    refused(&["history", "d"], &d, &["d.history.jsonl", "UTF-8"]);
    assert_eq!(std::fs::read(&h).unwrap(), b"\xff\xfe\n");
    // a non-UTF-8 requirement file names the line of the bad byte
    let req = d.join("requirements");
    std::fs::create_dir_all(&req).unwrap();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../requirements");
    for e in std::fs::read_dir(src).unwrap().flatten() {
        std::fs::copy(e.path(), req.join(e.file_name())).unwrap();
    }
    let mut bytes = std::fs::read(req.join("charge.yaml")).unwrap();
    let nl: Vec<usize> = (0..bytes.len()).filter(|i| bytes[*i] == b'\n').collect();
    bytes[nl[4] + 1] = 0xff; // first byte of line 6
    std::fs::write(req.join("charge.yaml"), &bytes).unwrap();
    refused(
        &["verify", "--requirements", "requirements"],
        &d,
        &["charge.yaml:6:", "UTF-8"],
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// A fit whose every parameter is held is a chi-square at those values, not a panic (nalgebra's
/// eigen-decomposition panicked on the empty normal matrix: seen while comparing a record with
/// its generator's truth).
#[test]
fn a_fit_with_every_parameter_held_reports_the_chi_square() {
    let d = scratch("allfixed");
    let ds = dataset(&d);
    let ds = ds.to_str().unwrap();
    let mut args = vec!["fit", ds, "--effects", "piezo", "--json"];
    for fix in [
        "piezo.R=371.2",
        "piezo.m=9e-4",
        "piezo.Ca=2.3e-7",
        "piezo.k=4.91e7",
        "piezo.b=9.77",
        "piezo.T=5.73",
    ] {
        args.extend(["--fix", fix]);
    }
    let o = geodesic(&args, &d);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    assert_eq!(v["n_free"], 0, "{v}");
    assert!(v["chi2"].as_f64().is_some_and(f64::is_finite), "{v}");
}
