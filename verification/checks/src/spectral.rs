//! `spectral-asd`: requirements whose limit is an amplitude spectral density curve (issue 16,
//! item 3). Generic: it gives evidence for every loaded requirement that names it in `check:`,
//! whatever the mission.
//!
//! For each such requirement, the time series named with `geodesic verify --series ID=FILE.yaml`
//! is read, its ASD estimated by Welch (Hann, 50 % overlap, segments of `4 fs / f_min` samples
//! rounded up to a power of two: `geodesic_fit::spectral`) and judged over the requirement's
//! band: the value is the worst `ASD / L(f)` times the level (margin = 1 - worst ratio), with the
//! frequency where it occurs, the 95 % upper-bound ratio and the estimator settings as inputs,
//! and a log-log plot of ASD, band and limit as artifact. Without a series the requirement is
//! not verified, and says how to supply one: no number is invented.
//!
//! A series is evidence of what its file declares it to be (`origin:` and `provenance:`,
//! docs/spectra.md): a measurement (basis `measurement`), a simulation (basis `model`); a
//! synthetic series, or one that does not say, is shown as an illustration and leaves the row
//! not verified (`data/spectra/lpf-da-example.yaml` is such an illustration).

use crate::plots;
use geodesic_core::requirement::Requirement;
use geodesic_core::{Basis, Check, CheckContext, CheckError, Evidence, Quantity};
use geodesic_fit::spectral::{self, Asd, Judgement, Series, SeriesOrigin, WelchOptions};
use geodesic_plot::prelude::*;
use std::path::Path;

/// Name of the check (what `check:` names in YAML).
pub const NAME: &str = "spectral-asd";

/// Checks a time series (this check's input, `verify --series ID=FILE`) before anything runs:
/// `Ok`, or the one-line cause.
pub fn validate_series(p: &Path) -> Result<(), String> {
    Series::load(p).map(|_| ()).map_err(|e| e.to_string())
}

/// Overlap of Welch's segments [-].
pub const OVERLAP: f64 = 0.5;

/// The checks of this family.
pub fn checks() -> Vec<Box<dyn Check>> {
    vec![Box::new(SpectralAsd)]
}

/// `spectral-asd`.
pub struct SpectralAsd;

/// The ASD of `series` judged against `req` (which must have a limit and a spectrum).
pub fn judge_series(req: &Requirement, series: &Series) -> Result<(Asd, Judgement), String> {
    let (Some(lim), Some(spec)) = (&req.limit, &req.spectrum) else {
        return Err(format!(
            "{} has no spectral limit (a `limit` with a `spectrum`)",
            req.id
        ));
    };
    if series.dim != lim.dim {
        return Err(format!(
            "{}: the series {} is in `{}` ({}), the requirement bounds a {}",
            req.id,
            series.path.display(),
            series.unit,
            series.dim,
            lim.dim
        ));
    }
    let fs = 1.0 / series.dt_s;
    let n = spectral::default_nperseg(series.values.len(), fs, spec.band_hz[0]);
    let asd = spectral::welch(
        &series.values,
        fs,
        WelchOptions {
            nperseg: n,
            overlap: OVERLAP,
        },
    )
    .map_err(|e| format!("{}: {e}", series.path.display()))?;
    let j = spectral::judge(&asd, spec, lim.value.value)
        .map_err(|e| format!("{}: {}: {e}", req.id, series.path.display()))?;
    Ok((asd, j))
}

