//! A second mission and spectral requirements end to end (issue 16, items 3 and 4): `geodesic
//! verify --requirements missions/NAME/requirements` (or `--mission NAME`) verifies that
//! mission, with its own document; `geodesic asd`
//! and `geodesic verify --series` judge a time series against a spectral requirement, with
//! exit 0 / 1 / 2.

mod common;
use common::{geodesic, scratch, workspace};
use serde_json::Value;
use std::fmt::Write;
use std::path::Path;

fn json_of(out: &std::process::Output) -> Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!("{e}: {}", String::from_utf8_lossy(&out.stderr));
    })
}

fn row<'a>(doc: &'a Value, id: &str) -> &'a Value {
    doc["requirements"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["id"] == id)
        .unwrap_or_else(|| panic!("no row {id}"))
}

/// The program registers every mission of the repository: `--mission NAME` picks one, and
/// `--requirements missions/NAME/requirements` finds it from the descriptor beside that folder
/// (the mission's own verdicts are tested in its crate, `missions/*/tests/`).
#[test]
fn another_mission_is_picked_by_name_or_by_its_requirement_folder() {
    let d = scratch("other-mission");
    let ws = workspace();
    let other = ws.join("missions/drag-free-cubesat");
    let reqs = other.join("requirements");
    let descriptor = std::fs::read_to_string(other.join("mission.yaml")).unwrap();
    let name = descriptor
        .lines()
        .find_map(|l| l.strip_prefix("name: "))
        .unwrap()
        .trim();
    let document = std::fs::read_to_string(other.join("document.yaml")).unwrap();
    let id = document
        .lines()
        .find_map(|l| l.strip_prefix("id: "))
        .unwrap()
        .trim();
    for (i, args) in [
        vec!["--requirements", reqs.to_str().unwrap()],
        vec!["--mission", name],
    ]
    .into_iter()
    .enumerate()
    {
        let r = format!("r{i}");
        let mut all = vec!["verify", "--json", "--reports", r.as_str()];
        all.extend(args);
        let out = geodesic(&all, &d);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let doc = json_of(&out);
        assert_eq!(doc["run"]["document"]["id"], id);
        // none of the root mission's rows
        let rows = doc["requirements"].as_array().unwrap();
        assert!(!rows.is_empty() && rows.iter().all(|r| r["id"] != "REL-GPRM-VEL"));
        // it declares no run option: no Monte Carlo keys in `run`
        assert!(doc["run"].get("mc_n").is_none() && doc["run"].get("seed").is_none());
    }
    // nor the root mission's --mc-n: refused (exit 2, one line), not silently ignored
    let out = geodesic(
        &[
            "verify",
            "--mission",
            name,
            "--mc-n",
            "10",
            "--reports",
            "r9",
        ],
        &d,
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!(
            "--mc-n: mission {name} declares no option `mc-n` (its options: none)"
        )) && err.trim().lines().count() == 1,
        "{err}"
    );
}

/// White noise of one-sided ASD `asd` [SI / sqrt(Hz)] at `fs` [Hz], in `unit` scaled by `k`.
fn series(dir: &Path, name: &str, asd: f64, fs: f64, n: usize, unit: &str, k: f64) -> String {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    let sd = asd / (2.0 / fs).sqrt();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let nd = Normal::new(0.0, sd).unwrap();
    let mut csv = String::from("t,v\n");
    for i in 0..n {
        let _ = writeln!(csv, "{},{:e}", i as f64 / fs, nd.sample(&mut rng) / k);
    }
    std::fs::write(dir.join(format!("{name}.csv")), csv).unwrap();
    std::fs::write(
        dir.join(format!("{name}.yaml")),
        format!(
            "origin: measurement\nprovenance: \"this test's bench: white noise of a known ASD, seed 9\"\ndata: {name}.csv\nchannel: v\nunit: \"{unit}\"\n"
        ),
    )
    .unwrap();
    format!("{name}.yaml")
}

