//! `tip-radius-tradeoff` (thesis ch. 6, "Lesson Learned"; issue 16, item 2): an illustration
//! beside REL-GPRM-VEL, never a verdict. The thesis's simple bottom and upper estimates of the
//! worst-case velocity against tip radius (`geodesic_release::tipradius`), their optimum, and the
//! release Monte Carlo at a handful of radii as the cross-check, plotted into the report; the
//! illustrated value is the Monte Carlo's 99.73 % point at the bottom estimate's optimum radius
//! ("what if the tip were that radius").

use crate::plots;
use crate::release::budget_of;
use geodesic_core::{Basis, Check, CheckContext, CheckError, Dim, Evidence, Quantity};
use geodesic_release::budget::Budget;
use geodesic_release::tipradius::{
    ESTIMATES, McPoint, SimpleInputs, Worst, initial_jerk_m_s3, monte_carlo_at, optimum_radius_m,
    worst_velocity,
};

/// Radii of the Monte Carlo cross-check [mm].
pub const MC_RADII_MM: [f64; 6] = [0.5, 1.0, 2.0, 5.0, 10.0, 20.0];

/// The checks of this family.
pub fn checks() -> Vec<Box<dyn Check>> {
    vec![Box::new(TipRadius)]
}

/// `tip-radius-tradeoff`.
pub struct TipRadius;

/// The simple model's fixed inputs from a budget: its modulus and mass means, the jerk of its
/// mean mechanism under its mean command, 120 MPa and 0.8 um (stated assumptions).
pub fn simple_inputs(budget: &Budget) -> SimpleInputs {
    SimpleInputs {
        e_star_pa: budget.e_star_pa.mean(),
        mass_kg: budget.tm_mass_kg.mean(),
        jerk_m_s3: initial_jerk_m_s3(
            budget.mechanism.mean(),
            geodesic_mechanism::VoltageCommand::ramp(budget.e0_v.mean(), budget.em_v_s.mean()),
        ),
        rupture_pa: 120e6,
        elongation_m: 0.8e-6,
    }
}

/// The curves of the two estimates over 0.05-50 mm, with their names.
pub fn curves(i: &SimpleInputs) -> Vec<(String, Vec<Worst>)> {
    ESTIMATES
        .iter()
        .map(|e| {
            (
                format!("{} ({} N, {} mm/s)", e.name, e.force_n, e.v_rt_m_s * 1e3),
                (0..=120)
                    .map(|k| worst_velocity(i, e, 0.05e-3 * 1000f64.powf(k as f64 / 120.0)))
                    .collect(),
            )
        })
        .collect()
}

/// The Monte Carlo cross-check at [`MC_RADII_MM`] with `n` draws each.
pub fn mc_points(budget: &Budget, n: usize, seed: u64) -> Result<Vec<McPoint>, CheckError> {
    MC_RADII_MM
        .iter()
        .map(|&r| mc_at(budget, radius_m(r), n, seed))
        .collect()
}

/// A radius in millimetres [mm] in metres [m] (one expression for the check and the fidelity
/// table, so that their points are the same numbers).
pub fn radius_m(mm: f64) -> f64 {
    mm * 1e-3
}

/// The points computed so far in this process, by their inputs (the budget, the radius's bits,
/// the draws and the seed).
type Memo = std::collections::HashMap<(String, u64, usize, u64), McPoint>;
static MEMO: std::sync::OnceLock<std::sync::Mutex<Memo>> = std::sync::OnceLock::new();

/// [`monte_carlo_at`], computed once per process for the same inputs: the fidelity table shows
/// the points at 1 and 10 mm that the check has computed (the same function of the same
/// inputs, so the same numbers: 40 000 releases of a `verify` not run twice).
pub fn mc_at(budget: &Budget, r_m: f64, n: usize, seed: u64) -> Result<McPoint, CheckError> {
    let key = (format!("{budget:?}"), r_m.to_bits(), n, seed);
    let memo = MEMO.get_or_init(Default::default);
    if let Some(p) = memo.lock().map_err(|_| poisoned())?.get(&key) {
        return Ok(*p);
    }
    let p = monte_carlo_at(budget, r_m, n, seed).map_err(|e| {
        CheckError::model(
            "tip-radius Monte Carlo",
            format!("tip-radius Monte Carlo at {} mm: {e}", r_m * 1e3),
        )
    })?;
    memo.lock().map_err(|_| poisoned())?.insert(key, p);
    Ok(p)
}

