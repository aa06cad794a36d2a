//! The measurement scenarios (interface.md `scenario:`): what the identification engine
//! (`geodesic-fit`) asks of a scenario, as a trait this crate implements once per scenario, and
//! the one registry that resolves a dataset's `scenario:` string.
//!
//! The engine names no scenario: it reads a dataset's channels and known constants, builds the
//! minimal model, prepares the record, tunes its search, synthesises records, holds the values a
//! model's exact symmetries leave free and reports the identifiable combinations through
//! [`ScenarioSpec`]. A scenario is a unit type implementing it, listed in [`registry`], with a
//! handle constant on [`Scenario`] that effects and tests name (`Scenario::TmmfRelease`).
//! docs/scenario.md, "Adding a scenario", says what to write.

use std::collections::BTreeMap;

use crate::profile::TipProfile;

/// The simulators of this crate a scenario's models are evaluated by (`Model::predict`): a
/// scenario reuses one, or adds one here and its branch in `predict.rs`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dynamics {
    /// The TM mock-up driven by the measured tip motion through force effects
    /// (`tmmf::simulate`, physics.md section 4).
    TmRelease,
    /// The release-tip mechanism, a linear ODE configured by mechanism effects
    /// (`predict::retraction`, physics.md section 5).
    TipMechanism,
}

/// The multi-start search's effort for a scenario's fits (the engine's successive halving,
/// `geodesic-fit`'s `estimate::search`). Fixed per scenario: deterministic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchHints {
    /// Successive-halving stages after screening: (iterations, starts kept for the next stage).
    pub stages: [(usize, usize); 2],
    /// Levenberg-Marquardt iterations of the refinement runs.
    pub refine_iterations: usize,
    /// The time window of each stage, as a fraction of the record after the trigger.
    pub windows: [f64; 2],
    /// Also run the stages on the whole record from the starts that fit it best, and refine
    /// the survivors of both.
    pub stages_on_whole_record: bool,
}

/// Defaults of `geodesic synth` for a scenario: the public examples' sampling and noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SynthDefaults {
    /// Known constants (name, value [SI]).
    pub known: &'static [(&'static str, f64)],
    /// White noise per channel (name, 1-sigma [SI]).
    pub noise: &'static [(&'static str, f64)],
    /// Sampling frequency [Hz].
    pub fs_hz: f64,
    /// Record before the trigger [s].
    pub pre_s: f64,
    /// Record after the trigger [s].
    pub post_s: f64,
}

/// Values a scenario's fits hold because the model has exact symmetries the record cannot
/// break (issue 33: the retraction's scaling), each known to `relative_sigma`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Holds {
    /// The effect a model must contain for the symmetries to exist.
    pub requires_effect: &'static str,
    /// The parameters the symmetries move: a user who fixes or bounds one of them chooses the
    /// holds (none is added).
    pub moved: &'static [&'static str],
    /// The parameters held at their nominal values, in order, each with why.
    pub held: &'static [(&'static str, &'static str)],
    /// Relative 1-sigma of a held value.
    pub relative_sigma: f64,
}

/// A product of powers of parameters that a scenario's records identify although the
/// parameters themselves are not (its exact symmetries leave it unchanged).
#[derive(Debug, Clone, PartialEq)]
pub struct CombinationSpec {
    /// Name in the fit object (`d0`).
    pub name: &'static str,
    /// Unit of the value.
    pub unit: &'static str,
    /// Its definition in words.
    pub formula: &'static str,
    /// Constant factor (a known constant, or 1).
    pub constant: f64,
    /// Exponent of each full parameter name.
    pub exponents: Vec<(&'static str, f64)>,
}

/// What a scenario's records look like, whose effects the catalogue's `code` uses when
/// `discover --scaffold` writes a new force term for it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaffoldForce {
    /// The [`Role`](crate::effects::Role) variant of a scaffolded force term (`Force`,
    /// `Mechanism`): the effect implements the capability trait of that name followed by
    /// `Effect`.
    pub kind: &'static str,
    /// The `effects` item its code needs beyond `Effect, FitHints, GuessContext, ParamSpec, Role,
    /// Scenario` and its capability trait (`TmState`, `RtConfig`).
    pub import: &'static str,
    /// Whether a restoring force has its own equilibrium (`x_eq`) as a parameter.
    pub equilibrium: bool,
    /// The restoring force (`position` term) in words.
    pub position_law: &'static str,
    /// The damping (`velocity` term) in words.
    pub velocity_law: &'static str,
    /// The method that implements the restoring force (`p[0]` its frequency `f0` [Hz], `p[1]`
    /// its equilibrium when `equilibrium`).
    pub position_code: &'static str,
    /// The method that implements the damping (`p[0]` its rate `gamma` [1/s]).
    pub velocity_code: &'static str,
}

