//! `--threads N`: the worker pool of a command that runs draws in parallel.

use crate::error::CliError;

/// Largest `--threads`.
pub const MAX_THREADS: usize = 1024;

/// Checks `--threads`: 1..=[`MAX_THREADS`].
pub fn check_threads(t: Option<usize>) -> Result<(), CliError> {
    match t {
        Some(t) if t == 0 || t > MAX_THREADS => Err(CliError::usage(format!(
            "--threads {t}: must be 1 to {MAX_THREADS}"
        ))),
        _ => Ok(()),
    }
}

/// Runs `go` on a pool of `threads` workers (`--threads`), or on rayon's global pool. The
/// results do not depend on it (every draw has its own random stream).
pub fn with_threads<R: Send>(
    threads: Option<usize>,
    go: impl FnOnce() -> R + Send,
) -> Result<R, CliError> {
    Ok(match threads {
        Some(t) => rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .map_err(|e| CliError::usage(format!("--threads: {e}")))?
            .install(go),
        None => go(),
    })
}
