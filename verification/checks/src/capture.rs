//! Checks of the `capture` family (thesis ch. 7; physics.md section 6). Every input is read at
//! run time: the requirement box `req_i` from the loaded TM state requirements (`TMS-*`), the
//! capture limits, the drift time and the per-state sources from the capture inputs file
//! (`models/capture/capture.yaml` or `verify --capture FILE`).
//!
//! - `capture-criterion`:
//!   - CAP-QUARTIC: the quartic sum at the corner of the loaded requirement box (flow-down) and
//!     at the predicted 99.73 % TM state of [`StateModel`] (release Monte Carlo for `vz`, drifts,
//!     flow-down assumptions: the basis is the weakest of its states);
//!   - CAP-XLIM-CONSISTENCY: `|sum_i (box_scale req_i / xlim_i)^4 - 1|` with the loaded box. When
//!     the inputs say xlim was derived from this constraint, it holds by construction and the
//!     residual only shows whether the loaded box is still the one xlim was derived for;
//!   - CAP-VZ-SINGLE: the single-state z-velocity limit, accepted from the E2E result the
//!     inputs cite (the thesis's 12 um/s): basis `accepted`.
//! - `capture-probability`: CAP-RELEASE-PROB, the fraction of release Monte Carlo draws whose
//!   12 states (from the same [`StateModel`] as the TMS rows) satisfy the criterion.
//!
//! [`CaptureSetup`] is the shared set-up, also used by the `tm_state` family.

use std::collections::BTreeMap;
use std::sync::Arc;

use geodesic_capture::{
    CaptureInputs, N_STATES, SourceKind, StateModel, StateName, StateSource, Xlim, XlimDerivation,
    box_corner, consistency_residual, consistency_sum, max_box_scale, quartic_sum,
    single_state_limits,
};
use geodesic_core::check::Sampling;
use geodesic_core::requirement::Op;
use geodesic_core::{Basis, Check, CheckContext, CheckError, Dim, Evidence, Quantity};
use serde_json::{Value, json};

/// Release Monte Carlo z velocities [m/s] with the inputs that produced them (N, seed, case,
/// budget file, ...), as a check needs them.
#[derive(Clone, Debug, Default)]
pub struct ReleaseVz {
    /// One z velocity per release draw [m/s] (signed or absolute: the criterion uses x^4).
    pub vz_m_s: Vec<f64>,
    /// Inputs of the release Monte Carlo, copied into the evidence.
    pub inputs: BTreeMap<String, Value>,
}

impl ReleaseVz {
    /// 99.73 % of |vz| (nearest rank) [m/s]; NaN when empty.
    pub fn p9973(&self) -> f64 {
        abs_p9973(&self.vz_m_s)
    }

    /// The `p` quantile of |vz| [m/s] with its order-statistic bounds at `confidence`; `None`
    /// when there are no draws.
    pub fn quantile(&self, p: f64, confidence: f64) -> Option<Sampling> {
        if self.vz_m_s.is_empty() {
            return None;
        }
        let mut a: Vec<f64> = self.vz_m_s.iter().map(|v| v.abs()).collect();
        a.sort_by(f64::total_cmp);
        Some(Sampling::quantile(&a, p, confidence))
    }
}

/// The TM state requirements a state model takes as met: those of the states drawn from a
/// flow-down assumption (`Normal(0, F x limit)`), directly or through a drift.
pub fn assumed_rows(setup: &CaptureSetup) -> Vec<String> {
    StateName::ALL
        .iter()
        .filter(|s| matches!(setup.inputs.states[s.index()], StateSource::FlowDown(_)))
        .map(|s| s.requirement_id().to_string())
        .collect()
}

/// Whether xlim was derived from the loaded requirement box (derivation `constraint` and the
/// consistency residual at the precision of the stored values): then the box corner's quartic
/// sum is `1 / box_scale^4` and the consistency holds by construction.
pub fn derived_from_this_box(setup: &CaptureSetup) -> bool {
    setup.inputs.derivation == XlimDerivation::Constraint
        && consistency_residual(&setup.xlim) <= 1e-5
}

