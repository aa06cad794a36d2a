//! The GPRM piezo release mechanism (thesis ch. 3, physics.md §1): electrical circuit, plunger
//! and release tip.
//!
//! Per mechanism the state is `[q, l, l', y, y']`: charge on the piezo stack [C], plunger
//! position [m] and velocity [m/s], tip position [m] and velocity [m/s]. The local axis points
//! from the mechanism towards the TM. The release simulator sees only the [`Mechanism`] trait, so
//! another mechanism model is one new type, not an edit of the simulator.
//!
//! ```
//! use geodesic_mechanism::{Mechanism, PiezoMechanism, PiezoParams, VoltageCommand};
//! let mech = PiezoMechanism::new(PiezoParams::nominal(), VoltageCommand::ramp(120.0, 5.0e7));
//! let s0 = mech.initial_state(0.0);
//! // free static extension at 120 V: T E / k = 14.0 um (physics.md §1)
//! assert!((mech.tip_position_m(&s0) - mech.plunger_position_m(&s0) - 14.0e-6).abs() < 0.05e-6);
//! ```

mod command;
mod piezo;

pub use command::VoltageCommand;
pub use num_complex::Complex64;
pub use piezo::{PiezoMechanism, PiezoParams};

/// Modal decomposition of a mechanism that is linear in its state, its command voltage and the
/// contact force: `s' = A s + b_voltage E(t) + b_force F_c` with `A = V diag(eigenvalues) V^-1`.
/// The release integrator of `geodesic-release` (exponential Gauss collocation) propagates the
/// linear part exactly with it; a mechanism without one is integrated by Dormand-Prince.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Modes {
    /// Eigenvalues of `A` [1/s], complex conjugate pairs adjacent.
    pub eigenvalues: [Complex64; MECH_STATES],
    /// Right eigenvectors: `vectors[i][m]` is component `i` (state order) of the eigenvector of
    /// eigenvalue `m` (any normalisation).
    pub vectors: [[Complex64; MECH_STATES]; MECH_STATES],
    /// Input vector of the command voltage [state units / (s V)].
    pub b_voltage: [f64; MECH_STATES],
    /// Input vector of the contact force on the tip, positive compressive [state units / (s N)].
    pub b_force: [f64; MECH_STATES],
    /// The command voltage `E(t)`.
    pub command: VoltageCommand,
}

/// Number of state variables of one mechanism.
pub const MECH_STATES: usize = 5;

/// A release mechanism driven by a command voltage and loaded by a contact force.
pub trait Mechanism: Send + Sync {
    /// Static equilibrium state `[q, l, l', y, y']` before release (t < 0) with a compressive
    /// contact force `preload_n` [N] on the tip (physics.md §3).
    fn initial_state(&self, preload_n: f64) -> [f64; MECH_STATES];

    /// Time derivative of the state at time `t_s` [s] under the contact force `contact_force_n`
    /// [N] on the tip (positive when compressive, i.e. the TM pushes the tip back).
    fn derivatives(
        &self,
        t_s: f64,
        s: &[f64; MECH_STATES],
        contact_force_n: f64,
        ds: &mut [f64; MECH_STATES],
    );

    /// Tip position [m] (towards the TM).
    fn tip_position_m(&self, s: &[f64; MECH_STATES]) -> f64 {
        s[3]
    }

    /// Tip velocity [m/s] (towards the TM).
    fn tip_velocity_m_s(&self, s: &[f64; MECH_STATES]) -> f64 {
        s[4]
    }

    /// Plunger position [m].
    fn plunger_position_m(&self, s: &[f64; MECH_STATES]) -> f64 {
        s[1]
    }

    /// Times after release [s] where the right-hand side has a kink (e.g. the end of the voltage
    /// ramp); the integrator steps onto them.
    fn breakpoints_s(&self) -> Vec<f64>;

    /// Typical magnitudes of the state variables, for absolute error tolerances.
    fn state_scales(&self) -> [f64; MECH_STATES];

    /// The modal decomposition if the mechanism is linear (see [`Modes`]); `None` (the default)
    /// when it is not or when the decomposition failed (then the release falls back to a
    /// general-purpose integrator).
    fn modes(&self) -> Option<Modes> {
        None
    }
}
