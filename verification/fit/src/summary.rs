//! The human-readable summary of a fit (what `geodesic fit` prints; numbers to four
//! significant digits).

use crate::FitReport;

/// Human-readable summary of a fit (numbers to four significant digits:
/// [`crate::outliers::fmt_sig`]).
pub fn summary(r: &FitReport) -> String {
    let mut s = format!(
        "{} [{}]: {}\n",
        r.dataset,
        r.scenario,
        r.effects.join(" + ")
    );
    for (ch, v) in &r.rms {
        s += &format!(
            "  rms {ch} = {v:.4e}  (noise {:.3e}, {})\n",
            r.noise[ch], r.noise_source[ch]
        );
    }
    s += &format!(
        "  chi2_red = {}  (N = {}, k = {})  residual white: {}  BIC = {}\n",
        crate::outliers::fmt_sig(r.chi2_red),
        r.n_samples,
        r.n_free,
        r.residual_white,
        crate::outliers::fmt_sig(r.bic)
    );
    s += &parameter_lines(r);
    s += &diagnostic_lines(r);
    s += &posterior_lines(r);
    if let Some(svg) = &r.svg {
        s += &format!("  plot: {svg}\n");
    }
    s
}

/// The parameters with their sigmas, what is held, the symmetries and the combinations.
fn parameter_lines(r: &FitReport) -> String {
    let mut s = String::new();
    for (k, p) in &r.params {
        let held = r.held.iter().any(|h| &h.param == k);
        let mut fixed = if held {
            "  (held at a stated value)"
        } else if p.fixed {
            "  (fixed)"
        } else {
            ""
        }
        .to_string();
        if let Some(f) = &p.flag {
            fixed += &format!("  AT {}", f.to_uppercase());
        }
        match p.sigma {
            Some(sig) => {
                s += &format!(
                    "  {k:<30} = {:>12.5e} +- {:<10.3e} {}{fixed}\n",
                    p.value, sig, p.unit
                )
            }
            None => {
                s += &format!(
                    "  {k:<30} = {:>12.5e}    (not resolved: no sigma) {}{fixed}\n",
                    p.value, p.unit
                )
            }
        }
    }
    for h in &r.held {
        s += &format!("  {} {}\n", h.param, h.reason);
    }
    for sym in &r.symmetries {
        let dir: Vec<String> = sym
            .direction
            .iter()
            .map(|(n, w)| format!("{w:+.2} {n}"))
            .collect();
        s += &format!(
            "  {} symmetry (not resolved by the data): {}\n",
            sym.kind,
            dir.join(" ")
        );
    }
    for (n, c) in &r.combinations {
        match c.sigma {
            Some(sig) => {
                s += &format!(
                    "  {n:<30} = {:>12.5e} +- {:<10.3e} {}  ({})\n",
                    c.value, sig, c.unit, c.formula
                )
            }
            None => {
                s += &format!(
                    "  {n:<30} = {:>12.5e}    (not resolved) {}  ({})\n",
                    c.value, c.unit, c.formula
                )
            }
        }
    }
    s
}

/// The outliers, the correlated pairs, what the data do not resolve, where the model fails.
fn diagnostic_lines(r: &FitReport) -> String {
    use crate::outliers::fmt_sig;
    let mut s = String::new();
    for o in &r.outliers {
        s += &format!(
            "  outlier {}{}: t = {} s, {} = {:.4e}, {} robust sigma off{}\n",
            o.channel,
            o.line.map_or(String::new(), |l| format!(" at line {l}")),
            fmt_sig(o.t),
            o.channel,
            o.value,
            fmt_sig(o.robust_sigma),
            if o.excluded {
                " its neighbours (excluded from the fit)"
            } else {
                " the model"
            }
        );
    }
    for c in &r.correlated {
        s += &format!("  correlated: {} ~ {} (rho {:.3})\n", c.a, c.b, c.rho);
    }
    if !r.unresolved.is_empty() {
        let list: Vec<String> = r
            .unresolved
            .iter()
            .map(|u| {
                if u.step_ratio.is_finite() {
                    format!("{} (x{:.2})", u.param, u.step_ratio)
                } else {
                    format!("{} (no finite sigma)", u.param)
                }
            })
            .collect();
        s += &format!(
            "  not resolved by the data: {}: the covariance sigma moves by that factor when the \
             difference steps are halved; read these sigmas as lower bounds (unless profiled \
             wider) and the parameters together with the correlated pairs\n",
            list.join(", ")
        );
    }
    for f in &r.failures {
        s += &format!(
            "  fails on {}: {:.4e} s .. {:.4e} s, peak {:.3e} ({} sigma)\n",
            f.channel,
            f.t_start,
            f.t_end,
            f.peak,
            fmt_sig(f.peak_sigma)
        );
    }
    s
}

/// The posterior's quantiles and flags, when sampled.
fn posterior_lines(r: &FitReport) -> String {
    let mut s = String::new();
    if let Some(post) = &r.posterior {
        let how = match &r.posterior_method {
            Some(crate::report::PosteriorMethod::Ensemble(m)) => format!(
                "sampled: {} walkers x {} steps, acceptance {:.2}; corner plot {}",
                m.walkers, m.steps, m.acceptance, m.corner_svg
            ),
            _ => "Laplace at the best fit".to_string(),
        };
        s += &format!("  posterior ({how}; flat priors on the range): median [68 %] [95 %]\n");
        for (n, p) in post {
            let mut flags: Vec<String> = Vec::new();
            if p.prior_limited == Some(true) {
                flags.push("PRIOR-LIMITED".into());
            }
            if p.multimodal == Some(true) {
                flags.push("MULTIMODAL".into());
            }
            if let (Some(false), Some(tau)) = (p.converged, p.autocorr_steps) {
                // an unconverged chain underestimates tau: a lower bound
                flags.push(format!(
                    "NOT-CONVERGED (autocorrelation at least {tau:.0} steps: needs over {:.0} \
                     --posterior-steps)",
                    (crate::numeric::ensemble::CONVERGED_TAUS * tau * 1.5).ceil()
                ));
            }
            s += &format!(
                "    {n}: {:.6e} [{:.6e}, {:.6e}] [{:.6e}, {:.6e}]{}\n",
                p.median,
                p.lo68,
                p.hi68,
                p.lo95,
                p.hi95,
                if flags.is_empty() {
                    String::new()
                } else {
                    format!("  {}", flags.join(" "))
                }
            );
        }
    }
    s
}
