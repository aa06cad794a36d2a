//! geodesic-plot: every SVG geodesic writes goes through this crate.
//!
//! - [`style`]: the one style: the font family and sizes, the palette, the legend box.
//! - [`render`]: a plotters SVG canvas filled white, drawn by a closure, returned as text.
//! - [`fit`]: the plots of a fit (data, model and residual; the fit history; a posterior's
//!   corner plot) from plain data, which the fit crate builds.
//! - [`histogram`]: the hand-written SVG histograms of the release velocities (the release model
//!   returns the velocities; the CLI and the checks render them here).
//! - [`log_tick`], [`nice_step`], [`fmt_tick`]: axis helpers.
//!
//! Text drawn by hand is escaped with [`geodesic_util::escape::text`]; plotters escapes its own.
//! plotters (SVG backend only: no font or system library) is re-exported as [`plotters`] so that
//! every plot uses the same version and features through this crate.

#![warn(missing_docs)]
pub mod fit;
pub mod histogram;
pub mod style;

pub use plotters;

use plotters::coord::Shift;
use plotters::prelude::*;

/// Everything a plot needs: plotters' prelude, the style and [`render`].
pub mod prelude {
    pub use crate::style::{self, font};
    pub use crate::{Canvas, PlotError, log_tick, perr, render};
    pub use plotters::prelude::*;
}

/// The drawing area of a plot being rendered.
pub type Canvas<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Why a plot was not drawn (plotters' error as text). Display: `plot: CAUSE`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlotError(pub String);

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "plot: {}", self.0)
    }
}

impl std::error::Error for PlotError {}

/// A plotters error as a [`PlotError`] (`.map_err(perr)?` in a drawing closure).
pub fn perr(e: impl std::fmt::Display) -> PlotError {
    PlotError(e.to_string())
}

/// An SVG document of `size` pixels (width, height): the canvas is filled white, `draw` draws
/// on it, and the document is returned as text.
pub fn render(
    size: (u32, u32),
    draw: impl FnOnce(&Canvas<'_>) -> Result<(), PlotError>,
) -> Result<String, PlotError> {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, size).into_drawing_area();
        root.fill(&WHITE).map_err(perr)?;
        draw(&root)?;
        root.present().map_err(perr)?;
    }
    Ok(out)
}

/// Tick label of a log axis: `0.001`, `0.01`, ..., `10`, `100` (no binary noise); empty between
/// decades (only the decades are labelled).
pub fn log_tick(v: &f64) -> String {
    let e = v.log10().round();
    if (v.log10() - e).abs() > 1e-6 {
        return String::new();
    }
    if e >= 0.0 {
        format!("{}", 10f64.powi(e as i32))
    } else {
        format!("{:.*}", (-e) as usize, 10f64.powi(e as i32))
    }
}

/// The round step (1, 2 or 5 times a power of ten) at or above `raw` (1 for a non-positive or
/// non-finite `raw`).
pub fn nice_step(raw: f64) -> f64 {
    if raw <= 0.0 || !raw.is_finite() {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    let n = if m <= 1.0 {
        1.0
    } else if m <= 2.0 {
        2.0
    } else if m <= 5.0 {
        5.0
    } else {
        10.0
    };
    n * p
}

/// A tick value with at most three decimals and no trailing zeros (`0.25`, `5`).
pub fn fmt_tick(v: f64) -> String {
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::prelude::*;
    use super::*;

    #[test]
    fn ticks_and_steps() {
        assert_eq!(log_tick(&0.01), "0.01");
        assert_eq!(log_tick(&100.0), "100");
        assert_eq!(log_tick(&30.0), "");
        assert_eq!(nice_step(0.3), 0.5);
        assert_eq!(nice_step(7.0), 10.0);
        assert_eq!(nice_step(f64::NAN), 1.0);
        assert_eq!(fmt_tick(0.250), "0.25");
        assert_eq!(fmt_tick(5.0), "5");
    }

    #[test]
    fn render_returns_a_white_svg_with_the_drawing() {
        let svg = render((200, 100), |root| {
            let mut c = ChartBuilder::on(root)
                .caption("a <title>", font(style::CAPTION))
                .build_cartesian_2d(0.0..1.0, 0.0..1.0)
                .map_err(perr)?;
            c.draw_series(LineSeries::new(vec![(0.0, 0.0), (1.0, 1.0)], style::BLUE))
                .map_err(perr)?;
            Ok(())
        })
        .unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("</svg>"), "{svg}");
        assert!(svg.contains("a &lt;title&gt;"), "plotters escapes its text");
        assert!(svg.contains("#FFFFFF"), "white canvas");
    }
}
