//! SVG plots: data, model and residual with the failure windows shaded; the fit history.

use std::path::Path;

use geodesic_plot::prelude::*;

use crate::error::{FitError, write_atomic};
use crate::history::Entry;
use crate::prepare::Prepared;
use crate::report::FitReport;

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

/// A tick label without binary noise: at most 3 significant digits, trailing zeros dropped
/// (`0.5`, `120`, `2.5e-9`).
pub fn tick(v: &f64) -> String {
    let v = *v;
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if (1e-3..1e4).contains(&a) {
        let d = (2 - a.log10().floor() as i32).max(0) as usize;
        let t = format!("{v:.d$}");
        if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t
        }
    } else {
        let t = format!("{v:.2e}");
        match t.split_once('e') {
            Some((m, e)) => format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.')),
            None => t,
        }
    }
}

/// A log-axis tick label: only the 1, 2 and 5 of each decade are labelled (no crowding).
fn log_tick(v: &f64) -> String {
    if *v <= 0.0 || !v.is_finite() {
        return String::new();
    }
    let m = *v / 10f64.powf(v.log10().floor());
    if [1.0, 2.0, 5.0, 10.0]
        .iter()
        .any(|k| (m - k).abs() < 1e-6 * k)
    {
        tick(v)
    } else {
        String::new()
    }
}

/// The 1-2-5 values of `[lo, hi]` (only the powers of ten when they span more than three
/// decades): the tick and grid values of a log axis, each once (plotters' own key points may
/// hold two values a rounding apart, which printed a label twice).
fn log_keys(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let mants: &[f64] = if hi / lo > 1e3 {
        &[1.0]
    } else {
        &[1.0, 2.0, 5.0]
    };
    let (e0, e1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    (e0..=e1)
        .flat_map(|e| mants.iter().map(move |m| m * 10f64.powi(e)))
        .filter(|v| *v >= lo && *v <= hi)
        .collect()
}

const FAIL: RGBColor = style::PALE_RED;

/// Renders data and model (top) and the residual with its +-3 sigma band (bottom), failure
/// windows shaded, as an SVG string. Lengths in nm, time in ms.
pub fn fit_svg(prep: &Prepared, pred: &[f64], report: &FitReport) -> Result<String, FitError> {
    let t: Vec<f64> = prep.dataset.t.iter().map(|v| v * 1e3).collect();
    let d: Vec<f64> = prep.data().iter().map(|v| v * 1e9).collect();
    let m: Vec<f64> = pred.iter().map(|v| v * 1e9).collect();
    let r: Vec<f64> = d.iter().zip(&m).map(|(a, b)| a - b).collect();
    let s3 = 3.0 * prep.marginal_sigma() * 1e9;
    render((1000, 700), |root| {
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
            .caption(title, font(24))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("t [ms]")
            .y_desc(format!("{} [nm]", prep.channel))
            .label_style(font(18))
            .axis_desc_style(font(19))
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()
            .map_err(perr)?;
        for (i, f) in report.failures.iter().enumerate() {
            let band = c
                .draw_series(std::iter::once(Rectangle::new(
                    [(f.t_start * 1e3, y0), (f.t_end * 1e3, y1)],
                    FAIL.filled(),
                )))
                .map_err(perr)?;
            if i == 0 {
                band.label("failure window (residual not white)")
                    .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 15, y + 6)], FAIL.filled()));
            }
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
        style::legend(&mut c, 18, 0.9)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(perr)?;
        let (ry0, ry1) = range(r.iter().copied().chain([-s3 * 1.2, s3 * 1.2]));
        // head room above the residual for the legend, so that it covers no data
        let ry1 = ry1 + 1.1 * (ry1 - ry0);
        let mut c2 = ChartBuilder::on(&bottom)
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..x1, ry0..ry1)
            .map_err(perr)?;
        c2.configure_mesh()
            .x_desc("t [ms]")
            .y_desc("residual [nm]")
            .label_style(font(18))
            .axis_desc_style(font(19))
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()
            .map_err(perr)?;
        let noise = style::PALE_GREEN;
        c2.draw_series(std::iter::once(Rectangle::new(
            [(x0, -s3), (x1, s3)],
            noise.mix(0.6).filled(),
        )))
        .map_err(perr)?
        .label(format!("noise band +-3 sigma ({} nm)", tick(&s3)))
        .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 15, y + 6)], noise.filled()));
        for (i, f) in report.failures.iter().enumerate() {
            let band = c2
                .draw_series(std::iter::once(Rectangle::new(
                    [(f.t_start * 1e3, ry0), (f.t_end * 1e3, ry1)],
                    FAIL.mix(0.8).filled(),
                )))
                .map_err(perr)?;
            if i == 0 {
                band.label("failure window")
                    .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 15, y + 6)], FAIL.filled()));
            }
        }
        c2.draw_series(LineSeries::new(
            t.iter().copied().zip(r.iter().copied()),
            &BLACK,
        ))
        .map_err(perr)?
        .label("residual = data - model")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], BLACK));
        style::legend(&mut c2, 18, 0.9)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(perr)?;
        Ok(())
    })
    .map_err(|e| FitError::input("plot", 0, e.0))
}

