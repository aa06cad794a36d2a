//! Fitting a model to a dataset, the crate's public face for it: the engine ([`crate::estimate`]:
//! data-driven multi-start Levenberg-Marquardt, covariance, profile likelihood), the prepared
//! dataset ([`crate::prepare`]) and the JSON report of interface.md ([`crate::report`]), under
//! the names callers have always used (`geodesic_fit::fit::FitReport`, ...). No module of this
//! crate imports this one: it only re-exports.

pub use crate::estimate::{
    FitOptions, FitOutcome, MAX_STARTS, SEARCH_SAMPLES, STEP_RATIO_TOLERANCE, SampledPosterior,
    default_starts, effective_sigma, fit, fit_model, model_for, posterior_of_fit, sample_posterior,
    scenario_effects,
};
pub use crate::prepare::{Prepared, ProfileFit};
pub use crate::report::{Correlation, FitReport, ParamOut};
