//! Electrification of the test mass (TM) at release (thesis ch. 7, "Electrification of the TM
//! during the Release"; physics.md section 7).
//!
//! - [`capacitance`]: `C_RT` of the release-tip spherical cap by quadrature, exactly and in the
//!   small-angle closed form;
//! - [`budget`]: `Q` and `V_TM` from the contact voltage differences, their 2-sigma bounds
//!   analytically and by a seeded Monte Carlo;
//! - [`inputs`]: the charge inputs file (`models/charge/charge.yaml`) the checks read;
//! - [`neutralise`]: the time cosmic-ray charging takes to neutralise a negative charge.
//!
//! Physics only: no file I/O (the inputs file is parsed from its text), no CLI.
//!
//! ```
//! use geodesic_charge::{c_rt_quadrature_f, ChargeInputs, TipGeometry};
//! let c_rt = c_rt_quadrature_f(&TipGeometry::THESIS, 1e-12);
//! let inputs = ChargeInputs::thesis_with_c_rt(c_rt);
//! assert!(inputs.q_2sigma_e() > 3.1e8 && inputs.q_2sigma_e() < 3.2e8);
//! assert!(inputs.v_2sigma_v() > 1.05 && inputs.v_2sigma_v() < 1.07);
//! ```

pub mod budget;
pub mod capacitance;
pub mod inputs;
pub mod neutralise;
pub mod plunger;
pub mod report;

pub use budget::{
    COVERAGE_2SIGMA, ChargeInputs, ChargeMonteCarlo, ELEMENTARY_CHARGE_C, monte_carlo,
};
pub use capacitance::{EPS0_F_M, TipGeometry, c_rt_exact_f, c_rt_quadrature_f, c_rt_small_angle_f};
pub use inputs::{ChargeFile, DEFAULT_CHARGE_YAML};
pub use neutralise::{DAY_S, THESIS_RATE_E_S, time_to_neutralise_s};