/// 99.73 % quantile of `|v|` (nearest rank); NaN for an empty slice.
pub fn abs_p9973(v: &[f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let mut a: Vec<f64> = v.iter().map(|v| v.abs()).collect();
    a.sort_by(f64::total_cmp);
    let idx = ((0.9973 * a.len() as f64).ceil() as usize).clamp(1, a.len()) - 1;
    a[idx]
}

/// Supplies the release Monte Carlo z velocities for a run (memoise inside if several checks
/// share it).
pub type ReleaseVzSource =
    Arc<dyn Fn(&CheckContext) -> Result<ReleaseVz, CheckError> + Send + Sync>;

/// The checks of this family. `release` supplies the release Monte Carlo z velocities; `None`
/// leaves what needs them not-verified with that reason.
pub fn checks_with(release: Option<ReleaseVzSource>) -> Vec<Box<dyn Check>> {
    vec![
        Box::new(CaptureCriterion {
            release: release.clone(),
        }),
        Box::new(CaptureProbabilityCheck { release }),
    ]
}

/// The checks of this family, without a release Monte Carlo source (see [`checks_with`]).
pub fn checks() -> Vec<Box<dyn Check>> {
    checks_with(None)
}

/// The requirement box `req_i` [SI] from the loaded TMS requirements, or why it cannot be had
/// (a TMS row missing, or not an upper bound).
pub fn requirement_box(reqs: &geodesic_core::Requirements) -> Result<[f64; N_STATES], String> {
    let mut out = [f64::NAN; N_STATES];
    for s in StateName::ALL {
        let id = s.requirement_id();
        let r = reqs
            .get(id)
            .ok_or_else(|| format!("{id} is not in the loaded requirements: no requirement box"))?;
        let Some(l) = &r.limit else {
            return Err(format!(
                "{id} is a qualitative requirement (no limit): no requirement box"
            ));
        };
        let positive = l.value.value.is_finite() && l.value.value > 0.0;
        if !matches!(l.op, Op::Le | Op::Lt) || !positive {
            return Err(format!(
                "{id} is not a positive upper bound (`{}`): no requirement box",
                l.text
            ));
        }
        out[s.index()] = l.value.value;
    }
    Ok(out)
}

/// What the capture checks and the TMS rows share for one run.
#[derive(Clone, Debug)]
pub struct CaptureSetup {
    /// The parsed capture inputs file.
    pub inputs: CaptureInputs,
    /// The requirement box from the loaded requirements [SI].
    pub req: [f64; N_STATES],
    /// xlim tied to that box.
    pub xlim: Xlim,
    /// The source of each state at the start of control.
    pub model: StateModel,
    /// Label and SHA-256 of the capture inputs file.
    pub file: (String, String),
}

impl CaptureSetup {
    /// The set-up of `ctx`: `Err` for a bad inputs file (a run error), `Ok(Err(reason))` when
    /// the requirement box cannot be formed (the checks are then not verified).
    pub fn of(ctx: &CheckContext) -> Result<Result<CaptureSetup, String>, CheckError> {
        let f = &ctx.inputs.file("capture")?;
        let inputs = CaptureInputs::from_yaml_str(&f.text, &f.label)
            .map_err(|e| CheckError::input(e.to_string()))?;
        let req = match requirement_box(&ctx.requirements) {
            Ok(r) => r,
            Err(why) => return Ok(Err(why)),
        };
        Ok(Ok(CaptureSetup {
            xlim: inputs.xlim(req),
            model: StateModel::new(&inputs, req),
            req,
            file: (f.label.clone(), f.sha256.clone()),
            inputs,
        }))
    }

    /// Inputs recorded with the evidence: the capture file and its hash, the box.
    pub fn evidence_inputs(&self) -> BTreeMap<String, Value> {
        let mut m = BTreeMap::new();
        m.insert("capture_file".into(), json!(self.file.0));
        m.insert("capture_sha256".into(), json!(self.file.1));
        m.insert("box_scale".into(), json!(self.inputs.box_scale));
        m.insert(
            "xlim_derivation".into(),
            json!(self.inputs.derivation.as_str()),
        );
        let boxv: BTreeMap<&str, f64> = StateName::ALL
            .iter()
            .map(|s| (s.as_str(), self.req[s.index()]))
            .collect();
        m.insert("requirement_box_si".into(), json!(boxv));
        m
    }

    /// Per-state sources, for the evidence.
    pub fn sources(&self) -> BTreeMap<&'static str, String> {
        StateName::ALL
            .iter()
            .map(|s| (s.as_str(), self.inputs.states[s.index()].describe()))
            .collect()
    }
}

