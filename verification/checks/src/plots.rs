//! Plots that checks attach to their evidence (SVG, inlined by the HTML report): the adhesion
//! force-to-elongation curves of the Monte Carlo adhesion distribution, and the quartic capture
//! criterion along the scaled requirement box.

use geodesic_capture::criterion::{self, box_corner};
use geodesic_capture::{StateName, Xlim};
use geodesic_core::CheckError;
use geodesic_plot::plotters::style::text_anchor::{HPos, Pos, VPos};
use geodesic_plot::prelude::*;
use geodesic_release::budget::Budget;
use geodesic_release::montecarlo::{Case, draw_inputs};
use std::path::Path;

/// Writes `svg` to `dir/name` (the directory is the staging directory of `geodesic verify`).
pub fn write(dir: &Path, name: &str, svg: &str) -> Result<String, CheckError> {
    let p = dir.join(name);
    let parent = p.parent().unwrap_or(dir);
    std::fs::create_dir_all(parent)
        .map_err(|e| CheckError::evidence(format!("{}: {e}", parent.display())))?;
    std::fs::write(&p, svg).map_err(|e| CheckError::evidence(format!("{}: {e}", p.display())))?;
    Ok(name.to_string())
}

/// Force-to-elongation curves `F(e) = A1 e exp(-e/lambda)` [mN] against `e` [um] for `n` draws
/// of the budget's adhesion distribution (draw `i` of case `adhesion`, side 2), with the TMMF
/// campaign's mean (20 mN) and maximum (48 mN) peak pull-off as reference lines.
pub fn adhesion_curves_svg(budget: &Budget, n: usize, seed: u64) -> Result<String, CheckError> {
    let e_max_um = 5.0;
    let curves: Vec<Vec<(f64, f64)>> = (0..n as u64)
        .map(|i| {
            let d = draw_inputs(budget, Case::Adhesion, seed, i);
            let (a1, lam) = (d.a1_n_m[1], d.lambda_m[1]);
            (0..=200)
                .map(|k| {
                    let e_um = e_max_um * k as f64 / 200.0;
                    let e = e_um * 1e-6;
                    let f = if lam > 0.0 {
                        a1 * e * (-e / lam).exp()
                    } else {
                        0.0
                    };
                    (e_um, f * 1e3)
                })
                .collect()
        })
        .collect();
    render((900, 480), |root| {
        let mut c = ChartBuilder::on(root)
            .caption(
                format!("Adhesion force-to-elongation curves: {n} draws of the Monte Carlo budget"),
                font(24),
            )
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..e_max_um, 0.0..55.0)
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("elongation e [um]")
            .y_desc("adhesion force [mN]")
            .x_label_formatter(&|v| format!("{v:.1}"))
            .y_label_formatter(&|v| format!("{v:.0}"))
            .label_style(font(18))
            .axis_desc_style(font(19))
            .draw()
            .map_err(perr)?;
        let curve = style::MUTED_BLUE.mix(0.5);
        for (i, pts) in curves.into_iter().enumerate() {
            let drawn = c.draw_series(LineSeries::new(pts, curve)).map_err(perr)?;
            if i == 0 {
                drawn
                    .label(format!("F(e) = A1 e exp(-e/lambda), {n} budget draws"))
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], curve));
            }
        }
        for (level, label, color) in [
            (20.0, "TMMF mean peak pull-off 20 mN", style::GREEN),
            (48.0, "TMMF max peak pull-off 48 mN", style::RED),
        ] {
            c.draw_series(LineSeries::new(
                vec![(0.0, level), (e_max_um, level)],
                color.stroke_width(2),
            ))
            .map_err(perr)?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color));
        }
        style::legend(&mut c, 18, 0.85).draw().map_err(perr)?;
        Ok(())
    })
    .map_err(|e| CheckError::evidence(e.to_string()))
}