/// A measurement scenario: everything the identification engine must know about it.
pub trait ScenarioSpec: Send + Sync + 'static {
    /// Name in datasets and JSON (`tmmf-release`).
    fn name(&self) -> &'static str;
    /// The name of its handle constant on [`Scenario`] (`TmmfRelease`), for generated code.
    fn handle_name(&self) -> &'static str;
    /// The simulator its models run on.
    fn dynamics(&self) -> Dynamics;
    /// The data channels it needs.
    fn required_channels(&self) -> &'static [&'static str];
    /// The channels a dataset may declare: those it needs, then the optional ones.
    fn channels(&self) -> &'static [&'static str];
    /// The channel the model predicts and the fit compares with.
    fn fitted_channel(&self) -> &'static str;
    /// The `known` constants it needs.
    fn required_known(&self) -> &'static [&'static str];
    /// The minimal model (the effects every model contains).
    fn base_effects(&self) -> &'static [&'static str];
    /// Preparation: the measured channel that drives the model through a smooth tip profile
    /// fitted to it, if any.
    fn tip_profile_channel(&self) -> Option<&'static str> {
        None
    }
    /// The search's effort.
    fn search(&self) -> SearchHints;
    /// Synthesis: the defaults of a synthetic record.
    fn synth_defaults(&self) -> SynthDefaults;
    /// Synthesis: the measured input channels written beside the fitted one, at `times` [s]
    /// (the tip's motion for a driven scenario).
    fn synth_inputs(&self, _profile: &TipProfile, _times: &[f64]) -> Vec<(&'static str, Vec<f64>)> {
        Vec::new()
    }
    /// Discovery: measured states (label, values at the record's samples) whose correlation
    /// with the residual `discover` reports, from the record's `channels` and the model's
    /// prediction `pred` of the fitted channel.
    fn measured_states(
        &self,
        _channels: &BTreeMap<String, Vec<f64>>,
        _pred: &[f64],
    ) -> Vec<(String, Vec<f64>)> {
        Vec::new()
    }
    /// Identification: the values its fits hold for exact symmetries, if any.
    fn holds(&self) -> Option<&'static Holds> {
        None
    }
    /// Identification: the combinations its records identify, for the record's `known`
    /// constants.
    fn combinations(&self, _known: &BTreeMap<String, f64>) -> Vec<CombinationSpec> {
        Vec::new()
    }
    /// `discover --scaffold`: how a force term is written for it.
    fn scaffold_force(&self) -> ScaffoldForce;
}

/// A handle on a registered scenario: what datasets, models and effects carry. Compares,
/// orders and hashes by name; dereferences to its [`ScenarioSpec`].
#[derive(Clone, Copy)]
pub struct Scenario(pub &'static dyn ScenarioSpec);

impl std::ops::Deref for Scenario {
    type Target = dyn ScenarioSpec;
    fn deref(&self) -> &Self::Target {
        self.0
    }
}

impl PartialEq for Scenario {
    fn eq(&self, other: &Self) -> bool {
        self.0.name() == other.0.name()
    }
}

impl Eq for Scenario {}

impl PartialOrd for Scenario {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Scenario {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.name().cmp(other.0.name())
    }
}

impl std::hash::Hash for Scenario {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.0.name().hash(state);
    }
}