#[test]
fn asd_judges_a_series_with_exit_0_1_2() {
    let d = scratch("asd");
    let low = series(&d, "low", 1e-14, 0.1, 8192, "fm/s^2", 1e-15);
    let out = geodesic(
        &[
            "asd",
            &low,
            "--requirement",
            "LPF-DA-ASD",
            "--json",
            "--plot",
            "p.svg",
        ],
        &d,
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc = json_of(&out);
    assert_eq!(doc["met"], true);
    let f = doc["worst_frequency_hz"].as_f64().unwrap();
    let truth = 1e-14 / (3e-14 * (1.0 + (f / 3e-3).powi(2)));
    let dof = doc["dof_per_bin"].as_f64().unwrap();
    let r = doc["worst_ratio"].as_f64().unwrap();
    assert!(
        (r / truth - 1.0).abs() < 4.0 * (1.0 / (2.0 * dof)).sqrt(),
        "{r} vs {truth}"
    );
    assert!(d.join("p.svg").is_file());
    let high = series(&d, "high", 8e-14, 0.1, 8192, "m/s^2", 1.0);
    let out = geodesic(&["asd", &high, "--requirement", "LPF-DA-ASD"], &d);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stdout).contains("NOT MET"));
    // wrong dimension, non-spectral requirement, unknown ID, too short, non-uniform: exit 2
    let volts = series(&d, "volts", 1e-14, 0.1, 8192, "V", 1.0);
    for (args, needle) in [
        (
            vec!["asd", volts.as_str(), "--requirement", "LPF-DA-ASD"],
            "bounds a acceleration",
        ),
        (
            vec!["asd", low.as_str(), "--requirement", "REL-GPRM-VEL"],
            "not a spectral requirement",
        ),
        (
            vec!["asd", low.as_str(), "--requirement", "NOPE-1"],
            "no such requirement",
        ),
    ] {
        let out = geodesic(&args, &d);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle) && err.lines().count() == 1, "{err}");
    }
    let short = series(&d, "short", 1e-14, 0.1, 80, "m/s^2", 1.0);
    let out = geodesic(&["asd", &short, "--requirement", "LPF-DA-ASD"], &d);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("coarser than the band's bottom"));
    std::fs::write(d.join("gap.csv"), "t,v\n0,1\n10,2\n20,3\n35,4\n40,5\n50,6\n60,7\n70,8\n80,9\n90,1\n100,2\n110,3\n120,4\n130,5\n140,6\n150,7\n160,8\n").unwrap();
    std::fs::write(
        d.join("gap.yaml"),
        "data: gap.csv\nchannel: v\nunit: m/s^2\n",
    )
    .unwrap();
    let out = geodesic(&["asd", "gap.yaml", "--requirement", "LPF-DA-ASD"], &d);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("gap.csv:5:") && err.contains("not uniform"),
        "{err}"
    );
}

