//! `discover --scaffold NAME` (issue 36): from the leading term outside the catalogue, a new
//! effect in the catalogue's own form. This module is the one template: [`Scaffold::from_term`]
//! turns a [`Term`] of `discover` (a fitted term outside the catalogue, as plain data) into the effect's parameters (units, ranges and starting
//! values from the fitted term), [`Scaffold::effect_source`] writes its source file,
//! [`Scaffold::edits`] its registration in `models/facility/src/effects/mod.rs` and its hiding
//! test and guard-list entry in `verification/discover/tests/hide_each.rs`, and [`write_all`] writes
//! every file or none.
//!
//! What each kind becomes (`x` the fitted channel, `t` the time since the trigger):
//!
//! | kind | `tmmf-release` | `rt-retraction` | parameters |
//! | --- | --- | --- | --- |
//! | `position` | force `-m w0^2 (x - x_eq)` | mechanism: `k += m w0^2` on the tip | `f0` [Hz] (`x_eq` [m]) |
//! | `velocity` | force `-m gamma dx/dt` | mechanism: `b += m gamma` on the tip | `gamma` [1/s] |
//! | `delay` | the model at `t - delay` | the same | `delay` [s] |
//! | `creep` | reading `+ c ln(1 + t / tau)` | the same | `c` [m], `tau` [s] |
//! | `slip` | reading `+ a H(t - t0)` | the same | `a` [m], `t0` [s] |
//! | `impulse` | reading `+ a (t - t0)+` | the same | `a` [m/s], `t0` [s] |
//! | `vibration` | reading `+ a_s sin(2 pi f t) + a_c cos(2 pi f t)` | the same | `f` [Hz], `a_s`, `a_c` [m] |

#![warn(missing_docs)]
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use geodesic_facility::Scenario;

/// Every kind `discover` reports, in its order.
pub const KINDS: [&str; 7] = [
    "position",
    "velocity",
    "delay",
    "creep",
    "slip",
    "impulse",
    "vibration",
];

/// Where the scaffold writes, relative to the repository's root.
pub const EFFECTS_DIR: &str = "models/facility/src/effects";
/// The catalogue's registration file.
pub const MOD_RS: &str = "models/facility/src/effects/mod.rs";
/// The hiding tests and the guard list.
pub const HIDE_EACH: &str = "verification/discover/tests/hide_each.rs";

/// A term outside the catalogue as `discover` fitted it (`geodesic_discover::kinds::KindFit`): what
/// the effect's code is written from.
#[derive(Debug, Clone, PartialEq)]
pub struct Term {
    /// Kind (`position`, `velocity`, `delay`, `creep`, `slip`, `impulse`, `vibration`).
    pub kind: String,
    /// The term in words, with its parameter.
    pub term: String,
    /// The physical parameter it implies.
    pub parameter: Option<TermParameter>,
    /// Its fitted coefficients [SI per unit column] (a vibration's sine and cosine amplitudes).
    pub coefs: Vec<f64>,
    /// `-delta_chi2 + k ln N` of the term: negative favours it.
    pub delta_bic: f64,
}

/// The physical parameter a [`Term`] implies.
#[derive(Debug, Clone, PartialEq)]
pub struct TermParameter {
    /// Name (`f0`, `gamma`, `delay`, `tau`, `t0`, `f`).
    pub name: String,
    /// Value [unit].
    pub value: f64,
    /// Unit.
    pub unit: String,
}

/// One parameter of the generated effect.
#[derive(Debug, Clone, PartialEq)]
pub struct GenParam {
    /// Name within the effect.
    pub name: &'static str,
    /// SI unit.
    pub unit: &'static str,
    /// Starting value and synth default (the fitted term's) [unit].
    pub nominal: f64,
    /// Lower and upper bounds [unit].
    pub lower: f64,
    /// Upper bound [unit].
    pub upper: f64,
    /// Fitted in log space.
    pub log: bool,
    /// Typical magnitude [unit] (linear parameters).
    pub scale: f64,
    /// What it is.
    pub doc: &'static str,
}

