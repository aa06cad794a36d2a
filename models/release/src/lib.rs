//! The two-sided in-flight release of the LISA Pathfinder test mass (thesis ch. 6, physics.md §3),
//! its integrators and its Monte Carlo.
//!
//! - [`model`]: the 12-state release system built from any [`geodesic_mechanism::Mechanism`] and
//!   [`geodesic_contact::ContactLaw`];
//! - [`integrator`]: the [`integrator::Integrator`] trait, an adaptive Dormand-Prince 5(4) with
//!   event localisation and a fixed-step RK4 reference;
//! - [`inputs`]: the explicit inputs of one release and the nominal values.
//!
//! ```
//! use geodesic_release::{inputs::ReleaseInputs, integrator::DormandPrince};
//! let mut r = ReleaseInputs::nominal();
//! r.a1_n_m[1] = 1.5e5;
//! r.lambda_m[1] = 8e-7;
//! let out = r.simulate(&DormandPrince::fast()).unwrap();
//! // adhesion on side 2 pulls the TM towards mechanism 2 (+X): about 1.43 um/s
//! assert!((out.v_tm_m_s * 1e6 - 1.4327).abs() < 0.01);
//! ```

pub mod budget;
pub mod calibration;
pub mod expgauss;
pub mod figures;
pub mod inputs;
pub mod integrator;
pub mod model;
pub mod montecarlo;
pub mod parts;
pub mod population;
pub mod report;
pub mod sensitivity;
pub mod stats;
pub mod tipradius;
