//! The effect catalogue: every named effect of interface.md, one Rust type per file.
//!
//! An effect is either a force on the TM mock-up (`tmmf-release`), a distortion of the
//! measurement, or a component of the release-tip mechanism (`rt-retraction`). Each declares its
//! parameters ([`ParamSpec`]: name, unit, nominal value, physical bounds) and its data-driven
//! starting points for the fit. [`catalogue`] is the one list that fit, diagnose, synth and the
//! reports read: adding an effect means adding a file here and one line to that list
//! (docs/fitting.md, "Adding an effect").

mod drift;
mod interferometer_cyclic;
mod needle_adhesion;
mod needle_contact;
mod needle_mass;
mod piezo;
mod plunger_compliance;
mod tip_adhesion;
mod tip_contact;
mod voltage_ramp;

pub use drift::Drift;
pub use interferometer_cyclic::InterferometerCyclic;
pub use needle_adhesion::NeedleAdhesion;
pub use needle_contact::NeedleContact;
pub use needle_mass::NeedleMass;
pub use piezo::Piezo;
pub use plunger_compliance::PlungerCompliance;
pub use tip_adhesion::TipAdhesion;
pub use tip_contact::TipContact;
pub use voltage_ramp::VoltageRamp;

use crate::retraction::RtConfig;
pub use crate::scenario::Scenario;

/// What an effect does to the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EffectKind {
    /// A force on the TM mock-up (`tmmf-release`).
    Force,
    /// A distortion of the measurement, added to the predicted channel.
    Distortion,
    /// A component of the release-tip mechanism ODE (`rt-retraction`).
    Mechanism,
}

impl EffectKind {
    /// The kind's name in `geodesic effects` (`force`, `distortion`, `mechanism`).
    pub fn name(self) -> &'static str {
        match self {
            EffectKind::Force => "force",
            EffectKind::Distortion => "distortion",
            EffectKind::Mechanism => "mechanism",
        }
    }
}

/// The JSON document of `geodesic effects --json` (interface.md, docs/outputs.md).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct EffectsDoc {
    /// The effects listed, in catalogue order.
    pub effects: Vec<EffectDoc>,
}

/// One effect of [`EffectsDoc`]. Fields are declared in byte order of their keys, the order
/// the document has always printed.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct EffectDoc {
    /// One-line summary.
    pub description: String,
    /// The effect's name.
    pub effect: String,
    /// What it does to the model: `force`, `distortion` or `mechanism`.
    pub kind: String,
    /// Its parameters.
    pub parameters: Vec<ParamDoc>,
    /// The scenario it belongs to (`tmmf-release`, `rt-retraction`).
    pub scenario: String,
}

/// One parameter of [`EffectDoc`], in byte order of its keys. `min` and `max` are in `unit`
/// and absent on an unbounded side.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct ParamDoc {
    /// Physical upper bound [unit]; absent when unbounded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
    /// Physical lower bound [unit]; absent when unbounded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    /// Full name, `effect.param`.
    pub name: String,
    /// Nominal value [unit].
    pub nominal: f64,
    /// SI unit of the value.
    pub unit: String,
}

impl EffectDoc {
    /// The document of effect `e`.
    pub fn of(e: &dyn Effect) -> EffectDoc {
        let finite = |v: f64| v.is_finite().then_some(v);
        EffectDoc {
            description: e.summary().to_string(),
            effect: e.name().to_string(),
            kind: e.kind().name().to_string(),
            parameters: e
                .params()
                .iter()
                .map(|p| ParamDoc {
                    max: finite(p.upper),
                    min: finite(p.lower),
                    name: format!("{}.{}", e.name(), p.name),
                    nominal: p.nominal,
                    unit: p.unit.to_string(),
                })
                .collect(),
            scenario: e.scenario().name().to_string(),
        }
    }
}

/// One parameter of an effect.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamSpec {
    /// Name within the effect (`k_nd`); the full name is `effect.name`.
    pub name: &'static str,
    /// SI unit of the value.
    pub unit: &'static str,
    /// Nominal value (thesis or physics.md), the default start and the synth default.
    pub nominal: f64,
    /// Physical lower bound.
    pub lower: f64,
    /// Physical upper bound.
    pub upper: f64,
    /// Fitted in `ln(value)` (strictly positive, spans decades) rather than linearly.
    pub log: bool,
    /// Typical magnitude, the step scale of a linear parameter [unit].
    pub scale: f64,
}

