//! geodesic-util: the bottom layer every geodesic crate may use (models and framework alike); it
//! depends on no geodesic crate.
//!
//! - [`hash`]: SHA-256 of inputs and of framed parts.
//! - [`normal`]: the standard normal distribution (CDF, quantile).
//! - [`stats`]: exact order-statistic and binomial confidence bounds.
//! - [`text`]: text of error messages (one line, clipped).
//! - [`output`]: outputs written whole or not at all ([`output::write_atomic`],
//!   [`output::PendingFile`]) and the registry of temporary paths removed on a signal.
//! - [`fsio`]: bounded reading of input files.
//! - [`yaml`]: the position and one-line cause of a YAML error.
//! - [`escape`]: XML, HTML and SVG escaping, one implementation.

#![warn(missing_docs)]
pub mod escape;
pub mod fsio;
pub mod hash;
pub mod normal;
pub mod output;
pub mod stats;
pub mod text;
pub mod yaml;

pub use yaml::{YamlError, yaml_error};