#[test]
fn verify_series_gives_a_measured_verdict() {
    let d = scratch("verify-series");
    let ws = workspace();
    std::fs::create_dir_all(d.join("reqs")).unwrap();
    std::fs::copy(
        ws.join("requirements/performance.yaml"),
        d.join("reqs/performance.yaml"),
    )
    .unwrap();
    let s = series(&d, "da", 1e-14, 0.1, 8192, "m/s^2", 1.0);
    let arg = format!("LPF-DA-ASD={s}");
    let out = geodesic(
        &[
            "verify",
            "--requirements",
            "reqs",
            "--series",
            &arg,
            "--json",
            "--reports",
            "r",
        ],
        &d,
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc = json_of(&out);
    let r = row(&doc, "LPF-DA-ASD");
    assert_eq!(
        (r["status"].as_str(), r["basis"].as_str()),
        (Some("compliant"), Some("measurement"))
    );
    assert_eq!(row(&doc, "LPF-IFO-ASD")["status"], "not-verified");
    assert!(
        row(&doc, "LPF-IFO-ASD")["reason"]
            .as_str()
            .unwrap()
            .contains("--series LPF-IFO-ASD=")
    );
    assert!(d.join("r/spectra/LPF-DA-ASD.svg").is_file());
    assert!(doc["run"]["inputs"]["series"]["LPF-DA-ASD"]["sha256"].is_string());
    // the repository's example series calls itself synthetic: an illustration, not a verdict
    let example = ws.join("data/spectra/lpf-da-example.yaml");
    let arg = format!("LPF-DA-ASD={}", example.display());
    let out = geodesic(
        &[
            "verify",
            "--requirements",
            "reqs",
            "--series",
            &arg,
            "--json",
            "--reports",
            "r2",
        ],
        &d,
    );
    assert_eq!(out.status.code(), Some(0));
    let doc = json_of(&out);
    let r = row(&doc, "LPF-DA-ASD");
    assert_eq!(r["status"], "not-verified", "{r}");
    assert!(r["basis"].is_null());
    assert!(
        r["reason"]
            .as_str()
            .unwrap()
            .contains("declares itself synthetic"),
        "{r}"
    );
    // a series for a requirement that is not spectral, or not loaded, is exit 2
    for bad in ["REL-GPRM-VEL=da.yaml", "LPF-DA-ASD"] {
        let out = geodesic(
            &[
                "verify",
                "--requirements",
                "reqs",
                "--series",
                bad,
                "--reports",
                "r3",
            ],
            &d,
        );
        assert_eq!(out.status.code(), Some(2), "{bad}");
    }
}

#[test]
fn tip_radius_trade_off_and_its_cross_check() {
    let d = scratch("tip-radius");
    let out = geodesic(
        &[
            "tip-radius",
            "--radii",
            "1,5,10",
            "--mc-n",
            "3000",
            "--json",
            "--plot",
            "t.svg",
        ],
        &d,
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc = json_of(&out);
    let est = doc["estimates"].as_array().unwrap();
    assert_eq!(est.len(), 2);
    for e in est {
        // the optimum is a minimum of the curve the command prints
        let opt = e["at_optimum_um_s"].as_f64().unwrap();
        for p in e["curve"].as_array().unwrap() {
            assert!(p["total_um_s"].as_f64().unwrap() >= opt * (1.0 - 1e-9));
        }
    }
    // the Monte Carlo grows with the radius when A1 grows with the contact area
    let mc: Vec<f64> = doc["monte_carlo"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["p9973_um_s"].as_f64().unwrap())
        .collect();
    assert!(mc[0] < mc[1] && mc[1] < mc[2], "{mc:?}");
    assert!(d.join("t.svg").is_file());
    let out = geodesic(&["tip-radius", "--radii", "0,1"], &d);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn plunger_command_reports_each_case_and_a_touch() {
    let d = scratch("plunger");
    let out = geodesic(&["plunger", "--json", "--plot", "p.svg"], &d);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc = json_of(&out);
    let cases = doc["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 8);
    for c in cases {
        // the step convergence check: half the step changes nothing that matters
        let (a, b) = (
            c["extra_velocity_um_s"].as_f64().unwrap(),
            c["extra_velocity_half_step_um_s"].as_f64().unwrap(),
        );
        assert!((a - b).abs() <= 1e-6 * a.abs().max(1e-9), "{c}");
        assert!(c["touched_at_s"].is_null());
    }
    assert!(d.join("p.svg").is_file());
    // a retraction slower than the TM: it touches, and says when
    let out = geodesic(
        &[
            "plunger",
            "--voltage",
            "2",
            "--retraction",
            "100:25",
            "--v0",
            "7.5um/s",
            "--json",
        ],
        &d,
    );
    assert_eq!(out.status.code(), Some(0));
    let t = json_of(&out)["cases"][0]["touched_at_s"].as_f64().unwrap();
    assert!(t > 0.0 && t < 3.7, "{t}");
    for bad in [
        ["--retraction", "10:5"],
        ["--capacitance", "cube:3"],
        ["--v0", "3 m"],
    ] {
        let out = geodesic(&["plunger", bad[0], bad[1]], &d);
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
    }
}
