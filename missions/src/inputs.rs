//! One input resolution for every command that reads a model input (issue 37, item 3), of the
//! inputs the root mission's descriptor declares (issue 51, item 2: `mission.yaml` `inputs:` is
//! the one declaration; the flag `--NAME`, the words, the default path and the built-in copy
//! derive from it).
//!
//! `verify`, `montecarlo`, `sensitivity`, `tip-radius`, `capture` and `charge` read the release
//! budget, the capture inputs and the charge inputs through [`resolve`] alone, so that they all
//! read the same file:
//!
//! 1. the file given with the command's flag (`--NAME`: `--budget`, `--capture`, `--charge`);
//! 2. else the repository's copy (the descriptor's `path`) when the command runs from the
//!    repository's root (the path exists relative to the current directory: how `verify` has
//!    always found it);
//! 3. else the copy built into the binary (the same bytes as the repository's file at build
//!    time).
//!
//! Each command says which (the JSON output's `inputs` object, or the run's `run.inputs` for
//! `verify`; a line of the human output; a line on standard error when progress is shown) and
//! identifies it by the SHA-256 of the file's bytes (of the built-in copy's bytes for the
//! built-in one): the same hex string in every command for the same file.

use crate::error::CliError;
use geodesic_core::check::{InputFile, InputOrigin};
use geodesic_verify::{InputSpec, Mission};
use std::path::Path;
use std::sync::OnceLock;

/// The root mission (its descriptor and built-in copies), built once.
fn root() -> &'static Mission {
    static M: OnceLock<Mission> = OnceLock::new();
    M.get_or_init(crate::lisa_pathfinder::mission)
}

/// A model input file that several commands read: one the root mission's descriptor
/// (`mission.yaml` `inputs:`) declares, by its name there. Its flag, its words, its default path
/// and its built-in copy are the descriptor's.
#[derive(Clone, Copy, Debug)]
pub struct ModelInput(&'static InputSpec);

impl ModelInput {
    /// The release Monte Carlo's uncertainty budget.
    pub fn budget() -> ModelInput {
        ModelInput::named("budget")
    }

    /// The capture inputs: xlim, drift time, state sources.
    pub fn capture() -> ModelInput {
        ModelInput::named("capture")
    }

    /// The charge inputs: capacitances, contact voltage spread, release-tip geometry.
    pub fn charge() -> ModelInput {
        ModelInput::named("charge")
    }

    /// The input `name` of the descriptor; panics when it declares none (tested for every name
    /// the commands read).
    pub fn named(name: &str) -> ModelInput {
        ModelInput(
            root()
                .spec
                .inputs
                .iter()
                .find(|i| i.name == name)
                .unwrap_or_else(|| panic!("mission.yaml declares no input `{name}`")),
        )
    }

    /// Its name in the descriptor.
    pub fn name(self) -> &'static str {
        &self.0.name
    }

    /// The flag that names another file: `--NAME`.
    pub fn flag(self) -> String {
        format!("--{}", self.0.name)
    }

    /// What it is, for a flag's help (the descriptor's `about`, else its words).
    pub fn about(self) -> &'static str {
        if self.0.about.is_empty() {
            &self.0.words
        } else {
            &self.0.about
        }
    }

    /// In words, for the human output.
    pub fn words(self) -> &'static str {
        &self.0.words
    }

    /// The repository's copy, relative to the repository's root.
    pub fn repository_path(self) -> &'static str {
        &self.0.path
    }

    /// The copy built into the binary.
    #[cfg(test)]
    pub fn builtin(self) -> &'static str {
        root()
            .builtin
            .get(&self.0.path)
            .copied()
            .unwrap_or_else(|| panic!("no built-in copy of {}", self.0.path))
    }
}

/// Resolves a model input: `given` (its flag) if set, else the repository's copy when it exists
/// relative to the current directory, else the built-in copy (as `verify` resolves it:
/// [`geodesic_verify::pipeline::resolve_file`]). The file is read whole (at most
/// [`geodesic_util::fsio::MAX_YAML_BYTES`], UTF-8); the error is one line naming the flag and
/// the file. Every parameter's pedigree and plausible range are questioned
/// ([`crate::ranges`]): a value outside its range is one line `file:line: cause`.
pub fn resolve(input: ModelInput, given: Option<&Path>) -> Result<InputFile, CliError> {
    let f = geodesic_verify::pipeline::resolve_file(
        root(),
        input.repository_path(),
        given,
        &input.flag(),
    )?
    .ok_or_else(|| {
        CliError::unreadable(format!("{}: not found", input.repository_path()))
            .in_file(input.repository_path(), 0)
    })?;
    crate::ranges::question(&f.text, &f.label, crate::ranges::of(input.name()))
        .map_err(|e| CliError::invalid(e).in_file(&f.label, 0))?;
    Ok(f)
}

/// One line saying which file a command read: `release budget: models/release/budget.yaml
/// (the repository's copy), sha256 758285c8...` (the whole hash).
pub fn line(input: ModelInput, f: &InputFile) -> String {
    format!(
        "{}: {} ({}), sha256 {}",
        input.words(),
        f.label,
        f.origin.map_or("given", InputOrigin::words),
        f.sha256
    )
}

/// With `--json`, the line of [`line`] on standard error when progress is shown
/// (`--progress`; never with `--quiet`): the JSON document says it always. Without `--json` the
/// command prints [`line`] in its human output on standard output instead (never twice).
pub fn announce(json: bool, input: ModelInput, f: &InputFile) {
    if json && crate::progress::enabled(json) {
        eprintln!("geodesic: {}", line(input, f));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_copy_hashes_as_the_repository_file() {
        // the built-in copy is the repository's file at build time: the same bytes, the same
        // SHA-256 (what `verify` prints for models/release/budget.yaml)
        for m in [
            ModelInput::budget(),
            ModelInput::capture(),
            ModelInput::charge(),
        ] {
            let path = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join(m.repository_path());
            let bytes = std::fs::read(&path).unwrap();
            let given = resolve(m, Some(&path)).unwrap();
            assert_eq!(given.origin, Some(InputOrigin::Given));
            assert_eq!(
                given.sha256,
                geodesic_util::hash::sha256_hex(&bytes),
                "{}",
                m.repository_path()
            );
            assert_eq!(
                geodesic_util::hash::sha256_hex(m.builtin().as_bytes()),
                given.sha256,
                "{}: the built-in copy differs from the file (rebuild)",
                m.repository_path()
            );
        }
    }

    #[test]
    fn a_missing_given_file_names_its_flag() {
        let e = resolve(ModelInput::budget(), Some(Path::new("no/such/budget.yaml")))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("--budget no/such/budget.yaml"), "{e}");
    }
}