impl ParamSpec {
    /// A positive parameter fitted in log space.
    pub const fn log(
        name: &'static str,
        unit: &'static str,
        nominal: f64,
        lower: f64,
        upper: f64,
    ) -> Self {
        ParamSpec {
            name,
            unit,
            nominal,
            lower,
            upper,
            log: true,
            scale: nominal,
        }
    }

    /// A signed parameter fitted linearly with the typical magnitude `scale`.
    pub const fn lin(name: &'static str, unit: &'static str, nominal: f64, scale: f64) -> Self {
        ParamSpec {
            name,
            unit,
            nominal,
            lower: f64::NEG_INFINITY,
            upper: f64::INFINITY,
            log: false,
            scale,
        }
    }
}

/// A force law of closed form, which the TMMF integration evaluates inline ([`ForceEffect::law`]):
/// the same value and own-state derivatives, bit for bit, as the effect's [`ForceEffect::force`]
/// (tested for every effect that offers one).
///
/// Why by hand: an RK4 step of a TMMF release is a chain of four dependent force evaluations;
/// through the trait each is a virtual call per effect with a [`TmState`] built for it, which
/// kept the compiler from inlining the step (perf: twice the cost of a step on FAC-FIT-QUAL's
/// fits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ForceLaw {
    /// `-k * g` while the needle gap `g = x - x_n0` is negative, 0 when a needle body replaces
    /// the spring [N] (`needle_contact`, `k` [N/m]).
    NeedleSpring {
        /// Stiffness [N/m].
        k: f64,
    },
    /// `k * e` while the tip elongation `e` is not positive [N] (`tip_contact`, `k` [N/m]).
    TipSpring {
        /// Stiffness [N/m].
        k: f64,
    },
    /// [`adhesion_force`]`(a1, lambda, e)` on the tip elongation `e` (`tip_adhesion`).
    TipAdhesion {
        /// `A1` [N/m].
        a1: f64,
        /// `lambda` [m].
        lambda: f64,
    },
    /// `-`[`adhesion_force`]`(a1, lambda, g)` on the needle gap `g` (`needle_adhesion`).
    NeedleAdhesion {
        /// `A1` [N/m].
        a1: f64,
        /// `lambda` [m].
        lambda: f64,
    },
    /// The needle body of `needle_mass` (its two own states: displacement [m], velocity
    /// [m/s]), with its parameters in the effect's order.
    NeedleBody {
        /// Body mass [kg].
        m_nd: f64,
        /// Body spring to ground [N/m].
        k_nd: f64,
        /// Contact stiffness with the TM [N/m].
        k_tm: f64,
        /// Body damping to ground [N s/m].
        c_nd: f64,
        /// Contact damping [N s/m].
        c_tm: f64,
    },
}

/// What a [`ForceLaw`] reads: the [`TmState`] fields, with at most two own states.
#[derive(Debug, Clone, Copy)]
pub struct LawState {
    /// TM displacement [m] and velocity [m/s].
    pub x: f64,
    /// TM velocity [m/s].
    pub v: f64,
    /// Tip contact elongation [m] ([`TmState::e_tip`]).
    pub e_tip: f64,
    /// Needle gap [m] ([`TmState::needle_gap`]).
    pub gap: f64,
    /// Needle preload [N].
    pub f_pre: f64,
    /// Whether a needle body replaces the fixed needle spring.
    pub body: bool,
    /// The law's own states (those of [`ForceLaw::NeedleBody`]; unused otherwise).
    pub own: [f64; 2],
}

impl LawState {
    /// The fields of `s` a law reads (its own states, if any, are the first two of `s.own`).
    pub fn of(s: &TmState) -> LawState {
        LawState {
            x: s.x,
            v: s.v,
            e_tip: s.e_tip,
            gap: s.needle_gap,
            f_pre: s.f_pre,
            body: s.needle_body,
            own: [
                s.own.first().copied().unwrap_or(0.0),
                s.own.get(1).copied().unwrap_or(0.0),
            ],
        }
    }
}