/// The conditions of the record the term came from, for the hiding test.
#[derive(Debug, Clone, PartialEq)]
pub struct Conditions {
    /// Sampling rate [Hz].
    pub fs_hz: f64,
    /// Record after the trigger [s].
    pub post_s: f64,
    /// Known constant of the scenario: `m` [kg] or `E0` [V].
    pub known: (&'static str, f64),
    /// Noise of the fitted channel [m].
    pub noise: f64,
    /// Tip profile (`tmmf-release`): jerk [m/s^3] and speed [m/s].
    pub jerk_m_s3: f64,
    /// Tip speed [m/s].
    pub v_m_s: f64,
}

/// A new effect from a term outside the catalogue.
#[derive(Debug, Clone, PartialEq)]
pub struct Scaffold {
    /// The effect's name (snake_case).
    pub name: String,
    /// Scenario.
    pub scenario: Scenario,
    /// The term's kind.
    pub kind: String,
    /// The record (as given on the command line).
    pub record: String,
    /// The term's delta BIC.
    pub delta_bic: f64,
    /// The term in words.
    pub term: String,
    /// Kinds the record could not tell from it.
    pub indistinguishable: Vec<String>,
    /// Why the leading term was passed over, when the effect is written from a term the record
    /// could not tell from it (`discover::new_effect::scaffold`): `None` for the leader itself.
    pub passed_over: Option<String>,
    /// The date (YYYY-MM-DD, UTC).
    pub date: String,
    /// Its parameters.
    pub params: Vec<GenParam>,
    /// The record's conditions.
    pub conditions: Conditions,
}

/// Rust keywords and names a new effect may not take.
const RESERVED: &[&str] = &[
    "as", "async", "await", "break", "const", "continue", "crate", "dyn", "else", "enum", "extern",
    "false", "fn", "for", "gen", "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut",
    "pub", "ref", "return", "self", "static", "struct", "super", "trait", "true", "type", "unsafe",
    "use", "where", "while", "abstract", "become", "box", "do", "final", "macro", "override",
    "priv", "try", "typeof", "unsized", "virtual", "yield", "tests",
];

/// Checks a new effect's name: a snake_case identifier (lower-case ASCII letters, digits and
/// single underscores, starting with a letter, at most 48 characters), not a Rust keyword, not
/// already in the catalogue and without a file in `effects_dir` (when given). `Err` is one line.
pub fn check_name(name: &str, effects_dir: Option<&Path>) -> Result<(), String> {
    let shown = name.escape_debug().to_string();
    let ok = !name.is_empty()
        && name.len() <= 48
        && name.starts_with(|c: char| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        && !name.ends_with('_')
        && !name.contains("__");
    if !ok {
        return Err(format!(
            "--scaffold {shown}: not a snake_case name (lower-case letters, digits and single underscores, starting with a letter, e.g. floor_pendulum)"
        ));
    }
    if RESERVED.contains(&name) {
        return Err(format!(
            "--scaffold {shown}: a Rust keyword, choose another name"
        ));
    }
    if geodesic_facility::effects::by_name(name).is_some() {
        return Err(format!(
            "--scaffold {shown}: an effect of that name is already in the catalogue (geodesic effects)"
        ));
    }
    if let Some(dir) = effects_dir {
        let f = dir.join(format!("{name}.rs"));
        if f.exists() {
            return Err(format!(
                "--scaffold {shown}: {} already exists (an effect not yet built into this binary? rebuild, or choose another name)",
                f.display()
            ));
        }
    }
    Ok(())
}

/// `snake_case` -> `CamelCase`.
pub fn camel(name: &str) -> String {
    name.split('_')
        .map(|w| {
            let mut c = w.chars();
            match c.next() {
                Some(f) => f.to_ascii_uppercase().to_string() + c.as_str(),
                None => String::new(),
            }
        })
        .collect()
}

/// `v` rounded to 6 significant digits, as a Rust `f64` literal.
pub fn lit(v: f64) -> String {
    let r: f64 = format!("{v:.5e}").parse().unwrap_or(v);
    let a = r.abs();
    if r == 0.0 {
        "0.0".into()
    } else if (1e-3..1e6).contains(&a) {
        let s = format!("{r:?}");
        if s.contains('.') || s.contains('e') {
            s
        } else {
            format!("{s}.0")
        }
    } else {
        format!("{r:e}")
    }
}

fn log_param(
    name: &'static str,
    unit: &'static str,
    v: f64,
    factor: f64,
    doc: &'static str,
) -> GenParam {
    let v = lit(v).parse().unwrap_or(v);
    GenParam {
        name,
        unit,
        nominal: v,
        lower: lit(v / factor).parse().unwrap_or(v / factor),
        upper: lit(v * factor).parse().unwrap_or(v * factor),
        log: true,
        scale: v,
        doc,
    }
}

fn lin_param(
    name: &'static str,
    unit: &'static str,
    v: f64,
    scale: f64,
    bound: f64,
    doc: &'static str,
) -> GenParam {
    let r = |x: f64| lit(x).parse().unwrap_or(x);
    GenParam {
        name,
        unit,
        nominal: r(v),
        lower: r(-bound),
        upper: r(bound),
        log: false,
        scale: r(scale),
        doc,
    }
}

/// The fitted value of the term's parameter `n` (`delay`, `tau`, ...).
fn fitted_parameter(k: &Term, n: &str) -> Result<f64, String> {
    k.parameter
        .as_ref()
        .filter(|p| p.name == n && p.value.is_finite())
        .map(|p| p.value)
        .ok_or_else(|| {
            format!(
                "the leading term ({}) carries no fitted {n}: nothing to scaffold from",
                k.kind
            )
        })
}

/// The term's fitted coefficient `j`.
fn fitted_coef(k: &Term, j: usize) -> Result<f64, String> {
    k.coefs
        .get(j)
        .copied()
        .filter(|c| c.is_finite())
        .ok_or_else(|| {
            format!(
                "the leading term ({}) carries no fitted coefficient {j}: nothing to scaffold from",
                k.kind
            )
        })
}

/// A `position` term: a restoring force of frequency `f0` [Hz], with its equilibrium `x_eq`
/// [m] in a scenario whose force has one. `Err` for an anti-restoring force.
fn restoring_params(k: &Term, scenario: Scenario) -> Result<Vec<GenParam>, String> {
    if k.coefs.first().is_some_and(|c| *c >= 0.0) || k.parameter.is_none() {
        return Err(format!(
            "the leading term is an anti-restoring force ({}): not a restoring force about an equilibrium, not scaffolded",
            k.term
        ));
    }
    let f0 = fitted_parameter(k, "f0")?;
    let mut v = vec![log_param(
        "f0",
        "Hz",
        f0,
        10.0,
        "frequency of the restoring force, w0 = 2 pi f0",
    )];
    if scenario.scaffold_force().equilibrium {
        let c0 = fitted_coef(k, 0)?;
        let x_eq = k.coefs.get(1).map_or(0.0, |c1| -c1 / c0);
        let x_eq = if x_eq.is_finite() { x_eq } else { 0.0 };
        v.push(lin_param(
            "x_eq",
            "m",
            x_eq,
            x_eq.abs().max(1e-7),
            (100.0 * x_eq.abs()).max(1e-3),
            "equilibrium of the restoring force (x at which it vanishes)",
        ));
    }
    Ok(v)
}

/// A `velocity` term: a damping of rate `gamma` [1/s]. `Err` for a negative damping.
fn damping_params(k: &Term) -> Result<Vec<GenParam>, String> {
    let g = fitted_parameter(k, "gamma")?;
    if g <= 0.0 {
        return Err(format!(
            "the leading term is a negative damping (gamma {g:.4e} 1/s): not a damping force, not scaffolded"
        ));
    }
    Ok(vec![log_param(
        "gamma",
        "1/s",
        g,
        100.0,
        "damping rate: the force is -m gamma times the velocity",
    )])
}

/// A `delay` term: the delay [s], bounded by ten times itself or 5 % of the record after the
/// trigger, `span` [s].
fn delay_params(k: &Term, span: f64) -> Result<Vec<GenParam>, String> {
    let d = fitted_parameter(k, "delay")?;
    Ok(vec![lin_param(
        "delay",
        "s",
        d,
        d.abs().max(1e-9),
        (10.0 * d.abs()).max(0.05 * span),
        "delay of the motion after the trigger: the model runs at t - delay",
    )])
}

/// A `creep` term: its amplitude `c` [m] and time constant `tau` [s].
fn creep_params(k: &Term) -> Result<Vec<GenParam>, String> {
    let tau = fitted_parameter(k, "tau")?;
    let c = fitted_coef(k, 0)?;
    Ok(vec![
        lin_param(
            "c",
            "m",
            c,
            c.abs().max(1e-12),
            (1e3 * c.abs()).max(1e-3),
            "creep amplitude",
        ),
        log_param("tau", "s", tau, 100.0, "creep time constant"),
    ])
}

/// A `slip` (a jump of the reading [m]) or an `impulse` (a velocity step [m/s]) at `t0` [s].
fn step_params(k: &Term) -> Result<Vec<GenParam>, String> {
    let t0 = fitted_parameter(k, "t0")?;
    let a = fitted_coef(k, 0)?;
    let (unit, doc_a) = if k.kind == "slip" {
        ("m", "jump of the reading")
    } else {
        ("m/s", "velocity step (the knock's impulse over the mass)")
    };
    Ok(vec![
        lin_param(
            "a",
            unit,
            a,
            a.abs().max(1e-12),
            (1e3 * a.abs()).max(1e-3),
            doc_a,
        ),
        log_param("t0", "s", t0, 2.0, "time of the jump after the trigger"),
    ])
}

/// A `vibration` term: its frequency `f` [Hz] and the amplitudes of its sine and cosine [m].
fn vibration_params(k: &Term) -> Result<Vec<GenParam>, String> {
    let f = fitted_parameter(k, "f")?;
    let (a_s, a_c) = (fitted_coef(k, 0)?, fitted_coef(k, 1)?);
    let amp = a_s.hypot(a_c).max(1e-15);
    Ok(vec![
        log_param("f", "Hz", f, 2.0, "vibration frequency"),
        lin_param(
            "a_s",
            "m",
            a_s,
            amp,
            (1e3 * amp).max(1e-3),
            "amplitude of the sine",
        ),
        lin_param(
            "a_c",
            "m",
            a_c,
            amp,
            (1e3 * amp).max(1e-3),
            "amplitude of the cosine",
        ),
    ])
}

/// The generated effect's parameters from the term `k` of a record of `scenario` with
/// `post_s` [s] after the trigger, every value finite.
fn params_of(k: &Term, scenario: Scenario, post_s: f64) -> Result<Vec<GenParam>, String> {
    let params = match k.kind.as_str() {
        "position" => restoring_params(k, scenario)?,
        "velocity" => damping_params(k)?,
        "delay" => delay_params(k, post_s.max(1e-9))?,
        "creep" => creep_params(k)?,
        "slip" | "impulse" => step_params(k)?,
        "vibration" => vibration_params(k)?,
        other => return Err(format!("no scaffold for a term of kind {other}")),
    };
    for p in &params {
        if !(p.nominal.is_finite() && p.lower.is_finite() && p.upper.is_finite()) {
            return Err(format!(
                "the leading term's {} is not finite: nothing to scaffold from",
                p.name
            ));
        }
    }
    Ok(params)
}

impl Scaffold {
    /// The effect `name` from the term `k` (a refined term of `discover`: its `coefs` and
    /// `parameter` set) of a record of `scenario` under `conditions`. `Err` (one line) for a
    /// term that is no physics of its kind (an anti-restoring force, a negative damping) or that
    /// lacks its fitted values.
    #[allow(clippy::too_many_arguments)]
    pub fn from_term(
        name: &str,
        scenario: Scenario,
        k: &Term,
        record: &str,
        indistinguishable: &[String],
        date: &str,
        conditions: Conditions,
    ) -> Result<Scaffold, String> {
        let params = params_of(k, scenario, conditions.post_s)?;
        Ok(Scaffold {
            name: name.to_string(),
            scenario,
            kind: k.kind.clone(),
            record: record.to_string(),
            delta_bic: k.delta_bic,
            term: k.term.clone(),
            indistinguishable: indistinguishable
                .iter()
                .filter(|s| **s != k.kind)
                .cloned()
                .collect(),
            passed_over: None,
            date: date.to_string(),
            params,
            conditions,
        })
    }

    /// The effect from the leading term of `terms` (a discover report's refined terms, the
    /// leader first), or, when the leader is no physics of its kind (an anti-restoring force, a
    /// negative damping) and the record could not tell it from another term (`twins`, the
    /// report's `indistinguishable`: joint fits within 10 in BIC), from the first such term that
    /// is, with the reason the leader was passed over (`passed_over`, in the doc comment it
    /// writes). Otherwise the leader's error; `Err` too when `terms` is empty.
    #[allow(clippy::too_many_arguments)]
    pub fn from_terms(
        name: &str,
        scenario: Scenario,
        terms: &[Term],
        record: &str,
        twins: &[String],
        date: &str,
        conditions: Conditions,
    ) -> Result<Scaffold, String> {
        let make = |k: &Term| {
            Scaffold::from_term(name, scenario, k, record, twins, date, conditions.clone())
        };
        let Some(lead) = terms.first() else {
            return Err("no term outside the catalogue: nothing to scaffold".to_string());
        };
        let refused = match make(lead) {
            Ok(s) => return Ok(s),
            Err(e) => e,
        };
        let others = terms.iter().skip(1);
        for k in others.filter(|k| k.kind != lead.kind && twins.contains(&k.kind)) {
            if let Ok(mut s) = make(k) {
                s.passed_over = Some(format!("`{}`: {refused}", lead.kind));
                return Ok(s);
            }
        }
        Err(refused)
    }

    /// The effect's type name.
    pub fn type_name(&self) -> String {
        camel(&self.name)
    }

    fn is_force(&self) -> bool {
        matches!(self.kind.as_str(), "position" | "velocity")
    }

    /// The [`Role`](geodesic_facility::effects::Role) variant of the effect (`Force`,
    /// `Mechanism`, `TimeShift`, `Distortion`); its capability trait is that name followed by
    /// `Effect`.
    fn role(&self) -> &'static str {
        if self.is_force() {
            self.scenario.scaffold_force().kind
        } else if self.kind == "delay" {
            "TimeShift"
        } else {
            "Distortion"
        }
    }

    /// The law in words (the doc comment and `summary`).
    pub fn law(&self) -> String {
        let force = self.scenario.scaffold_force();
        let ch = self.scenario.fitted_channel();
        match self.kind.as_str() {
            "position" => force.position_law.into(),
            "velocity" => force.velocity_law.into(),
            "delay" => "the motion delayed after the trigger: the model at t - delay".into(),
            "creep" => format!("creep c ln(1 + t/tau) after the trigger, added to {ch}"),
            "slip" => format!("a slip: a jump a at t0 after the trigger, added to {ch}"),
            "impulse" => {
                format!("an impulse: a velocity step a at t0, a (t - t0) after it, added to {ch}")
            }
            _ => format!("a vibration a_s sin(2 pi f t) + a_c cos(2 pi f t), added to {ch}"),
        }
    }

    /// The effect's source file (`models/facility/src/effects/NAME.rs`).
    pub fn effect_source(&self) -> String {
        let mut s = self.header();
        s.push_str(&self.params_static());
        s.push_str(&self.impl_effect());
        s.push('\n');
        let _ = writeln!(s, "impl {}Effect for {} {{", self.role(), self.type_name());
        s.push_str(&self.body());
        s.push_str("}\n\n");
        s.push_str(&self.impl_hints());
        s
    }

    /// The module comment, the imports and the type with its doc comment.
    fn header(&self) -> String {
        let name = &self.name;
        let mut s = String::new();
        s.push_str(&wrap(
            "//! ",
            &format!(
                "`{name}`: {} (scaffolded by `geodesic discover --scaffold`, issue 36).",
                self.law()
            ),
        ));
        s.push('\n');
        let capability = format!("{}Effect", self.role());
        let mut uses = vec![
            "Effect",
            "FitHints",
            "GuessContext",
            "ParamSpec",
            "Role",
            "Scenario",
            capability.as_str(),
        ];
        if self.is_force() {
            uses.push(self.scenario.scaffold_force().import);
        }
        uses.sort_unstable();
        let uses = uses.join(", ");
        let line = format!("use super::{{{uses}}};");
        if line.len() <= 100 {
            let _ = writeln!(s, "{line}");
        } else {
            // rustfmt breaks a long import one item a line
            s.push_str("use super::{\n");
            let _ = writeln!(s, "    {uses},");
            s.push_str("};\n");
        }
        s.push('\n');
        s.push_str(&wrap("/// ", &format!("{}.", capitalise(&self.law()))));
        s.push_str("///\n");
        let which = match &self.passed_over {
            None => "the leading term outside the catalogue".to_string(),
            Some(why) => format!(
                "a term outside the catalogue that the record could not tell from the leading one, which was passed over ({})",
                why.trim_end_matches('.')
            ),
        };
        let mut origin = format!(
            "Written by `geodesic discover {} --scaffold {name}` on {} from {which}: kind `{}`, delta BIC {:.1}: {}.",
            self.record.escape_debug(),
            self.date,
            self.kind,
            self.delta_bic,
            self.term.replace('\n', " ")
        );
        if !self.indistinguishable.is_empty() {
            origin.push_str(&format!(
                " The record could not tell it from: {} (joint fits within 10 in BIC).",
                self.indistinguishable.join(", ")
            ));
        }
        origin.push_str(
            " Starting values are the fitted term's, the ranges a decade or more around them: check them against the physics and cite a source.",
        );
        s.push_str(&wrap("/// ", &origin));
        s.push_str("#[derive(Debug, Clone, Copy)]\n");
        let _ = writeln!(s, "pub struct {};", self.type_name());
        s.push('\n');
        s
    }

    /// The `PARAMS` array, as rustfmt writes it.
    fn params_static(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "static PARAMS: [ParamSpec; {}] = [", self.params.len());
        for p in &self.params {
            let _ = writeln!(s, "    // {} [{}]", p.doc, p.unit);
            if p.log {
                let one = format!(
                    "    ParamSpec::log(\"{}\", \"{}\", {}, {}, {}),",
                    p.name,
                    p.unit,
                    lit(p.nominal),
                    lit(p.lower),
                    lit(p.upper)
                );
                // rustfmt's fn_call_width: 60
                let args = one.find('(').map_or(0, |i| one.len() - i - 3);
                if one.len() <= 100 && args <= 60 {
                    let _ = writeln!(s, "{one}");
                } else {
                    let _ = writeln!(s, "    ParamSpec::log(");
                    for a in [
                        format!("\"{}\"", p.name),
                        format!("\"{}\"", p.unit),
                        lit(p.nominal),
                        lit(p.lower),
                        lit(p.upper),
                    ] {
                        let _ = writeln!(s, "        {a},");
                    }
                    let _ = writeln!(s, "    ),");
                }
            } else {
                let _ = writeln!(s, "    ParamSpec {{");
                let _ = writeln!(s, "        name: \"{}\",", p.name);
                let _ = writeln!(s, "        unit: \"{}\",", p.unit);
                let _ = writeln!(s, "        nominal: {},", lit(p.nominal));
                let _ = writeln!(s, "        lower: {},", lit(p.lower));
                let _ = writeln!(s, "        upper: {},", lit(p.upper));
                let _ = writeln!(s, "        log: false,");
                let _ = writeln!(s, "        scale: {},", lit(p.scale));
                let _ = writeln!(s, "    }},");
            }
        }
        s.push_str("];\n\n");
        s
    }

