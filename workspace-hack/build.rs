//! Empty: a build script makes cargo build the `[build-dependencies]` of `Cargo.toml`, whose
//! features proc macros and build scripts then share (see `Cargo.toml`).
fn main() {}