impl ForceLaw {
    /// Force on the TM along +x [N] in state `s`; writes the time derivatives of the law's own
    /// states into `d_own` (only [`ForceLaw::NeedleBody`] has any).
    #[inline(always)]
    pub fn force(&self, s: &LawState, d_own: &mut [f64; 2]) -> f64 {
        match *self {
            ForceLaw::NeedleSpring { k } => {
                if s.body || s.gap >= 0.0 {
                    0.0
                } else {
                    -k * s.gap
                }
            }
            ForceLaw::TipSpring { k } => {
                if s.e_tip <= 0.0 {
                    k * s.e_tip
                } else {
                    0.0
                }
            }
            ForceLaw::TipAdhesion { a1, lambda } => adhesion_force(a1, lambda, s.e_tip),
            ForceLaw::NeedleAdhesion { a1, lambda } => -adhesion_force(a1, lambda, s.gap),
            ForceLaw::NeedleBody {
                m_nd,
                k_nd,
                k_tm,
                c_nd,
                c_tm,
            } => {
                let (u, du) = (s.own[0], s.own[1]);
                let delta = s.f_pre / k_tm + u - s.x;
                let fc = if delta > 0.0 {
                    (k_tm * delta + c_tm * (du - s.v)).max(0.0)
                } else {
                    0.0
                };
                d_own[0] = du;
                d_own[1] = (s.f_pre - k_nd * u - c_nd * du - fc) / m_nd;
                fc
            }
        }
    }
}

/// The instantaneous state handed to a force effect of `tmmf-release` (physics.md section 4).
#[derive(Debug, Clone, Copy)]
pub struct TmState<'a> {
    /// Time from the trigger [s].
    pub t: f64,
    /// TM displacement, + in the direction of tip retraction [m].
    pub x: f64,
    /// TM velocity [m/s].
    pub v: f64,
    /// Tip displacement (smooth profile) [m].
    pub y: f64,
    /// Tip contact elongation `e = (y - x) - F_pre/k_c` [m]; `e <= 0` is compression.
    pub e_tip: f64,
    /// Gap between TM and needles `x - x_n0` [m]; `<= 0` while they touch.
    pub needle_gap: f64,
    /// Preload of the needles on the TM at rest [N].
    pub f_pre: f64,
    /// True when an effect with its own body (`needle_mass`) replaces the fixed needle spring.
    pub needle_body: bool,
    /// TM mock-up mass [kg] (the dataset's `known.m`): a force given as an acceleration (a
    /// pendulum's `w0^2`, a damping rate `gamma`) is that times the mass.
    pub m_kg: f64,
    /// The effect's own internal states (e.g. needle body position and velocity).
    pub own: &'a [f64],
}

/// What a force effect may assume when the TMMF model asks whether it has let go of the TM for
/// good ([`ForceEffect::released`]).
#[derive(Debug, Clone, Copy)]
pub struct ReleaseCheck {
    /// Tip speed `y'(t)` now [m/s]; after the trigger the profile's speed never decreases.
    pub tip_speed_m_s: f64,
    /// Time left to the end of the record [s].
    pub horizon_s: f64,
    /// TM mock-up mass [kg].
    pub m_kg: f64,
    /// Largest displacement of the TM [m] that the force neglected from now on may cause by the
    /// end of the record.
    pub tol_m: f64,
}

impl ReleaseCheck {
    /// Largest displacement [m] of the TM over the horizon caused by a force whose remaining
    /// impulse is at most `impulse_n_s` [N s].
    pub fn displacement_of(&self, impulse_n_s: f64) -> f64 {
        impulse_n_s.abs() / self.m_kg * self.horizon_s
    }
}

/// Tail steps [`ForceEffect::smooth`] asks of an adhesion law per `lambda` of its argument's growth.
pub const SMOOTH_STEPS_PER_LAMBDA: f64 = 8.0;

/// Whether the adhesion law `A1 s exp(-s/lambda)` (`a1` [N/m], `lambda` [m]) of an argument `e`
/// [m] growing at `rate` [m/s] is smooth on the tail step `h` [s] for a TM of `m_kg` [kg]: the
/// bond open (`e > 0`, growing), the step advancing `e` by at most `lambda /`
/// [`SMOOTH_STEPS_PER_LAMBDA`], and at most a quarter radian of the adhesion well's own
/// oscillation (`h sqrt(A1 / m)`), whose stiffness is at most `A1`.
pub fn adhesion_smooth(a1: f64, lambda: f64, e: f64, rate: f64, h: f64, m_kg: f64) -> bool {
    e > 0.0
        && rate > 0.0
        && rate * h * SMOOTH_STEPS_PER_LAMBDA <= lambda
        && h * h * a1 <= 0.0625 * m_kg
}

