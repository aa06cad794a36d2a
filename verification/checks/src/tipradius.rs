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
    let p = monte_carlo_at(budget, r_m, n, seed)
        .map_err(|e| CheckError(format!("tip-radius Monte Carlo at {} mm: {e}", r_m * 1e3)))?;
    memo.lock().map_err(|_| poisoned())?.insert(key, p);
    Ok(p)
}

fn poisoned() -> CheckError {
    CheckError("tip-radius Monte Carlo: a thread panicked while it held the memo".into())
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
        let n = (ctx.mc_n / 5).max(1000);
        let mc = mc_points(&budget, n, ctx.seed)?;
        let r0 = budget.tip_radius_m.mean();
        let svg = plots::tip_radius_svg(&curves(&i), &mc, r0)?;
        let art = plots::write(&ctx.reports_dir, "tip-radius.svg", &svg)?;
        let opt = optimum_radius_m(&i, &ESTIMATES[0]);
        let at_opt = mc_at(&budget, opt, n, ctx.seed)?;
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
        .with_input("seed", ctx.seed)
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
