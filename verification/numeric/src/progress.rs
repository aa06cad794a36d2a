//! Progress of long fits (issue 35, item 6): a fit of a million-sample record takes seconds to
//! minutes, and a user must see where it is (the stage, the Levenberg-Marquardt iterations and
//! their chi-square). The library prints nothing itself: a front end (the CLI, under its quiet
//! rule: standard error only with `--progress` or on a terminal) installs a hook with
//! [`set_hook`]; without one, [`note`] costs a lock and nothing else, and the message is never
//! formatted. The hook never changes a result.

use std::sync::{Arc, Mutex};

/// A receiver of progress lines: `(line, milestone)`. A milestone (a stage done) should be
/// shown; the others (single iterations) may be thinned by the receiver.
pub type Hook = Arc<dyn Fn(&str, bool) + Send + Sync>;

static HOOK: Mutex<Option<Hook>> = Mutex::new(None);

/// Records shorter than this many samples report no iterations (their fits take a second or
/// less); their stages are still reported.
pub const ITERATION_SAMPLES: usize = 100_000;

/// Installs (`Some`) or removes (`None`) the process's progress hook.
pub fn set_hook(h: Option<Hook>) {
    if let Ok(mut g) = HOOK.lock() {
        *g = h;
    }
}

/// Sends a progress line to the hook, if one is installed (`msg` is only called then).
pub fn note(milestone: bool, msg: impl FnOnce() -> String) {
    let h = HOOK.lock().ok().and_then(|g| g.clone());
    if let Some(h) = h {
        h(&msg(), milestone);
    }
}
