//! Identification models of the measurement scenarios (physics.md sections 4 and 5).
//!
//! A model is a composition of named effects ([`effects::Effect`]), each one Rust type in its own
//! file under `effects/`, registered in one list ([`effects::catalogue`]) that fit, diagnose,
//! synth and the reports read. A scenario is a type implementing [`ScenarioSpec`], registered
//! in [`scenario::registry`]. Two scenarios exist:
//!
//! - `tmmf-release` ([`tmmf`]): one-sided release of a pendulum TM mock-up in the TMMF
//!   (thesis ch. 5, physics.md section 4); the measured tip motion drives the TM dynamics.
//! - `rt-retraction` ([`retraction`]): unloaded retraction of the GPRM release tip (thesis ch. 3,
//!   physics.md sections 1 and 5), a linear ODE in charge, plunger and tip.
//!
//! This crate does no I/O: datasets, fitting and reports live in `geodesic-fit`.

pub mod effects;
pub mod model;
pub mod predict;
pub mod profile;
pub mod retraction;
pub mod rk4;
pub mod scenario;
pub mod tmmf;
pub mod trap;

pub use effects::{Effect, EffectKind, ParamSpec, by_name, catalogue};
pub use model::{Model, ModelError};
pub use profile::TipProfile;
pub use scenario::{Scenario, ScenarioSpec};
