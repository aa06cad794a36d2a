//! Observers of long computations (issue 51, as argmin's observers): a fit of a million-sample
//! record takes seconds to minutes, and a user must see where it is (the stage, the
//! Levenberg-Marquardt iterations and their chi-square); a developer may want the search's
//! inner decisions. The library prints nothing itself and reads no global or environment
//! variable: the caller passes an [`Observer`] in with its options (a [`SharedObserver`] in
//! the identification options, a `&dyn Observer` in [`LmOptions`](crate::lm::LmOptions)).
//! Every method has a no-op default; [`Silent`] is the observer of a caller that passes none.
//! An observer never changes a result.

use std::sync::Arc;

/// Records shorter than this many samples report no iterations (their fits take a second or
/// less); their stages are still reported.
pub const ITERATION_SAMPLES: usize = 100_000;

/// A receiver of a computation's progress and debug lines. Both methods default to doing
/// nothing; an implementation overrides what it wants to see.
pub trait Observer: Send + Sync {
    /// A progress line. A `milestone` (a stage done) should be shown; the others (single
    /// iterations) may be thinned by the receiver.
    fn progress(&self, line: &str, milestone: bool) {
        let _ = (line, milestone);
    }

    /// A new stage of a long loop began (a discovery round, a screening pass): `label` says
    /// what runs now. A front end may show it in place of the previous one.
    fn stage(&self, label: &str) {
        let _ = label;
    }

    /// Whether [`debug`](Observer::debug) lines are wanted: a computation may skip the work
    /// of a diagnosis that only a debug line would show.
    fn debugging(&self) -> bool {
        false
    }

    /// A debug line (the search's inner decisions), formatted only when the observer calls
    /// `line`; by default it does not.
    fn debug(&self, line: &dyn Fn() -> String) {
        let _ = line;
    }
}

/// The observer that sees nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Observer for Silent {}

/// An observer shared by the options of a computation and the threads it runs on; its
/// default is [`Silent`]. It dereferences to the observer.
#[derive(Clone)]
pub struct SharedObserver(Arc<dyn Observer>);

impl SharedObserver {
    /// Shares `o`.
    pub fn new(o: impl Observer + 'static) -> Self {
        SharedObserver(Arc::new(o))
    }

    /// Shares an observer already in an [`Arc`] (the caller keeps its handle to read what
    /// the observer recorded).
    pub fn from_arc(o: Arc<dyn Observer>) -> Self {
        SharedObserver(o)
    }
}

impl Default for SharedObserver {
    fn default() -> Self {
        SharedObserver::new(Silent)
    }
}

impl std::fmt::Debug for SharedObserver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SharedObserver")
    }
}

impl std::ops::Deref for SharedObserver {
    type Target = dyn Observer;

    fn deref(&self) -> &Self::Target {
        &*self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    #[derive(Default)]
    struct Record(Mutex<Vec<(String, bool)>>);

    impl Observer for Record {
        fn progress(&self, line: &str, milestone: bool) {
            self.0.lock().unwrap().push((line.to_string(), milestone));
        }
    }

    #[test]
    fn the_defaults_format_nothing_and_a_shared_observer_reaches_its_receiver() {
        let called = std::sync::atomic::AtomicBool::new(false);
        Silent.debug(&|| {
            called.store(true, std::sync::atomic::Ordering::SeqCst);
            String::new()
        });
        assert!(!called.load(std::sync::atomic::Ordering::SeqCst));
        assert!(!Silent.debugging());
        let rec = Arc::new(Record::default());
        let shared = SharedObserver::from_arc(rec.clone());
        shared.clone().progress("stage done", true);
        assert_eq!(
            rec.0.lock().unwrap().as_slice(),
            &[("stage done".to_string(), true)]
        );
    }
}
