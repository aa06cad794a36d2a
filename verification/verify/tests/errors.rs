//! The run's error is typed: each kind of failure, made to happen through the public API, is
//! matched on its variant, kind, file and line (not on its text).

use std::path::{Path, PathBuf};

use geodesic_core::check::{Check, CheckContext, CheckError, Evidence};
use geodesic_verify::error::{Error, InputKind};
use geodesic_verify::{Mission, pipeline};

const DESCRIPTOR: &str = "name: demo
title: a demo mission
requirements: requirements
document: document.yaml
";

const REQUIREMENT: &str = "family: demo
requirements:
  - id: DEMO-A
    title: A
    text: The thing shall be slow.
    source: Spec Tab. 1
    quantity: velocity
    dimension: velocity
    limit: <= 5 um/s
    method: analysis
    activity: a check that fails
    check: failing
";

/// A check whose input is wrong at `design.yaml` line 3.
struct Failing;

impl Check for Failing {
    fn name(&self) -> &'static str {
        "failing"
    }
    fn verifies(&self) -> &'static [&'static str] {
        &["DEMO-A"]
    }
    fn run(&self, _: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        Err(CheckError::input("design.yaml:3: `mass_kg` is negative").in_file("design.yaml", 3))
    }
}

/// A mission folder (descriptor, document, one requirement file of text `reqs`) and the mission.
fn mission(reqs: &str) -> (tempfile::TempDir, Mission) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("requirements")).unwrap();
    std::fs::write(dir.path().join("requirements/demo.yaml"), reqs).unwrap();
    std::fs::write(
        dir.path().join("document.yaml"),
        "id: D-1\nissue: \"1\"\ntitle: demo\nproject: demo\n",
    )
    .unwrap();
    let m = Mission::with_checks(DESCRIPTOR, "mission.yaml", dir.path(), || {
        vec![Box::new(Failing) as Box<dyn Check>]
    })
    .unwrap();
    (dir, m)
}

fn load(reqs: &str) -> (Error, PathBuf) {
    let (dir, m) = mission(reqs);
    let e = pipeline::load_requirements(&m, None).unwrap_err();
    (e, dir.path().join("requirements/demo.yaml"))
}

fn run_err(m: &Mission, opts: &pipeline::Options) -> Error {
    match pipeline::run(m, opts) {
        Ok(_) => panic!("the run should fail"),
        Err(e) => e,
    }
}

fn options(dir: &Path) -> pipeline::Options {
    pipeline::Options {
        reports: dir.join("reports"),
        ..Default::default()
    }
}

#[test]
fn a_malformed_yaml_file_is_an_input_error_at_its_file_and_line() {
    let (e, file) = load(&REQUIREMENT.replace("    title: A\n", "    title: [A\n"));
    assert!(
        matches!(&e, Error::Input { kind: InputKind::Malformed, file: Some(f), line: Some(_), .. } if *f == file),
        "{e:?}"
    );
    // the requirement-file error is kept whole as the source
    let src = std::error::Error::source(&e).expect("a source");
    let le = src
        .downcast_ref::<geodesic_core::requirement::LoadError>()
        .expect("the loader's error");
    assert_eq!(le.kind, geodesic_core::requirement::LoadKind::Syntax);
    assert_eq!(e.line(), Some(le.origin.line as usize));
}

#[test]
fn an_unknown_unit_is_an_input_error_of_its_kind_at_its_line() {
    let (e, file) = load(&REQUIREMENT.replace("<= 5 um/s", "<= 5 furlong/s"));
    assert_eq!(e.kind(), Some(InputKind::UnknownUnit), "{e:?}");
    assert_eq!(e.file(), Some(file.as_path()));
    assert_eq!(e.line(), Some(9), "the `limit` line");
}

#[test]
fn a_number_that_is_not_finite_is_an_input_error_of_its_kind() {
    let (e, _) = load(&REQUIREMENT.replace("<= 5 um/s", "<= inf um/s"));
    assert_eq!(e.kind(), Some(InputKind::NotFinite), "{e:?}");
    assert_eq!(e.line(), Some(9));
}

#[test]
fn an_unknown_parent_id_is_an_unknown_id() {
    let t = REQUIREMENT.replace(
        "    check: failing\n",
        "    check: failing\n    parent: {id: DEMO-NONE, margin: 1.0}\n",
    );
    let (e, file) = load(&t);
    assert_eq!(e.kind(), Some(InputKind::UnknownId), "{e:?}");
    assert_eq!(e.file(), Some(file.as_path()));
}

