//! The capture inputs file (`models/capture/capture.yaml`): the DFACS capture limits `x_LIM`,
//! the drift time to the start of control and, for each of the 12 TM states, where its value
//! comes from ([`StateSource`]). The requirement box `req_i` is not in this file: the caller
//! passes it from the loaded requirements ([`CaptureInputs::xlim`], [`StateModel::new`]), so
//! that a change of a TM state limit moves every capture verdict.
//!
//! [`StateModel`] is the one source of the TM state at the start of control that the capture
//! criterion on the predicted state, the capture probability and the TM state rows all read:
//! they cannot contradict each other.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal, StandardUniform};
use serde::Deserialize;
use serde_saphyr::Spanned;

use crate::criterion::quartic_sum;
use crate::error::CaptureError;
use crate::limits::Xlim;
use crate::probability::CaptureProbability;
use crate::state::{N_STATES, NamedMap, StateName, TmState, named_entries};

/// The repository's capture inputs (embedded copy of `models/capture/capture.yaml`).
pub const DEFAULT_CAPTURE_YAML: &str = include_str!("../capture.yaml");

/// The 99.73 % point of a zero-mean normal in units of its sigma: 3, the convention of the
/// thesis and of the requirements (99.73 % = 3 sigma; the exact two-sided point is 2.99998) [-].
pub const Z_9973: f64 = 3.0;

/// How the `x_LIM` values were obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum XlimDerivation {
    /// Derived to satisfy the consistency constraint: the constraint holds by construction.
    Constraint,
    /// From a source of their own: the constraint is a real check.
    Independent,
}

impl XlimDerivation {
    /// As written in YAML.
    pub fn as_str(self) -> &'static str {
        match self {
            XlimDerivation::Constraint => "constraint",
            XlimDerivation::Independent => "independent",
        }
    }
}

/// Where one TM state at the start of DFACS control comes from.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum StateSource {
    /// The release Monte Carlo (only `vz`).
    Release,
    /// The rate state named here times the drift time, from a centred hold (`x` from `vx`,
    /// `thx` from `wx`, ...).
    Drift(String),
    /// `Normal(0, F * limit)` with the limit of the state's own requirement, read at run time.
    FlowDown(f64),
    /// Always 0 (an explicit assumption).
    Zero,
    /// Always this value [SI] (an explicit assumption).
    Fixed(f64),
    /// Normal(mean, sigma) [SI] (an explicit assumption).
    Normal {
        /// Mean [SI].
        mean: f64,
        /// Standard deviation [SI], >= 0.
        sigma: f64,
    },
    /// Uniform on [min, max) [SI] (an explicit assumption).
    Uniform {
        /// Lower bound [SI].
        min: f64,
        /// Upper bound [SI], >= min.
        max: f64,
    },
}

/// What a state's value rests on (mirrors the verification basis of `geodesic-core`, which this
/// model crate does not depend on).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum SourceKind {
    /// A model output (the release Monte Carlo, or a drift of one).
    Model,
    /// A flow-down of the loaded requirements.
    FlowDown,
    /// An explicit assumption of the inputs file.
    Assumption,
}

impl StateSource {
    /// One-line description for reports.
    pub fn describe(&self) -> String {
        match self {
            StateSource::Release => "release Monte Carlo".into(),
            StateSource::Drift(r) => format!("{r} x drift time from a centred hold"),
            StateSource::FlowDown(f) => {
                format!("flow-down assumption Normal(0, {f:.4} x requirement limit)")
            }
            StateSource::Zero => "assumed zero".into(),
            StateSource::Fixed(v) => format!("assumed fixed at {v:e}"),
            StateSource::Normal { mean, sigma } => {
                format!("assumed Normal({mean:e}, {sigma:e})")
            }
            StateSource::Uniform { min, max } => format!("assumed Uniform({min:e}, {max:e})"),
        }
    }
}

