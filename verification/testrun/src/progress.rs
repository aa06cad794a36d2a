//! How a recorded test run (`cargo xtask test`, a project's `cargo run -- test`) runs the build and shows its progress (issue 37, item 6): cargo's
//! output is streamed as it comes, and a status says what is happening while cargo is silent
//! (a large crate compiling, a long test binary running). On a terminal the status is a line
//! redrawn every second under the output (`[3 min 12 s] building: 180 compiled, now
//! geodesic-fit`); in a log (CI) it is a line of its own after every minute of silence. At the
//! end: the build's and the tests' durations and the slowest test binaries.
//!
//! The text returned for the record (`crate::output`) is cargo's output alone, byte for byte.

use std::io::{IsTerminal, Read, Write};
use std::process::{Command, ExitStatus};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// A log line after this long without output.
const HEARTBEAT: Duration = Duration::from_secs(60);

/// `12 s`, `3 min 4 s`.
pub fn fmt_duration(d: Duration) -> String {
    let s = d.as_secs();
    if s < 60 {
        format!("{s} s")
    } else {
        format!("{} min {} s", s / 60, s % 60)
    }
}

/// What cargo is doing, read from its output lines.
#[derive(Debug, Default)]
pub struct State {
    /// Crates compiled so far (`Compiling` lines).
    pub compiled: usize,
    /// The last crate that started compiling.
    pub last_compiling: String,
    /// When the first test binary started (the end of the build).
    pub tests_started: Option<Instant>,
    /// The test binary running and when it started.
    pub running: Option<(String, Instant)>,
    /// Tests of the running binary: done, and announced (`running N tests`).
    pub done: usize,
    /// Tests the running binary announced.
    pub announced: usize,
    /// Each finished test binary and how long it ran.
    pub binaries: Vec<(String, Duration)>,
}

impl State {
    /// Takes in one line of cargo's output (ANSI escapes and carriage returns already gone).
    pub fn line(&mut self, line: &str, now: Instant) {
        let t = line.trim();
        if let Some(rest) = t.strip_prefix("Compiling ") {
            self.compiled += 1;
            self.last_compiling = rest.split_whitespace().next().unwrap_or("").to_string();
        } else if let Some(name) = binary_name(t) {
            self.finish_binary(now);
            self.tests_started.get_or_insert(now);
            self.running = Some((name, now));
            self.done = 0;
            self.announced = 0;
        } else if let Some(n) = t
            .strip_prefix("running ")
            .and_then(|r| r.split_whitespace().next())
            .and_then(|n| n.parse().ok())
        {
            self.announced = n;
        } else if t.starts_with("test ") && !t.starts_with("test result") && t.contains(" ... ") {
            self.done += 1;
        }
    }

    /// Closes the running binary's time.
    pub fn finish_binary(&mut self, now: Instant) {
        if let Some((name, start)) = self.running.take() {
            self.binaries.push((name, now - start));
        }
    }

    /// One line: the phase, what runs now.
    pub fn status(&self, elapsed: Duration) -> String {
        match &self.running {
            Some((name, start)) => format!(
                "[{}] testing: {name}, {} of {} tests done, {} in this binary",
                fmt_duration(elapsed),
                self.done,
                self.announced,
                fmt_duration(start.elapsed())
            ),
            None if self.compiled == 0 => {
                format!(
                    "[{}] cargo is resolving and checking the build",
                    fmt_duration(elapsed)
                )
            }
            None => format!(
                "[{}] building: {} crates compiled, the last started: {}",
                fmt_duration(elapsed),
                self.compiled,
                self.last_compiling
            ),
        }
    }

    /// The closing summary: build and test durations, the slowest binaries.
    /// `prefix` names the program (`xtask test`).
    pub fn summary(&self, prefix: &str, start: Instant, end: Instant) -> String {
        let build = self.tests_started.map_or(end - start, |t| t - start);
        let tests = self.tests_started.map_or(Duration::ZERO, |t| end - t);
        let mut slow: Vec<&(String, Duration)> = self.binaries.iter().collect();
        slow.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let list: Vec<String> = slow
            .iter()
            .take(5)
            .map(|(n, d)| format!("{n} {}", fmt_duration(*d)))
            .collect();
        format!(
            "{prefix}: build {} ({} crates compiled), tests {}; slowest test binaries: {}",
            fmt_duration(build),
            self.compiled,
            fmt_duration(tests),
            if list.is_empty() {
                "none".to_string()
            } else {
                list.join(", ")
            }
        )
    }
}

/// The short name of a test binary from a `Running` or `Doc-tests` line
/// (`Running tests/hide_each.rs (target/release/deps/hide_each-0a1b)` gives
/// `geodesic-fit hide_each` when the path names the crate, else `hide_each`).
fn binary_name(t: &str) -> Option<String> {
    if let Some(rest) = t.strip_prefix("Doc-tests ") {
        return Some(format!("doc-tests {}", rest.trim()));
    }
    let rest = t.strip_prefix("Running ")?;
    let src = rest.split_whitespace().next().unwrap_or(rest);
    let bin = rest
        .rsplit(['/', '\\'])
        .next()
        .unwrap_or(rest)
        .trim_end_matches([')', '`']);
    let bin = bin.rsplit_once('-').map_or(bin, |(s, _)| s);
    Some(if src.starts_with("unittests") {
        format!("{bin} (unit tests)")
    } else {
        bin.to_string()
    })
}