fn poisoned() -> CheckError {
    CheckError::config("tip-radius Monte Carlo: a thread panicked while it held the memo")
}

impl Check for TipRadius {
    fn name(&self) -> &'static str {
        "tip-radius-tradeoff"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["REL-GPRM-VEL"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let budget = budget_of(ctx)?;
        let i = simple_inputs(&budget);
        let n = (ctx.option::<usize>("mc_n")? / 5).max(1000);
        let mc = mc_points(&budget, n, ctx.option::<u64>("seed")?)?;
        let r0 = budget.tip_radius_m.mean();
        let svg = plots::tip_radius_svg(&curves(&i), &mc, r0)?;
        let art = plots::write(&ctx.reports_dir, "tip-radius.svg", &svg)?;
        let opt = optimum_radius_m(&i, &ESTIMATES[0]);
        let at_opt = mc_at(&budget, opt, n, ctx.option::<u64>("seed")?)?;
        let mut ev = Evidence::measured(
            "REL-GPRM-VEL",
            Quantity::new(at_opt.p9973_um_s * 1e-6, Dim::VELOCITY),
            Basis::Illustration,
            format!(
                "What if the tips had the bottom estimate's optimum radius {:.2} mm: release Monte Carlo 99.73 % |X'| ({n} draws, A1 scaled with the contact area x {:.3}); the plot shows both estimates and the Monte Carlo at 0.5-20 mm",
                opt * 1e3,
                at_opt.a1_scale
            ),
        )
        .with_input("jerk_m_s3", i.jerk_m_s3)
        .with_input("mc_n_per_radius", n)
        .with_input("seed", ctx.option::<u64>("seed")?)
        .with_artifact(art);
        for e in &ESTIMATES {
            let o = optimum_radius_m(&i, e);
            ev = ev
                .with_input(&format!("optimum_radius_mm_{}", e.name), o * 1e3)
                .with_input(
                    &format!("worst_at_budget_radius_um_s_{}", e.name),
                    worst_velocity(&i, e, r0).total_m_s * 1e6,
                );
        }
        for p in &mc {
            ev = ev.with_input(
                &format!("mc_p9973_um_s_at_{}_mm", p.radius_m * 1e3),
                p.p9973_um_s,
            );
        }
        Ok(vec![ev])
    }
}

/// The document of `geodesic tip-radius`: the simple model's inputs, each estimate with its
/// optimum and curve, and the Monte Carlo cross-check. Its JSON keys are those the command has
/// always printed (printed through `serde_json::Value`: alphabetical order).
#[derive(Debug, Clone, serde::Serialize, schemars::JsonSchema)]
pub struct TradeOff {
    /// The budget's mean tip radius [mm].
    pub budget_radius_mm: f64,
    /// Initial tip jerk [m/s^3].
    pub jerk_m_s3: f64,
    /// Effective modulus [Pa].
    pub e_star_pa: f64,
    /// TM mass [kg].
    pub mass_kg: f64,
    /// Gold rupture strength [Pa].
    pub rupture_pa: f64,
    /// Bond elongation at rupture [m].
    pub elongation_m: f64,
    /// The two estimates.
    pub estimates: Vec<EstimateRow>,
    /// The Monte Carlo cross-check.
    pub monte_carlo: Vec<McRow>,
    /// Monte Carlo draws per radius.
    pub mc_n: usize,
    /// Seed.
    pub seed: u64,
    /// The input files read, by name (`budget`).
    pub inputs: std::collections::BTreeMap<String, geodesic_core::check::InputFile>,
    #[serde(skip)]
    curves: Vec<(String, Vec<Worst>)>,
    #[serde(skip)]
    mc: Vec<McPoint>,
    #[serde(skip)]
    r0_m: f64,
}

