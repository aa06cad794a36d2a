//! The worked example of docs/fitting.md, "Adding an effect", compiled and checked here so that
//! the documentation cannot rot: a `pendulum` restoring force on the TM mock-up.

use geodesic_facility::effects::{
    Effect, EffectKind, FitHints, ForceEffect, GuessContext, ParamSpec, Role, Scenario, TmState,
};

/// The TM mock-up hangs as a pendulum of length `l`: restoring force `F = -k_p*x` with
/// `k_p = m*g/l` (thesis ch. 5: TMMF pendulum).
#[derive(Debug, Clone, Copy)]
pub struct Pendulum;

static PARAMS: [ParamSpec; 1] = [ParamSpec::log("k_p", "N/m", 1.0, 1e-3, 1e3)];

impl Effect for Pendulum {
    fn name(&self) -> &'static str {
        "pendulum"
    }
    fn scenario(&self) -> Scenario {
        Scenario::TmmfRelease
    }
    fn summary(&self) -> &'static str {
        "pendulum restoring force F = -k_p*x, k_p = m*g/l (thesis ch. 5)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        &PARAMS
    }
    fn role(&self) -> Role<'_> {
        Role::Force(self)
    }
    fn hints(&self) -> &dyn FitHints {
        self
    }
}

impl ForceEffect for Pendulum {
    fn force(&self, p: &[f64], s: &TmState, _ds: &mut [f64]) -> f64 {
        -p[0] * s.x
    }
}

impl FitHints for Pendulum {
    fn null_params(&self) -> Option<Vec<f64>> {
        Some(vec![PARAMS[0].lower])
    }
    fn starts(&self, g: &GuessContext) -> Vec<Vec<f64>> {
        // lengths of 0.1 m to 3 m for the known mass
        [0.1, 1.0, 3.0]
            .iter()
            .map(|l| vec![g.m_kg * 9.81 / l])
            .collect()
    }
}

#[test]
fn the_worked_example_is_a_valid_force_effect() {
    let s = TmState {
        t: 0.0,
        x: 1e-6,
        v: 0.0,
        y: 0.0,
        e_tip: 0.0,
        needle_gap: 0.0,
        f_pre: 0.0,
        needle_body: false,
        m_kg: 0.089,
        own: &[],
    };
    assert!((Pendulum.force(&[0.87], &s, &mut []) + 0.87e-6).abs() < 1e-18);
    let g = GuessContext {
        m_kg: 0.089,
        ..Default::default()
    };
    assert_eq!(Pendulum.starts(&g).len(), 3);
    assert_eq!(Pendulum.role().kind(), EffectKind::Force);
    assert_eq!((&Pendulum as &dyn Effect).kind(), EffectKind::Force);
}

/// The guide docs/guide-effect.md ("Adding an effect") shows this file's code (with `use super::...` instead of the
/// crate path): the two must not drift apart.
#[test]
fn the_readme_shows_this_code_line_for_line() {
    let readme = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/guide-effect.md"
    ))
    .expect("docs/guide-effect.md in the workspace");
    let here = include_str!("worked_example.rs");
    let code = &here[here.find("/// The TM mock-up hangs").unwrap()..here.find("#[test]").unwrap()];
    let section = &readme[readme.find("## Steps").expect("the section")..];
    let start = section.find("```rust\n").expect("a rust block") + "```rust\n".len();
    let block: String = section[start..start + section[start..].find("```").unwrap()]
        .lines()
        .map(|l| l.strip_prefix("   ").unwrap_or(l))
        .collect::<Vec<_>>()
        .join("\n");
    let expected_head = "//! `pendulum`: restoring force of the TM mock-up's suspension (thesis ch. 5).\n\n\
                         use super::{Effect, FitHints, ForceEffect, GuessContext, ParamSpec, Role, Scenario, TmState};\n\n";
    assert!(
        block.starts_with(expected_head),
        "the guide's block starts differently:\n{block}"
    );
    assert_eq!(
        block[expected_head.len()..].trim_end(),
        code.trim_end(),
        "docs/guide-effect.md and models/facility/tests/worked_example.rs differ"
    );
}
