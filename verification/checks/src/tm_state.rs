//! Checks of the `tm_state` family: `tm-state-bounds` gives, for each row of the TM state
//! requirement (thesis Tab. "TM state requirement") except TMS-Z-VEL (the release Monte Carlo
//! verifies it), the value its source in the capture inputs gives, or why none does. The same
//! [`StateModel`](geodesic_capture::StateModel) feeds CAP-QUARTIC and CAP-RELEASE-PROB, so a
//! TMS row and the capture verdicts never contradict each other.
//!
//! | source of the state (capture inputs) | row |
//! | --- | --- |
//! | release Monte Carlo, or a drift of it (`z`) | `model`: 99.73 % of the Monte Carlo, x drift time |
//! | a drift of a flow-down state (`x` from `vx`) | `flow-down`: the rate's loaded limit x drift time |
//! | a flow-down assumption itself (`vx`, `wz`, ...) | not verified: the assumption cannot verify the requirement it assumes |
//! | an explicit assumption | not verified, its 99.73 % value shown as an illustration |
//!
//! The shear case of thesis ch. 6 (a hypothetical 50 mN tangential pull for 100 us, which the
//! thesis raises to argue against adding shear at the contact) is shown beside TMS-X/Y-VEL and
//! TMS-X/Y-RATE as an illustration, never as a verdict.

use geodesic_capture::{PulseShape, ShearInputs, SourceKind, StateName, StateSource};
use geodesic_core::{Basis, Check, CheckContext, CheckError, Dim, Evidence, Quantity};

use crate::capture::{CaptureSetup, ReleaseVz, ReleaseVzSource, basis_of};

/// The checks of this family; `release` supplies the release Monte Carlo z velocities (`None`:
/// the states that need them are not verified, with that reason).
pub fn checks_with(release: Option<ReleaseVzSource>) -> Vec<Box<dyn Check>> {
    vec![Box::new(TmStateBounds { release })]
}

/// The checks of this family without a release Monte Carlo source (see [`checks_with`]).
pub fn checks() -> Vec<Box<dyn Check>> {
    checks_with(None)
}

/// `tm-state-bounds`: evidence for the 11 TMS rows other than TMS-Z-VEL.
pub struct TmStateBounds {
    /// Source of the release Monte Carlo z velocities.
    pub release: Option<ReleaseVzSource>,
}

fn dim_of(s: StateName) -> Dim {
    match s.unit() {
        "m" => Dim::LENGTH,
        "m/s" => Dim::VELOCITY,
        "rad" => Dim::ANGLE,
        _ => Dim::ANGULAR_RATE,
    }
}

const ACTIVITY: &str = "TM state at the start of DFACS control from the capture inputs' sources.";

fn shear_illustration(s: StateName) -> Option<Evidence> {
    let sh = ShearInputs::THESIS;
    let (value, dim, formula) = match s {
        StateName::Vx | StateName::Vy => (
            sh.velocity_m_s(PulseShape::USED),
            Dim::VELOCITY,
            "dv = dt F / M",
        ),
        StateName::Wx | StateName::Wy => (
            sh.angular_rate_rad_s(PulseShape::USED),
            Dim::ANGULAR_RATE,
            "dw = dt F a / I",
        ),
        _ => return None,
    };
    Some(
        Evidence::measured(
            s.requirement_id(),
            Quantity::new(value, dim),
            Basis::Illustration,
            format!(
                "Illustration (thesis ch. 6 shear what-if, not a prediction): a hypothetical 50 mN \
                 tangential pull for 100 us, rectangular pulse, {formula}; the thesis itself argues \
                 there is no reason to expect it (the nominal retraction is along z)."
            ),
        )
        .with_input("pulse_shape_used", PulseShape::USED.as_str())
        .with_input("dt_s", sh.dt_s)
        .with_input("force_n", sh.force_n)
        .with_input("arm_m", sh.arm_m)
        .with_input("inertia_kg_m2", sh.inertia_kg_m2)
        .with_input("mass_kg", sh.mass_kg)
        .with_input(
            "triangular_pulse_value_si",
            if dim == Dim::VELOCITY {
                sh.velocity_m_s(PulseShape::Triangular)
            } else {
                sh.angular_rate_rad_s(PulseShape::Triangular)
            },
        ),
    )
}

/// Whether a state's source is a drift of the release Monte Carlo's velocity (or the velocity
/// itself): its value is a sampled quantile.
fn kind_needs_sampling(src: &StateSource) -> bool {
    matches!(src, StateSource::Release | StateSource::Drift(_))
}

