//! The campaign's report (issue 14, item 1): the thesis's table in Markdown, histograms of the
//! derived quantities like the thesis's (ch. 5), and the adhesion parameters' scatter with each
//! release's 1-sigma error ellipse and the deconvolved population's 1- and 2-sigma ellipses.
//!
//! Every figure on the page is read from the [`CampaignReport`] it is given (the same numbers
//! as `geodesic campaign --json`); nothing is recomputed here but the ellipses' outlines and the
//! histograms' bins (Sturges: `ceil(log2 n) + 1` bins over `[min, max]`).

use geodesic_plot::prelude::*;

use crate::{CampaignReport, PAIR, Release};
use geodesic_fit::FitError;
use geodesic_plot::fit::tick;

/// A quantity of the table: key, label on the page, unit, scale to the plotted unit, plotted unit.
const QUANTITIES: [(&str, &str, &str, f64, &str); 3] = [
    (
        "P_x_kg_m_s",
        "transferred momentum P_x",
        "kg m/s",
        1e6,
        "1e-6 kg m/s",
    ),
    ("F_peak_N", "peak pull-off force F_peak", "N", 1e3, "mN"),
    ("dt_s", "pull duration dt", "s", 1e3, "ms"),
];

fn model_values(r: &CampaignReport, key: &str) -> Vec<f64> {
    r.releases
        .iter()
        .map(|x: &Release| match key {
            "P_x_kg_m_s" => x.p_x_model,
            "F_peak_N" => x.f_peak_model,
            _ => x.dt_model,
        })
        .filter(|v| v.is_finite())
        .collect()
}

/// Bin counts of `v` over `[lo, hi]` with `k` bins.
fn bins(v: &[f64], lo: f64, hi: f64, k: usize) -> Vec<usize> {
    let mut c = vec![0; k];
    let w = (hi - lo) / k as f64;
    for x in v {
        let i = if w > 0.0 {
            (((x - lo) / w).floor() as usize).min(k - 1)
        } else {
            0
        };
        c[i] += 1;
    }
    c
}

/// The three histograms (P_x, F_peak, dt from the fitted models; P_x from the data overlaid)
/// side by side, as an SVG string.
pub fn histograms_svg(r: &CampaignReport) -> Result<String, FitError> {
    render((1350, 470), |root| {
        let areas = root.split_evenly((1, 3));
        for (area, (key, label, _, scale, unit)) in areas.iter().zip(QUANTITIES) {
            let v: Vec<f64> = model_values(r, key).iter().map(|x| x * scale).collect();
            let data: Vec<f64> = if key == "P_x_kg_m_s" {
                r.releases
                    .iter()
                    .map(|x| x.p_x_data * scale)
                    .filter(|v| v.is_finite())
                    .collect()
            } else {
                Vec::new()
            };
            let all: Vec<f64> = v.iter().chain(&data).copied().collect();
            let (mut lo, mut hi) = all
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                    (a.min(*x), b.max(*x))
                });
            if !lo.is_finite() {
                (lo, hi) = (0.0, 1.0);
            }
            if hi <= lo {
                let d = lo.abs().max(1e-12) * 0.05;
                (lo, hi) = (lo - d, hi + d);
            }
            let k = ((v.len().max(1) as f64).log2().ceil() as usize + 1).max(3);
            let cm = bins(&v, lo, hi, k);
            let cd = bins(&data, lo, hi, k);
            let top = cm.iter().chain(&cd).copied().max().unwrap_or(1).max(1) as f64 * 1.35;
            let w = (hi - lo) / k as f64;
            let mut c = ChartBuilder::on(area)
                .caption(format!("{label} ({} releases)", v.len()), font(19))
                .margin(12)
                .x_label_area_size(50)
                .y_label_area_size(55)
                .build_cartesian_2d(lo..hi, 0.0..top)
                .map_err(perr)?;
            c.configure_mesh()
                .x_desc(format!("{key} [{unit}]"))
                .y_desc("releases per bin")
                .x_labels(5)
                .label_style(font(16))
                .axis_desc_style(font(17))
                .x_label_formatter(&tick)
                .y_label_formatter(&|y| format!("{y:.0}"))
                .max_light_lines(0)
                .disable_x_mesh()
                .draw()
                .map_err(perr)?;
            let blue = RGBColor(70, 110, 190);
            c.draw_series(cm.iter().enumerate().map(|(i, n)| {
                let x0 = lo + w * i as f64;
                Rectangle::new([(x0, 0.0), (x0 + w, *n as f64)], blue.mix(0.55).filled())
            }))
            .map_err(perr)?
            .label("from the fitted model")
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 15, y + 6)], blue.filled()));
            if !data.is_empty() {
                c.draw_series(cd.iter().enumerate().map(|(i, n)| {
                    let x0 = lo + w * i as f64;
                    Rectangle::new([(x0, 0.0), (x0 + w, *n as f64)], BLACK.stroke_width(2))
                }))
                .map_err(perr)?
                .label("from the data (line fit)")
                .legend(|(x, y)| {
                    Rectangle::new([(x, y - 6), (x + 15, y + 6)], BLACK.stroke_width(2))
                });
            }
            if let Some(Some(s)) = r.table.get(key).and_then(|m| m.get("model")) {
                let red = style::RED;
                c.draw_series(DashedLineSeries::new(
                    vec![(s.mean * scale, 0.0), (s.mean * scale, top)],
                    6,
                    4,
                    red.stroke_width(2),
                ))
                .map_err(perr)?
                .label(format!("mean {}", tick(&(s.mean * scale))))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 15, y)], red.stroke_width(2))
                });
            }
            style::legend(&mut c, 15, 0.9)
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(perr)?;
        }
        Ok(())
    })
    .map_err(|e| FitError::input("campaign plot", 0, e.0))
}

