//! `discover --scaffold` (issue 36): the code the one template writes, for every kind a term can
//! have and both scenarios, is Rust that parses (syn), is already as rustfmt writes it, and
//! registers the effect where the catalogue, the hiding tests and the guard list are read. (The
//! generated effect is compiled, linted and run end to end by CI's `.ci/loop.py`, which follows
//! docs/loop.md on the public example: a full build per kind is minutes, too long for here.)

use geodesic_codegen::{Conditions, KINDS, Scaffold, Term, TermParameter, rustfmt};
use geodesic_facility::Scenario;
use std::path::Path;

fn term(kind: &str, scenario: Scenario) -> Term {
    let tm = scenario == Scenario::TmmfRelease;
    let (par, coefs) = match kind {
        "position" if tm => (("f0", 1.5664, "Hz"), vec![-96.86, 3.03e-3]),
        "position" => (("f0", 2.1e3, "Hz"), vec![-1.74e8, 0.1]),
        "velocity" => (("gamma", 100.566, "1/s"), vec![-100.566]),
        "delay" => (("delay", 3.0046e-6, "s"), vec![1.0]),
        "creep" => (("tau", 2e-4, "s"), vec![5e-9]),
        "slip" => (("t0", 1.2e-3, "s"), vec![-3e-9]),
        "impulse" => (("t0", 1.2e-3, "s"), vec![2e-6]),
        _ => (("f", 729.94, "Hz"), vec![3.7e-9, 1.5e-9]),
    };
    Term {
        kind: kind.into(),
        term: format!("x: a term of kind {kind}, with \"quotes\" and a \\ backslash"),
        parameter: Some(TermParameter {
            name: par.0.into(),
            value: par.1,
            unit: par.2.into(),
        }),
        delta_bic: -87477.8,
        coefs,
    }
}