    /// `impl Effect`: what every effect has, its role and its hints.
    fn impl_effect(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "impl Effect for {} {{", self.type_name());
        let _ = writeln!(
            s,
            "    fn name(&self) -> &'static str {{\n        \"{}\"\n    }}",
            self.name
        );
        let sc = self.scenario.handle_name();
        let _ = writeln!(
            s,
            "    fn scenario(&self) -> Scenario {{\n        Scenario::{sc}\n    }}"
        );
        let summary = format!("\"{} (from {})\"", self.law(), self.kind);
        if summary.len() + 8 <= 100 {
            let _ = writeln!(
                s,
                "    fn summary(&self) -> &'static str {{\n        {summary}\n    }}"
            );
        } else {
            let _ = writeln!(
                s,
                "    fn summary(&self) -> &'static str {{\n        \"{} \\\n         (from {})\"\n    }}",
                self.law(),
                self.kind
            );
        }
        s.push_str("    fn params(&self) -> &'static [ParamSpec] {\n        &PARAMS\n    }\n");
        let _ = writeln!(
            s,
            "    fn role(&self) -> Role<'_> {{\n        Role::{}(self)\n    }}",
            self.role()
        );
        s.push_str("    fn hints(&self) -> &dyn FitHints {\n        self\n    }\n");
        s.push_str("}\n");
        s
    }

    /// `impl FitHints`: where the effect vanishes, and the fitted term's values as the start.
    fn impl_hints(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "impl FitHints for {} {{", self.type_name());
        let null = match self.kind.as_str() {
            "position" | "velocity" => {
                let mut v = vec!["PARAMS[0].lower".to_string()];
                if self.params.len() > 1 {
                    v.push("0.0".into());
                }
                v
            }
            "delay" => vec!["0.0".into()],
            "creep" | "slip" | "impulse" => vec!["0.0".into(), "PARAMS[1].nominal".into()],
            _ => vec!["PARAMS[0].nominal".into(), "0.0".into(), "0.0".into()],
        };
        let _ = writeln!(
            s,
            "    fn null_params(&self) -> Option<Vec<f64>> {{\n        Some(vec![{}])\n    }}",
            null.join(", ")
        );
        s.push_str(
            "    fn starts(&self, _g: &GuessContext) -> Vec<Vec<f64>> {\n        // the fitted term's values\n        vec![PARAMS.iter().map(|p| p.nominal).collect()]\n    }\n",
        );
        s.push_str("}\n");
        s
    }

    /// The methods of the effect's law.
    fn body(&self) -> String {
        let force = self.scenario.scaffold_force();
        match self.kind.as_str() {
            "position" => force.position_code.into(),
            "velocity" => force.velocity_code.into(),
            "delay" => "    fn time_shift(&self, p: &[f64]) -> f64 {\n        p[0]\n    }\n".into(),
            "creep" => "    fn distortion(&self, p: &[f64], t: f64, _x: f64) -> f64 {\n        if t > 0.0 {\n            p[0] * (t / p[1]).ln_1p()\n        } else {\n            0.0\n        }\n    }\n".into(),
            "slip" => "    fn distortion(&self, p: &[f64], t: f64, _x: f64) -> f64 {\n        if t >= p[1] { p[0] } else { 0.0 }\n    }\n".into(),
            "impulse" => "    fn distortion(&self, p: &[f64], t: f64, _x: f64) -> f64 {\n        p[0] * (t - p[1]).max(0.0)\n    }\n".into(),
            _ => "    fn distortion(&self, p: &[f64], t: f64, _x: f64) -> f64 {\n        let w = std::f64::consts::TAU * p[0];\n        p[1] * (w * t).sin() + p[2] * (w * t).cos()\n    }\n".into(),
        }
    }

    /// The hiding test and the guard-list entry, as the new text of `hide_each.rs` from its
    /// old text `old`.
    pub fn hide_each(&self, old: &str) -> Result<String, String> {
        let marker = "    let tested = [\n";
        let i = old.find(marker).ok_or_else(|| {
            format!("{HIDE_EACH}: no guard list (`let tested = [`) to add the effect to")
        })?;
        let mut s = String::with_capacity(old.len() + 2048);
        s.push_str(&old[..i + marker.len()]);
        let _ = writeln!(s, "        \"{}\",", self.name);
        s.push_str(&old[i + marker.len()..]);
        if !s.ends_with('\n') {
            s.push('\n');
        }
        s.push('\n');
        s.push_str(&self.hiding_test());
        Ok(s)
    }

    /// The hiding test (appended to `hide_each.rs`).
    pub fn hiding_test(&self) -> String {
        let c = &self.conditions;
        let sc = self.scenario.handle_name();
        let mut s = String::new();
        s.push_str("#[test]\n");
        let _ = writeln!(s, "fn hidden_{}_is_named() {{", self.name);
        s.push_str(&wrap(
            "    // ",
            &format!(
                "discover --scaffold (issue 36): the conditions of {} (its sampling, length, noise and tip profile), the effect at its fitted values",
                self.record.escape_debug()
            ),
        ));
        s.push_str("    check_like(\n        &Case {\n");
        let _ = writeln!(s, "            scenario: Scenario::{sc},");
        let _ = writeln!(s, "            hidden: Some(\"{}\"),", self.name);
        let pairs: Vec<String> = self
            .params
            .iter()
            .map(|p| format!("(\"{}.{}\", {})", self.name, p.name, lit(p.nominal)))
            .collect();
        let one = format!("            params: &[{}],", pairs.join(", "));
        // rustfmt's array_width: 60
        if one.len() <= 100 && pairs.join(", ").len() <= 60 {
            let _ = writeln!(s, "{one}");
        } else {
            s.push_str("            params: &[\n");
            for p in &pairs {
                let _ = writeln!(s, "                {p},");
            }
            s.push_str("            ],\n");
        }
        let _ = writeln!(
            s,
            "            known: &[(\"{}\", {})],",
            c.known.0,
            lit(c.known.1)
        );
        let _ = writeln!(s, "            jerk: {},", lit(c.jerk_m_s3));
        s.push_str("            noise_in_yaml: true,\n");
        s.push_str("            seed: 36,\n");
        s.push_str("        },\n");
        let _ = writeln!(
            s,
            "        &Record {{\n            fs_hz: {},\n            post_s: {},\n            noise: {},\n            v_m_s: {},\n        }},",
            lit(c.fs_hz),
            lit(c.post_s),
            lit(c.noise),
            lit(c.v_m_s)
        );
        s.push_str("    );\n}\n");
        s
    }

    /// The registration (`mod`, `pub use`, the catalogue's line) as the new text of `mod.rs`
    /// from its old text `old`.
    pub fn mod_rs(&self, old: &str) -> Result<String, String> {
        let ty = self.type_name();
        let name = &self.name;
        let mut lines: Vec<String> = old.lines().map(str::to_string).collect();
        // in the sorted place among the lines of its kind (rustfmt sorts them)
        let sorted_in = |lines: &mut Vec<String>, prefix: &str, line: String| -> bool {
            let of_kind: Vec<usize> = (0..lines.len())
                .filter(|&j| lines[j].starts_with(prefix) && lines[j].ends_with(';'))
                .collect();
            let Some(&last) = of_kind.last() else {
                return false;
            };
            let at = of_kind
                .iter()
                .copied()
                .find(|&j| lines[j].as_str() > line.as_str())
                .unwrap_or(last + 1);
            lines.insert(at, line);
            true
        };
        if !sorted_in(&mut lines, "mod ", format!("mod {name};")) {
            return Err(format!(
                "{MOD_RS}: no `mod` lines to add `mod {name};` among"
            ));
        }
        if !sorted_in(&mut lines, "pub use ", format!("pub use {name}::{ty};")) {
            return Err(format!(
                "{MOD_RS}: no `pub use` lines to add the effect among"
            ));
        }
        let start = lines
            .iter()
            .position(|l| l.contains("fn catalogue()"))
            .ok_or_else(|| format!("{MOD_RS}: no `fn catalogue()`"))?;
        let end = (start..lines.len())
            .find(|&j| lines[j].trim_start().starts_with("];"))
            .ok_or_else(|| format!("{MOD_RS}: the list of `catalogue()` has no end (`];`)"))?;
        let item = (start..end)
            .rev()
            .find(|&j| {
                let t = lines[j].trim();
                t.starts_with('&') && t.ends_with(',')
            })
            .ok_or_else(|| format!("{MOD_RS}: the list of `catalogue()` has no entries"))?;
        let indent: String = lines[item]
            .chars()
            .take_while(|c| c.is_whitespace())
            .collect();
        lines.insert(item + 1, format!("{indent}&{ty},"));
        let mut s = lines.join("\n");
        s.push('\n');
        Ok(s)
    }

    /// Every file the scaffold writes under `root` (the repository's root), with its new text.
    pub fn edits(&self, root: &Path) -> Result<Vec<(PathBuf, String)>, String> {
        let read = |rel: &str| {
            std::fs::read_to_string(root.join(rel))
                .map_err(|e| format!("{}: {e}", root.join(rel).display()))
        };
        let mod_rs = self.mod_rs(&read(MOD_RS)?)?;
        let hide = self.hide_each(&read(HIDE_EACH)?)?;
        Ok(vec![
            (
                root.join(EFFECTS_DIR).join(format!("{}.rs", self.name)),
                self.effect_source(),
            ),
            (root.join(MOD_RS), mod_rs),
            (root.join(HIDE_EACH), hide),
        ])
    }
}

