//! SVG plots of the image analyses (plotters, SVG backend: no system library).

use crate::surfaces::Registration;
use crate::tiptrack::Trajectory;
use geodesic_plot::prelude::*;

/// x and z of the tip [um] against time [ms], with the spread across thresholds as a band.
pub fn trajectory_svg(tr: &Trajectory, title: &str) -> String {
    render((1000, 700), |root| {
        let parts = root.split_evenly((2, 1));
        for (k, area) in parts.iter().enumerate() {
            let (vals, sig, name) = if k == 0 {
                (&tr.x_m, &tr.sigma_x_m, "x from the left edge [um]")
            } else {
                (&tr.z_m, &tr.sigma_z_m, "z above the bottom edge [um]")
            };
            let pts: Vec<(f64, f64, f64)> = tr
                .t_s
                .iter()
                .zip(vals.iter().zip(sig))
                .filter_map(|(t, (v, s))| Some((t * 1e3, (*v)? * 1e6, s.unwrap_or(0.0) * 1e6)))
                .collect();
            if pts.is_empty() {
                continue;
            }
            let t_hi = pts.last().map(|p| p.0).unwrap_or(1.0).max(1e-9);
            let lo = pts.iter().map(|p| p.1 - p.2).fold(f64::INFINITY, f64::min);
            let hi = pts
                .iter()
                .map(|p| p.1 + p.2)
                .fold(f64::NEG_INFINITY, f64::max);
            let pad = ((hi - lo) * 0.1).max(1e-3);
            let Ok(mut chart) = ChartBuilder::on(area)
                .caption(if k == 0 { title } else { "" }, font(22))
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(80)
                .build_cartesian_2d(0.0..t_hi, (lo - pad)..(hi + pad))
            else {
                continue;
            };
            let _ = chart
                .configure_mesh()
                .x_desc("t [ms]")
                .y_desc(name)
                .label_style(font(16))
                .draw();
            let band: Vec<(f64, f64)> = pts
                .iter()
                .map(|p| (p.0, p.1 + p.2))
                .chain(pts.iter().rev().map(|p| (p.0, p.1 - p.2)))
                .collect();
            let _ = chart
                .draw_series(std::iter::once(Polygon::new(band, BLUE.mix(0.2).filled())))
                .map(|s| {
                    s.label("spread across thresholds").legend(|(x, y)| {
                        Rectangle::new([(x, y - 5), (x + 16, y + 5)], BLUE.mix(0.2).filled())
                    })
                });
            let _ = chart
                .draw_series(LineSeries::new(
                    pts.iter().map(|p| (p.0, p.1)),
                    BLUE.stroke_width(2),
                ))
                .map(|s| {
                    s.label("mean over thresholds").legend(|(x, y)| {
                        PathElement::new([(x, y), (x + 16, y)], BLUE.stroke_width(2))
                    })
                });
            let _ = style::legend(&mut chart, 15, 0.8).draw();
        }
        Ok(())
    })
    .unwrap_or_default()
}

/// The difference map AFTER - BEFORE (registered, offset removed) as blocks of at most
/// 160 x 160 cells (the mean of each block), blue below and red above zero, grey missing.
pub fn difference_svg(reg: &Registration, title: &str) -> String {
    let [rows, cols] = reg.shape;
    let step = rows.max(cols).div_ceil(160).max(1);
    let (br, bc) = (rows.div_ceil(step), cols.div_ceil(step));
    let mut blocks = vec![(0.0f64, 0usize); br * bc];
    for r in 0..rows {
        for c in 0..cols {
            let v = reg.difference[r * cols + c];
            if v.is_finite() {
                let b = &mut blocks[(r / step) * bc + c / step];
                b.0 += v;
                b.1 += 1;
            }
        }
    }
    let scale = (3.0 * reg.change_threshold_m).max(1e-30);
    render((900, 820), |root| {
        let Ok(mut chart) = ChartBuilder::on(root)
            .caption(title, font(20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..cols as f64, rows as f64..0.0)
        else {
            return Ok(());
        };
        let _ = chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("column [pixels]")
            .y_desc("row [pixels]")
            .label_style(font(16))
            .draw();
        let _ = chart.draw_series(blocks.iter().enumerate().map(|(i, &(s, n))| {
            let (r, c) = ((i / bc * step) as f64, (i % bc * step) as f64);
            let color = if n == 0 {
                style::LIGHT_GREY
            } else {
                let v = (s / n as f64 / scale).clamp(-1.0, 1.0);
                let k = (255.0 * (1.0 - v.abs())) as u8;
                if v >= 0.0 {
                    RGBColor(255, k, k)
                } else {
                    RGBColor(k, k, 255)
                }
            };
            Rectangle::new([(c, r), (c + step as f64, r + step as f64)], color.filled())
        }));
        Ok(())
    })
    .unwrap_or_default()
}