/// Bound [N s] on the impulse still to come from the adhesion law [`adhesion_force`] when the
/// elongation `e` [m] is at least `lambda` and grows at a rate of at least `rate` [m/s] > 0:
/// `int_e^inf A1 s exp(-s/lambda) ds / rate = A1 lambda (e + lambda) exp(-e/lambda) / rate`.
/// Infinite when the premises do not hold.
pub fn adhesion_tail_impulse(a1: f64, lambda: f64, e: f64, rate: f64) -> f64 {
    if e >= lambda && rate > 0.0 && lambda > 0.0 {
        a1 * lambda * (e + lambda) * exp_or_zero(-e / lambda) / rate
    } else {
        f64::INFINITY
    }
}

/// Whether the adhesion law's remaining impulse ([`adhesion_tail_impulse`] of `a1` [N/m],
/// `lambda` [m], `e` [m], `rate` [m/s]) moves the TM by less than `r.tol_m` by the end of the
/// record ([`ReleaseCheck::displacement_of`]): the adhesions' [`ForceEffect::released`].
///
/// The same answer, always, as `r.displacement_of(adhesion_tail_impulse(..)) < r.tol_m`, but
/// without its `exp` and two of its divisions while the answer is clearly no (asked at every
/// sample of a bond's tail, they were a tenth of a `discover`). The answer is first sought with
/// `low = 2^k`, `k = trunc(z log2 e) - 3 <= floor(z log2 e) - 2` for `z = -e/lambda`: a power
/// of two under half of `exp(z)` (the product `z log2 e` is off by less than 3e-13, and `exp`
/// by an ulp). When `a1 lambda (e + lambda) low horizon >= 2 tol rate m` (products of
/// positive factors, each off by at most a few ulps), the exact displacement, larger than that
/// bound's, is at least `tol_m`, and the answer is no.
pub fn adhesion_released(a1: f64, lambda: f64, e: f64, rate: f64, r: &ReleaseCheck) -> bool {
    if e >= lambda && rate > 0.0 && lambda > 0.0 {
        let c = -e / lambda * std::f64::consts::LOG2_E;
        // c <= -log2(e) < 0 here, so truncation rounds up: `k` is at most floor(c) - 2
        let k = c as i64 - 3;
        if k >= -1022 {
            // 2^k, k a normal exponent
            let low = f64::from_bits(((k + 1023) as u64) << 52);
            if a1 * lambda * (e + lambda) * low * r.horizon_s >= 2.0 * r.tol_m * rate * r.m_kg {
                return false;
            }
        }
    }
    r.displacement_of(adhesion_tail_impulse(a1, lambda, e, rate)) < r.tol_m
}

/// Data-driven quantities an effect may use for its starting points.
#[derive(Debug, Clone, Copy, Default)]
pub struct GuessContext {
    /// TM mock-up mass [kg] (`tmmf-release`).
    pub m_kg: f64,
    /// Late velocity of the fitted channel (slope over the last third of the record) [m/s].
    pub late_velocity_m_s: f64,
    /// Duration of the catapult: time from the trigger until the TM velocity first reaches 90 %
    /// of its late value [s] (0 if unknown).
    pub catapult_s: f64,
    /// Peak-to-peak span of the fitted channel [m].
    pub span_m: f64,
    /// Record length after the trigger [s].
    pub duration_s: f64,
    /// Initial voltage [V] (`rt-retraction`).
    pub e0_v: f64,
    /// Needle stiffness of an already fitted rigid-needle model [N/m] (0 if none): diagnose
    /// sets it so that `needle_mass` can start from what the baseline saw.
    pub k_needle_n_m: f64,
}