/// The evidence of one TMS row from the set-up, with the release Monte Carlo when wired; a
/// state from the release Monte Carlo is judged at the requirement's `probability`
/// (`probability`, a fraction) with bounds at `confidence`.
pub fn row_evidence_at(
    setup: &CaptureSetup,
    s: StateName,
    release: Option<&ReleaseVz>,
    probability: Option<f64>,
    confidence: f64,
) -> Vec<Evidence> {
    let id = s.requirement_id();
    let src = &setup.inputs.states[s.index()];
    let kind = setup.model.kind(s);
    let dt = setup.inputs.drift_time_s;
    let mut out = Vec::new();
    let needs_release = matches!(src, StateSource::Release)
        || (matches!(src, StateSource::Drift(_)) && kind == SourceKind::Model);
    let vz9973 = release.map_or(f64::NAN, ReleaseVz::p9973);
    let common = |mut e: Evidence| {
        e.inputs.extend(setup.evidence_inputs());
        e.inputs
            .insert("state_source".into(), src.describe().into());
        e
    };
    if needs_release && release.is_none_or(|r| r.vz_m_s.is_empty()) {
        out.push(common(Evidence::not_verified(
            id,
            format!("{s} comes from the release Monte Carlo, which is not wired or gave no draws"),
            ACTIVITY,
        )));
        return out;
    }
    match (src, kind) {
        (StateSource::FlowDown(f), _) => {
            let why = match s {
                StateName::Wz => format!(
                    "no model gives a rate about z (the contact lies on the z axis, so a pull there \
                     has no lever arm about z); the capture analyses assume Normal(0, {f:.4} x limit), \
                     a flow-down assumption that cannot verify the requirement it assumes"
                ),
                _ => format!(
                    "no model gives {s} at release (the nominal retraction is along z); the capture \
                     analyses assume Normal(0, {f:.4} x limit), a flow-down assumption that cannot \
                     verify the requirement it assumes"
                ),
            };
            out.push(common(Evidence::not_verified(id, why, ACTIVITY)));
        }
        (_, SourceKind::Assumption) => {
            out.push(common(Evidence::not_verified(
                id,
                format!(
                    "{s} is an explicit assumption of the capture inputs ({})",
                    src.describe()
                ),
                ACTIVITY,
            )));
            out.push(common(Evidence::measured(
                id,
                Quantity::new(setup.model.p9973(s, vz9973), dim_of(s)),
                Basis::Illustration,
                "99.73 % value of the assumed distribution (an assumption, not a verdict).",
            )));
        }
        (_, SourceKind::Model) if kind_needs_sampling(src) => {
            // a drift of the release velocity: the requirement's quantile of |vz| with its
            // order-statistic bounds, times the drift time
            let r = release.expect("checked above");
            let Some(p) = probability else {
                out.push(common(Evidence::not_verified(
                    id,
                    format!(
                        "{id} states no `probability`: {s} comes from the release Monte Carlo, and the requirement's probability says which quantile to judge"
                    ),
                    ACTIVITY,
                ).from_inputs(&["budget", "capture"])));
                return out;
            };
            let q = r
                .quantile(p, confidence)
                .expect("draws checked above")
                .scaled(dt);
            let mut e = common(Evidence::measured(
                id,
                Quantity::new(q.estimate, dim_of(s)),
                Basis::Model,
                format!(
                    "Offset after {dt} s of free drift from a centred hold at the {} |vz| of the \
                     release Monte Carlo ({:.4} um/s); hold offset not modelled, plunger \
                     attraction (< 0.1 um/s per the thesis) neglected.",
                    geodesic_core::units::fmt_pct(p),
                    q.estimate / dt * 1e6
                ),
            ))
            .with_sampling(q)
            .from_inputs(&["budget", "capture"])
            .with_input("drift_time_s", dt);
            for (key, val) in &r.inputs {
                e.inputs.insert(format!("release.{key}"), val.clone());
            }
            out.push(e);
        }
        (_, k) => {
            let v = setup.model.p9973(s, vz9973);
            let rate = geodesic_capture::drift_rate_of(s);
            let activity = match (k, rate) {
                (SourceKind::Model, Some(r)) => format!(
                    "Offset after {dt} s of free drift from a centred hold at the 99.73 % |{r}| of \
                     the release Monte Carlo ({:.4} um/s); hold offset not modelled, plunger \
                     attraction (< 0.1 um/s per the thesis) neglected.",
                    vz9973 * 1e6
                ),
                (SourceKind::FlowDown, Some(r)) => format!(
                    "Flow-down: {r} at its 99.73 % value under the flow-down assumption (3 sigma = \
                     the limit of {} read from the loaded requirements) drifting for {dt} s from a \
                     centred hold.",
                    r.requirement_id()
                ),
                _ => "99.73 % value from the release Monte Carlo.".to_string(),
            };
            let mut e = common(Evidence::measured(
                id,
                Quantity::new(v, dim_of(s)),
                basis_of(k),
                activity,
            ))
            .with_input("drift_time_s", dt)
            .from_inputs(&["capture"]);
            // a drift of a flow-down rate takes that rate's requirement as met
            if k == SourceKind::FlowDown
                && let Some(r) = rate
            {
                e = e.assuming([r.requirement_id()]);
            }
            if k == SourceKind::Model {
                e = e.with_input("v_z_p9973_m_s", vz9973);
                if let Some(r) = release {
                    for (key, val) in &r.inputs {
                        e.inputs.insert(format!("release.{key}"), val.clone());
                    }
                }
            }
            out.push(e);
        }
    }
    if let Some(ill) = shear_illustration(s) {
        out.push(ill);
    }
    out
}

