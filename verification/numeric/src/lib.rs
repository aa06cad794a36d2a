//! geodesic-numeric: the numeric core of the fitting engine, what a least-squares identification
//! needs from numerical analysis and statistics. It knows nothing of datasets, models, effects,
//! scenarios or physics: its dependencies are `nalgebra`, `rand`, `rayon`, `rustfft`, `serde` and
//! `geodesic-util` (the normal distribution); `geodesic-fit` builds identification on top of it.
//!
//! - [`lm`]: bounded Levenberg-Marquardt with finite-difference (or exact) Jacobians.
//! - [`linalg`]: symmetric eigen-decomposition and pseudo-inverse with stated failure.
//! - [`residual`]: noise from differences, Ljung-Box whiteness, failure windows.
//! - [`noise`]: coloured (AR) measurement noise, Burg's method, the whitening filter.
//! - [`ensemble`]: the affine-invariant ensemble sampler, autocorrelation times, marginals.
//! - [`posterior`]: posterior summaries (truncated normals of the Laplace approximation).
//! - [`spectral`]: the amplitude spectral density of a sampled series (Welch, Hann window), its
//!   degrees of freedom and 95 % band.
//! - [`observe`]: the [`Observer`](observe::Observer) a caller passes in to see progress and
//!   debug lines (no global, no environment variable).

#![warn(missing_docs)]
pub mod ensemble;
pub mod linalg;
pub mod lm;
pub mod noise;
pub mod observe;
pub mod posterior;
pub mod residual;
pub mod spectral;