/// Renders RMS and reduced chi-square per model version (log scale) as an SVG string. Versions
/// are named by the effects they add (`v1 base`, `v2 +tip_adhesion`); the noise floor is drawn
/// in both panels (the noise RMS, and chi2_red = 1).
pub fn history_svg(entries: &[Entry]) -> Result<String, FitError> {
    let names: Vec<String> = entries
        .iter()
        .enumerate()
        .map(|(i, e)| e.name(i.checked_sub(1).map(|j| &entries[j])))
        .collect();
    let base = entries
        .first()
        .map_or(String::new(), |e| e.effects.join(", "));
    render((900, 680), |root| {
        let (top, bottom) = root.split_vertically(340);
        let n = entries.len().max(1) as f64;
        let name = entries
            .first()
            .map_or("", |e| e.dataset.as_str())
            .to_string();
        let noise_rms = entries.iter().rev().find_map(|e| e.noise_rms);
        let label = |v: &f64| -> String {
            let k = v.round();
            if (v - k).abs() < 1e-6 && k >= 1.0 && k <= n {
                names[k as usize - 1].clone()
            } else {
                String::new()
            }
        };
        for (area, title, vals, floor, floor_label) in [
            (
                &top,
                format!("{name}: residual RMS [m] per model version (v1 base: {base})"),
                entries.iter().map(|e| e.rms).collect::<Vec<_>>(),
                noise_rms,
                noise_rms.map(|v| format!("noise floor: noise RMS {} m", tick(&v))),
            ),
            (
                &bottom,
                "reduced chi-square per model version".to_string(),
                entries.iter().map(|e| e.chi2_red).collect(),
                Some(1.0),
                Some("noise floor: chi2_red = 1".to_string()),
            ),
        ] {
            let pos: Vec<f64> = vals.iter().map(|v| v.max(1e-300)).collect();
            let lo = pos
                .iter()
                .cloned()
                .chain(floor)
                .fold(f64::INFINITY, f64::min)
                * 0.5;
            let hi = pos
                .iter()
                .cloned()
                .chain(floor)
                .fold(0.0, f64::max)
                .max(lo * 4.0)
                * 2.0;
            let mut c = ChartBuilder::on(area)
                .caption(title, font(21))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(80)
                .build_cartesian_2d(
                    0.5..n + 0.5,
                    (lo..hi).log_scale().with_key_points(log_keys(lo, hi)),
                )
                .map_err(perr)?;
            c.configure_mesh()
                .x_labels(2 * entries.len() + 1)
                .x_label_formatter(&label)
                .y_label_formatter(&log_tick)
                .disable_x_mesh()
                .label_style(font(18))
                .axis_desc_style(font(19))
                .x_desc("model version (effects added)")
                .draw()
                .map_err(perr)?;
            if let (Some(f), Some(l)) = (floor, floor_label) {
                let green = style::GREEN;
                c.draw_series(DashedLineSeries::new(
                    vec![(0.5, f), (n + 0.5, f)],
                    8,
                    5,
                    green.stroke_width(2),
                ))
                .map_err(perr)?
                .label(l)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], green.stroke_width(2))
                });
            }
            c.draw_series(LineSeries::new(
                pos.iter().enumerate().map(|(i, v)| (i as f64 + 1.0, *v)),
                BLUE.stroke_width(2),
            ))
            .map_err(perr)?
            .label("fit of this version")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(2)));
            c.draw_series(
                pos.iter()
                    .enumerate()
                    .map(|(i, v)| Circle::new((i as f64 + 1.0, *v), 5, BLUE.filled())),
            )
            .map_err(perr)?;
            style::legend(&mut c, 18, 0.9)
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(perr)?;
        }
        Ok(())
    })
    .map_err(|e| FitError::input("plot", 0, e.0))
}

