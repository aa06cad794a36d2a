//! `geodesic-fuzz TARGET|all|list [--iterations N | --seconds S] [--seed S] [--hang-seconds S]`
//! and `geodesic-fuzz replay TARGET FILE|DIR...`: see fuzz/README.md.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use geodesic_fuzz::run::{CURRENT, save};
use geodesic_fuzz::targets::Ctx;
use geodesic_fuzz::{Options, TARGETS, Target, find, fuzz, replay};

const USAGE: &str =
    "usage: geodesic-fuzz TARGET|all [--iterations N | --seconds S] [--seed S] [--hang-seconds S]
       geodesic-fuzz replay TARGET FILE|DIR...
       geodesic-fuzz list
Fuzzes geodesic's parsers (default: 60 s per target, seed 1, hang threshold 2 s). Failing
inputs are written to fuzz/crashes/<target>-<hash>; exit status 1 if any input panicked,
broke the parser's contract or hung, 2 on a usage error.";

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("fuzz/ is inside the repository")
        .to_path_buf()
}

fn usage(msg: &str) -> ExitCode {
    eprintln!("geodesic-fuzz: {msg}\n{USAGE}");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(first) = args.first() else {
        return usage("no target");
    };
    let root = root();
    let crash_dir = root.join("fuzz/crashes");
    match first.as_str() {
        "-h" | "--help" => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        "list" => {
            for t in TARGETS {
                println!("{:<18} {}", t.name, t.about);
            }
            return ExitCode::SUCCESS;
        }
        "replay" => return replay_cmd(&args[1..], &root),
        _ => {}
    }
    let targets: Vec<&'static Target> = if first == "all" {
        TARGETS.iter().collect()
    } else {
        match find(first) {
            Some(t) => vec![t],
            None => {
                return usage(&format!(
                    "unknown target `{first}` (see `geodesic-fuzz list`)"
                ));
            }
        }
    };
    let mut opts = Options {
        iterations: None,
        seconds: 60.0,
        seed: 1,
        hang: Some(Duration::from_secs(2)),
        crash_dir: Some(crash_dir.clone()),
        progress: true,
    };
    let mut it = args[1..].iter();
    while let Some(a) = it.next() {
        let Some(v) = it.next() else {
            return usage(&format!("{a} needs a value"));
        };
        let bad = || usage(&format!("{a} {v}: not a valid value"));
        match a.as_str() {
            "--iterations" => match v.parse() {
                Ok(n) => opts.iterations = Some(n),
                Err(_) => return bad(),
            },
            "--seconds" => match v.parse::<f64>() {
                Ok(s) if s.is_finite() && s > 0.0 => opts.seconds = s,
                _ => return bad(),
            },
            "--seed" => match v.parse() {
                Ok(s) => opts.seed = s,
                Err(_) => return bad(),
            },
            "--hang-seconds" => match v.parse::<f64>() {
                Ok(s) if s.is_finite() && s > 0.0 => opts.hang = Some(Duration::from_secs_f64(s)),
                _ => return bad(),
            },
            _ => return usage(&format!("unknown option {a}")),
        }
    }
    let ctx = match Ctx::new(&root) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("geodesic-fuzz: cannot create a scratch directory: {e}");
            return ExitCode::from(2);
        }
    };
    start_watchdog(opts.hang.unwrap_or(Duration::from_secs(2)), crash_dir);
    let mut failed = 0;
    for t in targets {
        eprintln!("== {}: {}", t.name, t.about);
        let st = fuzz(t, &ctx, &root, &opts);
        eprintln!(
            "{}: {} inputs in {:.1} s, {} accepted, {} refused, corpus {}, {} finding(s)",
            t.name,
            st.iterations,
            st.seconds,
            st.accepted,
            st.refused,
            st.corpus,
            st.findings.len()
        );
        for f in &st.findings {
            println!("{f}");
        }
        failed += st.findings.len();
    }
    if failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// A thread that ends the process when one input runs for 10 times the hang threshold (at
/// least 10 s): it never returns, so the loop cannot report it. The input is saved first.
fn start_watchdog(hang: Duration, crash_dir: PathBuf) {
    let limit = (hang * 10).max(Duration::from_secs(10));
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(Duration::from_millis(200));
            let stuck = CURRENT.lock().ok().and_then(|g| {
                g.as_ref()
                    .filter(|(t0, _, _)| t0.elapsed() > limit)
                    .map(|(_, name, data)| (*name, data.clone()))
            });
            if let Some((name, data)) = stuck {
                let saved = save(&crash_dir, name, &data);
                println!(
                    "{name}: hang: an input ran for more than {:.0} s{}",
                    limit.as_secs_f64(),
                    saved.map_or(String::new(), |p| format!(" (input: {})", p.display()))
                );
                std::process::exit(1);
            }
        }
    });
}

fn replay_cmd(args: &[String], root: &Path) -> ExitCode {
    let Some((name, paths)) = args.split_first() else {
        return usage("replay needs a target");
    };
    let Some(t) = find(name) else {
        return usage(&format!("unknown target `{name}`"));
    };
    let ctx = match Ctx::new(root) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("geodesic-fuzz: cannot create a scratch directory: {e}");
            return ExitCode::from(2);
        }
    };
    let mut failed = 0;
    for p in paths {
        let p = Path::new(p);
        if p.is_dir() {
            match replay(t, &ctx, p) {
                Ok(fs) => {
                    for f in &fs {
                        println!("{f}");
                    }
                    failed += fs.len();
                }
                Err(e) => {
                    eprintln!("geodesic-fuzz: {}: {e}", p.display());
                    return ExitCode::from(2);
                }
            }
        } else {
            let data = match std::fs::read(p) {
                Ok(d) => d,
                Err(e) => {
                    eprintln!("geodesic-fuzz: {}: {e}", p.display());
                    return ExitCode::from(2);
                }
            };
            match geodesic_fuzz::run::run_one(t, &ctx, &data) {
                Ok(o) => {
                    println!("{}: {o:?}", p.display());
                    if matches!(o, geodesic_fuzz::Outcome::Violation(_)) {
                        failed += 1;
                    }
                }
                Err(m) => {
                    println!("{}: panic: {m}", p.display());
                    failed += 1;
                }
            }
        }
    }
    if failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