/// `text` as comment lines of at most 100 characters, each starting with `prefix`.
pub fn wrap(prefix: &str, text: &str) -> String {
    // a word that would open a Markdown list, quote or heading at the start of a line stays
    // with the word before it (rustdoc, clippy's doc_lazy_continuation)
    let marker = |w: &str| {
        matches!(w, "+" | "-" | "*" | ">" | "=" | "|")
            || w.starts_with('#')
            || (w.len() > 1
                && w.ends_with(['.', ')'])
                && w[..w.len() - 1].chars().all(|c| c.is_ascii_digit()))
    };
    let mut units: Vec<String> = Vec::new();
    for w in text.split_whitespace() {
        match units.last_mut() {
            Some(last) if marker(w) => {
                last.push(' ');
                last.push_str(w);
            }
            _ => units.push(w.to_string()),
        }
    }
    let mut out = String::new();
    let mut line = String::from(prefix);
    for w in &units {
        if line.len() > prefix.len() && line.len() + 1 + w.len() > 100 {
            out.push_str(line.trim_end());
            out.push('\n');
            line = String::from(prefix);
        }
        if line.len() > prefix.len() {
            line.push(' ');
        }
        line.push_str(w);
    }
    out.push_str(line.trim_end());
    out.push('\n');
    out
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().collect::<String>() + c.as_str(),
        None => String::new(),
    }
}

