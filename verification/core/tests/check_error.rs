//! A check's error is typed: a caller matches the kind, the file and the line, and the text is
//! the one-line message.

use geodesic_core::check::{CheckError, InputFile, Inputs};

#[test]
fn an_input_the_mission_does_not_declare_is_a_configuration_error() {
    let mut inputs = Inputs::default();
    inputs.insert(
        "design",
        "design inputs",
        InputFile::new("design.yaml", "a: 1\n"),
    );
    let e = inputs.file("budget").unwrap_err();
    assert!(matches!(e, CheckError::Config(_)), "{e:?}");
    assert_eq!(
        e.to_string(),
        "no input `budget` in this run (the mission declares: design)"
    );
    assert_eq!((e.file(), e.line()), (None, None));
}

#[test]
fn an_input_error_carries_its_file_and_line_and_prints_its_message() {
    let e = CheckError::input("design.yaml:3: mass_kg is negative").in_file("design.yaml", 3);
    match &e {
        CheckError::Input { file, line, .. } => {
            assert_eq!((file.as_deref(), *line), (Some("design.yaml"), Some(3)))
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(e.to_string(), "design.yaml:3: mass_kg is negative");
    assert_eq!(e.message(), "design.yaml:3: mass_kg is negative");
    // line 0: the whole file
    let e = CheckError::input("design.yaml: empty").in_file("design.yaml", 0);
    assert_eq!((e.file(), e.line()), (Some("design.yaml"), None));
}

#[test]
fn a_model_failure_names_the_model() {
    let e = CheckError::model("release Monte Carlo", "release Monte Carlo: no draws");
    assert!(
        matches!(&e, CheckError::Model { model, .. } if model == "release Monte Carlo"),
        "{e:?}"
    );
    assert_eq!(e.to_string(), "release Monte Carlo: no draws");
    // a file is only an input error's
    assert_eq!(e.in_file("budget.yaml", 2).file(), None);
    assert!(matches!(CheckError::evidence("no limit"), CheckError::Evidence(m) if m == "no limit"));
}
