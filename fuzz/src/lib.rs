//! A mutation fuzzer for geodesic's parsers of untrusted input, on the stable toolchain.
//!
//! Why by hand: only the stable Rust toolchain is available to the project, so libFuzzer
//! (`cargo fuzz`, which needs nightly's `-Z sanitizer` coverage instrumentation) and AFL's
//! compiler plugins are out. What matters for issue 12 is that no input makes a parser panic,
//! abort, hang or accept non-finite values, and a small deterministic mutator seeded with the
//! repository's real files finds those well enough: the harness is a few hundred lines with no
//! dependency beyond the workspace's own (`rand_chacha` for the deterministic stream,
//! `tempfile` for the scratch directory).
//!
//! * [`targets`]: one target per parser; a target feeds the bytes to the parser (through a
//!   file in the run's scratch directory when the API takes a path) and checks its contract:
//!   `Ok`, or an error whose `Display` is one line naming the file; a success holds no NaN or
//!   infinity (see [`targets::non_finite`]).
//! * [`mutate`]: bit flips, byte insert/delete/duplicate, splicing two inputs, dictionary
//!   tokens per format (`NaN`, `1e308`, `&a`, `<!DOCTYPE`, ...), CRLF, BOM, invalid UTF-8, deep
//!   nesting, long strings, line duplication/deletion/swaps.
//! * [`run`]: the loop. Panics are caught with [`std::panic::catch_unwind`] (the panic hook
//!   silenced while fuzzing), failing inputs are written to `fuzz/crashes/<target>-<hash>`.
//!   A crude coverage signal keeps inputs whose outcome (the error message with numbers and
//!   quoted text removed) was not seen before, so the corpus grows towards new error paths.

pub mod mutate;
pub mod run;
pub mod targets;

pub use run::{Finding, FindingKind, Options, Stats, fuzz, replay};
pub use targets::{Ctx, Outcome, TARGETS, Target, find};
