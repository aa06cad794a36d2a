//! `geodesic new mission` (issue 51, item 1): the generated project's Cargo.toml names no
//! absolute path: a path relative to the checkout when it has no network remote (said on
//! standard error with how to share the project), the git URL and commit when given. Building
//! and running the project is `.ci/new-mission.sh`'s (docs/guide-mission.md).

mod common;
use common::{geodesic, scratch};

/// A folder `new mission` takes for a geodesic checkout (it looks for verification/core), in no
/// git work tree.
fn fake_checkout() -> std::path::PathBuf {
    let fw = scratch("checkout");
    std::fs::create_dir_all(fw.join("verification/core")).unwrap();
    std::fs::write(fw.join("verification/core/Cargo.toml"), "[package]\n").unwrap();
    fw
}

#[test]
fn a_checkout_without_remote_gives_a_relative_path_and_a_note() {
    let fw = fake_checkout();
    let projects = scratch("projects");
    let out = geodesic(
        &[
            "new",
            "mission",
            "demo",
            "--path",
            "team/demo",
            "--geodesic",
            fw.to_str().unwrap(),
        ],
        &projects,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let toml = std::fs::read_to_string(projects.join("team/demo/Cargo.toml")).unwrap();
    assert!(
        toml.contains(r#"geodesic-core = { path = "../../../checkout/verification/core" }"#)
            && toml.contains(
                r#"geodesic-verify = { path = "../../../checkout/verification/verify" }"#
            ),
        "{toml}"
    );
    assert!(!toml.contains(r#"path = "/"#), "an absolute path: {toml}");
    assert!(
        err.contains("relative path ../../../checkout") && err.contains("--geodesic-git URL"),
        "{err}"
    );
    let readme = std::fs::read_to_string(projects.join("team/demo/README.md")).unwrap();
    assert!(
        readme.contains("cargo run -- test")
            && readme.contains("cargo run -- verify --require-tests")
    );
}

#[test]
fn a_git_url_and_commit_are_written_as_given() {
    let fw = fake_checkout();
    let projects = scratch("projects");
    let out = geodesic(
        &[
            "new",
            "mission",
            "demo",
            "--path",
            "demo",
            "--geodesic",
            fw.to_str().unwrap(),
            "--geodesic-git",
            "https://example.org/geodesic.git",
            "--geodesic-rev",
            "0123abcd",
        ],
        &projects,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let toml = std::fs::read_to_string(projects.join("demo/Cargo.toml")).unwrap();
    assert!(
        toml.contains(
            r#"geodesic-verify = { git = "https://example.org/geodesic.git", rev = "0123abcd" }"#
        ),
        "{toml}"
    );
    assert!(!toml.contains("path ="), "{toml}");
}
