//! The Verification Control Document as an XLSX workbook (`vcd.xlsx`) for the engineers who
//! live in spreadsheets: sheet `VCD` with one row per requirement and the columns of
//! [`crate::vcd::COLUMNS`] (ECSS-E-ST-10-02C Annex B), the compliance and ID cells coloured by
//! status, the header row and ID column frozen, an autofilter over every column; sheet
//! `Document` with the document identification and the run (date, tool version, commit,
//! hashes, command line).
//!
//! `value`, `limit` and `margin` are number cells, so that a spreadsheet (and pandas, openpyxl)
//! sorts, filters and computes with them: the value and the limit in the requirement's unit,
//! which is in the `unit` column and also in their number format (`1.329 um/s` shown, 1.329
//! stored), the margin as a fraction in a percentage format (`73.4%` shown, 0.734 stored); a
//! row with none has an empty cell. Every other column is text, as in `vcd.csv`
//! (`value_text`, `limit_text`, `margin_text` as the reports write them).
//!
//! Written with `rust_xlsxwriter` (pure Rust, no system library, default features off). The
//! workbook's creation date is the run's date, so two runs of the same inputs differ in the
//! date only.

use crate::Report;
use crate::vcd::{COLUMNS, cells, lines};
use rust_xlsxwriter::{
    Color, DocProperties, ExcelDateTime, Format, FormatAlign, FormatBorder, Workbook, XlsxError,
};

/// Name of the VCD sheet.
pub const VCD_SHEET: &str = "VCD";
/// Name of the metadata sheet.
pub const META_SHEET: &str = "Document";

/// Fill colour of a compliance value: green (yes), red (no), amber (partial, not verified).
pub fn status_color(compliance: &str) -> u32 {
    match compliance {
        "yes" => 0xD7F5DD,
        "no" => 0xFBD5D5,
        // qualified compliance (`yes (flow-down)`), partial, not verified
        _ => 0xFFF3CD,
    }
}

fn width(col: &str) -> f64 {
    match col {
        "id" => 22.0,
        "title" | "source" | "activity" | "close_out_reason" | "remarks" | "references" => 40.0,
        "text" | "evidence" | "evidence_detail" => 60.0,
        "reverify_reason" => 30.0,
        "parent" | "children" | "section" | "close_out_reference" | "document" => 24.0,
        _ => 14.0,
    }
}

/// `base` with a number format showing the value followed by `unit` (`General" um/s"`).
fn unit_format(base: &Format, unit: &str) -> Format {
    let unit = unit.trim().replace(['"', '\\'], "'");
    if unit.is_empty() {
        base.clone()
    } else {
        base.clone().set_num_format(format!("General\" {unit}\""))
    }
}