/// The quartic sum along the requirement box scaled by `s` (every state at `s req_i`), and with
/// the z velocity alone at `s x 5 um/s`, against the capture boundary (sum = 1). Log scale on
/// the sum, so neither curve is clipped and the boundary sits mid-plot; the legend is in the
/// empty lower right, away from the labels of the box lines.
pub fn capture_criterion_svg(x: &Xlim) -> Result<String, CheckError> {
    let (s_min, s_max) = (0.3, 2.6);
    let (y_min, y_max) = (1e-4, 100.0);
    let grid = |f: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> {
        (0..=240)
            .map(|k| {
                let s = s_min + (s_max - s_min) * k as f64 / 240.0;
                (s, f(s).clamp(y_min, y_max))
            })
            .collect()
    };
    let corner = grid(&|s| criterion::quartic_sum(x, &box_corner(x, s)));
    let vz_req = x.requirement(StateName::Vz);
    let vz_lim = x.limit(StateName::Vz);
    let vz_only = grid(&|s| (s * vz_req / vz_lim).powi(4));
    let s_box = criterion::max_box_scale(x);
    render((900, 520), |root| {
        let mut c = ChartBuilder::on(root)
            .caption("DFACS quartic capture criterion", font(24))
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(s_min..s_max, (y_min..y_max).log_scale())
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("scale s of the TM state requirement box")
            .y_desc("sum_i (x0_i / xlim_i)^4 (log)")
            .label_style(font(18))
            .axis_desc_style(font(19))
            .y_label_formatter(&log_tick)
            .x_label_formatter(&|v| format!("{v:.1}"))
            .draw()
            .map_err(perr)?;
        let blue = style::BLUE;
        let orange = style::ORANGE;
        let red = style::RED;
        c.draw_series(LineSeries::new(corner, blue.stroke_width(2)))
            .map_err(perr)?
            .label("all 12 states at s x req")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], blue.stroke_width(2))
            });
        c.draw_series(LineSeries::new(vz_only, orange.stroke_width(2)))
            .map_err(perr)?
            .label(format!(
                "z velocity alone at s x {} um/s (xlim {:.1} um/s)",
                geodesic_core::units::fmt_num(vz_req * 1e6),
                vz_lim * 1e6
            ))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], orange.stroke_width(2))
            });
        c.draw_series(LineSeries::new(
            vec![(s_min, 1.0), (s_max, 1.0)],
            red.stroke_width(2),
        ))
        .map_err(perr)?
        .label("capture boundary (sum = 1)")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], red.stroke_width(2)));
        for (i, (s, label)) in [(1.0, "requirement box"), (s_box, "largest capturable box")]
            .into_iter()
            .enumerate()
        {
            let dashed = c
                .draw_series(DashedLineSeries::new(
                    vec![(s, y_min), (s, y_max)],
                    6,
                    4,
                    BLACK.stroke_width(1),
                ))
                .map_err(perr)?;
            if i == 0 {
                dashed
                    .label("requirement box and largest capturable box (s)")
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], BLACK));
            }
            // the requirement box's label left of its line, the other's right of its own: the
            // two labels never cross a line
            let pos = if i == 0 {
                Pos::new(HPos::Right, VPos::Center)
            } else {
                Pos::new(HPos::Left, VPos::Center)
            };
            let style = TextStyle::from(font(18).into_font()).pos(pos);
            c.draw_series(std::iter::once(Text::new(
                format!("{label} (s = {s:.2})"),
                (if i == 0 { s - 0.03 } else { s + 0.03 }, 40.0),
                style,
            )))
            .map_err(perr)?;
        }
        style::legend(&mut c, 18, 0.9)
            .position(SeriesLabelPosition::LowerRight)
            .draw()
            .map_err(perr)?;
        Ok(())
    })
    .map_err(|e| CheckError::evidence(e.to_string()))
}

