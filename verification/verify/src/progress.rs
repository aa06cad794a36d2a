//! Progress on standard error for runs longer than a few seconds.
//!
//! Standard error otherwise carries errors and the warnings a user must see only (issue 35):
//! a run piped into a log or a CI step prints its one-line error alone.
//!
//! Shown when standard error is a terminal and the command was not asked for `--json`; never
//! with `--quiet`; always with `--progress` (then, when standard error is not a terminal, as
//! plain lines: a start line, one line per 10 % of a counted task of 20 steps or more, and an end line with the
//! elapsed time, so a CI log shows where a long run is). Standard output is never touched.

use std::io::IsTerminal;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// When progress is shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// On a terminal, without `--json`.
    Auto,
    /// Always (`--progress`).
    Always,
    /// Never (`--quiet`).
    Never,
}

static MODE: OnceLock<Mode> = OnceLock::new();

/// Sets the mode once, from the global flags.
pub fn set_mode(m: Mode) {
    let _ = MODE.set(m);
}

fn mode() -> Mode {
    *MODE.get().unwrap_or(&Mode::Auto)
}

/// Whether a command run with (or without) `--json` shows progress.
pub fn enabled(json: bool) -> bool {
    match mode() {
        Mode::Always => true,
        Mode::Never => false,
        Mode::Auto => !json && std::io::stderr().is_terminal(),
    }
}

/// A callback receiving a library's progress lines (`line`, `milestone`).
pub type LineHook = std::sync::Arc<dyn Fn(&str, bool) + Send + Sync>;

/// A task whose progress is shown: a counted bar or a spinner with the elapsed time.
pub struct Task {
    bar: Option<indicatif::ProgressBar>,
    plain: bool,
    label: String,
    name: String,
    total: u64,
    done: AtomicU64,
    next_tenth: AtomicU64,
    t0: Instant,
}

impl Task {
    fn new(json: bool, label: &str, total: Option<u64>) -> Task {
        let on = enabled(json);
        let tty = std::io::stderr().is_terminal();
        let bar = (on && tty).then(|| {
            let (b, template) = match total {
                Some(n) => (
                    indicatif::ProgressBar::new(n),
                    "geodesic: {msg} {bar:30} {pos}/{len} ({elapsed}, eta {eta})",
                ),
                None => (
                    indicatif::ProgressBar::new_spinner(),
                    "geodesic: {spinner} {msg} ({elapsed})",
                ),
            };
            if let Ok(style) = indicatif::ProgressStyle::with_template(template) {
                b.set_style(style);
            }
            b.set_message(label.to_string());
            if total.is_none() {
                b.enable_steady_tick(Duration::from_millis(200));
            }
            b
        });
        let plain = on && !tty;
        if plain {
            eprintln!("geodesic: {label} ...");
        }
        Task {
            bar,
            plain,
            label: label.to_string(),
            name: label.to_string(),
            total: total.unwrap_or(0),
            done: AtomicU64::new(0),
            next_tenth: AtomicU64::new(1),
            t0: Instant::now(),
        }
    }

    /// A task of `total` steps (releases, fits).
    pub fn counter(json: bool, label: &str, total: u64) -> Task {
        Task::new(json, label, Some(total))
    }

    /// A task of unknown length: a spinner with the elapsed time.
    pub fn spinner(json: bool, label: &str) -> Task {
        Task::new(json, label, None)
    }

    /// Adds `k` done steps (thread-safe).
    pub fn inc(&self, k: u64) {
        if let Some(b) = &self.bar {
            b.inc(k);
        }
        if self.plain && self.total >= 20 {
            let done = self.done.fetch_add(k, Ordering::Relaxed) + k;
            let reached = (done.min(self.total) * 10 / self.total).min(9);
            let next = self.next_tenth.load(Ordering::Relaxed);
            if reached >= next
                && self
                    .next_tenth
                    .compare_exchange(next, reached + 1, Ordering::Relaxed, Ordering::Relaxed)
                    .is_ok()
            {
                eprintln!(
                    "geodesic: {} {} % ({done}/{}, {:.1} s)",
                    self.label,
                    reached * 10,
                    self.total,
                    self.t0.elapsed().as_secs_f64()
                );
            }
        }
    }

    /// Replaces the label shown (e.g. the check now running).
    pub fn set_label(&mut self, label: &str) {
        if let Some(b) = &self.bar {
            b.set_message(label.to_string());
        }
        if self.plain {
            eprintln!("geodesic: {label} ...");
        }
        self.label = label.to_string();
    }

    /// A line of progress (a check's wall time, a fit's iteration): above the bar on a
    /// terminal, a plain line with `--progress`, nothing when progress is not shown.
    pub fn note(&self, line: &str) {
        if let Some(b) = &self.bar {
            b.println(format!("geodesic: {line}"));
        } else if self.plain {
            eprintln!("geodesic: {line}");
        }
    }

    /// A hook for a library's progress lines (the fit library's `progress::Hook`) while this task runs:
    /// on a terminal the line replaces the spinner's message; with `--progress` elsewhere each
    /// stage is a line and the iterations between are thinned to one line every 2 s; `None`
    /// when progress is not shown.
    pub fn fit_hook(&self) -> Option<LineHook> {
        if self.bar.is_none() && !self.plain {
            return None;
        }
        let bar = self.bar.clone();
        let label = self.name.clone();
        let last: std::sync::Mutex<Option<Instant>> = std::sync::Mutex::new(None);
        Some(std::sync::Arc::new(move |line: &str, milestone: bool| {
            if let Some(b) = &bar {
                b.set_message(format!("{label}: {line}"));
                return;
            }
            let Ok(mut last) = last.lock() else { return };
            if milestone || last.is_none_or(|t| t.elapsed() >= Duration::from_secs(2)) {
                eprintln!("geodesic: {label}: {line}");
                *last = Some(Instant::now());
            }
        }))
    }

    /// Ends the task: clears the bar; in plain mode prints the elapsed time.
    pub fn finish(self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
        if self.plain {
            eprintln!(
                "geodesic: {} done ({:.1} s)",
                self.name,
                self.t0.elapsed().as_secs_f64()
            );
        }
    }
}