/// Outline of the ellipse of means `(mx, my)`, sigmas `(sx, sy)` and correlation `rho`, scaled
/// by `k` sigma: `x = mx + k sx cos t`, `y = my + k sy (rho cos t + sqrt(1 - rho^2) sin t)`.
pub fn ellipse(mx: f64, my: f64, sx: f64, sy: f64, rho: f64, k: f64) -> Vec<(f64, f64)> {
    let rho = rho.clamp(-1.0, 1.0);
    let q = (1.0 - rho * rho).max(0.0).sqrt();
    (0..=72)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 72.0;
            (
                mx + k * sx * t.cos(),
                my + k * sy * (rho * t.cos() + q * t.sin()),
            )
        })
        .collect()
}

fn pop_num(r: &CampaignReport, name: &str, key: &str) -> Option<f64> {
    r.population.get(name)?.get(key)?.as_f64()
}

fn pop_rho(r: &CampaignReport) -> Option<f64> {
    r.population.get("correlation")?.get(PAIR)?.as_f64()
}

/// The releases' `(A1, lambda)` with their 1-sigma error ellipses (from each fit's sigmas and
/// correlation) and the population's 1- and 2-sigma ellipses (deconvolved spreads and
/// correlation), as an SVG string; A1 in 1e3 N/m, lambda in nm. `None` when no release has both
/// parameters free.
pub fn adhesion_svg(r: &CampaignReport) -> Result<Option<String>, FitError> {
    // (A1 [kN/m], sigma, lambda [nm], sigma, corr)
    let pts: Vec<(f64, f64, f64, f64, f64)> = r
        .releases
        .iter()
        .filter_map(|x| {
            let a = x.params.get("tip_adhesion.A1")?;
            let l = x.params.get("tip_adhesion.lambda")?;
            (!a.fixed && !l.fixed && a.value.is_finite() && l.value.is_finite()).then(|| {
                (
                    a.value * 1e-3,
                    a.sigma.unwrap_or(f64::NAN) * 1e-3,
                    l.value * 1e9,
                    l.sigma.unwrap_or(f64::NAN) * 1e9,
                    x.corr_a1_lambda.unwrap_or(0.0),
                )
            })
        })
        .collect();
    if pts.is_empty() {
        return Ok(None);
    }
    let pop = (
        pop_num(r, "tip_adhesion.A1", "mean"),
        pop_num(r, "tip_adhesion.A1", "sd"),
        pop_num(r, "tip_adhesion.lambda", "mean"),
        pop_num(r, "tip_adhesion.lambda", "sd"),
    );
    let pop = match pop {
        (Some(ma), Some(sa), Some(ml), Some(sl)) => {
            Some((ma * 1e-3, sa * 1e-3, ml * 1e9, sl * 1e9, pop_rho(r)))
        }
        _ => None,
    };
    let mut outline: Vec<(f64, f64)> = pts
        .iter()
        .flat_map(|p| ellipse(p.0, p.2, p.1, p.3, p.4, 1.0))
        .collect();
    if let Some((ma, sa, ml, sl, rho)) = pop {
        outline.extend(ellipse(ma, ml, sa, sl, rho.unwrap_or(0.0), 2.0));
    }
    let (x0, x1, y0, y1) = outline.iter().fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |(a, b, c, d), (x, y)| (a.min(*x), b.max(*x), c.min(*y), d.max(*y)),
    );
    let (px, py) = ((x1 - x0).max(1e-9) * 0.06, (y1 - y0).max(1e-9) * 0.06);
    // head room for the legend above the points
    let (x0, x1, y0, y1) = (x0 - px, x1 + px, y0 - py, y1 + 0.45 * (y1 - y0) + py);
    render((900, 700), |root| {
        let rho_txt = match (pop.and_then(|p| p.4), r.correlation_ci95.get(PAIR).copied()) {
            (Some(v), Some([lo, hi])) => format!("rho {v:+.2} [{lo:+.2}, {hi:+.2}]"),
            (Some(v), None) => format!("rho {v:+.2}"),
            _ => "rho not estimated".to_string(),
        };
        let mut c = ChartBuilder::on(root)
            .caption(
                format!("adhesion across {} releases: {rho_txt}", pts.len()),
                font(21),
            )
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("tip_adhesion.A1 [1e3 N/m]")
            .y_desc("tip_adhesion.lambda [nm]")
            .label_style(font(17))
            .axis_desc_style(font(18))
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()
            .map_err(perr)?;
        let grey = style::DARK_GREY;
        for (i, p) in pts.iter().enumerate() {
            let s = c
                .draw_series(std::iter::once(PathElement::new(
                    ellipse(p.0, p.2, p.1, p.3, p.4, 1.0),
                    grey.stroke_width(1),
                )))
                .map_err(perr)?;
            if i == 0 {
                s.label("1-sigma error ellipse of each release's fit")
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], grey));
            }
        }
        c.draw_series(
            pts.iter()
                .map(|p| Circle::new((p.0, p.2), 3, BLUE.filled())),
        )
        .map_err(perr)?
        .label("fitted (A1, lambda) of a release")
        .legend(|(x, y)| Circle::new((x + 9, y), 3, BLUE.filled()));
        if let Some((ma, sa, ml, sl, rho)) = pop {
            let red = style::RED;
            let rho = rho.unwrap_or(0.0);
            c.draw_series(std::iter::once(PathElement::new(
                ellipse(ma, ml, sa, sl, rho, 1.0),
                red.stroke_width(3),
            )))
            .map_err(perr)?
            .label("population 1-sigma (errors deconvolved)")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], red.stroke_width(3)));
            c.draw_series(DashedLineSeries::new(
                ellipse(ma, ml, sa, sl, rho, 2.0),
                7,
                5,
                red.stroke_width(2),
            ))
            .map_err(perr)?
            .label("population 2-sigma")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], red.stroke_width(2)));
            c.draw_series(std::iter::once(Cross::new(
                (ma, ml),
                8,
                red.stroke_width(3),
            )))
            .map_err(perr)?
            .label("population mean")
            .legend(move |(x, y)| Cross::new((x + 9, y), 6, red.stroke_width(3)));
        }
        style::legend(&mut c, 16, 0.9)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(perr)?;
        Ok(())
    })
    .map(Some)
    .map_err(|e| FitError::input("campaign plot", 0, e.0))
}

