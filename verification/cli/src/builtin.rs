//! The built-in requirements, embedded so that `geodesic verify` works from any directory.
//! `geodesic verify` reads `./requirements/` when it exists (so edits take effect), else these.

/// `(file name, YAML text)` of every family in `requirements/`.
pub const REQUIREMENTS: &[(&str, &str)] = &[
    (
        "capture.yaml",
        include_str!("../../../requirements/capture.yaml"),
    ),
    (
        "charge.yaml",
        include_str!("../../../requirements/charge.yaml"),
    ),
    (
        "facility.yaml",
        include_str!("../../../requirements/facility.yaml"),
    ),
    (
        "performance.yaml",
        include_str!("../../../requirements/performance.yaml"),
    ),
    (
        "plunger.yaml",
        include_str!("../../../requirements/plunger.yaml"),
    ),
    (
        "release.yaml",
        include_str!("../../../requirements/release.yaml"),
    ),
    (
        "tm-state.yaml",
        include_str!("../../../requirements/tm-state.yaml"),
    ),
];

#[cfg(test)]
mod tests {
    #[test]
    fn every_family_file_is_embedded() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../requirements");
        let mut on_disk: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".yaml"))
            .collect();
        on_disk.sort();
        let embedded: Vec<String> = super::REQUIREMENTS
            .iter()
            .map(|(n, _)| n.to_string())
            .collect();
        assert_eq!(on_disk, embedded);
    }
}
