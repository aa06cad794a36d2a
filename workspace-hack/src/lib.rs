//! Nothing to call: this crate only asks for the features every geodesic build shares (its
//! `Cargo.toml` says why).
