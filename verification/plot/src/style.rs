//! The one style of geodesic's plots: a single font family, the palette, and the legend box.
//! Sizes are pixels of the SVG canvas; each plot picks its sizes from the scale below by its
//! canvas (a 1250-px-wide sensitivity panel uses smaller text than a 900-px check plot).

use plotters::chart::{ChartContext, SeriesLabelStyle};
use plotters::coord::CoordTranslate;
use plotters::prelude::*;
use plotters::style::FontDesc;

/// The font family of every plot (no font file: the SVG names a generic family).
pub const FONT: &str = "sans-serif";

/// The font of every plot at `px` pixels.
pub fn font(px: u32) -> FontDesc<'static> {
    (FONT, px).into()
}

/// Caption of a full-width plot [px].
pub const CAPTION: u32 = 22;
/// Tick labels [px].
pub const LABEL: u32 = 16;
/// Axis descriptions [px].
pub const AXIS: u32 = 17;

/// The reference blue of a model curve or a measurement.
pub const BLUE: RGBColor = RGBColor(40, 90, 170);
/// A light blue (a secondary case, a band's edge).
pub const LIGHT_BLUE: RGBColor = RGBColor(120, 160, 220);
/// A pale blue (a band, a cloud of samples).
pub const PALE_BLUE: RGBColor = RGBColor(170, 190, 220);
/// A muted blue (many overlaid curves, half transparent).
pub const MUTED_BLUE: RGBColor = RGBColor(70, 110, 180);
/// The red of a requirement limit or a failure.
pub const RED: RGBColor = RGBColor(200, 30, 30);
/// A pale red (a failure window).
pub const PALE_RED: RGBColor = RGBColor(255, 200, 200);
/// The green of a reference value or a pass.
pub const GREEN: RGBColor = RGBColor(0, 140, 60);
/// A darker green (a second reference).
pub const DARK_GREEN: RGBColor = RGBColor(0, 130, 70);
/// A pale green (a noise band).
pub const PALE_GREEN: RGBColor = RGBColor(200, 235, 200);
/// An orange (a percentile point, a threshold).
pub const ORANGE: RGBColor = RGBColor(220, 120, 20);
/// Near-black (the nominal case).
pub const INK: RGBColor = RGBColor(30, 30, 30);
/// Dark grey (reference lines).
pub const DARK_GREY: RGBColor = RGBColor(90, 90, 90);
/// Grey (secondary lines).
pub const GREY: RGBColor = RGBColor(120, 120, 120);
/// Light grey (grid, a background image).
pub const LIGHT_GREY: RGBColor = RGBColor(200, 200, 200);

/// The legend box of a chart: font `px`, white background of opacity `opacity` (0.8 to 0.9:
/// the curves behind it stay visible), black border. Position it and `.draw()` it.
pub fn legend<'a, 'b, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &'b mut ChartContext<'a, DB, CT>,
    px: u32,
    opacity: f64,
) -> SeriesLabelStyle<'a, 'b, DB, CT> {
    let mut l = chart.configure_series_labels();
    l.label_font(font(px))
        .background_style(WHITE.mix(opacity))
        .border_style(BLACK);
    l
}
