//! One module per `geodesic` command; each owns its clap `Args` and a `run` function.

pub mod asd;
pub mod campaign;
pub mod capture;
pub mod charge;
pub mod diagnose;
pub mod discover;
pub mod effects;
pub mod export;
pub mod fit;
pub mod history;
pub mod import;
pub mod merge;
pub mod montecarlo;
pub mod new;
pub mod plunger;
pub mod requirements;
pub mod sensitivity;
pub mod surfaces;
pub mod synth;
pub mod tipradius;
pub mod tiptrack;
pub mod verify;