impl std::fmt::Debug for Scenario {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.0.handle_name())
    }
}

impl Scenario {
    /// One-sided release of a pendulum TM mock-up in the TMMF (physics.md section 4).
    #[allow(non_upper_case_globals)]
    pub const TmmfRelease: Scenario = Scenario(&TmmfRelease);
    /// Unloaded retraction of the release tip (physics.md section 5).
    #[allow(non_upper_case_globals)]
    pub const RtRetraction: Scenario = Scenario(&RtRetraction);

    /// The scenario's name in datasets and JSON.
    pub fn name(self) -> &'static str {
        self.0.name()
    }

    /// Parses a scenario name through the [`registry`].
    pub fn from_name(s: &str) -> Option<Scenario> {
        registry().iter().copied().find(|r| r.name() == s)
    }
}

/// Every scenario, in interface.md order: the one list a dataset's `scenario:` resolves in.
pub fn registry() -> &'static [Scenario] {
    static LIST: &[Scenario] = &[Scenario::TmmfRelease, Scenario::RtRetraction];
    LIST
}

/// The names of the registered scenarios, in order.
pub fn names() -> Vec<&'static str> {
    registry().iter().map(|s| s.name()).collect()
}

/// `tmmf-release`: one-sided release of a pendulum TM mock-up in the TMMF (thesis ch. 5,
/// physics.md section 4); the measured tip motion `y` drives the TM, whose displacement `x` the
/// interferometer reads.
#[derive(Debug, Clone, Copy)]
pub struct TmmfRelease;

impl ScenarioSpec for TmmfRelease {
    fn name(&self) -> &'static str {
        "tmmf-release"
    }
    fn handle_name(&self) -> &'static str {
        "TmmfRelease"
    }
    fn dynamics(&self) -> Dynamics {
        Dynamics::TmRelease
    }
    fn required_channels(&self) -> &'static [&'static str] {
        &["x", "y"]
    }
    fn channels(&self) -> &'static [&'static str] {
        &["x", "y"]
    }
    fn fitted_channel(&self) -> &'static str {
        "x"
    }
    fn required_known(&self) -> &'static [&'static str] {
        &["m"]
    }
    fn base_effects(&self) -> &'static [&'static str] {
        &["needle_contact", "tip_contact"]
    }
    fn tip_profile_channel(&self) -> Option<&'static str> {
        Some("y")
    }
    /// A TMMF release is decided in its first milliseconds (contact, catapult, bond); the
    /// record after mostly extrapolates it, so starts are judged and first refined on the
    /// first quarter, then half, of the record, and the stages also run on the whole record.
    fn search(&self) -> SearchHints {
        SearchHints {
            stages: [(10, 8), (40, 3)],
            refine_iterations: 200,
            windows: [0.25, 0.5],
            stages_on_whole_record: true,
        }
    }
    fn synth_defaults(&self) -> SynthDefaults {
        SynthDefaults {
            known: &[("m", 0.089)],
            noise: &[("x", 8e-10), ("y", 3e-9)],
            fs_hz: 2e5,
            pre_s: 1e-3,
            post_s: 8e-3,
        }
    }
    fn synth_inputs(&self, profile: &TipProfile, times: &[f64]) -> Vec<(&'static str, Vec<f64>)> {
        vec![("y", times.iter().map(|&t| profile.y(t)).collect())]
    }
    fn measured_states(
        &self,
        channels: &BTreeMap<String, Vec<f64>>,
        pred: &[f64],
    ) -> Vec<(String, Vec<f64>)> {
        let Some(y) = channels.get("y") else {
            return Vec::new();
        };
        vec![
            ("tip y [m]".into(), y.clone()),
            (
                "tip-TM gap y - x (model) [m]".into(),
                y.iter().zip(pred).map(|(y, x)| y - x).collect(),
            ),
        ]
    }
    fn scaffold_force(&self) -> ScaffoldForce {
        ScaffoldForce {
            kind: "Force",
            import: "TmState",
            equilibrium: true,
            position_law: "restoring force F = -m (2 pi f0)^2 (x - x_eq) on the TM",
            velocity_law: "damping force F = -m gamma dx/dt on the TM",
            position_code: "    fn force(&self, p: &[f64], s: &TmState, _ds: &mut [f64]) -> f64 {\n        let w0 = std::f64::consts::TAU * p[0];\n        -s.m_kg * w0 * w0 * (s.x - p[1])\n    }\n",
            velocity_code: "    fn force(&self, p: &[f64], s: &TmState, _ds: &mut [f64]) -> f64 {\n        -s.m_kg * p[0] * s.v\n    }\n",
        }
    }
}