fn scaffold(kind: &str, scenario: Scenario) -> Scaffold {
    let known = if scenario == Scenario::TmmfRelease {
        ("m", 0.089)
    } else {
        ("E0", 120.0)
    };
    Scaffold::from_term(
        &format!("outside_{kind}"),
        scenario,
        &term(kind, scenario),
        "data/examples/tmmf-\"odd\" name.yaml",
        &["slip".into(), kind.into()],
        "2026-11-27",
        Conditions {
            fs_hz: 1e5,
            post_s: 0.02,
            known,
            noise: 8e-10,
            jerk_m_s3: 6000.0,
            v_m_s: 3e-3,
        },
    )
    .expect("a scaffold of every kind")
}

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// Whether rustfmt runs here (it does wherever cargo fmt does).
fn have_rustfmt() -> bool {
    std::process::Command::new("rustfmt")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn every_kind_generates_rust_that_parses_and_is_formatted() {
    let fmt = have_rustfmt();
    if !fmt {
        eprintln!("rustfmt not found: the formatting half of this test is skipped");
    }
    for scenario in [Scenario::TmmfRelease, Scenario::RtRetraction] {
        for kind in KINDS {
            let s = scaffold(kind, scenario);
            let src = s.effect_source();
            let file =
                syn::parse_file(&src).unwrap_or_else(|e| panic!("{kind} {scenario:?}: {e}\n{src}"));
            // one struct; one impl of Effect, of its capability and of FitHints, each with
            // the methods of its trait
            let mut impls: Vec<(String, Vec<String>)> = Vec::new();
            for item in &file.items {
                if let syn::Item::Impl(i) = item {
                    let tr = i.trait_.as_ref().expect("an impl of a trait");
                    let name = tr.1.get_ident().expect("a trait name").to_string();
                    let methods = i
                        .items
                        .iter()
                        .filter_map(|it| match it {
                            syn::ImplItem::Fn(f) => Some(f.sig.ident.to_string()),
                            _ => None,
                        })
                        .collect();
                    impls.push((name, methods));
                }
            }
            let tm = scenario == Scenario::TmmfRelease;
            let (role, law) = match kind {
                "position" | "velocity" if tm => ("Force", "force"),
                "position" | "velocity" => ("Mechanism", "configure_rt"),
                "delay" => ("TimeShift", "time_shift"),
                _ => ("Distortion", "distortion"),
            };
            let capability = format!("{role}Effect");
            let expected: [(&str, &[&str]); 3] = [
                (
                    "Effect",
                    &["name", "scenario", "summary", "params", "role", "hints"],
                ),
                (&capability, &[law]),
                ("FitHints", &["null_params", "starts"]),
            ];
            assert_eq!(
                impls.len(),
                expected.len(),
                "{kind} {scenario:?}: {impls:?}"
            );
            for ((name, methods), (want, want_methods)) in impls.iter().zip(expected) {
                assert_eq!(name, want, "{kind} {scenario:?}: {impls:?}");
                assert_eq!(methods, want_methods, "{kind} {scenario:?}: {name}");
            }
            assert!(
                src.contains(&format!("Role::{role}(self)")),
                "{kind}: not Role::{role}\n{src}"
            );
            // the parameter count declared is the number written
            let n = s.params.len();
            assert!(src.contains(&format!("[ParamSpec; {n}]")), "{src}");
            assert!(src.contains("delta BIC -87477.8"), "{src}");
            assert!(src.contains("kind `"), "{src}");
            assert!(src.contains("2026-11-27"), "{src}");
            for l in src.lines() {
                assert!(l.len() <= 100, "{kind}: a line over 100 characters: {l}");
            }
            let test = s.hiding_test();
            syn::parse_file(&test).unwrap_or_else(|e| panic!("{kind}: {e}\n{test}"));
            if fmt {
                assert_eq!(rustfmt(&src, root()).unwrap(), src, "{kind} {scenario:?}");
                assert_eq!(rustfmt(&test, root()).unwrap(), test, "{kind} {scenario:?}");
            }
        }
    }
}

#[test]
fn registration_and_hiding_test_go_into_the_repository_files() {
    let s = scaffold("vibration", Scenario::TmmfRelease);
    let edits = s.edits(root()).expect("the repository's files");
    assert_eq!(edits.len(), 3);
    assert!(
        edits[0]
            .0
            .ends_with("models/facility/src/effects/outside_vibration.rs")
    );
    for (p, text) in &edits {
        syn::parse_file(text).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        if have_rustfmt() {
            assert_eq!(&rustfmt(text, root()).unwrap(), text, "{}", p.display());
        }
    }
    let mod_rs = &edits[1].1;
    assert!(mod_rs.contains("\nmod outside_vibration;\n"));
    assert!(mod_rs.contains("\npub use outside_vibration::OutsideVibration;\n"));
    let cat = mod_rs.find("fn catalogue()").unwrap();
    assert!(mod_rs[cat..].contains("        &OutsideVibration,\n    ];"));
    let hide = &edits[2].1;
    assert!(hide.contains("let tested = [\n        \"outside_vibration\","));
    assert!(hide.contains("fn hidden_outside_vibration_is_named()"));
    assert!(hide.contains("(\"outside_vibration.f\", 729.94)"));
}

/// When the leading term is no physics of its kind (an anti-restoring force) and the record
/// could not tell it from another term, the effect is written from that term, and says why the
/// leader was passed over; without such a twin the leader's refusal stands (issue 36: a
/// damping record whose joint fits put an anti-restoring force first by a few in BIC).
#[test]
fn an_unphysical_leader_passes_to_its_indistinguishable_twin() {
    let scenario = Scenario::TmmfRelease;
    let mut anti = term("position", scenario);
    anti.coefs = vec![1.04e4, 0.0];
    let damping = term("velocity", scenario);
    let conditions = Conditions {
        fs_hz: 1e5,
        post_s: 0.02,
        known: ("m", 0.089),
        noise: 8e-10,
        jerk_m_s3: 6000.0,
        v_m_s: 3e-3,
    };
    let terms = vec![anti.clone(), damping.clone()];
    let make = |twins: &[String]| {
        Scaffold::from_terms(
            "viscous",
            scenario,
            &terms,
            "r.yaml",
            twins,
            "2026-11-28",
            conditions.clone(),
        )
    };
    let alone = make(&[]).expect_err("an anti-restoring leader alone is refused");
    assert!(alone.contains("anti-restoring"), "{alone}");
    let s = make(&["position".into(), "velocity".into()]).expect("the twin is scaffolded");
    assert_eq!(s.kind, "velocity");
    let why = s
        .passed_over
        .as_deref()
        .expect("the leader was passed over");
    assert!(
        why.contains("`position`") && why.contains("anti-restoring"),
        "{why}"
    );
    assert_eq!(s.indistinguishable, vec!["position".to_string()]);
    let code = s.effect_source().replace("\n/// ", " ");
    assert!(code.contains("which was passed over (`position`"), "{code}");
    // a twin that is no physics either leaves the leader's refusal
    let mut negative = damping;
    negative.coefs = vec![50.0];
    negative.parameter.as_mut().unwrap().value = -50.0;
    let e = Scaffold::from_terms(
        "viscous",
        scenario,
        &[anti, negative],
        "r.yaml",
        &["position".into(), "velocity".into()],
        "2026-11-28",
        conditions,
    )
    .expect_err("no twin that scaffolds");
    assert!(e.contains("anti-restoring"), "{e}");
}