/// What an effect does to the model: the capability it implements, returned by
/// [`Effect::role`]. A model's code asks the role, never the kind, so that an effect's kind and
/// the methods it implements cannot disagree.
#[derive(Clone, Copy)]
pub enum Role<'a> {
    /// A force on the TM mock-up (`tmmf-release`).
    Force(&'a dyn ForceEffect),
    /// A distortion of the measurement, added to the predicted channel.
    Distortion(&'a dyn DistortionEffect),
    /// A delay of the record's time axis (a distortion of the measurement's time, of kind
    /// [`EffectKind::Distortion`]).
    TimeShift(&'a dyn TimeShiftEffect),
    /// A component of the release-tip mechanism ODE (`rt-retraction`).
    Mechanism(&'a dyn MechanismEffect),
}

impl Role<'_> {
    /// The kind of the role (a time shift distorts the measurement: [`EffectKind::Distortion`]).
    pub fn kind(&self) -> EffectKind {
        match self {
            Role::Force(_) => EffectKind::Force,
            Role::Distortion(_) | Role::TimeShift(_) => EffectKind::Distortion,
            Role::Mechanism(_) => EffectKind::Mechanism,
        }
    }
}

/// A named effect: what every effect has (name, scenario, description, parameters), what it
/// does ([`Effect::role`]: a force on the TM, a distortion of the measurement, a time shift or a
/// mechanism component) and its hints for the fit ([`Effect::hints`]).
pub trait Effect: Send + Sync {
    /// Name in datasets, CLI and JSON (`tip_adhesion`).
    fn name(&self) -> &'static str;
    /// The scenario the effect belongs to.
    fn scenario(&self) -> Scenario;
    /// One-line description with its law and source.
    fn summary(&self) -> &'static str;
    /// The parameters, in the order of the parameter slices handed to the other methods.
    fn params(&self) -> &'static [ParamSpec];
    /// Full names of other effects' parameters this effect makes unidentifiable (held fixed).
    fn supersedes(&self) -> &'static [&'static str] {
        &[]
    }
    /// What the effect does: the one capability it implements (`Role::Force(self)`, ...).
    fn role(&self) -> Role<'_>;
    /// The effect's hints for the fit (`self`: every effect implements [`FitHints`], whose
    /// methods all have defaults).
    fn hints(&self) -> &dyn FitHints;
}

impl dyn Effect + '_ {
    /// What the effect does, derived from its [`Effect::role`].
    pub fn kind(&self) -> EffectKind {
        self.role().kind()
    }
}

/// A force on the TM mock-up (`tmmf-release`, [`Role::Force`]).
pub trait ForceEffect: Send + Sync {
    /// Number of internal ODE states (a force effect with its own dynamics).
    fn n_states(&self) -> usize {
        0
    }
    /// Force on the TM along +x [N]; writes the time derivatives of the effect's own states
    /// into `ds` (length [`ForceEffect::n_states`]).
    fn force(&self, p: &[f64], s: &TmState, ds: &mut [f64]) -> f64;
    /// The force as a closed-form law the integration evaluates inline (at most two own
    /// states); `None` (the default) keeps the call to [`ForceEffect::force`].
    fn law(&self, _p: &[f64]) -> Option<ForceLaw> {
        None
    }
    /// Whether the force has let go of the TM for good (`tmmf-release`): `true` only if, from
    /// state `s` on, with the TM in free flight at its present velocity `s.v` and the tip
    /// retracting at a speed that never falls below `r.tip_speed_m_s`, the force stays zero, or
    /// its remaining impulse moves the TM by less than `r.tol_m` by the end of the record,
    /// whatever the effect's own states do. When every force effect of a model says so, the
    /// model propagates the TM exactly in free flight (no integration) for the rest of the
    /// record. The default, `false`, is always correct (the model then integrates to the end of
    /// the record).
    fn released(&self, _p: &[f64], _s: &TmState, _r: &ReleaseCheck) -> bool {
        false
    }
    /// Whether a force that has not let go ([`ForceEffect::released`] false) varies, from state
    /// `s` on and as long as it stays true, slowly enough for the tail step `h_tail` [s]
    /// (`tmmf-release`: when every force effect is released or smooth, the model integrates with
    /// that step instead of the contact step; it asks again at every sample). The default,
    /// `false`, keeps the contact step: a force that may still act abruptly, or an effect that
    /// does not say.
    fn smooth(&self, _p: &[f64], _s: &TmState, _r: &ReleaseCheck, _h_tail: f64) -> bool {
        false
    }
    /// Whether the effect's own states ([`ForceEffect::n_states`] of them), once the force has
    /// let go ([`ForceEffect::released`]), evolve slowly enough for the tail step `h_tail` [s]
    /// that the integration may take it (they no longer act on the TM, but the release is
    /// judged on them at every sample). The default, `false`, keeps the contact step for a
    /// model with own states.
    fn own_states_slow(&self, _p: &[f64], _h_tail: f64) -> bool {
        false
    }
}