/// The parameters the retraction's exact scaling multiplies by `s` (with `piezo.R` divided by
/// `s`).
const SCALED: &[&str] = &[
    "piezo.R",
    "piezo.m",
    "piezo.Ca",
    "piezo.k",
    "piezo.b",
    "piezo.T",
    "plunger_compliance.Mg",
    "plunger_compliance.Kg",
];

/// The retraction's holds: `piezo.Ca` for the scaling and `piezo.R` for the electrical time
/// `R Ca` (which the record's identifiable combinations leave free), known to the release
/// budget's 11.5 % per mechanism parameter (models/release/budget.yaml, physics.md s.3).
static RT_HOLDS: Holds = Holds {
    requires_effect: "piezo",
    moved: SCALED,
    held: &[
        (
            "piezo.Ca",
            "the retraction is unchanged when m, b, k, Ca, T, Mg, Kg are multiplied by s and R \
             divided by it (its scale)",
        ),
        (
            "piezo.R",
            "the record fixes the poles and the stroke, not the electrical time R Ca apart from \
             the mechanics (a second exact symmetry)",
        ),
    ],
    relative_sigma: 0.115,
};

/// `rt-retraction`: unloaded retraction of the GPRM release tip (thesis ch. 3, physics.md
/// sections 1 and 5), a linear ODE in charge, plunger and tip; the tip displacement `y` is
/// fitted, the drive voltage `E` may be recorded.
#[derive(Debug, Clone, Copy)]
pub struct RtRetraction;