/// The verification basis of a state-model kind.
pub fn basis_of(k: SourceKind) -> Basis {
    match k {
        SourceKind::Model => Basis::Model,
        SourceKind::FlowDown => Basis::FlowDown,
        SourceKind::Assumption => Basis::Illustration,
    }
}

fn not_verified(ids: &[&str], why: &str) -> Vec<Evidence> {
    ids.iter()
        .map(|id| Evidence::not_verified(id, why, "Capture analysis."))
        .collect()
}

/// `capture-criterion`: CAP-QUARTIC, CAP-XLIM-CONSISTENCY and CAP-VZ-SINGLE.
pub struct CaptureCriterion {
    /// Source of the release z velocities (for the predicted-state evidence of CAP-QUARTIC).
    pub release: Option<ReleaseVzSource>,
}

impl CaptureCriterion {
    /// The evidence of a set-up, with the release Monte Carlo's 99.73 % |vz| when there is one
    /// (its bounds at the default confidence, see [`CaptureCriterion::evidence_at`]).
    pub fn evidence(setup: &CaptureSetup, release: Option<&ReleaseVz>) -> Vec<Evidence> {
        Self::evidence_at(setup, release, crate::DEFAULT_CONFIDENCE)
    }

    /// The evidence of a set-up; the predicted state takes vz at the upper `confidence` bound
    /// of the release Monte Carlo's 99.73 % |vz|.
    pub fn evidence_at(
        setup: &CaptureSetup,
        release: Option<&ReleaseVz>,
        confidence: f64,
    ) -> Vec<Evidence> {
        let x = &setup.xlim;
        let common = |mut e: Evidence| {
            e.inputs.extend(setup.evidence_inputs());
            e
        };
        let corner = quartic_sum(x, &box_corner(x, 1.0));
        let derived = derived_from_this_box(setup);
        let mut box_ev = Evidence::measured(
            "CAP-QUARTIC",
            Quantity::new(corner, Dim::DIMENSIONLESS),
            Basis::FlowDown,
            "Quartic sum at the corner of the TM state requirement box (every state at the \
             limit of its loaded TMS requirement) with the capture limits xlim.",
        )
        .with_input("max_box_scale", max_box_scale(x))
        .from_inputs(&["capture"]);
        if derived {
            box_ev = box_ev.by_construction(format!(
                "xlim was derived from this very requirement box scaled by {} (capture inputs, derivation: constraint), so the corner's sum is 1/{}^4 = {} whatever the box; it shows only that the box is still the one xlim was derived for",
                setup.inputs.box_scale,
                setup.inputs.box_scale,
                geodesic_core::units::fmt_num(setup.inputs.box_scale.powi(-4))
            ));
        }
        let mut out = vec![common(box_ev)];
        if let Some(r) = release {
            let q = r.quantile(0.9973, confidence);
            match q.as_ref().and_then(|q| q.upper.map(|u| (q, u))) {
                Some((q, vz)) => {
                    let state = setup.model.p9973_state(vz);
                    let sum = quartic_sum(x, &state);
                    let mut e = common(
                        Evidence::measured(
                            "CAP-QUARTIC",
                            Quantity::new(sum, Dim::DIMENSIONLESS),
                            basis_of(setup.model.weakest_kind()),
                            format!(
                                "Quartic sum at the predicted TM state, every state at its 99.73 % \
                                 value from its source (vz: the upper {} bound of the release Monte \
                                 Carlo's 99.73 % |vz|, {:.4} um/s, estimate {:.4} um/s; positions \
                                 and angles: rate x {} s; others: the capture inputs' assumptions).",
                                geodesic_core::units::fmt_pct(confidence),
                                vz * 1e6,
                                q.estimate * 1e6,
                                setup.inputs.drift_time_s
                            ),
                        )
                        .with_input("state_p9973_si", json!(state.0))
                        .with_input("state_sources", json!(setup.sources()))
                        .assuming(assumed_rows(setup))
                        .from_inputs(&["budget", "capture"]),
                    );
                    for (k, v) in &r.inputs {
                        e.inputs.insert(format!("release.{k}"), v.clone());
                    }
                    out.push(e);
                }
                None => out.push(common(
                    Evidence::not_verified(
                        "CAP-QUARTIC",
                        format!(
                            "the predicted state needs the upper {} bound of the release Monte Carlo's 99.73 % |vz|, which N = {} cannot give (N >= {})",
                            geodesic_core::units::fmt_pct(confidence),
                            r.vz_m_s.len(),
                            geodesic_util::stats::min_n(0.9973, confidence)
                        ),
                        "Quartic sum at the predicted TM state.",
                    )
                    .from_inputs(&["budget", "capture"]),
                )),
            }
        }
        let by_construction = setup.inputs.derivation == XlimDerivation::Constraint;
        let mut xe = common(
            Evidence::measured(
                "CAP-XLIM-CONSISTENCY",
                Quantity::new(consistency_residual(x), Dim::DIMENSIONLESS),
                if by_construction {
                    Basis::FlowDown
                } else {
                    Basis::Accepted
                },
                if by_construction {
                    "By construction (inspection): xlim was derived to satisfy this constraint; \
                     the residual with the loaded requirement box shows whether the box is still \
                     the one xlim was derived for."
                        .to_string()
                } else {
                    format!(
                        "Constraint evaluated on independent capture limits ({}) with the loaded \
                         requirement box.",
                        setup.inputs.xlim_source
                    )
                },
            )
            .with_input("consistency_sum", consistency_sum(x))
            .with_input("xlim_source", setup.inputs.xlim_source.clone())
            .from_inputs(&["capture"]),
        );
        if by_construction {
            xe = xe.by_construction(
                "xlim was derived to satisfy this constraint (capture inputs, derivation: constraint): the residual is the rounding of the stored values while the loaded box is the one xlim was derived for",
            );
        }
        out.push(xe);
        let vz = single_state_limits(x)[StateName::Vz.index()];
        let cited = match &setup.inputs.anchor {
            Some((StateName::Vz, src)) => src.clone(),
            _ => setup.inputs.xlim_source.clone(),
        };
        let mut ve = Evidence::measured(
            "CAP-VZ-SINGLE",
            Quantity::new(vz, Dim::VELOCITY),
            Basis::Accepted,
            format!(
                "Accepted: the single-state z-velocity limit of the capture limits (= xlim_vz), \
                 taken from a cited DFACS result ({cited}), not computed by a geodesic model."
            ),
        )
        .with_input("accepted_from", cited)
        .from_inputs(&["capture"]);
        if matches!(setup.inputs.anchor, Some((StateName::Vz, _))) {
            ve = ve.by_construction(
                "the single-state limit is xlim_vz itself, set from the same E2E result the requirement states: the row compares that value with itself",
            );
        }
        out.push(common(ve));
        out
    }
}