/// The checked capture inputs.
#[derive(Clone, Debug, PartialEq)]
pub struct CaptureInputs {
    /// Capture limits `x_LIM,i` [SI unit of each state].
    pub xlim: [f64; N_STATES],
    /// Box scale factor of the consistency constraint (thesis: 1.4) [-].
    pub box_scale: f64,
    /// How `xlim` was obtained.
    pub derivation: XlimDerivation,
    /// Where `xlim` comes from (free text).
    pub xlim_source: String,
    /// The state whose limit is anchored on an accepted external result, and that result.
    pub anchor: Option<(StateName, String)>,
    /// Release to start of control [s].
    pub drift_time_s: f64,
    /// Source of each state, canonical order.
    pub states: [StateSource; N_STATES],
    /// File the inputs came from.
    pub file: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawInputs {
    xlim: RawXlim,
    drift_time_s: Spanned<f64>,
    states: Spanned<NamedMap<StateSource>>,
    /// The parameters' pedigree (issue 49), read by `geodesic_core::pedigree`, not here.
    #[serde(default, rename = "pedigree")]
    _pedigree: Option<serde::de::IgnoredAny>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawXlim {
    derivation: Spanned<String>,
    source: String,
    #[serde(default)]
    anchor: Option<RawAnchor>,
    box_scale: Spanned<f64>,
    values: Spanned<NamedMap<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawAnchor {
    state: Spanned<String>,
    source: String,
}

fn bad(file: &str, line: u64, name: &str, value: String, cause: &str) -> CaptureError {
    CaptureError::BadValue {
        file: file.to_owned(),
        line,
        name: name.to_owned(),
        value,
        cause: cause.to_owned(),
    }
}

/// The rate state a position or angle drifts from (`x` -> `vx`, `thz` -> `wz`).
pub fn drift_rate_of(s: StateName) -> Option<StateName> {
    use StateName::*;
    Some(match s {
        X => Vx,
        Y => Vy,
        Z => Vz,
        Thx => Wx,
        Thy => Wy,
        Thz => Wz,
        _ => return None,
    })
}

impl CaptureInputs {
    /// The repository's default inputs (embedded copy).
    pub fn default_inputs() -> CaptureInputs {
        CaptureInputs::from_yaml_str(
            DEFAULT_CAPTURE_YAML,
            "<built-in>/models/capture/capture.yaml",
        )
        .expect("embedded capture.yaml is valid (unit-tested)")
    }

    /// Parses and checks a capture inputs file; every error names `file:line`.
    pub fn from_yaml_str(text: &str, file: &str) -> Result<CaptureInputs, CaptureError> {
        let raw: RawInputs =
            serde_saphyr::from_str(text).map_err(|e| CaptureError::yaml(file, &e))?;
        let derivation = match raw.xlim.derivation.value.trim() {
            "constraint" => XlimDerivation::Constraint,
            "independent" => XlimDerivation::Independent,
            other => {
                return Err(bad(
                    file,
                    raw.xlim.derivation.referenced.line(),
                    "xlim.derivation",
                    other.into(),
                    "must be `constraint` or `independent`",
                ));
            }
        };
        let bs = raw.xlim.box_scale.value;
        if !(bs.is_finite() && bs > 0.0) {
            return Err(bad(
                file,
                raw.xlim.box_scale.referenced.line(),
                "xlim.box_scale",
                bs.to_string(),
                "must be finite and positive",
            ));
        }
        let values_line = raw.xlim.values.referenced.line();
        let mut xlim = [f64::NAN; N_STATES];
        for (name, v, line) in named_entries(raw.xlim.values.value, file)? {
            if !(v.is_finite() && v > 0.0) {
                return Err(bad(
                    file,
                    line,
                    &format!("xlim.values.{name}"),
                    v.to_string(),
                    "must be finite and positive",
                ));
            }
            xlim[name.index()] = v;
        }
        if let Some(s) = StateName::ALL.iter().find(|s| xlim[s.index()].is_nan()) {
            return Err(CaptureError::Missing {
                file: file.to_owned(),
                line: values_line,
                section: "xlim.values".into(),
                name: s.to_string(),
            });
        }
        let anchor = match raw.xlim.anchor {
            Some(a) => {
                let s = StateName::parse(a.state.value.trim()).ok_or_else(|| {
                    CaptureError::UnknownState {
                        file: file.to_owned(),
                        line: a.state.referenced.line(),
                        name: a.state.value.clone(),
                    }
                })?;
                Some((s, a.source))
            }
            None => None,
        };
        let dt = raw.drift_time_s.value;
        if !(dt.is_finite() && dt >= 0.0) {
            return Err(bad(
                file,
                raw.drift_time_s.referenced.line(),
                "drift_time_s",
                dt.to_string(),
                "must be finite and >= 0",
            ));
        }
        let states_line = raw.states.referenced.line();
        let mut states: [Option<StateSource>; N_STATES] = Default::default();
        for (name, src, line) in named_entries(raw.states.value, file)? {
            let fail = |cause: &str| {
                bad(
                    file,
                    line,
                    &format!("states.{name}"),
                    format!("{src:?}"),
                    cause,
                )
            };
            let finite = |v: f64| v.is_finite();
            match &src {
                StateSource::Release if name != StateName::Vz => {
                    return Err(fail("only vz comes from the release Monte Carlo"));
                }
                StateSource::Drift(r) => {
                    let want = drift_rate_of(name)
                        .ok_or_else(|| fail("only positions and angles drift"))?;
                    if r.trim() != want.as_str() {
                        return Err(fail(&format!("{name} drifts from {want}, not `{r}`")));
                    }
                }
                StateSource::FlowDown(f) if !(finite(*f) && *f > 0.0) => {
                    return Err(fail("the flow-down fraction must be finite and positive"));
                }
                StateSource::Fixed(v) if !finite(*v) => return Err(fail("must be finite")),
                StateSource::Normal { mean, sigma }
                    if !(finite(*mean) && finite(*sigma) && *sigma >= 0.0) =>
                {
                    return Err(fail("mean and sigma must be finite, sigma >= 0"));
                }
                StateSource::Uniform { min, max }
                    if !(finite(*min) && finite(*max) && max >= min) =>
                {
                    return Err(fail("min and max must be finite, max >= min"));
                }
                _ => {}
            }
            states[name.index()] = Some(src);
        }
        if let Some(s) = StateName::ALL.iter().find(|s| states[s.index()].is_none()) {
            return Err(CaptureError::Missing {
                file: file.to_owned(),
                line: states_line,
                section: "states".into(),
                name: s.to_string(),
            });
        }
        Ok(CaptureInputs {
            xlim,
            box_scale: bs,
            derivation,
            xlim_source: raw.xlim.source,
            anchor,
            drift_time_s: dt,
            states: states.map(|s| s.expect("checked above")),
            file: file.to_owned(),
        })
    }

    /// Reads a capture inputs file from disk.
    pub fn load(path: &std::path::Path) -> Result<CaptureInputs, CaptureError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| CaptureError::Io {
            file: file.clone(),
            cause: e.to_string(),
        })?;
        CaptureInputs::from_yaml_str(&text, &file)
    }

    /// The xlim set tied to a requirement box `req` (from the loaded requirements) [SI].
    pub fn xlim(&self, req: [f64; N_STATES]) -> Xlim {
        Xlim {
            req,
            xlim: self.xlim,
            box_scale: self.box_scale,
            source: self.file.clone(),
        }
    }
}

/// The TM state at the start of control, state by state, as [`CaptureInputs::states`] says:
/// one draw for the capture probability, or the 99.73 % value of each state.
#[derive(Clone, Debug)]
pub struct StateModel {
    /// Source of each state.
    pub states: [StateSource; N_STATES],
    /// Requirement box `req_i` from the loaded requirements [SI].
    pub req: [f64; N_STATES],
    /// Drift time [s].
    pub drift_time_s: f64,
}

impl StateModel {
    /// The model of `inputs` with the requirement box `req` [SI].
    pub fn new(inputs: &CaptureInputs, req: [f64; N_STATES]) -> StateModel {
        StateModel {
            states: inputs.states.clone(),
            req,
            drift_time_s: inputs.drift_time_s,
        }
    }