/// Worst-case release velocity against tip radius: the thesis's simple bottom and upper
/// estimates (push, adhesion and total) on log-log axes, with the release Monte Carlo's
/// 99.73 % point at a handful of radii as the cross-check (thesis ch. 6, "Lesson Learned").
pub fn tip_radius_svg(
    curves: &[(String, Vec<geodesic_release::tipradius::Worst>)],
    mc: &[geodesic_release::tipradius::McPoint],
    current_radius_m: f64,
) -> Result<String, CheckError> {
    let (x0, x1) = (0.05, 50.0); // mm
    let mut ys: Vec<f64> = curves
        .iter()
        .flat_map(|(_, w)| {
            w.iter()
                .flat_map(|p| [p.push_m_s, p.adhesion_m_s, p.total_m_s])
        })
        .map(|v| v * 1e6)
        .chain(mc.iter().map(|p| p.p9973_um_s))
        .filter(|v| *v > 0.0)
        .collect();
    ys.push(5.0);
    let y0 = ys.iter().copied().fold(f64::INFINITY, f64::min) / 2.0;
    let y1 = ys.iter().copied().fold(0.0f64, f64::max) * 2.0;
    render((900, 540), |root| {
        let mut c = ChartBuilder::on(root)
            .caption("Worst-case release velocity against tip radius", font(22))
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("tip radius [mm] (log)")
            .y_desc("|X'| [um/s] (log)")
            .label_style(font(16))
            .x_label_formatter(&log_tick)
            .y_label_formatter(&log_tick)
            .draw()
            .map_err(perr)?;
        let colours = [style::BLUE, style::RED];
        for (i, (name, w)) in curves.iter().enumerate() {
            let col = colours[i % 2];
            let total: Vec<(f64, f64)> = w
                .iter()
                .map(|p| (p.radius_m * 1e3, p.total_m_s * 1e6))
                .collect();
            c.draw_series(LineSeries::new(total, col.stroke_width(2)))
                .map_err(perr)?
                .label(format!("{name}: push + adhesion"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], col.stroke_width(2))
                });
            for (k, sel) in [0usize, 1].into_iter().enumerate() {
                let pts: Vec<(f64, f64)> = w
                    .iter()
                    .map(|p| {
                        (
                            p.radius_m * 1e3,
                            if sel == 0 { p.push_m_s } else { p.adhesion_m_s } * 1e6,
                        )
                    })
                    .collect();
                let s = c
                    .draw_series(DashedLineSeries::new(
                        pts,
                        3 + 3 * k as u32,
                        3,
                        col.stroke_width(1),
                    ))
                    .map_err(perr)?;
                if i == 0 {
                    s.label(if sel == 0 {
                        "push (catapult) term, dashed"
                    } else {
                        "adhesion term, long dashes"
                    })
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], BLACK));
                }
            }
        }
        c.draw_series(
            mc.iter()
                .map(|p| Circle::new((p.radius_m * 1e3, p.p9973_um_s), 5, BLACK.filled())),
        )
        .map_err(perr)?
        .label("release Monte Carlo, 99.73 % (A1 scaled with contact area)")
        .legend(|(x, y)| Circle::new((x + 12, y), 5, BLACK.filled()));
        c.draw_series(DashedLineSeries::new(
            vec![(x0, 5.0), (x1, 5.0)],
            8,
            4,
            style::GREY.stroke_width(1),
        ))
        .map_err(perr)?
        .label("requirement 5 um/s")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style::GREY));
        let r = current_radius_m * 1e3;
        c.draw_series(DashedLineSeries::new(
            vec![(r, y0), (r, y1)],
            4,
            4,
            BLACK.stroke_width(1),
        ))
        .map_err(perr)?
        .label(format!("today's radius {r:.0} mm"))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], BLACK));
        style::legend(&mut c, 13, 0.85)
            .position(SeriesLabelPosition::LowerRight)
            .draw()
            .map_err(perr)?;
        Ok(())
    })
    .map_err(|e| CheckError::evidence(e.to_string()))
}

