//! The reports of `geodesic verify` are controlled documents: each carries the document
//! identifier and issue with the run's identification, and two runs of the same commit and
//! inputs produce the same content apart from the date.
//!
//! Only the release, charge and TM-state families are loaded (the facility's identification fits are slow
//! in the test profile): the release Monte Carlo writes the per-requirement plots.

mod common;
use common::{geodesic, scratch, workspace};

use std::collections::BTreeMap;
use std::path::Path;

/// Runs `verify` in `d` (its own copy of two requirement families) and returns the run date and
/// every text report by relative path.
fn run(d: &Path) -> (String, BTreeMap<String, String>) {
    let req = d.join("requirements");
    std::fs::create_dir_all(&req).unwrap();
    for f in ["release.yaml", "charge.yaml", "tm-state.yaml"] {
        std::fs::copy(workspace().join("requirements").join(f), req.join(f)).unwrap();
    }
    let out = geodesic(
        &[
            "verify",
            "--json",
            "--mc-n",
            "1000",
            "--no-fidelity",
            "--requirements",
            "requirements",
            "--reports",
            "reports",
            "--junit",
            "junit.xml",
        ],
        d,
    );
    let code = out.status.code().unwrap();
    assert!(
        code == 0 || code == 1,
        "exit {code}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let date = doc["run"]["date"].as_str().unwrap().to_string();
    let mut files = BTreeMap::new();
    let mut stack = vec![d.join("reports")];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            let p = e.path();
            if e.file_name() == ".geodesic" {
                continue; // the report sets behind the links: a reader sees the links
            }
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x != "xlsx") {
                let rel = p.strip_prefix(d).unwrap().display().to_string();
                files.insert(rel, std::fs::read_to_string(&p).unwrap());
            }
        }
    }
    files.insert(
        "junit.xml".into(),
        std::fs::read_to_string(d.join("junit.xml")).unwrap(),
    );
    assert!(d.join("reports/vcd.xlsx").is_file(), "vcd.xlsx written");
    (date, files)
}

/// `text` with the run's wall times masked: the `timings` object of the JSON and the value
/// of the run line `wall time (differs run to run; not compared)` of the other reports.
fn mask_timings(text: &str) -> String {
    if let Ok(mut v) = serde_json::from_str::<serde_json::Value>(text) {
        if let Some(run) = v.get_mut("run").and_then(|r| r.as_object_mut()) {
            assert!(run.remove("timings").is_some(), "run.timings");
        }
        return serde_json::to_string_pretty(&v).unwrap();
    }
    let label = "wall time (differs run to run; not compared)";
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(label) {
        out.push_str(&rest[..i + label.len()]);
        rest = &rest[i + label.len()..];
        // the value starts at `total` (after `: ` or `</th><td>`) and runs to the end of the
        // line or of the table cell
        let start = rest.find("total").expect("the timings' total");
        out.push_str(&rest[..start]);
        rest = &rest[start..];
        let end = rest.find(['\n', '<']).unwrap_or(rest.len());
        out.push_str("<TIMINGS>");
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

#[test]
fn two_runs_differ_only_in_their_date_lines_and_every_report_names_the_document() {
    let (date_a, a) = run(&scratch("run-a"));
    let (date_b, b) = run(&scratch("run-b"));
    assert_eq!(
        a.keys().collect::<Vec<_>>(),
        b.keys().collect::<Vec<_>>(),
        "same report set"
    );
    let doc = "GEO-LPF-TMR-VCD-001";
    for (name, text) in &a {
        if !name.ends_with(".svg") {
            assert!(text.contains(doc), "{name} lacks the document identifier");
        }
        if !(name.ends_with(".svg") || name.ends_with(".csv")) {
            assert!(text.contains(&date_a), "{name} lacks the run date");
            assert!(text.contains("commit"), "{name} lacks the commit");
        }
        // the date is the only thing allowed to differ: with each run's date (and day) masked,
        // the files are equal byte for byte (index.html is a few long lines, so a line-wise
        // "date lines may differ" rule would be too weak there)
        // the wall times (run.timings, and the run line that states them) differ run to run
        // and are masked too; they are there
        assert!(
            name.ends_with(".svg")
                || name.ends_with(".csv")
                || name == "junit.xml"
                || text.contains("wall time")
                || text.contains("\"timings\""),
            "{name} lacks the run's wall times"
        );
        let mask = |t: &str, date: &str| {
            mask_timings(t)
                .replace(date, "<DATE>")
                .replace(&date[..10], "<DAY>")
        };
        let (ma, mb) = (mask(text, &date_a), mask(&b[name], &date_b));
        if ma != mb {
            let (la, lb): (Vec<&str>, Vec<&str>) = (ma.lines().collect(), mb.lines().collect());
            let first = la.iter().zip(&lb).find(|(x, y)| x != y);
            panic!("{name}: differs beyond the date: {first:?}");
        }
        let (ta, tb) = (mask_timings(text), mask_timings(&b[name]));
        let changed = ta.lines().zip(tb.lines()).filter(|(x, y)| x != y);
        for (x, _) in changed {
            assert!(x.contains(&date_a[..10]), "{name}: {x}");
        }
    }
    // the plots of this run: each velocity requirement on its own plot
    for id in ["REL-GPRM-VEL", "REL-DFACS-VEL"] {
        assert!(a.contains_key(&format!("reports/release-velocity-{id}.svg")));
    }
}