    /// Only the release z velocity, every other state zero (no drift): for reference tests.
    pub fn vz_only() -> StateModel {
        let mut states: [StateSource; N_STATES] = std::array::from_fn(|_| StateSource::Zero);
        states[StateName::Vz.index()] = StateSource::Release;
        StateModel {
            states,
            req: crate::limits::THESIS_BOX,
            drift_time_s: 0.0,
        }
    }

    /// What the value of state `s` rests on.
    pub fn kind(&self, s: StateName) -> SourceKind {
        match &self.states[s.index()] {
            StateSource::Release => SourceKind::Model,
            StateSource::Drift(_) => {
                drift_rate_of(s).map_or(SourceKind::Assumption, |r| self.kind(r))
            }
            StateSource::FlowDown(_) => SourceKind::FlowDown,
            _ => SourceKind::Assumption,
        }
    }

    /// The weakest basis over all 12 states.
    pub fn weakest_kind(&self) -> SourceKind {
        StateName::ALL
            .map(|s| self.kind(s))
            .into_iter()
            .max()
            .unwrap_or(SourceKind::Model)
    }

    fn sample(&self, s: StateName, vz_m_s: f64, rng: &mut ChaCha8Rng) -> f64 {
        let normal = |rng: &mut ChaCha8Rng| -> f64 { StandardNormal.sample(rng) };
        match &self.states[s.index()] {
            StateSource::Release => vz_m_s,
            StateSource::Drift(_) => f64::NAN, // filled from the rate after the rates are drawn
            StateSource::FlowDown(f) => f * self.req[s.index()] * normal(rng),
            StateSource::Zero => 0.0,
            StateSource::Fixed(v) => *v,
            StateSource::Normal { mean, sigma } => mean + sigma * normal(rng),
            StateSource::Uniform { min, max } => {
                let u: f64 = StandardUniform.sample(rng);
                min + (max - min) * u
            }
        }
    }