/// Whether `root` is the repository's root: the catalogue's registration and the hiding tests
/// are where the scaffold writes. `Err` is one line.
pub fn check_root(root: &Path) -> Result<(), String> {
    for rel in [MOD_RS, HIDE_EACH, "Cargo.toml"] {
        if !root.join(rel).is_file() {
            let shown = std::fs::canonicalize(root).unwrap_or_else(|_| root.to_path_buf());
            return Err(format!(
                "--scaffold writes into the repository: run it from the repository's root ({} has no {rel})",
                shown.display()
            ));
        }
    }
    Ok(())
}

/// `text` formatted by `rustfmt` (edition 2024, the repository's `rustfmt.toml` if any, found
/// from the working directory) when it runs; the text unchanged when rustfmt is not installed.
/// `Err` when rustfmt runs and refuses the text (a template bug).
pub fn rustfmt(text: &str, root: &Path) -> Result<String, String> {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let child = Command::new("rustfmt")
        .args(["--edition", "2024", "--emit", "stdout"])
        .current_dir(root)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn();
    let Ok(mut child) = child else {
        return Ok(text.to_string());
    };
    if let Some(mut stdin) = child.stdin.take() {
        stdin
            .write_all(text.as_bytes())
            .map_err(|e| format!("rustfmt: {e}"))?;
    }
    let out = child
        .wait_with_output()
        .map_err(|e| format!("rustfmt: {e}"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!(
            "rustfmt refused the generated code: {}",
            err.lines().next().unwrap_or("")
        ));
    }
    String::from_utf8(out.stdout).map_err(|e| format!("rustfmt: {e}"))
}

