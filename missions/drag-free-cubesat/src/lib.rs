//! The Drag-Free CubeSat TM housing (thesis ch. 8), a mission verified with geodesic's framework:
//! everything of it lives in `missions/drag-free-cubesat/` (its descriptor, requirements, design
//! inputs and document, and this crate: the housing's model, its checks, its fidelity table,
//! the plausible ranges of its inputs and its traced tests). The `geodesic` program registers
//! [`mission`] (`geodesic verify --mission drag-free-cubesat`); `src/main.rs` is the mission's
//! own program, as a generated project's.

pub mod checks;
pub mod fidelity;
pub mod housing;
pub mod ranges;

pub use housing::{DEFAULT_DESIGN_YAML, Design};

use geodesic_verify::{Mission, Session};

/// The descriptor, built into the program.
pub const DESCRIPTOR: &str = include_str!("../mission.yaml");

/// Where the mission lies, relative to the repository's root.
pub const ROOT: &str = "missions/drag-free-cubesat";

const FILES: &[(&str, &str)] = &[
    (
        "requirements/housing.yaml",
        include_str!("../requirements/housing.yaml"),
    ),
    ("document.yaml", include_str!("../document.yaml")),
    ("design.yaml", DEFAULT_DESIGN_YAML),
];

fn session() -> Session {
    let mut checks = checks::checks();
    checks.extend(geodesic_checks::spectral::checks());
    Session {
        checks,
        reference: Some(Box::new(|ctx| {
            if ctx.requirements.items.iter().any(|r| r.family == "housing") {
                fidelity::table(ctx)
            } else {
                Ok(Vec::new())
            }
        })),
    }
}

/// The mission, found in `missions/drag-free-cubesat/` under the current directory or built in.
pub fn mission() -> Mission {
    let mut m = Mission::new(
        DESCRIPTOR,
        "missions/drag-free-cubesat/mission.yaml",
        ROOT,
        session,
    )
    .expect("the built-in mission.yaml is valid (tested)")
    .series(geodesic_checks::spectral::validate_series)
    .validate("design", |f| {
        Design::from_yaml(&f.text, &f.label)?;
        ranges::question(&f.text, &f.label)
    });
    for (p, t) in FILES {
        m = m.builtin(p, t);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_builtin_descriptor_builds_and_its_checks_cover_its_requirements() {
        let m = mission();
        let names = m.check_names();
        let reqs = geodesic_core::Requirements::from_sources(&[(
            "requirements/housing.yaml".into(),
            FILES[0].1.to_string(),
        )])
        .unwrap();
        reqs.validate_checks(&names).unwrap();
        for c in m.session().checks {
            for id in c.verifies() {
                assert!(reqs.get(id).is_some(), "{} names {id}", c.name());
            }
        }
    }
}