impl ScenarioSpec for RtRetraction {
    fn name(&self) -> &'static str {
        "rt-retraction"
    }
    fn handle_name(&self) -> &'static str {
        "RtRetraction"
    }
    fn dynamics(&self) -> Dynamics {
        Dynamics::TipMechanism
    }
    fn required_channels(&self) -> &'static [&'static str] {
        &["y"]
    }
    fn channels(&self) -> &'static [&'static str] {
        &["y", "E"]
    }
    fn fitted_channel(&self) -> &'static str {
        "y"
    }
    fn required_known(&self) -> &'static [&'static str] {
        &["E0"]
    }
    fn base_effects(&self) -> &'static [&'static str] {
        &["piezo"]
    }
    /// The retraction rings at about 73 kHz for a millisecond: a 10 % error on a frequency
    /// slips seven cycles by the end of the record, a forest of local minima; fitting the first
    /// fifth of the record, then half, then all (continuation) follows the phase. Its exactly
    /// propagated linear model costs about 50 times less per evaluation and its nine parameters
    /// need longer runs along correlated valleys.
    fn search(&self) -> SearchHints {
        SearchHints {
            stages: [(40, 12), (200, 4)],
            refine_iterations: 800,
            windows: [0.2, 0.5],
            stages_on_whole_record: false,
        }
    }
    fn synth_defaults(&self) -> SynthDefaults {
        SynthDefaults {
            known: &[("E0", 120.0)],
            noise: &[("y", 1e-9)],
            fs_hz: 1e6,
            pre_s: 2e-5,
            post_s: 1e-3,
        }
    }
    fn holds(&self) -> Option<&'static Holds> {
        Some(&RT_HOLDS)
    }
    /// Each exponent vector sums to zero over the scaled parameters with `R` counted negative,
    /// so that the scaling leaves it unchanged.
    fn combinations(&self, known: &BTreeMap<String, f64>) -> Vec<CombinationSpec> {
        let e0 = known.get("E0").copied().unwrap_or(120.0);
        let c = |name, unit, formula, constant, exponents| CombinationSpec {
            name,
            unit,
            formula,
            constant,
            exponents,
        };
        vec![
            c(
                "d0",
                "m",
                "T E0 / k (static stroke)",
                e0,
                vec![("piezo.T", 1.0), ("piezo.k", -1.0)],
            ),
            c(
                "tau_e",
                "s",
                "R Ca (electrical time)",
                1.0,
                vec![("piezo.R", 1.0), ("piezo.Ca", 1.0)],
            ),
            c(
                "w_tip",
                "rad/s",
                "sqrt(k / m) (tip on the stack)",
                1.0,
                vec![("piezo.k", 0.5), ("piezo.m", -0.5)],
            ),
            c(
                "b_over_m",
                "1/s",
                "b / m (damping rate)",
                1.0,
                vec![("piezo.b", 1.0), ("piezo.m", -1.0)],
            ),
            c(
                "kappa",
                "1",
                "T^2 / (Ca k) (electromechanical coupling)",
                1.0,
                vec![("piezo.T", 2.0), ("piezo.Ca", -1.0), ("piezo.k", -1.0)],
            ),
            c(
                "mass_ratio",
                "1",
                "Mg / m",
                1.0,
                vec![("plunger_compliance.Mg", 1.0), ("piezo.m", -1.0)],
            ),
            c(
                "stiffness_ratio",
                "1",
                "Kg / k",
                1.0,
                vec![("plunger_compliance.Kg", 1.0), ("piezo.k", -1.0)],
            ),
            c(
                "em",
                "V/s",
                "em (voltage slope)",
                1.0,
                vec![("voltage_ramp.em", 1.0)],
            ),
        ]
    }
    fn scaffold_force(&self) -> ScaffoldForce {
        ScaffoldForce {
            kind: "Mechanism",
            import: "RtConfig",
            equilibrium: false,
            position_law: "restoring force on the tip: stiffness m (2 pi f0)^2 added to k",
            velocity_law: "damping of the tip: m gamma added to b",
            position_code: "    fn configure_rt(&self, p: &[f64], rt: &mut RtConfig) {\n        let w0 = std::f64::consts::TAU * p[0];\n        rt.k_n_m += rt.m_kg * w0 * w0;\n    }\n",
            velocity_code: "    fn configure_rt(&self, p: &[f64], rt: &mut RtConfig) {\n        rt.b_ns_m += rt.m_kg * p[0];\n    }\n",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_registry_resolves_every_scenario_by_its_name_and_only_those() {
        for s in registry() {
            assert_eq!(Scenario::from_name(s.name()), Some(*s));
            assert_eq!(format!("{s:?}"), s.handle_name());
            for c in s.required_channels() {
                assert!(s.channels().contains(c), "{}: {c}", s.name());
            }
            assert!(s.channels().contains(&s.fitted_channel()));
        }
        assert_eq!(names(), ["tmmf-release", "rt-retraction"]);
        assert_eq!(Scenario::from_name("tmmf"), None);
        assert_ne!(Scenario::TmmfRelease, Scenario::RtRetraction);
    }

    /// Each retraction combination is unchanged by the exact scaling (the scaled parameters
    /// times `s`, `piezo.R` over `s`): the exponents of the scaled parameters, `R` counted
    /// negative, sum to zero.
    #[test]
    fn the_retraction_combinations_are_invariant_under_its_scaling() {
        for c in RtRetraction.combinations(&BTreeMap::new()) {
            let sum: f64 = c
                .exponents
                .iter()
                .filter(|(n, _)| SCALED.contains(n))
                .map(|(n, e)| if *n == "piezo.R" { -e } else { *e })
                .sum();
            assert!(sum.abs() < 1e-12, "{}: {sum}", c.name);
        }
    }
}
