//! The fuzzing loop, crash files and the replay of a regression corpus.

use std::collections::HashSet;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, Once};
use std::time::{Duration, Instant};

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::mutate::mutate;
use crate::targets::{Ctx, Outcome, Target};

/// How long and how to fuzz one target.
#[derive(Clone, Debug)]
pub struct Options {
    /// Mutated inputs to run (after the seeds); `None`: until `seconds`.
    pub iterations: Option<u64>,
    /// Wall-clock budget [s] when `iterations` is `None`.
    pub seconds: f64,
    /// Seed of the mutation stream (mixed with the target's name).
    pub seed: u64,
    /// An input running longer than this is a hang (binary only; `None`: not timed).
    pub hang: Option<Duration>,
    /// Where to write failing inputs (`None`: not written).
    pub crash_dir: Option<PathBuf>,
    /// Progress lines on stderr.
    pub progress: bool,
}

/// What went wrong with one input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FindingKind {
    /// The parser panicked.
    Panic,
    /// The parser broke its contract (see [`Outcome::Violation`]).
    Violation,
    /// The input took longer than the hang threshold.
    Hang,
}

impl std::fmt::Display for FindingKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FindingKind::Panic => "panic",
            FindingKind::Violation => "contract violation",
            FindingKind::Hang => "hang",
        })
    }
}

/// A failing input.
#[derive(Clone, Debug)]
pub struct Finding {
    /// Target name.
    pub target: &'static str,
    /// Kind.
    pub kind: FindingKind,
    /// One-line cause (panic message and location, violation, duration).
    pub message: String,
    /// The input.
    pub input: Vec<u8>,
    /// Where it was written.
    pub saved: Option<PathBuf>,
}

impl std::fmt::Display for Finding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut m = self.message.replace('\n', " ");
        if m.len() > 300 {
            let mut cut = 300;
            while !m.is_char_boundary(cut) {
                cut -= 1;
            }
            m.truncate(cut);
            m.push('…');
        }
        write!(f, "{}: {}: {m}", self.target, self.kind)?;
        if let Some(p) = &self.saved {
            write!(f, " (input: {})", p.display())?;
        }
        Ok(())
    }
}

/// Counts of one run.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// Inputs run (seeds included).
    pub iterations: u64,
    /// Inputs accepted.
    pub accepted: u64,
    /// Inputs refused with a proper error.
    pub refused: u64,
    /// Corpus size at the end (seeds and inputs with a new outcome).
    pub corpus: usize,
    /// Failing inputs.
    pub findings: Vec<Finding>,
    /// Wall-clock time [s].
    pub seconds: f64,
}

/// The message and location of the last panic, recorded by the silent panic hook.
static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);
static HOOK: Once = Once::new();

thread_local! {
    /// Whether this thread is running a fuzz input (its panics are findings, not failures).
    static IN_TARGET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Installs (once per process) a panic hook that records the panics of fuzz inputs instead of
/// printing them, and hands every other panic (a failing assertion of a test, a bug of the
/// harness) to the hook that was there before.
pub fn silence_panics() {
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if IN_TARGET.with(|f| f.get()) {
                if let Ok(mut g) = LAST_PANIC.lock() {
                    *g = Some(info.to_string().replace('\n', " "));
                }
            } else {
                previous(info);
            }
        }));
    });
}

/// Runs one input; `Err` is the panic's message.
pub fn run_one(t: &Target, ctx: &Ctx, data: &[u8]) -> Result<Outcome, String> {
    silence_panics();
    IN_TARGET.with(|f| f.set(true));
    let outcome = catch_unwind(AssertUnwindSafe(|| (t.run)(ctx, data)));
    IN_TARGET.with(|f| f.set(false));
    match outcome {
        Ok(o) => Ok(o),
        Err(payload) => {
            let recorded = LAST_PANIC.lock().ok().and_then(|mut g| g.take());
            Err(recorded.unwrap_or_else(|| {
                payload
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| payload.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "panic with a non-string payload".into())
            }))
        }
    }
}

/// The first 16 hex digits of the SHA-256 of `data`.
pub fn short_hash(data: &[u8]) -> String {
    geodesic_util::hash::sha256_hex(data)[..16].to_string()
}

/// Writes a failing input to `dir/<target>-<hash>`.
pub fn save(dir: &Path, target: &str, data: &[u8]) -> Option<PathBuf> {
    std::fs::create_dir_all(dir).ok()?;
    let p = dir.join(format!("{target}-{}", short_hash(data)));
    std::fs::write(&p, data).ok()?;
    Some(p)
}

/// A coarse identity of an outcome (the crude coverage signal): the message with digits and
/// quoted text removed, cut to 80 characters.
fn signature(o: &Outcome) -> String {
    let m = match o {
        Outcome::Accepted => return "ok".into(),
        Outcome::Refused(m) | Outcome::Violation(m) => m,
    };
    let mut out = String::new();
    let mut quote: Option<char> = None;
    for c in m.chars() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '`' || c == '"' || c == '\'' => quote = Some(c),
            None if c.is_ascii_digit() => {}
            None => out.push(c),
        }
        if out.len() >= 80 {
            break;
        }
    }
    out
}