/// [`row_evidence_at`] at 99.73 % and the default confidence.
pub fn row_evidence(
    setup: &CaptureSetup,
    s: StateName,
    release: Option<&ReleaseVz>,
) -> Vec<Evidence> {
    row_evidence_at(setup, s, release, Some(0.9973), crate::DEFAULT_CONFIDENCE)
}

impl Check for TmStateBounds {
    fn name(&self) -> &'static str {
        "tm-state-bounds"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &[
            "TMS-X-POS",
            "TMS-Y-POS",
            "TMS-Z-POS",
            "TMS-X-VEL",
            "TMS-Y-VEL",
            "TMS-X-ANG",
            "TMS-Y-ANG",
            "TMS-Z-ANG",
            "TMS-X-RATE",
            "TMS-Y-RATE",
            "TMS-Z-RATE",
        ]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let setup = match CaptureSetup::of(ctx)? {
            Ok(s) => s,
            Err(why) => {
                return Ok(self
                    .verifies()
                    .iter()
                    .map(|id| Evidence::not_verified(id, &why, ACTIVITY))
                    .collect());
            }
        };
        let release = match &self.release {
            Some(src) => Some(src(ctx)?),
            None => None,
        };
        // every state but vz, whose row the release Monte Carlo verifies
        Ok(StateName::ALL
            .iter()
            .filter(|s| **s != StateName::Vz)
            .flat_map(|s| {
                row_evidence_at(
                    &setup,
                    *s,
                    release.as_ref(),
                    ctx.probability(s.requirement_id()),
                    ctx.confidence,
                )
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesic_core::Outcome;
    use std::collections::BTreeMap;
    use std::sync::Arc;

    fn ctx() -> CheckContext {
        crate::builtin_context(crate::scratch_dir(), 100, 1)
    }

    fn source() -> ReleaseVzSource {
        Arc::new(|_| {
            Ok(ReleaseVz {
                vz_m_s: (1..=10_000).map(|k| -(k as f64) * 1e-10).collect(),
                inputs: BTreeMap::new(),
            })
        })
    }

    fn deciding(ev: &[Evidence], id: &str) -> Option<(f64, Basis)> {
        ev.iter()
            .filter(|e| e.requirement == id && e.basis != Some(Basis::Illustration))
            .find_map(|e| match &e.outcome {
                Outcome::Measured(q) => Some((q.value, e.basis.unwrap())),
                Outcome::NotVerified(_) => None,
            })
    }

    #[test]
    fn every_declared_row_has_evidence() {
        let c = TmStateBounds {
            release: Some(source()),
        };
        let ev = c.run(&ctx()).unwrap();
        for id in c.verifies() {
            assert!(ev.iter().any(|e| e.requirement == *id), "{id}");
        }
    }

    #[test]
    fn rows_follow_their_sources() {
        let ev = TmStateBounds {
            release: Some(source()),
        }
        .run(&ctx())
        .unwrap();
        // z: 99.73 % of |vz| = 9973e-10 m/s, times 15 s (model)
        let (z, b) = deciding(&ev, "TMS-Z-POS").unwrap();
        assert!((z - 9973e-10 * 15.0).abs() < 1e-15, "{z}");
        assert_eq!(b, Basis::Model);
        // x: the loaded 5 um/s limit of TMS-X-VEL times 15 s (flow-down)
        let (x, b) = deciding(&ev, "TMS-X-POS").unwrap();
        assert!((x - 75e-6).abs() < 1e-15, "{x}");
        assert_eq!(b, Basis::FlowDown);
        // angles: 100 urad/s x 15 s
        let (a, _) = deciding(&ev, "TMS-Y-ANG").unwrap();
        assert!((a - 1.5e-3).abs() < 1e-15, "{a}");
        // no model: not verified, shear shown as an illustration only
        assert!(deciding(&ev, "TMS-X-VEL").is_none());
        assert!(deciding(&ev, "TMS-X-RATE").is_none());
        assert!(deciding(&ev, "TMS-Z-RATE").is_none());
        assert!(
            ev.iter()
                .any(|e| e.requirement == "TMS-X-RATE" && e.basis == Some(Basis::Illustration))
        );
    }

    #[test]
    fn without_release_the_z_offset_is_not_verified() {
        let ev = TmStateBounds { release: None }.run(&ctx()).unwrap();
        assert!(deciding(&ev, "TMS-Z-POS").is_none());
        assert!(deciding(&ev, "TMS-X-POS").is_some());
    }
}