#[test]
fn an_unknown_requirement_id_given_to_only_is_an_unknown_id() {
    let (dir, m) = mission(REQUIREMENT);
    let opts = pipeline::Options {
        only: vec!["DEMO-Z".to_string()],
        ..options(dir.path())
    };
    let e = run_err(&m, &opts);
    assert_eq!(e.kind(), Some(InputKind::UnknownId), "{e:?}");
}

#[test]
fn an_unknown_check_name_is_an_unknown_name_at_its_line() {
    let (dir, m) = mission(&REQUIREMENT.replace("check: failing", "check: no-such-check"));
    let e = run_err(&m, &options(dir.path()));
    assert_eq!(e.kind(), Some(InputKind::UnknownName), "{e:?}");
    assert_eq!(e.line(), Some(12), "the `check` line");
}

#[test]
fn a_failing_check_carries_its_name_and_its_typed_error() {
    let (dir, m) = mission(REQUIREMENT);
    let e = run_err(&m, &options(dir.path()));
    match &e {
        Error::Check {
            check,
            source: CheckError::Input { file, line, .. },
        } => {
            assert_eq!(check, "failing");
            assert_eq!((file.as_deref(), *line), (Some("design.yaml"), Some(3)));
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        (e.file(), e.line()),
        (Some(Path::new("design.yaml")), Some(3))
    );
    // printed as before: `check NAME: CAUSE`
    assert_eq!(
        e.to_string(),
        "check failing: design.yaml:3: `mass_kg` is negative"
    );
}

#[test]
fn a_recorded_test_run_that_is_not_one_is_unusable_evidence() {
    let (dir, m) = mission(REQUIREMENT);
    let tests = dir.path().join("run.json");
    std::fs::write(&tests, "{\"x\":\n").unwrap();
    let opts = pipeline::Options {
        tests: Some(tests.clone()),
        ..options(dir.path())
    };
    let e = run_err(&m, &opts);
    assert_eq!(e.kind(), Some(InputKind::Evidence), "{e:?}");
    assert_eq!(e.file(), Some(tests.as_path()));
}

#[test]
fn a_missing_input_file_is_unreadable() {
    let (dir, m) = mission(REQUIREMENT);
    let baseline = dir.path().join("no-such-baseline.json");
    let opts = pipeline::Options {
        baseline: Some(baseline.clone()),
        ..options(dir.path())
    };
    let e = run_err(&m, &opts);
    assert_eq!(e.kind(), Some(InputKind::Unreadable), "{e:?}");
    assert_eq!(e.file(), Some(baseline.as_path()));
}

#[test]
fn an_output_folder_that_is_a_file_is_an_io_error_at_its_path() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("a-file");
    std::fs::write(&f, "x").unwrap();
    let e = geodesic_verify::preflight::out_dir("--out", &f).unwrap_err();
    assert!(
        matches!(&e, Error::Io { path: Some(p), .. } if *p == f),
        "{e:?}"
    );
}

#[test]
fn a_malformed_descriptor_is_an_input_error_at_its_line_and_a_duplicate_a_conflict() {
    let e = Mission::with_checks(
        "name: demo\ntitle: t\nrequirements: [r\n",
        "m.yaml",
        ".",
        Vec::new,
    )
    .err()
    .unwrap();
    assert_eq!(e.kind(), Some(InputKind::Malformed), "{e:?}");
    assert_eq!(e.file(), Some(Path::new("m.yaml")));
    assert!(e.line().is_some_and(|l| l >= 3), "{e:?}");
    let twice = "name: demo\ntitle: t\nrequirements: r\ninputs:\n  - {name: a, words: w, path: a.yaml}\n  - {name: a, words: w, path: b.yaml}\n";
    let e = Mission::with_checks(twice, "m.yaml", ".", Vec::new)
        .err()
        .unwrap();
    assert_eq!(e.kind(), Some(InputKind::Conflict), "{e:?}");
}

#[test]
fn a_check_error_outside_a_run_keeps_its_kind_file_and_line() {
    let e = Error::from(CheckError::input("d.yaml:4: bad").in_file("d.yaml", 4));
    assert_eq!(e.kind(), Some(InputKind::Invalid));
    assert_eq!((e.file(), e.line()), (Some(Path::new("d.yaml")), Some(4)));
    assert_eq!(e.to_string(), "d.yaml:4: bad");
    let e = Error::from(CheckError::model(
        "release Monte Carlo",
        "release Monte Carlo: NaN",
    ));
    assert!(matches!(&e, Error::Model { model: Some(m), .. } if m == "release Monte Carlo"));
    assert_eq!(e.exit_status(), 2);
}