impl Check for CaptureCriterion {
    fn name(&self) -> &'static str {
        "capture-criterion"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["CAP-QUARTIC", "CAP-XLIM-CONSISTENCY", "CAP-VZ-SINGLE"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let setup = match CaptureSetup::of(ctx)? {
            Ok(s) => s,
            Err(why) => return Ok(not_verified(self.verifies(), &why)),
        };
        let release = match &self.release {
            Some(src) => Some(src(ctx)?),
            None => None,
        };
        let mut ev = CaptureCriterion::evidence_at(&setup, release.as_ref(), ctx.confidence);
        let svg = crate::plots::capture_criterion_svg(&setup.xlim)?;
        let file = crate::plots::write(&ctx.reports_dir, "capture-criterion.svg", &svg)?;
        if let Some(q) = ev.iter_mut().find(|e| e.requirement == "CAP-QUARTIC") {
            q.artifacts.push(file);
        }
        Ok(ev)
    }
}

/// `capture-probability`: CAP-RELEASE-PROB from the release Monte Carlo z velocities.
pub struct CaptureProbabilityCheck {
    /// Source of the release z velocities; `None`: not-verified.
    pub release: Option<ReleaseVzSource>,
}

/// CAP-RELEASE-PROB evidence: draw `k` takes the release z velocity `release.vz_m_s[k]` and the
/// other states from the set-up's [`StateModel`] (stream `k` of `seed`); the basis is the
/// weakest of the states' sources. The fraction captured carries its Clopper-Pearson bounds at
/// `confidence` ([`Sampling::proportion`]) against the probability `probability` the
/// requirement asks for (its limit): the matrix decides by the lower bound.
pub fn capture_probability_evidence(
    setup: &CaptureSetup,
    release: &ReleaseVz,
    seed: u64,
    probability: f64,
    confidence: f64,
) -> Evidence {
    if release.vz_m_s.is_empty() {
        return Evidence::not_verified(
            "CAP-RELEASE-PROB",
            "the release Monte Carlo gave no z velocities",
            "Capture probability of the release Monte Carlo.",
        );
    }
    let p = setup
        .model
        .capture_probability(&release.vz_m_s, &setup.xlim, seed);
    let mut e = Evidence::measured(
        "CAP-RELEASE-PROB",
        Quantity::new(p.probability, Dim::DIMENSIONLESS),
        basis_of(setup.model.weakest_kind()),
        format!(
            "Fraction of {} release Monte Carlo draws captured by the quartic criterion: vz from \
             the release model, the other states from the capture inputs' sources (the same as \
             the TMS rows: {}).",
            p.n,
            StateName::ALL
                .iter()
                .map(|s| format!("{s}: {}", setup.inputs.states[s.index()].describe()))
                .collect::<Vec<_>>()
                .join("; ")
        ),
    )
    .with_sampling(Sampling::proportion(
        p.captured as u64,
        p.n as u64,
        probability,
        confidence,
    ))
    .assuming(assumed_rows(setup))
    .from_inputs(&["budget", "capture"])
    .with_input("n", p.n)
    .with_input("captured", p.captured)
    .with_input("quartic_sum_p9973", p.sum_p9973)
    .with_input("quartic_sum_max", p.sum_max)
    .with_input("state_seed", p.seed)
    .with_input("state_sources", json!(setup.sources()));
    e.inputs.extend(setup.evidence_inputs());
    for (k, v) in &release.inputs {
        e.inputs.insert(format!("release.{k}"), v.clone());
    }
    e
}