/// A corner plot of a posterior chain: per free parameter a histogram of its marginal (the
/// diagonal, median and 95 % interval marked) and, below the diagonal, the pairs' samples
/// (thinned to at most 1 500 points), in physical units (`back[i]` maps the fit coordinate of
/// parameter `i` back), as an SVG string.
pub fn corner_svg(
    names: &[String],
    chain: &crate::numeric::ensemble::Chain,
    back: &[&dyn Fn(f64) -> f64],
) -> Result<String, FitError> {
    let k = names.len();
    let cell = if k <= 3 { 260 } else { (900 / k.max(1)) as u32 }.max(150);
    let size = (cell * k as u32 + 40, cell * k as u32 + 70);
    let vals: Vec<Vec<f64>> = (0..k)
        .map(|i| chain.samples.iter().map(|s| back[i](s[i])).collect())
        .collect();
    let stride = (chain.samples.len() / 1500).max(1);
    render(size, |root| {
        let (title, grid) = root.split_vertically(50);
        title
            .draw(&Text::new(
                format!(
                    "posterior: {} walkers, {} samples kept, acceptance {:.2}",
                    chain.walkers,
                    chain.samples.len(),
                    chain.acceptance
                ),
                (20, 15),
                font(20),
            ))
            .map_err(perr)?;
        let cells = grid.split_evenly((k, k));
        for r in 0..k {
            for c in 0..k {
                let area = &cells[r * k + c];
                if c > r {
                    continue;
                }
                let mut sx = vals[c].clone();
                sx.sort_by(f64::total_cmp);
                let (x0, x1) = range(
                    [
                        crate::numeric::ensemble::quantile(&sx, 0.001),
                        crate::numeric::ensemble::quantile(&sx, 0.999),
                    ]
                    .into_iter(),
                );
                let xl = if r == k - 1 { names[c].as_str() } else { "" };
                if r == c {
                    let nb = 30;
                    let w = (x1 - x0) / nb as f64;
                    let mut h = vec![0usize; nb];
                    for v in &vals[c] {
                        if *v >= x0 && *v < x1 {
                            h[(((v - x0) / w) as usize).min(nb - 1)] += 1;
                        }
                    }
                    let top = *h.iter().max().unwrap_or(&1) as f64 * 1.1;
                    let mut ch = ChartBuilder::on(area)
                        .margin(6)
                        .x_label_area_size(if r == k - 1 { 40 } else { 18 })
                        .y_label_area_size(18)
                        .build_cartesian_2d(x0..x1, 0.0..top.max(1.0))
                        .map_err(perr)?;
                    ch.configure_mesh()
                        .x_desc(xl)
                        .x_labels(3)
                        .y_labels(0)
                        .x_label_formatter(&tick)
                        .label_style(font(13))
                        .axis_desc_style(font(14))
                        .disable_mesh()
                        .draw()
                        .map_err(perr)?;
                    ch.draw_series(h.iter().enumerate().map(|(i, n)| {
                        let a = x0 + w * i as f64;
                        Rectangle::new([(a, 0.0), (a + w, *n as f64)], BLUE.mix(0.5).filled())
                    }))
                    .map_err(perr)?;
                    for (q, style) in [
                        (0.025, RED.stroke_width(1)),
                        (0.5, RED.stroke_width(2)),
                        (0.975, RED.stroke_width(1)),
                    ] {
                        let x = crate::numeric::ensemble::quantile(&sx, q);
                        ch.draw_series(std::iter::once(PathElement::new(
                            vec![(x, 0.0), (x, top)],
                            style,
                        )))
                        .map_err(perr)?;
                    }
                } else {
                    let mut sy = vals[r].clone();
                    sy.sort_by(f64::total_cmp);
                    let (y0, y1) = range(
                        [
                            crate::numeric::ensemble::quantile(&sy, 0.001),
                            crate::numeric::ensemble::quantile(&sy, 0.999),
                        ]
                        .into_iter(),
                    );
                    let mut ch = ChartBuilder::on(area)
                        .margin(6)
                        .x_label_area_size(if r == k - 1 { 40 } else { 18 })
                        .y_label_area_size(if c == 0 { 70 } else { 18 })
                        .build_cartesian_2d(x0..x1, y0..y1)
                        .map_err(perr)?;
                    ch.configure_mesh()
                        .x_desc(xl)
                        .y_desc(if c == 0 { names[r].as_str() } else { "" })
                        .x_labels(3)
                        .y_labels(3)
                        .x_label_formatter(&tick)
                        .y_label_formatter(&tick)
                        .label_style(font(13))
                        .axis_desc_style(font(14))
                        .disable_mesh()
                        .draw()
                        .map_err(perr)?;
                    ch.draw_series(
                        (0..vals[c].len()).step_by(stride).map(|i| {
                            Circle::new((vals[c][i], vals[r][i]), 1, BLUE.mix(0.4).filled())
                        }),
                    )
                    .map_err(perr)?;
                }
            }
        }
        Ok(())
    })
    .map_err(|e| FitError::input("plot", 0, e.0))
}

