//! Every target for a fixed number of mutated inputs with a fixed seed, the seeds from the
//! repository's real files, and the regression corpus `fuzz/regressions/<target>/`.

use std::path::{Path, PathBuf};

use geodesic_fuzz::run::run_one;
use geodesic_fuzz::{Ctx, Options, Outcome, TARGETS, fuzz, replay};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

#[test]
fn every_target_survives_a_fixed_run() {
    let root = root();
    let ctx = Ctx::new(&root).unwrap();
    let opts = Options {
        iterations: Some(400),
        seconds: 0.0,
        seed: 12,
        hang: None,
        crash_dir: None,
        progress: false,
    };
    let mut failures = Vec::new();
    for t in TARGETS {
        let st = fuzz(t, &ctx, &root, &opts);
        assert!(
            st.iterations >= 400,
            "{}: {} inputs run",
            t.name,
            st.iterations
        );
        assert!(
            st.refused > 0,
            "{}: the mutations never reached an error",
            t.name
        );
        failures.extend(st.findings.iter().map(|f| f.to_string()));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_seeds_reach_the_success_path() {
    // every real file given as a seed keeps the parser's contract, and each target has seeds
    // the parser accepts (the harness reaches the success path). Some seeds are refused by
    // design: a ReqIF sample that needs `--attribute`, a shard that is merged only with its
    // siblings.
    let root = root();
    let ctx = Ctx::new(&root).unwrap();
    for t in TARGETS {
        let seeds = (t.seeds)(&root);
        assert!(!seeds.is_empty(), "{}: no seed", t.name);
        let mut accepted = 0;
        for (i, s) in seeds.iter().enumerate() {
            let o = run_one(t, &ctx, s).unwrap_or_else(|p| panic!("{} seed {i}: {p}", t.name));
            assert!(
                !matches!(o, Outcome::Violation(_)),
                "{} seed {i}: {o:?}",
                t.name
            );
            accepted += usize::from(o == Outcome::Accepted);
        }
        assert!(accepted > 0, "{}: no seed accepted", t.name);
    }
}

#[test]
fn the_regression_corpus_is_refused_cleanly() {
    let root = root();
    let ctx = Ctx::new(&root).unwrap();
    let mut replayed = 0;
    for t in TARGETS {
        let dir = root.join("fuzz/regressions").join(t.name);
        if !dir.is_dir() {
            continue;
        }
        let failures = replay(t, &ctx, &dir).unwrap();
        let msgs: Vec<String> = failures.iter().map(|f| f.to_string()).collect();
        assert!(msgs.is_empty(), "{}", msgs.join("\n"));
        for e in std::fs::read_dir(&dir).unwrap() {
            let data = std::fs::read(e.unwrap().path()).unwrap();
            // each was a crash or a contract violation: now a one-line refusal
            assert!(matches!(run_one(t, &ctx, &data), Ok(Outcome::Refused(_))));
            replayed += 1;
        }
    }
    assert!(replayed > 0, "no regression input found");
}

#[test]
fn the_same_seed_gives_the_same_run() {
    let root = root();
    let ctx = Ctx::new(&root).unwrap();
    let t = geodesic_fuzz::find("units").unwrap();
    let opts = Options {
        iterations: Some(300),
        seconds: 0.0,
        seed: 5,
        hang: None,
        crash_dir: None,
        progress: false,
    };
    let a = fuzz(t, &ctx, &root, &opts);
    let b = fuzz(t, &ctx, &root, &opts);
    assert_eq!(
        (a.accepted, a.refused, a.corpus),
        (b.accepted, b.refused, b.corpus)
    );
}