    /// Draw `k` of `seed` (ChaCha8 stream `k`: independent of thread count and order), with the
    /// release z velocity `vz_m_s` of that draw.
    pub fn draw(&self, vz_m_s: f64, seed: u64, k: u64) -> TmState {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(k);
        let mut st = TmState::zero();
        for s in StateName::ALL {
            st.set(s, self.sample(s, vz_m_s, &mut rng));
        }
        for s in StateName::ALL {
            if let (StateSource::Drift(_), Some(r)) = (&self.states[s.index()], drift_rate_of(s)) {
                st.set(s, st.get(r) * self.drift_time_s);
            }
        }
        st
    }

    /// The 99.73 % value of |state| [SI], given the release Monte Carlo's 99.73 % |vz|
    /// `vz_p9973_m_s`.
    pub fn p9973(&self, s: StateName, vz_p9973_m_s: f64) -> f64 {
        match &self.states[s.index()] {
            StateSource::Release => vz_p9973_m_s,
            StateSource::Drift(_) => drift_rate_of(s).map_or(f64::NAN, |r| {
                self.p9973(r, vz_p9973_m_s) * self.drift_time_s
            }),
            StateSource::FlowDown(f) => Z_9973 * f * self.req[s.index()],
            StateSource::Zero => 0.0,
            StateSource::Fixed(v) => v.abs(),
            StateSource::Normal { mean, sigma } => mean.abs() + Z_9973 * sigma,
            StateSource::Uniform { min, max } => min.abs().max(max.abs()),
        }
    }

    /// The 99.73 % state (every state at its 99.73 % |value|, see [`StateModel::p9973`]).
    pub fn p9973_state(&self, vz_p9973_m_s: f64) -> TmState {
        TmState(StateName::ALL.map(|s| self.p9973(s, vz_p9973_m_s)))
    }

