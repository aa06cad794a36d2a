//! `release-sensitivity` (issue 14, item 4: "a table and a plot in the report"): an
//! illustration beside REL-GPRM-VEL, never a verdict. What drives the release velocity: the
//! variance-based first-order and total indices of `|v_TM|` for each uncertainty group of the
//! run's budget (`geodesic_release::sensitivity`, Saltelli/Jansen with bootstrap intervals) and
//! the shift of the 99.73 % point when each group is frozen at nominal. The illustrated value is
//! the 99.73 % point with the group of the largest total index frozen: "what if that
//! uncertainty were bought down".

use crate::plots;
use crate::release::budget_of;
use geodesic_core::{Basis, Check, CheckContext, CheckError, Dim, Evidence, Quantity};
use geodesic_release::sensitivity::release_sensitivity;

/// The checks of this family.
pub fn checks() -> Vec<Box<dyn Check>> {
    vec![Box::new(ReleaseSensitivity)]
}

/// `release-sensitivity`.
pub struct ReleaseSensitivity;

/// Draws per sample matrix for a run of `mc_n` Monte Carlo releases: `mc_n / 25`, at least
/// 1 000 (the analysis costs 18 releases per draw: 72 000 at the default 1e5).
pub fn draws_for(mc_n: usize) -> usize {
    (mc_n / 25).max(1000)
}

impl Check for ReleaseSensitivity {
    fn name(&self) -> &'static str {
        "release-sensitivity"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["REL-GPRM-VEL"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let budget = budget_of(ctx)?;
        let n = draws_for(ctx.option::<usize>("mc_n")?);
        let s = release_sensitivity(&budget, n, ctx.option::<u64>("seed")?, &|_| {})
            .map_err(|e| CheckError::model("sensitivity", format!("sensitivity: {e}")))?;
        let svg = plots::sensitivity_svg(&s)?;
        let art = plots::write(&ctx.reports_dir, "release-sensitivity.svg", &svg)?;
        let (top, shift) = s
            .groups
            .iter()
            .max_by(|a, b| a.0.total.total_cmp(&b.0.total))
            .map(|(g, sh)| (g.group.clone(), *sh))
            .ok_or_else(|| CheckError::config("sensitivity: no uncertainty group"))?;
        let sum_first: f64 = s.groups.iter().map(|(g, _)| g.first).sum();
        let mut ev = Evidence::measured(
            "REL-GPRM-VEL",
            Quantity::new((s.p9973_um_s + shift) * 1e-6, Dim::VELOCITY),
            Basis::Illustration,
            format!(
                "What drives |X'|: with '{top}' (largest total index) frozen at nominal the 99.73 % point moves {:+.3} um/s from {:.3} um/s ({n} x 2 draws, Saltelli/Jansen indices; the plot and inputs give every group)",
                shift, s.p9973_um_s
            ),
        )
        .with_input("draws_per_matrix", n)
        .with_input("seed", ctx.option::<u64>("seed")?)
        .with_input("p9973_um_s_all_free", s.p9973_um_s)
        .with_input("sum_first_order", sum_first)
        .with_artifact(art);
        for (g, sh) in &s.groups {
            let key = g.group.replace([',', ' '], "_").replace("__", "_");
            ev = ev
                .with_input(&format!("first_{key}"), g.first)
                .with_input(&format!("total_{key}"), g.total)
                .with_input(&format!("p9973_shift_um_s_{key}"), *sh);
        }
        Ok(vec![ev])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesic_core::Outcome;

    /// The illustration is what its inputs say: an illustration (never a verdict), the value the
    /// all-free 99.73 % point plus the shift of the group with the largest total index, that
    /// group an adhesion side (the thesis's finding), every group's indices in the inputs and
    /// the plot written.
    #[test]
    fn the_illustration_is_recomputable_from_its_inputs() {
        let ctx = crate::builtin_context(crate::scratch_dir(), 25_000, 2);
        let ev = ReleaseSensitivity.run(&ctx).unwrap();
        assert_eq!(ev.len(), 1);
        let e = &ev[0];
        assert_eq!(e.basis, Some(Basis::Illustration));
        let Outcome::Measured(q) = &e.outcome else {
            panic!("not measured")
        };
        let num = |k: &str| e.inputs[k].as_f64().unwrap_or_else(|| panic!("{k}"));
        let groups = [
            "adhesion_side_1",
            "adhesion_side_2",
            "mechanism_1",
            "mechanism_2",
            "command_slope",
            "tip_radii",
            "preload",
        ];
        let top = groups
            .iter()
            .max_by(|a, b| num(&format!("total_{a}")).total_cmp(&num(&format!("total_{b}"))))
            .unwrap();
        assert!(top.starts_with("adhesion"), "largest total index: {top}");
        let want = num("p9973_um_s_all_free") + num(&format!("p9973_shift_um_s_{top}"));
        assert!((q.value * 1e6 - want).abs() < 1e-9, "{} vs {want}", q.value);
        let sum: f64 = groups.iter().map(|g| num(&format!("first_{g}"))).sum();
        assert!((sum - num("sum_first_order")).abs() < 1e-12);
        assert!(
            e.activity
                .contains("(largest total index) frozen at nominal")
        );
        assert!(ctx.reports_dir.join("release-sensitivity.svg").is_file());
    }
}
