//! SVG plots: data, model and residual with the failure windows shaded; the fit history.

use std::path::Path;

use plotters::prelude::*;

use crate::error::{FitError, write_atomic};
use crate::fit::{FitReport, Prepared};
use crate::history::Entry;

fn perr(e: impl std::fmt::Display) -> FitError {
    FitError::input("plot", 0, e.to_string())
}

fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in v {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if !lo.is_finite() || !hi.is_finite() {
        return (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-30);
    (lo - pad, hi + pad)
}

/// Renders data and model (top) and the residual with its +-3 sigma band (bottom), failure
/// windows shaded, as an SVG string. Lengths in nm, time in ms.
pub fn fit_svg(prep: &Prepared, pred: &[f64], report: &FitReport) -> Result<String, FitError> {
    let t: Vec<f64> = prep.dataset.t.iter().map(|v| v * 1e3).collect();
    let d: Vec<f64> = prep.data().iter().map(|v| v * 1e9).collect();
    let m: Vec<f64> = pred.iter().map(|v| v * 1e9).collect();
    let r: Vec<f64> = d.iter().zip(&m).map(|(a, b)| a - b).collect();
    let s3 = 3.0 * prep.sigma * 1e9;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (1000, 700)).into_drawing_area();
        root.fill(&WHITE).map_err(perr)?;
        let (top, bottom) = root.split_vertically(420);
        let (x0, x1) = range(t.iter().copied());
        let (y0, y1) = range(d.iter().chain(&m).copied());
        let title = format!(
            "{}: {} (chi2_red {:.3})",
            report.dataset,
            report.effects.join("+"),
            report.chi2_red
        );
        let mut c = ChartBuilder::on(&top)
            .caption(title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("t [ms]")
            .y_desc(format!("{} [nm]", prep.channel))
            .draw()
            .map_err(perr)?;
        for f in &report.failures {
            c.draw_series(std::iter::once(Rectangle::new(
                [(f.t_start * 1e3, y0), (f.t_end * 1e3, y1)],
                RGBColor(255, 210, 210).filled(),
            )))
            .map_err(perr)?;
        }
        c.draw_series(LineSeries::new(
            t.iter().copied().zip(d.iter().copied()),
            &BLUE,
        ))
        .map_err(perr)?
        .label("data")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], BLUE));
        c.draw_series(LineSeries::new(
            t.iter().copied().zip(m.iter().copied()),
            &RED,
        ))
        .map_err(perr)?
        .label("model")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], RED));
        c.configure_series_labels()
            .border_style(BLACK)
            .background_style(WHITE)
            .draw()
            .map_err(perr)?;
        let (ry0, ry1) = range(r.iter().copied().chain([-s3 * 1.2, s3 * 1.2]));
        let mut c2 = ChartBuilder::on(&bottom)
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, ry0..ry1)
            .map_err(perr)?;
        c2.configure_mesh()
            .x_desc("t [ms]")
            .y_desc("residual [nm]")
            .draw()
            .map_err(perr)?;
        for f in &report.failures {
            c2.draw_series(std::iter::once(Rectangle::new(
                [(f.t_start * 1e3, ry0), (f.t_end * 1e3, ry1)],
                RGBColor(255, 210, 210).filled(),
            )))
            .map_err(perr)?;
        }
        c2.draw_series(LineSeries::new(
            t.iter().copied().zip(r.iter().copied()),
            &BLACK,
        ))
        .map_err(perr)?;
        for lvl in [-s3, s3] {
            c2.draw_series(LineSeries::new([(x0, lvl), (x1, lvl)], &GREEN))
                .map_err(perr)?;
        }
        root.present().map_err(perr)?;
    }
    Ok(out)
}

/// Renders RMS and reduced chi-square per model version (log scale) as an SVG string.
pub fn history_svg(entries: &[Entry]) -> Result<String, FitError> {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (800, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(perr)?;
        let (top, bottom) = root.split_vertically(300);
        let n = entries.len().max(1) as f64;
        let name = entries
            .first()
            .map_or("", |e| e.dataset.as_str())
            .to_string();
        for (area, title, vals) in [
            (
                &top,
                format!("{name}: residual RMS [m] per model version"),
                entries.iter().map(|e| e.rms).collect::<Vec<_>>(),
            ),
            (
                &bottom,
                "reduced chi-square per model version".to_string(),
                entries.iter().map(|e| e.chi2_red).collect(),
            ),
        ] {
            let pos: Vec<f64> = vals.iter().map(|v| v.max(1e-300)).collect();
            let lo = pos.iter().cloned().fold(f64::INFINITY, f64::min).min(1.0) * 0.5;
            let hi = pos.iter().cloned().fold(0.0, f64::max).max(lo * 4.0) * 2.0;
            let mut c = ChartBuilder::on(area)
                .caption(title, ("sans-serif", 16))
                .margin(10)
                .x_label_area_size(30)
                .y_label_area_size(70)
                .build_cartesian_2d(0.5..n + 0.5, (lo..hi).log_scale())
                .map_err(perr)?;
            c.configure_mesh().x_desc("version").draw().map_err(perr)?;
            c.draw_series(LineSeries::new(
                pos.iter().enumerate().map(|(i, v)| (i as f64 + 1.0, *v)),
                &BLUE,
            ))
            .map_err(perr)?;
            c.draw_series(
                pos.iter()
                    .enumerate()
                    .map(|(i, v)| Circle::new((i as f64 + 1.0, *v), 4, BLUE.filled())),
            )
            .map_err(perr)?;
        }
        root.present().map_err(perr)?;
    }
    Ok(out)
}

/// Writes an SVG atomically.
pub fn write_svg(path: &Path, svg: &str) -> Result<(), FitError> {
    write_atomic(path, svg.as_bytes())
}
