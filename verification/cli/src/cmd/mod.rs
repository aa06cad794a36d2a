//! One module per `geodesic` command; each owns its clap `Args` and a `run` function.

pub mod asd;
pub mod diagnose;
pub mod discover;
pub mod effects;
pub mod export;
pub mod fit;
pub mod history;
pub mod import;
pub mod new;
pub mod requirements;
pub mod schema;
pub mod surfaces;
pub mod synth;
pub mod tiptrack;
pub mod verify;