/// The evidence for one requirement and series, with its plot written to `reports_dir`.
pub fn evidence(
    req: &Requirement,
    series: &Series,
    csv_sha256: &str,
    reports_dir: &Path,
) -> Result<Evidence, String> {
    let (asd, j) = judge_series(req, series)?;
    let (lim, spec) = (
        req.limit.as_ref().expect("limit"),
        req.spectrum.as_ref().expect("spectrum"),
    );
    let scale = lim.unit.scale;
    let svg = asd_svg(req, &asd).map_err(|e| e.to_string())?;
    let name = format!("spectra/{}.svg", req.id);
    plots::write(reports_dir, &name, &svg).map_err(|e| e.to_string())?;
    // a series is evidence of what it declares itself to be: a measurement with its
    // provenance, a simulation (a model's output), or else an illustration
    let (basis, what) = match series.origin {
        SeriesOrigin::Measurement => (Basis::Measurement, "measured series"),
        SeriesOrigin::Simulation => (Basis::Model, "simulated series"),
        SeriesOrigin::Synthetic | SeriesOrigin::Unstated => (
            Basis::Illustration,
            "series (an illustration, not a measurement)",
        ),
    };
    // evidence is judged by the ASD's 95 % bounds, never its estimate: met when the upper
    // bound is within the limit in every bin, violated when the lower bound exceeds it in one,
    // else inconclusive (an illustration shows its estimate)
    let (ratio, bound) = if !basis.decides() {
        (j.worst_ratio, "estimate")
    } else if lim.op.holds(j.worst_ratio_hi95, 1.0) {
        (j.worst_ratio_hi95, "upper 95 % bound")
    } else if !lim.op.holds(j.worst_ratio_lo95, 1.0) {
        (j.worst_ratio_lo95, "lower 95 % bound")
    } else {
        (f64::NAN, "")
    };
    let mut ev = Evidence::measured(
        req.id.as_str(),
        Quantity::new(ratio * lim.value.value, lim.dim),
        basis,
        format!(
            "Welch ASD of the supplied {what} (Hann, {:.0} % overlap, {} segments of {} samples, {:.1} dof per bin) judged by its {bound} against {} x ({}) over {}: worst ratio {:.3} at {:.4e} Hz (estimate), {:.3} at {:.4e} Hz (upper 95 % bound)",
            OVERLAP * 100.0,
            asd.segments,
            asd.options.nperseg,
            asd.dof,
            lim.text.trim_start_matches(['<', '=', ' ']),
            spec.shape_text,
            spec.band_text,
            j.worst_ratio,
            j.worst_f_hz,
            j.worst_ratio_hi95,
            j.worst_f_hi95_hz
        ),
    )
    .with_input("series", series.path.display().to_string())
    .with_input("origin", series.origin.as_str())
    .with_input(
        "provenance",
        series.provenance.clone().unwrap_or_else(|| "none stated".into()),
    )
    .with_input("series_csv_sha256", csv_sha256)
    .with_input("sample_rate_hz", asd.fs_hz)
    .with_input("samples", series.values.len())
    .with_input("nperseg", asd.options.nperseg)
    .with_input("overlap", OVERLAP)
    .with_input("segments", asd.segments)
    .with_input("dof_per_bin", asd.dof)
    .with_input("window", asd.window)
    .with_input("bins_judged", j.bins)
    .with_input("judged_from_hz", j.judged_hz[0])
    .with_input("judged_to_hz", j.judged_hz[1])
    .with_input("worst_ratio", j.worst_ratio)
    .with_input("worst_frequency_hz", j.worst_f_hz)
    .with_input("asd_at_worst", j.worst_asd / scale)
    .with_input("limit_at_worst", j.worst_limit / scale)
    .with_input("unit", lim.unit.symbol.clone())
    .with_input("worst_ratio_upper95", j.worst_ratio_hi95)
    .with_input("worst_frequency_upper95_hz", j.worst_f_hi95_hz)
    .with_input("worst_ratio_lower95", j.worst_ratio_lo95)
    .with_artifact(name);
    if ratio.is_nan() {
        ev.basis = None;
        ev.outcome = geodesic_core::check::Outcome::NotVerified(format!(
            "inconclusive at 95 % confidence: the estimate's worst ratio to the limit is {:.3} at {:.4e} Hz, but its upper 95 % bound reaches {:.3} at {:.4e} Hz and no lower bound exceeds the limit (worst {:.3}); a longer series (more segments) decides",
            j.worst_ratio, j.worst_f_hz, j.worst_ratio_hi95, j.worst_f_hi95_hz, j.worst_ratio_lo95
        ));
    }
    Ok(ev)
}

/// SHA-256 of the CSV a series YAML names (empty if it cannot be read: the loader reports it).
fn csv_sha(series_yaml: &Path) -> String {
    let Ok(text) = std::fs::read_to_string(series_yaml) else {
        return String::new();
    };
    let data = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("data:"))
        .map(|d| d.trim().trim_matches(['"', '\'']).to_string());
    match data {
        Some(d) => {
            let p = series_yaml.parent().unwrap_or(Path::new(".")).join(d);
            std::fs::read(&p)
                .map(|b| geodesic_util::hash::sha256_hex(&b))
                .unwrap_or_default()
        }
        None => String::new(),
    }
}