/// Runs cargo with stdout and stderr into one pipe (so that cargo's `Running` lines and the
/// tests' output stay in order), copies it to our stdout as it comes with the status of
/// [`State`], and returns cargo's text and exit status. `prefix` names the program on the
/// status lines (`xtask test`).
pub fn run_streamed(mut cmd: Command, prefix: &str) -> std::io::Result<(String, ExitStatus)> {
    let start = Instant::now();
    let (mut reader, writer) = std::io::pipe()?;
    cmd.stdout(writer.try_clone()?).stderr(writer);
    let mut child = cmd.spawn()?;
    drop(cmd); // closes our copies of the pipe's write end
    let (tx, rx) = mpsc::channel::<Vec<u8>>();
    let pump = std::thread::spawn(move || {
        let mut buf = [0u8; 8192];
        loop {
            match reader.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => {
                    if tx.send(buf[..n].to_vec()).is_err() {
                        break;
                    }
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(_) => break,
            }
        }
    });
    let tty = std::io::stdout().is_terminal();
    let mut out = std::io::stdout().lock();
    let mut text = Vec::new();
    let mut state = State::default();
    let mut partial = Vec::new();
    let mut last_output = Instant::now();
    let mut shown = false;
    loop {
        match rx.recv_timeout(Duration::from_secs(1)) {
            Ok(chunk) => {
                if tty && shown {
                    let _ = out.write_all(b"\r\x1b[K");
                    shown = false;
                }
                let _ = out.write_all(&chunk);
                text.extend_from_slice(&chunk);
                partial.extend_from_slice(&chunk);
                while let Some(i) = partial.iter().position(|&b| b == b'\n') {
                    let line: Vec<u8> = partial.drain(..=i).collect();
                    state.line(
                        &crate::output::strip_ansi(&String::from_utf8_lossy(&line)),
                        Instant::now(),
                    );
                }
                last_output = Instant::now();
                // a partial line (a test printing without a newline) is left alone
                if tty && partial.is_empty() {
                    let _ = write!(out, "{}", state.status(start.elapsed()));
                    shown = true;
                }
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if tty && partial.is_empty() {
                    let _ = write!(out, "\r\x1b[K{}", state.status(start.elapsed()));
                    shown = true;
                } else if !tty && last_output.elapsed() >= HEARTBEAT {
                    let _ = writeln!(out, "{prefix}: {}", state.status(start.elapsed()));
                    last_output = Instant::now();
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
        }
        let _ = out.flush();
    }
    if tty && shown {
        let _ = out.write_all(b"\r\x1b[K");
    }
    let _ = pump.join();
    let status = child.wait()?;
    let end = Instant::now();
    state.finish_binary(end);
    let _ = writeln!(out, "{}", state.summary(prefix, start, end));
    let _ = out.flush();
    Ok((String::from_utf8_lossy(&text).into_owned(), status))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_state_follows_the_build_and_the_tests() {
        let t0 = Instant::now();
        let mut s = State::default();
        for l in [
            "   Compiling serde v1.0.229",
            "   Compiling geodesic-fit v0.1.0 (/w/verification/fit)",
        ] {
            s.line(l, t0);
        }
        assert_eq!((s.compiled, s.last_compiling.as_str()), (2, "geodesic-fit"));
        assert!(
            s.status(Duration::from_secs(75))
                .starts_with("[1 min 15 s] building: 2 crates")
        );
        let t1 = t0 + Duration::from_secs(300);
        s.line(
            "     Running tests/hide_each.rs (target/release/deps/hide_each-0123abcd4567ef89)",
            t1,
        );
        s.line("running 3 tests", t1);
        s.line("test hidden_drift_is_named ... ok", t1);
        assert_eq!((s.done, s.announced), (1, 3));
        assert!(
            s.status(Duration::from_secs(301))
                .contains("testing: hide_each, 1 of 3")
        );
        s.line(
            "     Running unittests src/lib.rs (target/release/deps/geodesic_fit-0123abcd4567ef89)",
            t1 + Duration::from_secs(90),
        );
        s.line("   Doc-tests geodesic_core", t1 + Duration::from_secs(100));
        s.finish_binary(t1 + Duration::from_secs(101));
        let names: Vec<&str> = s.binaries.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            vec![
                "hide_each",
                "geodesic_fit (unit tests)",
                "doc-tests geodesic_core"
            ]
        );
        let sum = s.summary("xtask test", t0, t1 + Duration::from_secs(101));
        assert!(
            sum.contains("build 5 min 0 s (2 crates compiled), tests 1 min 41 s")
                && sum.contains("slowest test binaries: hide_each 1 min 30 s"),
            "{sum}"
        );
    }

    #[test]
    fn durations_read_as_minutes_and_seconds() {
        assert_eq!(fmt_duration(Duration::from_secs(59)), "59 s");
        assert_eq!(fmt_duration(Duration::from_secs(754)), "12 min 34 s");
    }
}
