//! The short compliance table printed on a terminal by `geodesic verify`: one row per
//! requirement, its credibility level and weakest factor last ([`geodesic_core::credibility`]).

use crate::{basis_word, fmt_limit, fmt_margin, fmt_value, tests_word, verdict};
use geodesic_core::matrix::{Matrix, Status};

/// Renders the matrix as an aligned text table with a summary line.
pub fn table(m: &Matrix, color: bool) -> String {
    table_for(m, color, geodesic_core::testrun::RECORD_COMMAND)
}

/// [`table`], naming `record_command` as the command that records the traced tests (a
/// project's own `cargo run -- test`).
pub fn table_for(m: &Matrix, color: bool, record_command: &str) -> String {
    let head = [
        "ID",
        "status",
        "basis",
        "value",
        "limit",
        "margin",
        "tests",
        "credibility",
    ];
    let run = m.test_run.is_some();
    let rows: Vec<[String; 8]> = m
        .requirements
        .iter()
        .map(|r| {
            [
                r.id.clone(),
                verdict(r),
                basis_word(r).to_string(),
                fmt_value(r),
                fmt_limit(r),
                fmt_margin(r.margin),
                tests_word(r, run),
                crate::credibility_word(r),
            ]
        })
        .collect();
    let mut w = head.map(|h| h.chars().count());
    for r in &rows {
        for (i, c) in r.iter().enumerate() {
            w[i] = w[i].max(c.chars().count());
        }
    }
    let pad = |s: &str, n: usize| format!("{s}{}", " ".repeat(n.saturating_sub(s.chars().count())));
    let mut out = String::new();
    let line: Vec<String> = head.iter().enumerate().map(|(i, h)| pad(h, w[i])).collect();
    out.push_str(line.join("  ").trim_end());
    out.push('\n');
    for (r, row) in rows.iter().zip(&m.requirements) {
        let cells: Vec<String> = r
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let p = pad(c, w[i]);
                if i == 1 && color {
                    let code = match row.status {
                        Status::Compliant => "32",
                        Status::NonCompliant => "31",
                        Status::NotVerified => "33",
                    };
                    format!("\x1b[{code}m{p}\x1b[0m")
                } else {
                    p
                }
            })
            .collect();
        out.push_str(cells.join("  ").trim_end());
        out.push('\n');
    }
    out.push_str(&m.summary.line());
    out.push('\n');
    match &m.test_run {
        Some(_) => out.push_str(&format!("test results: {}\n", crate::test_run_line(m))),
        None => out.push_str(&format!(
            "test results: none recorded (run `{record_command}` to record the traced tests)\n"
        )),
    }
    out
}