/// One estimate of the simple model.
#[derive(Debug, Clone, serde::Serialize, schemars::JsonSchema)]
pub struct EstimateRow {
    /// Name (`bottom`, `upper`).
    pub estimate: &'static str,
    /// Contact force [N].
    pub force_n: f64,
    /// Constant tip speed [m/s].
    pub v_rt_m_s: f64,
    /// Radius of the least worst-case velocity [mm].
    pub optimum_radius_mm: f64,
    /// Worst-case velocity there [um/s].
    pub at_optimum_um_s: f64,
    /// Worst-case velocity at the budget's radius [um/s].
    pub at_budget_radius_um_s: f64,
    /// Its push part [um/s].
    pub push_at_budget_radius_um_s: f64,
    /// Its adhesion part [um/s].
    pub adhesion_at_budget_radius_um_s: f64,
    /// The curve over 0.05-50 mm.
    pub curve: Vec<CurvePoint>,
}

/// A point of an estimate's curve.
#[derive(Debug, Clone, Copy, serde::Serialize, schemars::JsonSchema)]
pub struct CurvePoint {
    /// Tip radius [mm].
    pub radius_mm: f64,
    /// Push velocity [um/s].
    pub push_um_s: f64,
    /// Adhesion velocity [um/s].
    pub adhesion_um_s: f64,
    /// Sum [um/s].
    pub total_um_s: f64,
}

/// A Monte Carlo point of the cross-check.
#[derive(Debug, Clone, Copy, serde::Serialize, schemars::JsonSchema)]
pub struct McRow {
    /// Mean tip radius [mm].
    pub radius_mm: f64,
    /// 99.73 % point of |X'| [um/s].
    pub p9973_um_s: f64,
    /// Scale applied to A1 [-].
    pub a1_scale: f64,
}

impl TradeOff {
    /// The trade-off of `budget` with the Monte Carlo points `mc` (`mc_n` draws each, `seed`).
    pub fn new(budget: &Budget, mc: &[McPoint], mc_n: usize, seed: u64) -> TradeOff {
        let inputs = simple_inputs(budget);
        let r0 = budget.tip_radius_m.mean();
        let curves = curves(&inputs);
        let estimates = ESTIMATES
            .iter()
            .zip(&curves)
            .map(|(e, (_, w))| {
                let opt = optimum_radius_m(&inputs, e);
                let at_opt = worst_velocity(&inputs, e, opt);
                let at_r0 = worst_velocity(&inputs, e, r0);
                EstimateRow {
                    estimate: e.name,
                    force_n: e.force_n,
                    v_rt_m_s: e.v_rt_m_s,
                    optimum_radius_mm: opt * 1e3,
                    at_optimum_um_s: at_opt.total_m_s * 1e6,
                    at_budget_radius_um_s: at_r0.total_m_s * 1e6,
                    push_at_budget_radius_um_s: at_r0.push_m_s * 1e6,
                    adhesion_at_budget_radius_um_s: at_r0.adhesion_m_s * 1e6,
                    curve: w
                        .iter()
                        .map(|p| CurvePoint {
                            radius_mm: p.radius_m * 1e3,
                            push_um_s: p.push_m_s * 1e6,
                            adhesion_um_s: p.adhesion_m_s * 1e6,
                            total_um_s: p.total_m_s * 1e6,
                        })
                        .collect(),
                }
            })
            .collect();
        TradeOff {
            budget_radius_mm: r0 * 1e3,
            jerk_m_s3: inputs.jerk_m_s3,
            e_star_pa: inputs.e_star_pa,
            mass_kg: inputs.mass_kg,
            rupture_pa: inputs.rupture_pa,
            elongation_m: inputs.elongation_m,
            estimates,
            monte_carlo: mc
                .iter()
                .map(|p| McRow {
                    radius_mm: p.radius_m * 1e3,
                    p9973_um_s: p.p9973_um_s,
                    a1_scale: p.a1_scale,
                })
                .collect(),
            mc_n,
            seed,
            inputs: Default::default(),
            curves,
            mc: mc.to_vec(),
            r0_m: r0,
        }
    }

    /// The document naming an input file it read.
    pub fn with_input(mut self, name: &str, file: geodesic_core::check::InputFile) -> Self {
        self.inputs.insert(name.to_string(), file);
        self
    }

    /// The plot: both estimates' curves, the Monte Carlo points and the budget's radius.
    pub fn svg(&self) -> Result<String, CheckError> {
        plots::tip_radius_svg(&self.curves, &self.mc, self.r0_m)
    }
}