/// The release sensitivity as an SVG: per uncertainty group, the first-order (filled) and total
/// (outlined) variance indices of `|v_TM|` with their 95 % intervals (left), and the shift of
/// the 99.73 % point when the group is frozen at nominal (right).
pub fn sensitivity_svg(
    s: &geodesic_release::sensitivity::Sensitivity,
) -> Result<String, CheckError> {
    let k = s.groups.len();
    let names: Vec<String> = s.groups.iter().map(|(g, _)| g.group.clone()).collect();
    let name_of = move |y: &f64| -> String {
        let i = y.round();
        if (y - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < names.len() {
            names[names.len() - 1 - i as usize].clone()
        } else {
            String::new()
        }
    };
    // group g is drawn at y = k - 1 - g (the first at the top)
    let yk = |g: usize| (k - 1 - g) as f64;
    let xmax = s
        .groups
        .iter()
        .flat_map(|(g, _)| [g.total_ci[1], g.first_ci[1], g.total])
        .fold(0.1f64, f64::max)
        .min(1.5)
        * 1.1;
    let smin = s.groups.iter().map(|(_, sh)| *sh).fold(0.0f64, f64::min);
    let smax = s.groups.iter().map(|(_, sh)| *sh).fold(0.0f64, f64::max);
    let pad = ((smax - smin) * 0.1).max(0.01);
    render((1250, 520), |root| {
        let (left, right) = root.split_horizontally(700);
        let blue = style::BLUE;
        let mut c = ChartBuilder::on(&left)
            .caption(
                format!(
                    "Variance indices of |X'| ({} x 2 draws, seed {})",
                    s.n, s.seed
                ),
                font(20),
            )
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(150)
            .build_cartesian_2d(0.0..xmax, -0.6..(k as f64 + 1.4))
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("index (share of the variance)")
            .y_labels(2 * k + 6)
            .y_label_formatter(&name_of)
            .label_style(font(16))
            .axis_desc_style(font(17))
            .disable_y_mesh()
            .draw()
            .map_err(perr)?;
        c.draw_series(s.groups.iter().enumerate().map(|(g, (ix, _))| {
            let y = yk(g);
            Rectangle::new(
                [(0.0, y - 0.35), (ix.first.max(0.0), y - 0.02)],
                blue.mix(0.7).filled(),
            )
        }))
        .map_err(perr)?
        .label("first-order index (alone)")
        .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 15, y + 6)], blue.filled()));
        c.draw_series(s.groups.iter().enumerate().map(|(g, (ix, _))| {
            let y = yk(g);
            Rectangle::new(
                [(0.0, y + 0.02), (ix.total.max(0.0), y + 0.35)],
                BLACK.stroke_width(2),
            )
        }))
        .map_err(perr)?
        .label("total index (with its interactions)")
        .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 15, y + 6)], BLACK.stroke_width(2)));
        for (g, (ix, _)) in s.groups.iter().enumerate() {
            let y = yk(g);
            for (ci, dy) in [(ix.first_ci, -0.18), (ix.total_ci, 0.18)] {
                c.draw_series(std::iter::once(PathElement::new(
                    vec![(ci[0].max(0.0), y + dy), (ci[1].min(xmax), y + dy)],
                    style::RED.stroke_width(2),
                )))
                .map_err(perr)?;
            }
        }
        c.draw_series(std::iter::once(PathElement::new(
            vec![(0.0, -10.0), (0.0, -10.0)],
            style::RED.stroke_width(2),
        )))
        .map_err(perr)?
        .label("95 % bootstrap interval")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], style::RED.stroke_width(2)));
        style::legend(&mut c, 15, 0.9)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(perr)?;
        let mut c2 = ChartBuilder::on(&right)
            .caption(
                format!("99.73 % point {:.3} um/s: shift when frozen", s.p9973_um_s),
                font(20),
            )
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(20)
            .build_cartesian_2d((smin - pad)..(smax + pad), -0.6..(k as f64 + 1.4))
            .map_err(perr)?;
        c2.configure_mesh()
            .x_desc("shift of the 99.73 % point [um/s]")
            .x_label_formatter(&|v: &f64| {
                let t = format!("{v:.2}");
                if t == "-0.00" { "0.00".into() } else { t }
            })
            .y_labels(0)
            .label_style(font(16))
            .axis_desc_style(font(17))
            .disable_y_mesh()
            .draw()
            .map_err(perr)?;
        let green = style::DARK_GREEN;
        c2.draw_series(s.groups.iter().enumerate().map(|(g, (_, sh))| {
            let y = yk(g);
            Rectangle::new([(0.0, y - 0.3), (*sh, y + 0.3)], green.mix(0.7).filled())
        }))
        .map_err(perr)?
        .label("group frozen at nominal")
        .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 15, y + 6)], green.filled()));
        c2.draw_series(std::iter::once(PathElement::new(
            vec![(0.0, -0.6), (0.0, k as f64 - 0.4)],
            BLACK.stroke_width(1),
        )))
        .map_err(perr)?;
        style::legend(&mut c2, 15, 0.9)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(perr)?;
        Ok(())
    })
    .map_err(|e| CheckError::evidence(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plots_render() {
        let a = adhesion_curves_svg(&Budget::default_budget(), 5, 1).unwrap();
        assert!(a.starts_with("<svg") && a.contains("48 mN"));
        let c = capture_criterion_svg(&Xlim::default_set()).unwrap();
        assert!(c.contains("capture boundary"));
        assert_eq!(log_tick(&0.001), "0.001");
        assert_eq!(log_tick(&100.0), "100");
        assert_eq!(log_tick(&0.003), "");
    }
}