/// Writes every file of `edits` or none: each new text goes to a temporary file beside its
/// target, then all are renamed into place; on a failure, the files already replaced are
/// restored and the new ones removed. `Err` is one line.
pub fn write_all(edits: &[(PathBuf, String)]) -> Result<(), String> {
    let tmp = |p: &Path| {
        let mut s = p.as_os_str().to_owned();
        s.push(".scaffold-tmp");
        PathBuf::from(s)
    };
    // stage
    for (i, (p, text)) in edits.iter().enumerate() {
        if let Err(e) = std::fs::write(tmp(p), text) {
            for (q, _) in &edits[..=i] {
                let _ = std::fs::remove_file(tmp(q));
            }
            return Err(format!("{}: {e}", tmp(p).display()));
        }
    }
    // keep the old texts, then move into place
    let old: Vec<Option<Vec<u8>>> = edits.iter().map(|(p, _)| std::fs::read(p).ok()).collect();
    for (i, (p, _)) in edits.iter().enumerate() {
        if let Err(e) = std::fs::rename(tmp(p), p) {
            for (j, (q, _)) in edits.iter().enumerate() {
                if j < i {
                    match &old[j] {
                        Some(b) => {
                            let _ = std::fs::write(q, b);
                        }
                        None => {
                            let _ = std::fs::remove_file(q);
                        }
                    }
                } else {
                    let _ = std::fs::remove_file(tmp(q));
                }
            }
            return Err(format!("{}: {e}", p.display()));
        }
    }
    Ok(())
}

