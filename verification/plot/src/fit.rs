//! The plots of a fit, from plain data (the fit crate builds it: `geodesic_fit::plot`): data,
//! model and residual with the failure windows shaded ([`fit_svg`]); residual RMS and reduced
//! chi-square per model version ([`history_svg`]); a posterior's corner plot ([`corner_svg`]).

use crate::prelude::*;

/// What [`fit_svg`] draws, in SI units (the plot shows nm and ms).
#[derive(Debug, Clone, PartialEq)]
pub struct FitSeries<'a> {
    /// The title (dataset, model, reduced chi-square).
    pub title: String,
    /// The fitted channel's name (`x`).
    pub channel: &'a str,
    /// Sample times [s].
    pub t_s: &'a [f64],
    /// The measured channel [m].
    pub data_m: &'a [f64],
    /// The model's prediction [m].
    pub model_m: &'a [f64],
    /// The channel's 1-sigma noise [m] (the residual's +-3 sigma band).
    pub sigma_m: f64,
    /// Failure windows (start, end) [s], shaded.
    pub failures_s: Vec<(f64, f64)>,
}

/// One model version of [`history_svg`].
#[derive(Debug, Clone, PartialEq)]
pub struct Version {
    /// Its name on the axis (`v1 base`, `v2 +tip_adhesion`).
    pub name: String,
    /// Residual RMS over the fitted channels [SI].
    pub rms: f64,
    /// Reduced chi-square.
    pub chi2_red: f64,
    /// RMS of the measurement noise [SI], when kept.
    pub noise_rms: Option<f64>,
}

/// One parameter's marginal of [`corner_svg`]: its samples in physical units and the quantiles
/// drawn, each of the sorted samples (linear interpolation).
#[derive(Debug, Clone, PartialEq)]
pub struct Marginal {
    /// The parameter's name (axis label).
    pub name: String,
    /// Its samples, in chain order [unit].
    pub values: Vec<f64>,
    /// Its 0.1 % and 99.9 % quantiles (the axis range, padded) [unit].
    pub range: [f64; 2],
    /// Its 2.5 %, 50 % and 97.5 % quantiles (the marks on the diagonal) [unit].
    pub marks: [f64; 3],
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
pub fn fit_svg(f: &FitSeries<'_>) -> Result<String, PlotError> {
    let t: Vec<f64> = f.t_s.iter().map(|v| v * 1e3).collect();
    let d: Vec<f64> = f.data_m.iter().map(|v| v * 1e9).collect();
    let m: Vec<f64> = f.model_m.iter().map(|v| v * 1e9).collect();
    let r: Vec<f64> = d.iter().zip(&m).map(|(a, b)| a - b).collect();
    let s3 = 3.0 * f.sigma_m * 1e9;
    render((1000, 700), |root| {
        let (top, bottom) = root.split_vertically(420);
        let (x0, x1) = range(t.iter().copied());
        let (y0, y1) = range(d.iter().chain(&m).copied());
        let mut c = ChartBuilder::on(&top)
            .caption(f.title.as_str(), font(24))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("t [ms]")
            .y_desc(format!("{} [nm]", f.channel))
            .label_style(font(18))
            .axis_desc_style(font(19))
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()
            .map_err(perr)?;
        for (i, (t0, t1)) in f.failures_s.iter().enumerate() {
            let band = c
                .draw_series(std::iter::once(Rectangle::new(
                    [(t0 * 1e3, y0), (t1 * 1e3, y1)],
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
        for (i, (t0, t1)) in f.failures_s.iter().enumerate() {
            let band = c2
                .draw_series(std::iter::once(Rectangle::new(
                    [(t0 * 1e3, ry0), (t1 * 1e3, ry1)],
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
}

/// Renders RMS and reduced chi-square per model version (log scale) as an SVG string. Versions
/// are named by the effects they add (`v1 base`, `v2 +tip_adhesion`); the noise floor is drawn
/// in both panels (the noise RMS, and chi2_red = 1). `dataset` names the record, `base` the
/// first version's effects (`a, b`).
pub fn history_svg(dataset: &str, base: &str, entries: &[Version]) -> Result<String, PlotError> {
    let names: Vec<String> = entries.iter().map(|e| e.name.clone()).collect();
    let base = base.to_string();
    render((900, 680), |root| {
        let (top, bottom) = root.split_vertically(340);
        let n = entries.len().max(1) as f64;
        let name = dataset.to_string();
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
}

/// A corner plot of a posterior chain: per free parameter a histogram of its marginal (the
/// diagonal, median and 95 % interval marked) and, below the diagonal, the pairs' samples
/// (thinned to at most 1 500 points), in physical units, as an SVG string.
/// `samples` is the chain's kept samples, `walkers` its walkers and `acceptance` its fraction of
/// accepted moves (the title).
pub fn corner_svg(
    marginals: &[Marginal],
    samples: usize,
    walkers: usize,
    acceptance: f64,
) -> Result<String, PlotError> {
    let k = marginals.len();
    let cell = if k <= 3 { 260 } else { (900 / k.max(1)) as u32 }.max(150);
    let size = (cell * k as u32 + 40, cell * k as u32 + 70);
    let vals: Vec<&[f64]> = marginals.iter().map(|m| m.values.as_slice()).collect();
    let stride = (samples / 1500).max(1);
    render(size, |root| {
        let (title, grid) = root.split_vertically(50);
        title
            .draw(&Text::new(
                format!(
                    "posterior: {} walkers, {} samples kept, acceptance {:.2}",
                    walkers, samples, acceptance
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
                let (x0, x1) = range(marginals[c].range.into_iter());
                let xl = if r == k - 1 {
                    marginals[c].name.as_str()
                } else {
                    ""
                };
                if r == c {
                    let nb = 30;
                    let w = (x1 - x0) / nb as f64;
                    let mut h = vec![0usize; nb];
                    for v in vals[c] {
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
                    for (x, style) in [
                        (marginals[c].marks[0], RED.stroke_width(1)),
                        (marginals[c].marks[1], RED.stroke_width(2)),
                        (marginals[c].marks[2], RED.stroke_width(1)),
                    ] {
                        ch.draw_series(std::iter::once(PathElement::new(
                            vec![(x, 0.0), (x, top)],
                            style,
                        )))
                        .map_err(perr)?;
                    }
                } else {
                    let (y0, y1) = range(marginals[r].range.into_iter());
                    let mut ch = ChartBuilder::on(area)
                        .margin(6)
                        .x_label_area_size(if r == k - 1 { 40 } else { 18 })
                        .y_label_area_size(if c == 0 { 70 } else { 18 })
                        .build_cartesian_2d(x0..x1, y0..y1)
                        .map_err(perr)?;
                    ch.configure_mesh()
                        .x_desc(xl)
                        .y_desc(if c == 0 {
                            marginals[r].name.as_str()
                        } else {
                            ""
                        })
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
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let e = |name: &str, rms: f64, chi: f64| Version {
            name: name.into(),
            rms,
            chi2_red: chi,
            noise_rms: Some(1e-9),
        };
        let h = [e("v1 base", 3e-8, 72.0), e("v2 +c", 1.05e-9, 1.05)];
        let svg = history_svg("d.yaml", "a, b", &h).unwrap();
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