/// A distortion of the measurement, added to the predicted channel ([`Role::Distortion`]).
pub trait DistortionEffect: Send + Sync {
    /// Additive distortion of the measured channel [m] at time `t` [s] and true value `x` [m].
    fn distortion(&self, p: &[f64], t: f64, x: f64) -> f64;
    /// The distortion's derivatives at time `t` [s] and true value `x` [m]: writes
    /// `d distortion / d p[i]` into `d_p` (one per parameter) and returns `d distortion / d x`
    /// (the fit's exact Jacobian, `tmmf::simulate_with_tangents`); `None` (the default) when
    /// the effect does not offer them (the fit then takes finite differences).
    fn distortion_gradient(&self, _p: &[f64], _t: f64, _x: f64, _d_p: &mut [f64]) -> Option<f64> {
        None
    }
}

/// A delay of the record's time axis ([`Role::TimeShift`]): the model is evaluated at
/// `t - delay` (a trigger that fires before the motion starts).
pub trait TimeShiftEffect: Send + Sync {
    /// The delay [s] under the effect's parameters `p`. The shifts of a model's effects add up
    /// ([`Model::time_shift`](crate::model::Model::time_shift)).
    fn time_shift(&self, p: &[f64]) -> f64;
}

/// A component of the release-tip mechanism ODE (`rt-retraction`, [`Role::Mechanism`]).
pub trait MechanismEffect: Send + Sync {
    /// Writes the effect's parameters into the mechanism configuration.
    fn configure_rt(&self, p: &[f64], rt: &mut RtConfig);
}

/// An effect's hints for the fit: where it vanishes, its canonical forms and its starting
/// points ([`Effect::hints`]; every method has a default).
pub trait FitHints: Effect {
    /// Parameters at which the effect (nearly) vanishes, if any: a candidate fit started there
    /// from the baseline's values can only improve on the baseline.
    fn null_params(&self) -> Option<Vec<f64>> {
        None
    }
    /// Equivalent parameter vectors in a preferred (canonical) form, tried after a fit: one that
    /// fits as well replaces the fitted values (e.g. a cyclic error fitted on its second
    /// harmonic is re-expressed with half the period).
    fn alternatives(&self, _p: &[f64]) -> Vec<Vec<f64>> {
        Vec::new()
    }
    /// Starting points for the fit (each a full parameter vector of this effect), from the data;
    /// the default, the nominal values.
    fn starts(&self, _g: &GuessContext) -> Vec<Vec<f64>> {
        vec![self.params().iter().map(|p| p.nominal).collect()]
    }
    /// Whether the fitted parameters `p` are physically plausible on a record showing `r`,
    /// beyond the ranges of [`Effect::params`] (which the fit already holds): relations to the
    /// record, such as a distortion smaller than the motion it distorts. `Err` says which
    /// parameter, its value and the bound, in one sentence (issue 50: `discover` adds an effect
    /// only when this holds). The default: no relation.
    fn plausible(&self, _p: &[f64], _r: &RecordStats) -> Result<(), String> {
        Ok(())
    }
}

/// What a record shows that an effect's plausibility may depend on ([`FitHints::plausible`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordStats {
    /// Peak-to-peak of the fitted channel's model prediction [m] (the motion the reading
    /// follows).
    pub motion_pp_m: f64,
    /// Duration of the record [s].
    pub span_s: f64,
}

/// The catalogue: every effect of every scenario, in interface.md order.
pub fn catalogue() -> &'static [&'static dyn Effect] {
    static LIST: &[&dyn Effect] = &[
        &NeedleContact,
        &TipContact,
        &TipAdhesion,
        &NeedleAdhesion,
        &NeedleMass,
        &InterferometerCyclic,
        &Drift,
        &Piezo,
        &PlungerCompliance,
        &VoltageRamp,
    ];
    LIST
}

/// Looks an effect up by name.
pub fn by_name(name: &str) -> Option<&'static dyn Effect> {
    catalogue().iter().copied().find(|e| e.name() == name)
}

/// The effects of one scenario, in catalogue order.
pub fn of_scenario(s: Scenario) -> Vec<&'static dyn Effect> {
    catalogue()
        .iter()
        .copied()
        .filter(|e| e.scenario() == s)
        .collect()
}