fn target_seed(seed: u64, name: &str) -> u64 {
    // FNV-1a of the name, so that every target has its own stream for one --seed
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in name.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    seed ^ h
}

/// The input being run, for a watchdog thread that catches real hangs (an input that never
/// returns): see the binary.
pub static CURRENT: Mutex<Option<(Instant, &'static str, Vec<u8>)>> = Mutex::new(None);

/// Fuzzes `t`: its seeds first, then mutated inputs until `opts` says stop.
pub fn fuzz(t: &'static Target, ctx: &Ctx, root: &Path, opts: &Options) -> Stats {
    let t0 = Instant::now();
    let mut rng = ChaCha8Rng::seed_from_u64(target_seed(opts.seed, t.name));
    let seeds = (t.seeds)(root);
    let mut corpus: Vec<Vec<u8>> = seeds.clone();
    if corpus.is_empty() {
        corpus.push(Vec::new());
    }
    let mut seen: HashSet<String> = HashSet::new();
    let mut st = Stats::default();
    let mut reported: HashSet<String> = HashSet::new();
    let mut last_progress = Instant::now();
    let mut i: u64 = 0;
    loop {
        let data = if (i as usize) < seeds.len() {
            seeds[i as usize].clone()
        } else {
            let done = match opts.iterations {
                Some(n) => i >= seeds.len() as u64 + n,
                None => t0.elapsed().as_secs_f64() >= opts.seconds,
            };
            if done {
                break;
            }
            let parent = &corpus[rng.random_range(0..corpus.len())];
            mutate(&mut rng, parent, &corpus, t.dict)
        };
        i += 1;
        let timed = opts.hang.is_some();
        if timed && let Ok(mut g) = CURRENT.lock() {
            *g = Some((Instant::now(), t.name, data.clone()));
        }
        let started = Instant::now();
        let r = run_one(t, ctx, &data);
        let took = started.elapsed();
        if timed && let Ok(mut g) = CURRENT.lock() {
            *g = None;
        }
        st.iterations += 1;
        let mut found: Vec<(FindingKind, String)> = Vec::new();
        let outcome = match r {
            Ok(o) => Some(o),
            Err(panic) => {
                found.push((FindingKind::Panic, panic));
                None
            }
        };
        if let Some(h) = opts.hang
            && took > h
        {
            found.push((
                FindingKind::Hang,
                format!(
                    "took {:.1} s (threshold {:.1} s)",
                    took.as_secs_f64(),
                    h.as_secs_f64()
                ),
            ));
        }
        match &outcome {
            Some(Outcome::Accepted) => st.accepted += 1,
            Some(Outcome::Refused(_)) => st.refused += 1,
            Some(Outcome::Violation(m)) => found.push((FindingKind::Violation, m.clone())),
            None => {}
        }
        for (kind, message) in found {
            // one report per distinct cause (the message without numbers and quotes)
            let head = message.split('`').next().unwrap_or("");
            let key = format!("{kind}:{}", signature(&Outcome::Refused(head.to_string())));
            if !reported.insert(key) {
                continue;
            }
            let saved = opts
                .crash_dir
                .as_deref()
                .and_then(|d| save(d, t.name, &data));
            let f = Finding {
                target: t.name,
                kind,
                message,
                input: data.clone(),
                saved,
            };
            if opts.progress {
                eprintln!("FOUND {f}");
            }
            st.findings.push(f);
        }
        let Some(outcome) = outcome else {
            continue;
        };
        if seen.insert(signature(&outcome)) && corpus.len() < 4096 && !data.is_empty() {
            corpus.push(data);
        }
        if opts.progress && last_progress.elapsed() >= Duration::from_secs(5) {
            last_progress = Instant::now();
            eprintln!(
                "{}: {} inputs ({:.0}/s), {} accepted, {} refused, corpus {}, findings {}",
                t.name,
                st.iterations,
                st.iterations as f64 / t0.elapsed().as_secs_f64(),
                st.accepted,
                st.refused,
                corpus.len(),
                st.findings.len()
            );
        }
    }
    st.corpus = corpus.len();
    st.seconds = t0.elapsed().as_secs_f64();
    st
}

/// Runs every file of `dir` (sorted by name) through `t`; returns the failures.
pub fn replay(t: &'static Target, ctx: &Ctx, dir: &Path) -> std::io::Result<Vec<Finding>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    let mut out = Vec::new();
    for p in files {
        let data = std::fs::read(&p)?;
        let (kind, message) = match run_one(t, ctx, &data) {
            Err(m) => (FindingKind::Panic, m),
            Ok(Outcome::Violation(m)) => (FindingKind::Violation, m),
            Ok(_) => continue,
        };
        out.push(Finding {
            target: t.name,
            kind,
            message,
            input: data,
            saved: Some(p),
        });
    }
    Ok(out)
}