impl Check for CaptureProbabilityCheck {
    fn name(&self) -> &'static str {
        "capture-probability"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["CAP-RELEASE-PROB"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let setup = match CaptureSetup::of(ctx)? {
            Ok(s) => s,
            Err(why) => return Ok(not_verified(self.verifies(), &why)),
        };
        let Some(source) = &self.release else {
            return Ok(not_verified(
                self.verifies(),
                "no release Monte Carlo z velocities are wired into capture-probability",
            ));
        };
        // the probability to show is the limit; a `probability` that says otherwise is refused
        let req = ctx.requirements.get("CAP-RELEASE-PROB");
        let limit = req
            .and_then(|r| r.limit.as_ref())
            .map(|l| l.value.value)
            .filter(|l| *l > 0.0 && *l < 1.0);
        let Some(limit) = limit else {
            return Ok(not_verified(
                self.verifies(),
                "CAP-RELEASE-PROB's limit is not a probability between 0 and 1",
            ));
        };
        if let Some(p) = req.and_then(|r| r.probability_value)
            && (p - limit).abs() > 1e-9
        {
            return Ok(not_verified(
                self.verifies(),
                &format!(
                    "CAP-RELEASE-PROB states probability {} but its limit asks for {}: which one the capture probability must show is ambiguous",
                    geodesic_core::units::fmt_pct(p),
                    geodesic_core::units::fmt_pct(limit)
                ),
            ));
        }
        let release = source(ctx)?;
        Ok(vec![capture_probability_evidence(
            &setup,
            &release,
            ctx.option::<u64>("seed")?,
            limit,
            ctx.confidence,
        )])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesic_core::Outcome;

    fn ctx() -> CheckContext {
        crate::builtin_context(crate::scratch_dir(), 1000, 3)
    }

    fn value(e: &Evidence) -> f64 {
        match &e.outcome {
            Outcome::Measured(q) => q.value,
            Outcome::NotVerified(r) => panic!("not verified: {r}"),
        }
    }

    fn release(v: f64, n: usize) -> ReleaseVz {
        ReleaseVz {
            vz_m_s: vec![v; n],
            inputs: BTreeMap::from([("n".to_string(), json!(n))]),
        }
    }

    #[test]
    fn criterion_evidence_for_the_default_inputs() {
        let setup = CaptureSetup::of(&ctx()).unwrap().unwrap();
        let ev = CaptureCriterion::evidence(&setup, Some(&release(1e-6, 2000)));
        let ids: Vec<&str> = ev.iter().map(|e| e.requirement.as_str()).collect();
        assert_eq!(
            ids,
            [
                "CAP-QUARTIC",
                "CAP-QUARTIC",
                "CAP-XLIM-CONSISTENCY",
                "CAP-VZ-SINGLE"
            ]
        );
        assert!((value(&ev[0]) - 1.0 / 1.4f64.powi(4)).abs() < 1e-6);
        // the predicted state has vz = 1 um/s and z = 15 um instead of the box's 5 um/s, 200 um
        assert!(value(&ev[1]) < value(&ev[0]));
        assert_eq!(ev[1].basis, Some(Basis::FlowDown));
        assert!(value(&ev[2]) < 1e-6);
        assert_eq!(value(&ev[3]), 12e-6);
        assert_eq!(ev[3].basis, Some(Basis::Accepted));
        // what holds by construction says so
        assert!(ev[0].by_construction.is_some() && ev[2].by_construction.is_some());
        assert!(ev[3].by_construction.is_some());
        // the predicted state assumes the flow-down states' rows
        assert_eq!(
            ev[1].assumes,
            [
                "TMS-X-VEL",
                "TMS-Y-VEL",
                "TMS-X-RATE",
                "TMS-Y-RATE",
                "TMS-Z-RATE"
            ]
        );
        // too few draws for the bound: that piece says so, the box corner still decides
        let ev = CaptureCriterion::evidence(&setup, Some(&release(1e-6, 10)));
        assert!(matches!(&ev[1].outcome, Outcome::NotVerified(w) if w.contains("N >= 1109")));
    }

    #[test]
    fn a_loosened_box_is_no_longer_by_construction() {
        let mut c = ctx();
        let mut reqs = (*c.requirements).clone();
        let r = reqs
            .items
            .iter_mut()
            .find(|r| r.id.as_str() == "TMS-X-RATE")
            .unwrap();
        r.limit.as_mut().unwrap().value.value = 200e-6;
        c.requirements = Arc::new(reqs);
        let setup = CaptureSetup::of(&c).unwrap().unwrap();
        let ev = CaptureCriterion::evidence(&setup, None);
        assert!(ev[0].by_construction.is_none());
        assert!(value(&ev[1]) > 1e-3, "the residual shows the box moved");
    }

    #[test]
    fn a_looser_requirement_moves_the_capture_verdicts() {
        let mut c = ctx();
        let mut reqs = (*c.requirements).clone();
        let r = reqs
            .items
            .iter_mut()
            .find(|r| r.id.as_str() == "TMS-X-VEL")
            .unwrap();
        r.limit.as_mut().unwrap().value.value = 20e-6;
        c.requirements = Arc::new(reqs);
        let setup = CaptureSetup::of(&c).unwrap().unwrap();
        let ev = CaptureCriterion::evidence(&setup, None);
        // (20/13.14641)^4 alone exceeds 1
        assert!(value(&ev[0]) > 5.0, "{}", value(&ev[0]));
        assert!(value(&ev[1]) > 0.1, "{}", value(&ev[1]));
    }

    #[test]
    fn missing_box_row_is_not_verified() {
        let mut c = ctx();
        let mut reqs = (*c.requirements).clone();
        reqs.items.retain(|r| r.id.as_str() != "TMS-Y-RATE");
        c.requirements = Arc::new(reqs);
        let ev = CaptureCriterion { release: None }.run(&c).unwrap();
        for e in &ev {
            let Outcome::NotVerified(why) = &e.outcome else {
                panic!("{e:?}")
            };
            assert!(why.contains("TMS-Y-RATE"), "{why}");
        }
    }

    #[test]
    fn unwired_probability_is_not_verified() {
        let ev = CaptureProbabilityCheck { release: None }
            .run(&ctx())
            .unwrap();
        assert!(matches!(ev[0].outcome, Outcome::NotVerified(_)));
    }

    #[test]
    fn wired_probability_uses_the_source() {
        let source: ReleaseVzSource = Arc::new(|_| Ok(release(1e-6, 99)));
        let ev = CaptureProbabilityCheck {
            release: Some(source),
        }
        .run(&ctx())
        .unwrap();
        assert!(value(&ev[0]) > 0.9);
        assert_eq!(ev[0].inputs["release.n"], json!(99));
        assert_eq!(ev[0].basis, Some(Basis::FlowDown));
    }

    #[test]
    fn p9973_nearest_rank() {
        let v: Vec<f64> = (1..=10_000).map(f64::from).collect();
        assert_eq!(abs_p9973(&v), 9973.0);
        assert!(abs_p9973(&[]).is_nan());
    }
}