/// Today's date, `YYYY-MM-DD` (UTC).
pub fn today() -> String {
    geodesic_core::disposition::civil_from_days(geodesic_core::disposition::today())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A term of each kind, as `discover` reports it after its joint fit.
    pub(crate) fn term(kind: &str) -> Term {
        let (par, coefs) = match kind {
            "position" => (("f0", 1.6, "Hz"), vec![-101.06, 3.03e-3]),
            "velocity" => (("gamma", 100.0, "1/s"), vec![-100.0]),
            "delay" => (("delay", 3.0046e-6, "s"), vec![1.0]),
            "creep" => (("tau", 2e-4, "s"), vec![5e-9]),
            "slip" => (("t0", 1.2e-3, "s"), vec![-3e-9]),
            "impulse" => (("t0", 1.2e-3, "s"), vec![2e-6]),
            _ => (("f", 730.0, "Hz"), vec![3.7e-9, 1.5e-9]),
        };
        Term {
            kind: kind.into(),
            term: format!("a {kind} term"),
            parameter: Some(TermParameter {
                name: par.0.into(),
                value: par.1,
                unit: par.2.into(),
            }),
            delta_bic: -9990.5,
            coefs,
        }
    }

    fn conditions() -> Conditions {
        Conditions {
            fs_hz: 1e5,
            post_s: 0.02,
            known: ("m", 0.089),
            noise: 8e-10,
            jerk_m_s3: 6000.0,
            v_m_s: 3e-3,
        }
    }

    pub(crate) fn scaffold(kind: &str, scenario: Scenario) -> Scaffold {
        Scaffold::from_term(
            &format!("new_{kind}"),
            scenario,
            &term(kind),
            "data/examples/some record.yaml",
            &["slip".to_string()],
            "2026-11-27",
            conditions(),
        )
        .expect("a scaffold")
    }

    #[test]
    fn names_are_checked() {
        assert!(check_name("floor_pendulum", None).is_ok());
        for bad in [
            "",
            "Floor",
            "floor-pendulum",
            "2floor",
            "_floor",
            "floor_",
            "a__b",
            "fn",
            "tip_adhesion",
        ] {
            let e = check_name(bad, None).unwrap_err();
            assert!(!e.contains('\n') && e.starts_with("--scaffold"), "{e}");
        }
        assert!(
            check_name("tip_adhesion", None)
                .unwrap_err()
                .contains("catalogue")
        );
    }

    #[test]
    fn parameters_come_from_the_term() {
        let p = scaffold("position", Scenario::TmmfRelease).params;
        assert_eq!((p[0].name, p[0].nominal, p[0].unit), ("f0", 1.6, "Hz"));
        // x_eq = -c1 / c0
        assert!(
            (p[1].nominal - 3.03e-3 / 101.06).abs() < 1e-9,
            "{}",
            p[1].nominal
        );
        assert!(p[0].lower < 1.6 && 1.6 < p[0].upper && p[0].log);
        let v = scaffold("vibration", Scenario::TmmfRelease).params;
        assert_eq!(
            (v[0].nominal, v[1].nominal, v[2].nominal),
            (730.0, 3.7e-9, 1.5e-9)
        );
        let d = scaffold("delay", Scenario::RtRetraction).params;
        assert_eq!(d[0].nominal, 3.0046e-6);
        assert!(d[0].lower < 0.0 && d[0].upper > 3e-6);
        let mut anti = term("position");
        anti.coefs[0] = 50.0;
        let e = Scaffold::from_term(
            "x",
            Scenario::TmmfRelease,
            &anti,
            "r.yaml",
            &[],
            "2026-11-27",
            conditions(),
        )
        .unwrap_err();
        assert!(e.contains("anti-restoring"), "{e}");
    }

    #[test]
    fn comments_wrap_at_100_without_opening_a_list() {
        let text = "creep c ln(1 + t/tau) after the trigger ".repeat(12);
        let w = wrap("/// ", &text);
        for l in w.lines() {
            assert!(l.len() <= 100 && l.starts_with("/// "), "{l}");
            let body = &l[4..];
            assert!(!body.starts_with("+ ") && !body.starts_with("- "), "{l}");
        }
        assert_eq!(
            w.split_whitespace()
                .filter(|x| *x != "///")
                .collect::<Vec<_>>(),
            text.split_whitespace().collect::<Vec<_>>()
        );
    }

    #[test]
    fn literals_are_rust_floats() {
        for (v, s) in [
            (1.6, "1.6"),
            (100.0, "100.0"),
            (3e-5, "3e-5"),
            (-2.5e-9, "-2.5e-9"),
            (1.234567891, "1.23457"),
            (0.0, "0.0"),
            (2e6, "2e6"),
        ] {
            assert_eq!(lit(v), s);
        }
    }

    #[test]
    fn registration_goes_after_the_last_of_each_kind() {
        let old = "mod a;\nmod b;\n\npub use a::A;\npub use b::B;\n\npub fn catalogue() -> X {\n    static LIST: &[&dyn Effect] = &[\n        &A,\n        &B,\n    ];\n    LIST\n}\n";
        let s = scaffold("velocity", Scenario::TmmfRelease);
        let new = s.mod_rs(old).unwrap();
        assert_eq!(
            new,
            "mod a;\nmod b;\nmod new_velocity;\n\npub use a::A;\npub use b::B;\npub use new_velocity::NewVelocity;\n\npub fn catalogue() -> X {\n    static LIST: &[&dyn Effect] = &[\n        &A,\n        &B,\n        &NewVelocity,\n    ];\n    LIST\n}\n"
        );
        let hide = s
            .hide_each("fn g() {\n    let tested = [\n        \"drift\",\n    ];\n}\n")
            .unwrap();
        assert!(hide.contains("    let tested = [\n        \"new_velocity\",\n        \"drift\","));
        assert!(hide.contains("fn hidden_new_velocity_is_named()"));
        assert!(s.hide_each("fn g() {}\n").is_err());
    }

    #[test]
    fn write_all_writes_every_file_or_none() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.rs");
        std::fs::write(&a, "old").unwrap();
        let ok = vec![
            (a.clone(), "new".to_string()),
            (dir.path().join("b.rs"), "b".into()),
        ];
        write_all(&ok).unwrap();
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "new");
        // the second target's folder does not exist: nothing changes
        let bad = vec![
            (a.clone(), "newer".to_string()),
            (dir.path().join("no/such/c.rs"), "c".into()),
        ];
        assert!(write_all(&bad).is_err());
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "new");
        let left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left.len(), 2, "{left:?}");
    }
}
