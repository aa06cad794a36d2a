//! Capture of the test mass (TM) by the drag-free and attitude control system after release
//! (thesis ch. 7; physics.md section 6).
//!
//! - [`state`]: the 12 TM states (offsets, velocities, angles, rates) and their YAML form;
//! - [`inputs`]: the capture inputs file (`capture.yaml`: `x_LIM`, drift time, the source of
//!   each state) and [`StateModel`], the one source of the TM state at the start of control
//!   that the capture checks and the TM state rows share;
//! - [`limits`]: the capture limits tied to a requirement box, and the derivation of the
//!   default limits;
//! - [`criterion`]: the quartic criterion `sum_i (x0_i/x_LIM,i)^4 < 1`, the consistency
//!   constraint, single-state limits and the largest capturable box scale;
//! - [`probability`]: statistics of a capture probability;
//! - [`shear`]: the shear illustration of thesis ch. 6 (tangential pull -> rate and velocity);
//!
//! Physics only: no I/O beyond reading YAML configuration, no CLI.
//!
//! ```
//! use geodesic_capture::{evaluate, StateName, TmState, Xlim};
//! let xlim = Xlim::default_set();
//! let mut s = TmState::zero();
//! s.set(StateName::Vz, -3e-6);
//! let e = evaluate(&xlim, &s);
//! assert!(e.captured);
//! assert_eq!(e.dominant[0].state, StateName::Vz);
//! ```

pub mod criterion;
pub mod error;
pub mod inputs;
pub mod limits;
pub mod probability;
pub mod report;
pub mod shear;
pub mod state;

pub use criterion::{
    Evaluation, Term, box_corner, consistency_residual, consistency_sum, evaluate, is_captured,
    max_box_scale, quartic_sum, single_state_limits, terms,
};
pub use error::CaptureError;
pub use inputs::{
    CaptureInputs, DEFAULT_CAPTURE_YAML, SourceKind, StateModel, StateSource, XlimDerivation,
    Z_9973, drift_rate_of,
};
pub use limits::{DeriveError, THESIS_BOX, Xlim, derive_xlim, derived_factor};
pub use probability::CaptureProbability;
pub use shear::{PulseShape, ShearInputs, THESIS_PRINTED_RATE_RAD_S, THESIS_PRINTED_VELOCITY_M_S};
pub use state::{N_STATES, StateName, TmState};
