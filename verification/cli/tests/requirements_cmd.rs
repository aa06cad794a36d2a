//! `geodesic requirements check|list|show ID` and `verify --only ID,...` (issue 37, item 5).

mod common;

use common::{geodesic, scratch, workspace};
use serde_json::Value;
use std::path::Path;

fn run(args: &[&str], cwd: &Path) -> (i32, String, String) {
    let o = geodesic(args, cwd);
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn json(s: &str) -> Value {
    serde_json::from_str(s).unwrap_or_else(|e| panic!("{e}: {s}"))
}

#[test]
fn check_counts_a_valid_set_and_refuses_a_broken_one_with_file_line_column() {
    let (code, out, _) = run(&["requirements", "check", "--json"], &workspace());
    assert_eq!(code, 0);
    let v = json(&out);
    let n = v["requirements"].as_u64().unwrap();
    let files = std::fs::read_dir(workspace().join("requirements"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "yaml")
        })
        .count();
    assert_eq!(v["files"].as_array().unwrap().len(), files);
    assert!(n >= 20, "{n}");

    // a typo in a field: verify's loader refuses it with file:line:column, exit 2
    let dir = scratch("broken");
    let reqs = dir.join("reqs");
    std::fs::create_dir_all(&reqs).unwrap();
    for e in std::fs::read_dir(workspace().join("requirements")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, reqs.join(p.file_name().unwrap())).unwrap();
    }
    let f = reqs.join("charge.yaml");
    let text = std::fs::read_to_string(&f).unwrap();
    let bad = text.replacen("method:", "methd:", 1);
    assert_ne!(bad, text);
    std::fs::write(&f, bad).unwrap();
    let (code, out, err) = run(
        &[
            "requirements",
            "check",
            "--requirements",
            reqs.to_str().unwrap(),
        ],
        &dir,
    );
    assert_eq!(code, 2, "{out}{err}");
    assert!(out.is_empty(), "{out}");
    assert_eq!(err.lines().count(), 1, "{err}");
    let at = format!("{}:", f.display());
    assert!(err.contains(&at), "{err}");
    let rest = err.split(&at).nth(1).unwrap();
    let mut nums = rest.split(':').take(2);
    assert!(nums.next().unwrap().parse::<u32>().is_ok(), "{err}");
    assert!(nums.next().unwrap().parse::<u32>().is_ok(), "{err}");
}

#[test]
fn show_names_flow_down_and_an_unknown_id_its_nearest() {
    let dir = scratch("show");
    // built-in requirements (no ./requirements here): REL-DFACS-VEL's parent is REL-GPRM-VEL
    let (code, out, err) = run(&["requirements", "show", "REL-DFACS-VEL", "--json"], &dir);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert_eq!(v["parent"]["id"], "REL-GPRM-VEL");
    assert!(v["last_run"].is_null());
    let (_, out, _) = run(&["requirements", "show", "REL-GPRM-VEL", "--json"], &dir);
    let v = json(&out);
    assert!(
        v["children"]
            .as_array()
            .unwrap()
            .iter()
            .any(|c| c == "REL-DFACS-VEL"),
        "{v}"
    );

    let (code, out, err) = run(&["requirements", "show", "REL-GPRM-VLE"], &dir);
    assert_eq!(code, 2);
    assert!(out.is_empty());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("nearest: REL-GPRM-VEL"), "{err}");

    let (code, _, err) = run(&["verify", "--only", "CHG-VV", "--mc-n", "2000"], &dir);
    assert_eq!(code, 2);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("--only CHG-VV") && err.contains("CHG-V"),
        "{err}"
    );
}

#[test]
fn only_runs_the_chosen_rows_and_their_dependencies_and_the_gate_refuses_it() {
    let dir = scratch("only");
    let reports = dir.join("out");
    let r = reports.to_str().unwrap();
    let (code, out, err) = run(
        &[
            "verify",
            "--only",
            "REL-DFACS-VEL",
            "--mc-n",
            "3000",
            "--reports",
            r,
            "--json",
        ],
        &dir,
    );
    assert!(code == 0 || code == 1, "{err}");
    let v = json(&out);
    let rows = v["requirements"].as_array().unwrap();
    let role = |id: &str| {
        rows.iter()
            .find(|r| r["id"] == id)
            .map(|r| r["selection"]["role"].as_str().unwrap().to_string())
    };
    assert_eq!(role("REL-DFACS-VEL").as_deref(), Some("chosen"));
    // its parent, the parent's parent, and the row that judges the budget it is computed from
    assert_eq!(role("REL-GPRM-VEL").as_deref(), Some("dependency"));
    assert_eq!(role("TMS-Z-VEL").as_deref(), Some("dependency"));
    assert_eq!(role("FAC-ADH-CAL").as_deref(), Some("dependency"));
    // nothing else ran: no charge, capture or image rows
    assert!(role("CHG-Q").is_none() && role("CAP-QUARTIC").is_none());
    assert_eq!(v["summary"]["total"].as_u64().unwrap() as usize, rows.len());
    assert_eq!(v["run"]["partial"]["only"][0], "REL-DFACS-VEL");
    assert!(v["run"]["fidelity"].as_array().unwrap().is_empty());
    // the same verdict words as a whole run: the budget FAC-ADH-CAL rejects is named
    let fac = rows.iter().find(|r| r["id"] == "FAC-ADH-CAL").unwrap();
    if fac["status"] == "non-compliant" {
        let dfacs = rows.iter().find(|r| r["id"] == "REL-DFACS-VEL").unwrap();
        assert!(
            dfacs["verdict"]
                .as_str()
                .unwrap()
                .contains("budget rejected by FAC-ADH-CAL"),
            "{dfacs}"
        );
    }
    let md = std::fs::read_to_string(reports.join("compliance.md")).unwrap();
    assert!(md.contains("partial run"), "{md}");

    // the gate: never a partial run, neither as the run nor as the baseline (exit 2 at once)
    let base = reports.join("compliance.json");
    let b = base.to_str().unwrap();
    let (code, _, err) = run(&["verify", "--only", "CHG-V", "--baseline", b], &dir);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("partial run is never gated"), "{err}");
    let (code, _, err) = run(&["verify", "--baseline", b], &dir);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("a partial run"), "{err}");

    // the requirement list reads this last run: statuses for its rows, the others not run
    let (code, out, err) = run(&["requirements", "list", "--reports", r, "--json"], &dir);
    assert_eq!(code, 0, "{err}");
    let l = json(&out);
    assert_eq!(l["last_run"]["partial"], true);
    let by = |id: &str| {
        l["requirements"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["id"] == id)
            .unwrap()
            .clone()
    };
    assert!(by("REL-DFACS-VEL")["status"].is_string());
    assert!(by("CHG-Q")["status"].is_null());
    assert_eq!(by("CHG-Q")["verdict"], "not in the last run (partial)");
    let (code, out, _) = run(&["requirements", "list"], &dir);
    assert_eq!(code, 0);
    assert!(out.contains("no last run"), "{out}");
}