impl Check for SpectralAsd {
    fn name(&self) -> &'static str {
        NAME
    }

    fn verifies(&self) -> &'static [&'static str] {
        // generic: the requirements that name it in `check:` (see the module doc)
        &[]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let mut out = Vec::new();
        for req in &ctx.requirements.items {
            if req.check.as_deref() != Some(NAME) {
                continue;
            }
            if req.spectrum.is_none() {
                return Err(CheckError::input(format!(
                    "{} names check {NAME} but has no `spectrum` (band and shape of its limit)",
                    req.id
                )));
            }
            let activity =
                "Welch ASD of a measured or simulated time series against the limit curve";
            let Some(file) = ctx.inputs.series.get(req.id.as_str()) else {
                out.push(Evidence::not_verified(
                    req.id.as_str(),
                    format!(
                        "no time series of {} supplied (geodesic verify --series {}=FILE.yaml)",
                        if req.quantity.is_empty() {
                            "the quantity"
                        } else {
                            req.quantity.as_str()
                        },
                        req.id
                    ),
                    activity,
                ));
                continue;
            };
            let path = Path::new(&file.label);
            let series = Series::load(path)
                .map_err(|e| CheckError::input(e.to_string()).in_file(&file.label, 0))?;
            let ev = evidence(req, &series, &csv_sha(path), &ctx.reports_dir)
                .map_err(CheckError::evidence)?
                .with_input("series_yaml_sha256", file.sha256.clone());
            if matches!(
                series.origin,
                SeriesOrigin::Synthetic | SeriesOrigin::Unstated
            ) {
                out.push(Evidence::not_verified(
                    req.id.as_str(),
                    format!(
                        "the series {} is not a measurement ({}): its spectrum is shown as an illustration; a series that is evidence declares `origin: measurement` (or `simulation`) with its `provenance`",
                        file.label,
                        match series.origin {
                            SeriesOrigin::Synthetic => "it declares itself synthetic",
                            _ => "it does not declare its origin",
                        }
                    ),
                    activity,
                ));
            }
            out.push(ev);
        }
        Ok(out)
    }
}

/// Log-log plot of the ASD with its 95 % band and the limit curve over the band.
pub fn asd_svg(req: &Requirement, asd: &Asd) -> Result<String, CheckError> {
    let (lim, spec) = match (&req.limit, &req.spectrum) {
        (Some(l), Some(s)) => (l, s),
        _ => {
            return Err(CheckError::evidence(format!(
                "{}: no spectral limit",
                req.id
            )));
        }
    };
    let scale = lim.unit.scale;
    let pts: Vec<(f64, f64, f64, f64)> = (1..asd.f_hz.len())
        .map(|j| {
            (
                asd.f_hz[j],
                asd.asd[j] / scale,
                asd.lo95[j] / scale,
                asd.hi95[j] / scale,
            )
        })
        .filter(|p| p.1 > 0.0 && p.2 > 0.0)
        .collect();
    if pts.is_empty() {
        return Err(CheckError::evidence(format!(
            "{}: the ASD is zero everywhere",
            req.id
        )));
    }
    let limit: Vec<(f64, f64)> = (0..=200)
        .map(|i| {
            let f = spec.band_hz[0] * (spec.band_hz[1] / spec.band_hz[0]).powf(i as f64 / 200.0);
            (f, lim.value.value * spec.shape(f) / scale)
        })
        .collect();
    let (x0, x1) = (pts[0].0, pts[pts.len() - 1].0);
    let ys = pts
        .iter()
        .flat_map(|p| [p.2, p.3])
        .chain(limit.iter().map(|p| p.1));
    let (mut y0, mut y1) = (f64::INFINITY, 0.0f64);
    for y in ys {
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let (y0, y1) = (y0 / 2.0, y1 * 2.0);
    render((900, 520), |root| {
        let mut c = ChartBuilder::on(root)
            .caption(
                format!("{}: amplitude spectral density against its limit", req.id),
                font(22),
            )
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(90)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(perr)?;
        c.configure_mesh()
            .x_desc("frequency [Hz] (log)")
            .y_desc(format!("ASD [{}] (log)", lim.unit.symbol))
            .label_style(font(16))
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(perr)?;
        let grey = style::PALE_BLUE;
        let blue = style::BLUE;
        let red = style::RED;
        c.draw_series(LineSeries::new(
            pts.iter().map(|p| (p.0, p.3)),
            grey.stroke_width(1),
        ))
        .map_err(perr)?
        .label("95 % confidence band")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], grey));
        c.draw_series(LineSeries::new(
            pts.iter().map(|p| (p.0, p.2)),
            grey.stroke_width(1),
        ))
        .map_err(perr)?;
        c.draw_series(LineSeries::new(
            pts.iter().map(|p| (p.0, p.1)),
            blue.stroke_width(2),
        ))
        .map_err(perr)?
        .label(format!(
            "Welch ASD ({} segments, {:.0} dof)",
            asd.segments, asd.dof
        ))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], blue.stroke_width(2)));
        c.draw_series(LineSeries::new(limit, red.stroke_width(2)))
            .map_err(perr)?
            .label(format!(
                "limit {} x ({}) over {}",
                lim.text, spec.shape_text, spec.band_text
            ))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], red.stroke_width(2)));
        style::legend(&mut c, 15, 0.85)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(perr)?;
        Ok(())
    })
    .map_err(|e| CheckError::evidence(e.to_string()))
}