/// The workbook as bytes.
pub fn render(rep: &Report) -> Result<Vec<u8>, XlsxError> {
    let mut wb = Workbook::new();
    let d = &rep.run.document;
    let mut props = DocProperties::new()
        .set_title(format!("{} issue {}: {}", d.id, d.issue, d.title))
        .set_subject("Verification Control Document (ECSS-E-ST-10-02C Annex B)")
        .set_company(&d.project)
        .set_author("geodesic verify");
    if let Ok(dt) = ExcelDateTime::parse_from_str(&rep.run.date) {
        props = props.set_creation_datetime(&dt);
    }
    wb.set_properties(&props);
    let header = Format::new()
        .set_bold()
        .set_background_color(Color::RGB(0xEEF1F6))
        .set_border(FormatBorder::Thin)
        .set_text_wrap()
        .set_align(FormatAlign::Top);
    let cell = Format::new()
        .set_text_wrap()
        .set_align(FormatAlign::Top)
        .set_border(FormatBorder::Thin);
    let ls = lines(rep);
    {
        let ws = wb.add_worksheet();
        ws.set_name(VCD_SHEET)?;
        for (c, name) in COLUMNS.iter().enumerate() {
            let c = c as u16;
            ws.write_string_with_format(0, c, *name, &header)?;
            ws.set_column_width(c, width(name))?;
        }
        let percent = cell.clone().set_num_format("0.0%");
        for (i, l) in ls.iter().enumerate() {
            let row = i as u32 + 1;
            let colored = cell
                .clone()
                .set_background_color(Color::RGB(status_color(&l.compliance)))
                .set_bold();
            for (c, (name, v)) in COLUMNS.iter().zip(cells(rep, l)).enumerate() {
                let c = c as u16;
                let unit = unit_format(&cell, &l.unit);
                let num = match *name {
                    "value" => Some((l.value_number, &unit)),
                    "limit" => Some((l.limit_number, &unit)),
                    "margin" => Some((l.margin_fraction, &percent)),
                    _ => None,
                };
                match num {
                    Some((Some(x), f)) => ws.write_number_with_format(row, c, x, f)?,
                    Some((None, _)) => ws.write_blank(row, c, &cell)?,
                    None => {
                        let f = if matches!(*name, "id" | "compliance" | "close_out") {
                            &colored
                        } else {
                            &cell
                        };
                        ws.write_string_with_format(row, c, v, f)?
                    }
                };
            }
        }
        ws.set_freeze_panes(1, 1)?;
        ws.autofilter(0, 0, ls.len() as u32, COLUMNS.len() as u16 - 1)?;
    }
    {
        let ws = wb.add_worksheet();
        ws.set_name(META_SHEET)?;
        ws.write_string_with_format(0, 0, "field", &header)?;
        ws.write_string_with_format(0, 1, "value", &header)?;
        ws.set_column_width(0, 18.0)?;
        ws.set_column_width(1, 110.0)?;
        let mut rows: Vec<(String, String)> = vec![
            ("document id".into(), d.id.clone()),
            ("issue".into(), d.issue.clone()),
            ("title".into(), d.title.clone()),
            ("project".into(), d.project.clone()),
        ];
        rows.extend(
            crate::run_lines(rep)
                .into_iter()
                .filter(|(k, _)| !matches!(*k, "document" | "project"))
                .map(|(k, v)| (k.to_string(), v)),
        );
        rows.push(("summary".into(), rep.matrix.summary.line()));
        for (i, (k, v)) in rows.iter().enumerate() {
            ws.write_string_with_format(i as u32 + 1, 0, k, &header)?;
            ws.write_string_with_format(i as u32 + 1, 1, v, &cell)?;
        }
    }
    wb.save_to_buffer()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::report;
    use calamine::{Data, Reader, Xlsx};

    #[test]
    fn reads_back_with_every_row_and_the_metadata() {
        let mut r = report(1.3, 6.0);
        r.reverify.insert("F-B".into(), "margin moved".into());
        let bytes = render(&r).unwrap();
        let mut wb: Xlsx<_> = Xlsx::new(std::io::Cursor::new(bytes)).unwrap();
        assert_eq!(wb.sheet_names(), vec![VCD_SHEET, META_SHEET]);
        let vcd = wb.worksheet_range(VCD_SHEET).unwrap();
        let rows: Vec<Vec<String>> = vcd
            .rows()
            .map(|row| {
                row.iter()
                    .map(|c| match c {
                        Data::String(s) => s.clone(),
                        Data::Empty => String::new(),
                        other => other.to_string(),
                    })
                    .collect()
            })
            .collect();
        assert_eq!(rows[0], COLUMNS.map(String::from).to_vec());
        let expect: Vec<Vec<String>> = lines(&r).iter().map(|l| cells(&r, l)).collect();
        assert_eq!(rows.len(), expect.len() + 1, "one row per requirement");
        let col = |name: &str| COLUMNS.iter().position(|c| *c == name).unwrap();
        for (got, want) in rows[1..].iter().zip(&expect) {
            for (c, (g, w)) in got.iter().zip(want).enumerate() {
                if ![col("value"), col("limit"), col("margin")].contains(&c) {
                    assert_eq!(g, w, "every text cell of every row reads back");
                }
            }
        }
        // value, limit and margin are numbers: the value and limit in the requirement's unit
        // (its own column), the margin a fraction (shown as a percentage)
        for (i, row) in vcd.rows().skip(1).enumerate() {
            let m = &r.matrix.requirements[i];
            assert_eq!(row[col("value")], Data::Float(m.value.unwrap()));
            assert_eq!(row[col("limit")], Data::Float(m.limit.unwrap()));
            assert_eq!(row[col("margin")], Data::Float(m.margin.unwrap()));
            assert_eq!(row[col("unit")], Data::String("um/s".into()));
            assert_eq!(
                row[col("value_text")],
                Data::String(super::super::fmt_value(m))
            );
        }
        assert!(((r.matrix.requirements[0].value.unwrap()) - 1.3).abs() < 1e-12);
        assert!((r.matrix.requirements[1].margin.unwrap() + 0.2).abs() < 1e-12);
        assert_eq!(rows[1][col("compliance")], "yes");
        assert_eq!(rows[2][col("compliance")], "no");
        assert_eq!(rows[2][col("reverify")], "yes");
        let meta = wb.worksheet_range(META_SHEET).unwrap();
        let text: Vec<String> = meta.rows().map(|r| format!("{}={}", r[0], r[1])).collect();
        for want in [
            "document id=DOC-1",
            "issue=2",
            "commit=c",
            "date (UTC)=2026-01-01T00:00:00Z",
        ] {
            assert!(text.iter().any(|t| t == want), "{want} not in {text:?}");
        }
    }

    #[test]
    fn same_report_same_bytes() {
        let r = report(1.3, 6.0);
        assert_eq!(render(&r).unwrap(), render(&r).unwrap());
    }
}