    /// Capture probability of release draws `vz_m_s` [m/s]: draw `k` takes `vz_m_s[k]` and the
    /// other states from [`StateModel::draw`].
    pub fn capture_probability(
        &self,
        vz_m_s: &[f64],
        xlim: &Xlim,
        seed: u64,
    ) -> CaptureProbability {
        let sums: Vec<f64> = vz_m_s
            .iter()
            .enumerate()
            .map(|(k, &vz)| quartic_sum(xlim, &self.draw(vz, seed, k as u64)))
            .collect();
        CaptureProbability::from_sums(sums, seed)
    }
}

impl Xlim {
    /// The repository's capture limits (`models/capture/capture.yaml`) tied to the thesis's
    /// requirement box [`crate::limits::THESIS_BOX`]: for examples and tests.
    pub fn default_set() -> Xlim {
        CaptureInputs::default_inputs().xlim(crate::limits::THESIS_BOX)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const THESIS_BOX: [f64; N_STATES] = [
        200e-6, 200e-6, 200e-6, 5e-6, 5e-6, 5e-6, 2e-3, 2e-3, 2e-3, 100e-6, 100e-6, 100e-6,
    ];

    #[test]
    fn default_inputs_parse_and_match_the_derivation() {
        let c = CaptureInputs::default_inputs();
        assert_eq!(c.derivation, XlimDerivation::Constraint);
        assert_eq!(c.drift_time_s, 15.0);
        let d = crate::derive_xlim(&THESIS_BOX, 1.4, StateName::Vz, 12e-6).unwrap();
        assert_eq!(d.len(), N_STATES);
        for (i, (x, d)) in c.xlim.iter().zip(&d).enumerate() {
            assert!((x - d).abs() <= 5e-7 * d, "{i}");
        }
    }

    #[test]
    fn drift_states_follow_their_rate_in_the_same_draw() {
        let c = CaptureInputs::default_inputs();
        let m = StateModel::new(&c, THESIS_BOX);
        let s = m.draw(1e-6, 7, 3);
        assert_eq!(s.get(StateName::Z), 15.0 * 1e-6);
        assert_eq!(s.get(StateName::X), 15.0 * s.get(StateName::Vx));
        assert_eq!(s.get(StateName::Thy), 15.0 * s.get(StateName::Wy));
        assert_eq!(m.kind(StateName::Z), SourceKind::Model);
        assert_eq!(m.kind(StateName::X), SourceKind::FlowDown);
        assert_eq!(m.weakest_kind(), SourceKind::FlowDown);
    }

    #[test]
    fn flow_down_scales_with_the_requirement_box() {
        let c = CaptureInputs::default_inputs();
        let mut b = THESIS_BOX;
        let m1 = StateModel::new(&c, b);
        b[StateName::Vx.index()] = 20e-6;
        let m2 = StateModel::new(&c, b);
        let (a, z) = (m1.p9973(StateName::X, 1e-6), m2.p9973(StateName::X, 1e-6));
        // 3 sigma of Normal(0, limit/3) x 15 s = limit x 15 s
        assert!((a / 75e-6 - 1.0).abs() < 1e-12, "{a}");
        assert!((z / 300e-6 - 1.0).abs() < 1e-12, "{z}");
    }

    #[test]
    fn bad_sources_name_their_line() {
        let t = DEFAULT_CAPTURE_YAML;
        let cases = [
            (
                t.replace("x: {drift: vx}", "x: {drift: vy}"),
                "drifts from vx",
            ),
            (t.replace("vx: {flow-down", "vx: release #"), "only vz"),
            (
                t.replace("wz: {flow-down: 0.3333333333333333}", "wz: {flow-down: -1}"),
                "positive",
            ),
            (
                t.replace("derivation: constraint", "derivation: guess"),
                "constraint",
            ),
            (
                t.replace("  wz: {flow-down: 0.3333333333333333}\n", ""),
                "wz",
            ),
        ];
        for (text, want) in cases {
            let e = CaptureInputs::from_yaml_str(&text, "c.yaml")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("c.yaml:") && e.contains(want), "{e}");
        }
    }
}
