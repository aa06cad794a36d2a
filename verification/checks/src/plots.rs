//! Plots that checks attach to their evidence (SVG, inlined by the HTML report): the adhesion
//! force-to-elongation curves of the Monte Carlo adhesion distribution, and the quartic capture
//! criterion along the scaled requirement box.

use geodesic_capture::criterion::{self, box_corner};
use geodesic_capture::{StateName, Xlim};
use geodesic_core::CheckError;
use geodesic_release::budget::Budget;
use geodesic_release::montecarlo::{Case, draw_inputs};
use plotters::prelude::*;
use std::path::Path;

fn perr(e: impl std::fmt::Display) -> CheckError {
    CheckError(format!("plot: {e}"))
}

/// Writes `svg` to `dir/name` (the directory is the staging directory of `geodesic verify`).
pub fn write(dir: &Path, name: &str, svg: &str) -> Result<String, CheckError> {
    std::fs::create_dir_all(dir).map_err(|e| CheckError(format!("{}: {e}", dir.display())))?;
    let p = dir.join(name);
    std::fs::write(&p, svg).map_err(|e| CheckError(format!("{}: {e}", p.display())))?;
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
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (900, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(perr)?;
        let mut c = ChartBuilder::on(&root)
            .caption(
                format!("Adhesion force-to-elongation curves: {n} draws of the Monte Carlo budget"),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..e_max_um, 0.0..55.0)
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("elongation e [um]")
            .y_desc("adhesion force [mN]")
            .draw()
            .map_err(perr)?;
        for pts in curves {
            c.draw_series(LineSeries::new(pts, RGBColor(70, 110, 180).mix(0.5)))
                .map_err(perr)?;
        }
        for (level, label, color) in [
            (20.0, "TMMF mean peak pull-off 20 mN", RGBColor(0, 140, 60)),
            (48.0, "TMMF max peak pull-off 48 mN", RGBColor(200, 30, 30)),
        ] {
            c.draw_series(LineSeries::new(
                vec![(0.0, level), (e_max_um, level)],
                color.stroke_width(2),
            ))
            .map_err(perr)?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color));
        }
        c.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(perr)?;
        root.present().map_err(perr)?;
    }
    Ok(out)
}

/// The quartic sum along the requirement box scaled by `s` (every state at `s req_i`), and with
/// the z velocity alone at `s x 5 um/s`, against the capture boundary (sum = 1).
pub fn capture_criterion_svg(x: &Xlim) -> Result<String, CheckError> {
    let s_max = 2.6;
    let corner: Vec<(f64, f64)> = (0..=260)
        .map(|k| {
            let s = s_max * k as f64 / 260.0;
            (s, criterion::quartic_sum(x, &box_corner(x, s)))
        })
        .collect();
    let vz_req = x.requirement(StateName::Vz);
    let vz_lim = x.limit(StateName::Vz);
    let vz_only: Vec<(f64, f64)> = (0..=260)
        .map(|k| {
            let s = s_max * k as f64 / 260.0;
            (s, (s * vz_req / vz_lim).powi(4))
        })
        .collect();
    let s_box = criterion::max_box_scale(x);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (900, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(perr)?;
        let mut c = ChartBuilder::on(&root)
            .caption("DFACS quartic capture criterion", ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..s_max, 0.0..2.0)
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("scale s of the TM state requirement box")
            .y_desc("sum_i (x0_i / xlim_i)^4")
            .draw()
            .map_err(perr)?;
        let blue = RGBColor(40, 90, 170);
        let orange = RGBColor(220, 120, 20);
        let red = RGBColor(200, 30, 30);
        c.draw_series(LineSeries::new(corner, blue.stroke_width(2)))
            .map_err(perr)?
            .label("all 12 states at s x req")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], blue));
        c.draw_series(LineSeries::new(vz_only, orange.stroke_width(2)))
            .map_err(perr)?
            .label(format!(
                "z velocity alone at s x 5 um/s (limit {:.1} um/s)",
                vz_lim * 1e6
            ))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], orange));
        c.draw_series(LineSeries::new(
            vec![(0.0, 1.0), (s_max, 1.0)],
            red.stroke_width(2),
        ))
        .map_err(perr)?
        .label("capture boundary (sum = 1)")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], red));
        for (s, label) in [(1.0, "requirement box"), (s_box, "largest capturable box")] {
            c.draw_series(DashedLineSeries::new(
                vec![(s, 0.0), (s, 2.0)],
                6,
                4,
                BLACK.stroke_width(1),
            ))
            .map_err(perr)?;
            c.draw_series(std::iter::once(Text::new(
                format!("{label} (s = {s:.2})"),
                (s + 0.02, 1.85 - 0.12 * f64::from(u8::from(s > 1.0))),
                ("sans-serif", 13),
            )))
            .map_err(perr)?;
        }
        c.configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(perr)?;
        root.present().map_err(perr)?;
    }
    Ok(out)
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
    }
}