/// `z.exp()`, the same bits, without the library's underflow path for the arguments whose
/// exponential rounds to +0 (below `ln 2^-1075` = -745.13): an adhesion law far from its
/// surface asks for `exp(-1e4)` at every step after the contact opens, and glibc answers those
/// through a slow path that raises the underflow flag (3 % of a 400 000-sample `discover`,
/// 2026-11-28).
#[inline]
pub fn exp_or_zero(z: f64) -> f64 {
    if z < -746.0 { 0.0 } else { z.exp() }
}

/// The adhesion law of thesis eq. (adh), physics.md section 2: `A1 * e * exp(-e/lambda)` for
/// `e > 0`, else 0 [N]; `a1` [N/m], `lambda` [m], `e` [m].
pub fn adhesion_force(a1: f64, lambda: f64, e: f64) -> f64 {
    if e > 0.0 {
        a1 * e * exp_or_zero(-e / lambda)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `exp_or_zero` is the bits of `exp` on both sides of its cut and at the edges.
    #[test]
    fn exp_or_zero_is_the_bits_of_exp() {
        let mut zs: Vec<f64> = (0..200_000).map(|i| -2000.0 + i as f64 * 0.0133).collect();
        zs.extend([
            -745.1332191019411,
            -745.1332191019412,
            -745.1332191019413,
            -745.9999999999999,
            -746.0,
            -746.0000000000001,
            -1e300,
            f64::NEG_INFINITY,
            f64::NAN,
            -0.0,
            700.0,
        ]);
        for z in zs {
            let (a, b) = (exp_or_zero(z), z.exp());
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{z}: {a} {b}"
            );
        }
    }

    /// `adhesion_released` gives the answer of the impulse bound computed in full, on a grid
    /// of elongations through the bond's whole tail (the answer turns from no to yes inside
    /// it, where the shortcut's power of two no longer decides), four parameter pairs, three
    /// rates, horizons and masses, and at the edges (below `lambda`, zero rate and horizon).
    #[test]
    fn adhesion_released_is_the_full_bound() {
        let mut turns = 0;
        for (a1, lambda) in [(1.3e5, 6e-7), (1e7, 1e-8), (1e1, 3e-6), (1e6, 1e-9)] {
            for rate in [0.0, 1e-6, 3e-3, 0.5] {
                for (horizon, m) in [(0.0, 0.089), (2e-3, 0.0096), (2.0, 1.96)] {
                    let r = ReleaseCheck {
                        tip_speed_m_s: 0.0,
                        horizon_s: horizon,
                        m_kg: m,
                        tol_m: 1e-15, // the models' tolerance (tmmf::RELEASE_TOL_M)
                    };
                    let mut last = None;
                    for i in 0..20_000 {
                        let e = lambda * (0.5 + i as f64 * 0.0371);
                        let full =
                            r.displacement_of(adhesion_tail_impulse(a1, lambda, e, rate)) < r.tol_m;
                        assert_eq!(
                            adhesion_released(a1, lambda, e, rate, &r),
                            full,
                            "A1 {a1} lambda {lambda} e {e} rate {rate} horizon {horizon}"
                        );
                        turns += usize::from(last == Some(!full));
                        last = Some(full);
                    }
                }
            }
        }
        assert!(turns > 10, "{turns}");
    }

    #[test]
    fn catalogue_names_are_unique_and_match_interface() {
        let names: Vec<&str> = catalogue().iter().map(|e| e.name()).collect();
        let mut sorted = names.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), names.len());
        assert_eq!(by_name("needle_mass").unwrap().params().len(), 5);
        assert_eq!(by_name("piezo").unwrap().params().len(), 6);
        for e in catalogue() {
            for p in e.params() {
                assert!(
                    p.lower <= p.nominal && p.nominal <= p.upper,
                    "{}.{}",
                    e.name(),
                    p.name
                );
            }
            assert!(
                !e.hints()
                    .starts(&GuessContext {
                        m_kg: 0.089,
                        ..Default::default()
                    })
                    .is_empty()
            );
        }
    }

    #[test]
    fn adhesion_peaks_at_lambda() {
        let (a1, l) = (1.3e5, 6e-7);
        let peak = adhesion_force(a1, l, l);
        assert!((peak - a1 * l / std::f64::consts::E).abs() < 1e-15);
        assert!(adhesion_force(a1, l, 0.9 * l) < peak && adhesion_force(a1, l, 1.1 * l) < peak);
        assert_eq!(adhesion_force(a1, l, -1e-9), 0.0);
    }
}