fn e4(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.4e}")
    } else {
        "-".into()
    }
}

/// The campaign's page in Markdown: the table in the thesis's form, the population, each
/// release's identified parameters with their sigmas, the failures and the plots (`plots` are
/// the file names written beside the page).
pub fn markdown(r: &CampaignReport, source: &str, effects: &[&str], plots: &[&str]) -> String {
    let mut m = String::new();
    m.push_str(&format!("# Campaign {source}\n\n"));
    m.push_str(&format!(
        "{} releases fitted, {} failed; model: {}.\n\n",
        r.releases.len(),
        r.failed.len(),
        effects.join(", ")
    ));
    m.push_str("## Table (thesis ch. 5 form)\n\n");
    m.push_str("| quantity | unit | source | mean | sd | sd of the mean | min | max |\n");
    m.push_str("|---|---|---|---|---|---|---|---|\n");
    for (key, _, unit, _, _) in QUANTITIES {
        if let Some(srcs) = r.table.get(key) {
            for (src, s) in srcs {
                match s {
                    Some(s) => m.push_str(&format!(
                        "| {key} | {unit} | {src} | {} | {} | {} | {} | {} |\n",
                        e4(s.mean),
                        e4(s.sd),
                        e4(s.sd_mean),
                        e4(s.min),
                        e4(s.max)
                    )),
                    None => m.push_str(&format!(
                        "| {key} | {unit} | {src} | not derived from the data (a second \
                         derivative of the noisy position) | | | | |\n"
                    )),
                }
            }
        }
    }
    m.push_str("\n## Adhesion population (measurement errors deconvolved)\n\n");
    m.push_str("| parameter | unit | mean | 1-sigma of the mean | 95 % interval (Hartung-Knapp) | spread (sd) | 1-sigma of the spread | 95 % interval (Q-profile) | releases |\n");
    m.push_str("|---|---|---|---|---|---|---|---|---|\n");
    for (name, unit) in [("tip_adhesion.A1", "N/m"), ("tip_adhesion.lambda", "m")] {
        if let Some(p) = r.population.get(name) {
            let f = |k: &str| e4(p.get(k).and_then(|v| v.as_f64()).unwrap_or(f64::NAN));
            let ci = |k: &str| match p.get(k).and_then(|v| v.as_array()) {
                Some(a) if a.len() == 2 => format!(
                    "[{}, {}]",
                    e4(a[0].as_f64().unwrap_or(f64::NAN)),
                    e4(a[1].as_f64().unwrap_or(f64::NAN))
                ),
                _ => "-".into(),
            };
            m.push_str(&format!(
                "| {name} | {unit} | {} | {} | {} | {} | {} | {} | {} |\n",
                f("mean"),
                f("mean_sigma"),
                ci("mean_ci95"),
                f("sd"),
                f("sd_sigma"),
                ci("sd_ci95"),
                p.get("n").map_or("-".into(), |v| v.to_string())
            ));
        }
    }
    match (pop_rho(r), r.correlation_ci95.get(PAIR)) {
        (Some(v), Some([lo, hi])) => m.push_str(&format!(
            "\nA1-lambda correlation across the population: {v:+.3} (95 % bootstrap interval \
             [{lo:+.3}, {hi:+.3}]).\n"
        )),
        (Some(v), None) => m.push_str(&format!(
            "\nA1-lambda correlation across the population: {v:+.3} (no interval: too few \
             resamples with a population spread).\n"
        )),
        _ => m.push_str("\nA1-lambda correlation: not estimated (fewer than 3 releases with both parameters free, or no population spread).\n"),
    }
    m.push_str("\n## Releases\n\n");
    m.push_str("| release | chi2_red | A1 [N/m] | lambda [m] | corr(A1, lambda) | P_x model [kg m/s] | P_x data [kg m/s] | F_peak [N] | dt [s] |\n");
    m.push_str("|---|---|---|---|---|---|---|---|---|\n");
    for x in &r.releases {
        let pm = |n: &str| {
            x.params.get(n).map_or("-".to_string(), |p| {
                if p.fixed {
                    format!("{} (fixed)", e4(p.value))
                } else {
                    match p.sigma {
                        Some(s) => format!("{} +- {:.2e}", e4(p.value), s),
                        None => format!("{} (not resolved)", e4(p.value)),
                    }
                }
            })
        };
        m.push_str(&format!(
            "| {} | {:.3} | {} | {} | {} | {} | {} | {} | {} |\n",
            x.file,
            x.chi2_red,
            pm("tip_adhesion.A1"),
            pm("tip_adhesion.lambda"),
            x.corr_a1_lambda.map_or("-".into(), |c| format!("{c:+.3}")),
            e4(x.p_x_model),
            e4(x.p_x_data),
            e4(x.f_peak_model),
            e4(x.dt_model)
        ));
    }
    if !r.failed.is_empty() {
        m.push_str("\n## Not fitted\n\n");
        for f in &r.failed {
            m.push_str(&format!(
                "- {}: {}\n",
                f.file,
                geodesic_util::text::one_line(&f.cause)
            ));
        }
    }
    if !plots.is_empty() {
        m.push_str("\n## Plots\n\n");
        for p in plots {
            m.push_str(&format!("![{p}]({p})\n\n"));
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ellipse_has_the_stated_moments() {
        // the outline's points, as a uniform sample of the angle, have the means, the sigmas
        // (times 1/sqrt(2) for a circle's cos) and the correlation given
        let e = ellipse(1.0, 2.0, 3.0, 0.5, -0.7, 1.0);
        let pts = &e[..72];
        let n = pts.len() as f64;
        let (mx, my) = (
            pts.iter().map(|p| p.0).sum::<f64>() / n,
            pts.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let sx = (pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>() / n).sqrt();
        let sy = (pts.iter().map(|p| (p.1 - my).powi(2)).sum::<f64>() / n).sqrt();
        let r = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / n / (sx * sy);
        assert!((mx - 1.0).abs() < 1e-12 && (my - 2.0).abs() < 1e-12);
        assert!((sx - 3.0 / 2f64.sqrt()).abs() < 1e-12, "{sx}");
        assert!((sy - 0.5 / 2f64.sqrt()).abs() < 1e-12, "{sy}");
        assert!((r + 0.7).abs() < 1e-12, "{r}");
    }

    #[test]
    fn bins_count_every_value_once() {
        let v = [0.0, 0.1, 0.5, 0.99, 1.0];
        let b = bins(&v, 0.0, 1.0, 4);
        assert_eq!(b, vec![2, 0, 1, 2]);
        assert_eq!(b.iter().sum::<usize>(), v.len());
    }
}
