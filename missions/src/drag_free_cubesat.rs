//! The Drag-Free CubeSat TM housing (thesis ch. 8): `missions/drag-free-cubesat/`.

use geodesic_verify::{Mission, Session};

/// The descriptor, built into the program.
pub const DESCRIPTOR: &str = include_str!("../drag-free-cubesat/mission.yaml");

/// Where the mission lies, relative to the repository's root.
pub const ROOT: &str = "missions/drag-free-cubesat";

const FILES: &[(&str, &str)] = &[
    (
        "requirements/housing.yaml",
        include_str!("../drag-free-cubesat/requirements/housing.yaml"),
    ),
    (
        "document.yaml",
        include_str!("../drag-free-cubesat/document.yaml"),
    ),
    ("design.yaml", geodesic_housing::DEFAULT_DESIGN_YAML),
];

fn session() -> Session {
    let mut checks = geodesic_checks::dfc::checks();
    checks.extend(geodesic_checks::spectral::checks());
    Session {
        checks,
        reference: Some(Box::new(|ctx| {
            if ctx.requirements.items.iter().any(|r| r.family == "housing") {
                geodesic_checks::fidelity::dfc_table(ctx)
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
    .series(crate::series)
    .validate("design", |f| {
        geodesic_housing::Design::from_yaml(&f.text, &f.label)?;
        crate::ranges::question(&f.text, &f.label, crate::ranges::DESIGN)
    });
    for (p, t) in FILES {
        m = m.builtin(p, t);
    }
    m
}
