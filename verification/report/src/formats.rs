//! The report formats: one registered list that drives what `verify` writes, its `--help` and
//! the docs. A format is one type implementing [`ReportFormat`], listed in [`formats`].

use crate::Report;
use crate::baseline::Diff;
use std::path::Path;

/// What a format renders from: the run's report, the baseline comparison when the run gated,
/// the compliance JSON already serialised, and the folder the set is being written to (a
/// page may link the artifacts there).
pub struct RenderInput<'a> {
    /// The run's report.
    pub report: &'a Report,
    /// The comparison with the baseline (`verify --baseline`), if any.
    pub diff: Option<&'a Diff>,
    /// `compliance.json`'s text (the report plus `baseline_diff`).
    pub json: &'a str,
    /// The folder the report set is staged in.
    pub dir: &'a Path,
}

/// One report format.
pub trait ReportFormat: Send + Sync {
    /// The file written in the reports folder (`vcd.xlsx`).
    fn file(&self) -> &'static str;
    /// What it holds, for `--help` and the docs (one line).
    fn about(&self) -> &'static str;
    /// Its bytes; `None` when the run has nothing for it (a baseline diff without a baseline).
    fn render(&self, input: &RenderInput) -> Result<Option<Vec<u8>>, String>;
}

macro_rules! format_type {
    ($ty:ident, $file:expr, $about:expr, |$i:ident| $body:expr) => {
        #[doc = $about]
        pub struct $ty;
        impl ReportFormat for $ty {
            fn file(&self) -> &'static str {
                $file
            }
            fn about(&self) -> &'static str {
                $about
            }
            fn render(&self, $i: &RenderInput) -> Result<Option<Vec<u8>>, String> {
                $body
            }
        }
    };
}

format_type!(
    ComplianceJson,
    "compliance.json",
    "the compliance matrix and the run's identification, machine-readable (the gate's baseline)",
    |i| Ok(Some(i.json.as_bytes().to_vec()))
);
format_type!(
    ComplianceMarkdown,
    "compliance.md",
    "the compliance matrix with each verdict's evidence, for reading",
    |i| Ok(Some(crate::markdown::render(i.report).into_bytes()))
);
format_type!(
    VcdMarkdown,
    "vcd.md",
    "the Verification Control Document (ECSS-E-ST-10-02C), Markdown",
    |i| Ok(Some(crate::vcd::markdown(i.report).into_bytes()))
);
format_type!(
    VcdCsv,
    "vcd.csv",
    "the Verification Control Document, one row per requirement, CSV",
    |i| Ok(Some(crate::vcd::csv(i.report).into_bytes()))
);
format_type!(
    VcdXlsx,
    "vcd.xlsx",
    "the Verification Control Document as a spreadsheet",
    |i| crate::xlsx::render(i.report)
        .map(Some)
        .map_err(|e| format!("vcd.xlsx: {e}"))
);
format_type!(
    VcdHtml,
    "vcd.html",
    "the Verification Control Document as a printable page",
    |i| Ok(Some(crate::html::render_vcd(i.report).into_bytes()))
);
format_type!(
    IndexHtml,
    "index.html",
    "one self-contained page: identification, matrix, VCD, fidelity, each requirement's evidence and plots",
    |i| Ok(Some(crate::html::render(i.report, &[i.dir]).into_bytes()))
);
format_type!(
    BaselineDiffMarkdown,
    "baseline-diff.md",
    "what changed against the baseline and what regressed (with --baseline only)",
    |i| Ok(i.diff.map(|d| crate::baseline::markdown(d).into_bytes()))
);

/// Every report format, in the order they are written.
pub fn formats() -> Vec<Box<dyn ReportFormat>> {
    vec![
        Box::new(ComplianceJson),
        Box::new(ComplianceMarkdown),
        Box::new(VcdMarkdown),
        Box::new(VcdCsv),
        Box::new(VcdXlsx),
        Box::new(VcdHtml),
        Box::new(IndexHtml),
        Box::new(BaselineDiffMarkdown),
    ]
}

/// The formats as help text: `  FILE  about` per line.
pub fn help() -> String {
    formats()
        .iter()
        .map(|f| format!("  {:<18} {}", f.file(), f.about()))
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_format_has_a_distinct_file() {
        let f = super::formats();
        let mut files: Vec<&str> = f.iter().map(|f| f.file()).collect();
        files.sort();
        files.dedup();
        assert_eq!(files.len(), f.len());
    }
}
