//! The verification test binary: property-based (proptest) and snapshot (insta) tests that
//! declare, with `geodesic_core::verifies!`, the requirement IDs they verify. One module per
//! family.

mod capture;
mod charge;
mod fit;
mod framework;
mod images;
mod plunger;
mod release;
mod spectral;
