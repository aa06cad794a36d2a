//! The plots of a fit, drawn by `geodesic_plot::fit` from plain data: this module builds that
//! data from a prepared dataset, a report, a history or a posterior chain, and writes the SVG.

use std::path::Path;

use geodesic_plot::fit::{FitSeries, Marginal, Version};

use crate::error::{FitError, write_atomic};
use crate::history::Entry;
use crate::prepare::Prepared;
use crate::report::FitReport;

fn plot_error(e: geodesic_plot::PlotError) -> FitError {
    FitError::input("plot", 0, e.0)
}

/// Renders data and model (top) and the residual with its +-3 sigma band (bottom), failure
/// windows shaded, as an SVG string. Lengths in nm, time in ms.
pub fn fit_svg(prep: &Prepared, pred: &[f64], report: &FitReport) -> Result<String, FitError> {
    geodesic_plot::fit::fit_svg(&FitSeries {
        title: format!(
            "{}: {} (chi2_red {:.3})",
            report.dataset,
            report.effects.join("+"),
            report.chi2_red
        ),
        channel: prep.channel,
        t_s: &prep.dataset.t,
        data_m: prep.data(),
        model_m: pred,
        sigma_m: prep.marginal_sigma(),
        failures_s: report
            .failures
            .iter()
            .map(|f| (f.t_start, f.t_end))
            .collect(),
    })
    .map_err(plot_error)
}

/// Renders RMS and reduced chi-square per model version (log scale) as an SVG string. Versions
/// are named by the effects they add (`v1 base`, `v2 +tip_adhesion`, [`Entry::name`]); the
/// noise floor is drawn in both panels (the noise RMS, and chi2_red = 1).
pub fn history_svg(entries: &[Entry]) -> Result<String, FitError> {
    let versions: Vec<Version> = entries
        .iter()
        .enumerate()
        .map(|(i, e)| Version {
            name: e.name(i.checked_sub(1).map(|j| &entries[j])),
            rms: e.rms,
            chi2_red: e.chi2_red,
            noise_rms: e.noise_rms,
        })
        .collect();
    let first = entries.first();
    let base = first.map_or(String::new(), |e| e.effects.join(", "));
    let dataset = first.map_or("", |e| e.dataset.as_str());
    geodesic_plot::fit::history_svg(dataset, &base, &versions).map_err(plot_error)
}

/// A corner plot of a posterior chain in physical units (`back[i]` maps the fit coordinate of
/// parameter `i` back), as an SVG string ([`geodesic_plot::fit::corner_svg`]).
pub fn corner_svg(
    names: &[String],
    chain: &crate::numeric::ensemble::Chain,
    back: &[&dyn Fn(f64) -> f64],
) -> Result<String, FitError> {
    use crate::numeric::ensemble::quantile;
    let marginals: Vec<Marginal> = names
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let values: Vec<f64> = chain.samples.iter().map(|s| back[i](s[i])).collect();
            let mut sorted = values.clone();
            sorted.sort_by(f64::total_cmp);
            let q = |p: f64| quantile(&sorted, p);
            Marginal {
                name: name.clone(),
                range: [q(0.001), q(0.999)],
                marks: [q(0.025), q(0.5), q(0.975)],
                values,
            }
        })
        .collect();
    geodesic_plot::fit::corner_svg(
        &marginals,
        chain.samples.len(),
        chain.walkers,
        chain.acceptance,
    )
    .map_err(plot_error)
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
}