/// Writes an SVG atomically.
pub fn write_svg(path: &Path, svg: &str) -> Result<(), FitError> {
    write_atomic(path, svg.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A history of two versions and a fit with failure windows, plotted (moved from
    /// `history`'s tests so that `history` does not depend on `plot`).
    #[test]
    fn plots_a_history_and_a_fit_with_its_failure_windows() {
        use crate::estimate::{FitOptions, fit};
        use crate::history::{append, path_for, read};
        use crate::synth::{SynthSpec, generate};
        use geodesic_facility::Scenario;
        let mut spec = SynthSpec::defaults(Scenario::RtRetraction, &["piezo", "voltage_ramp"]);
        spec.post_s = 2e-4;
        let prep = Prepared::new(generate(&spec, "h.yaml").unwrap());
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().to_path_buf();
        for effects in [vec!["piezo"], vec!["piezo", "voltage_ramp"]] {
            let o = fit(&prep, &effects, &FitOptions::default()).unwrap();
            append(&dir, "h", &FitReport::new(&prep, &o)).unwrap();
        }
        let h = read(&path_for(&dir, "h")).unwrap();
        let svg = history_svg(&h).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("</svg>"));
        let o = fit(&prep, &["piezo"], &FitOptions::default()).unwrap();
        let r = FitReport::new(&prep, &o);
        let fsvg = fit_svg(&prep, &o.pred, &r).unwrap();
        assert!(!r.failures.is_empty());
        assert!(
            fsvg.to_uppercase().contains("#FFC8C8"),
            "failure windows are shaded"
        );
        assert!(
            fsvg.contains("failure window") && fsvg.contains("noise band"),
            "every shaded band is in a legend"
        );
    }

    /// A log axis's keys are its 1-2-5 values inside the range, each once and increasing; over
    /// more than three decades only the powers of ten (the history plot's axis printed 1e-8 twice).
    #[test]
    fn log_keys_are_the_1_2_5_values_each_once() {
        let k = log_keys(4e-10, 1.4e-8);
        let want = [5e-10, 1e-9, 2e-9, 5e-9, 1e-8];
        assert_eq!(k.len(), want.len(), "{k:?}");
        for (a, b) in k.iter().zip(want) {
            assert!((a / b - 1.0).abs() < 1e-12, "{k:?}");
        }
        assert_eq!(log_keys(0.5, 2000.0), vec![1.0, 10.0, 100.0, 1000.0]);
        assert!(log_keys(0.0, 1.0).is_empty() && log_keys(2.0, 1.0).is_empty());
    }

    #[test]
    fn ticks_have_no_binary_noise() {
        assert_eq!(tick(&(0.1 + 0.2 - 0.3 + 1e-9)), "1e-9");
        assert_eq!(tick(&(3.0 * 0.1)), "0.3");
        assert_eq!(tick(&2.5e-9), "2.5e-9");
        assert_eq!(tick(&0.6000000000000001), "0.6");
        assert_eq!(tick(&120.0), "120");
        assert_eq!(log_tick(&2e-9), "2e-9");
        assert_eq!(log_tick(&7e-9), "");
    }

    #[test]
    fn history_names_versions_and_draws_the_noise_floor() {
        let e = |v: usize, eff: &[&str], rms: f64, chi: f64| Entry {
            version: v,
            dataset: "d.yaml".into(),
            effects: eff.iter().map(|s| s.to_string()).collect(),
            n_free: 2,
            rms,
            chi2_red: chi,
            bic: 0.0,
            noise_rms: Some(1e-9),
        };
        let h = [
            e(1, &["a", "b"], 3e-8, 72.0),
            e(2, &["a", "b", "c"], 1.05e-9, 1.05),
        ];
        let svg = history_svg(&h).unwrap();
        for want in [
            "v1 base",
            "v2 +c",
            "noise floor: noise RMS 1e-9 m",
            "chi2_red = 1",
        ] {
            assert!(svg.contains(want), "{want}");
        }
        assert!(!svg.contains("0000000"), "garbled tick label");
    }
}
