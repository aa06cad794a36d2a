//! One input resolution for every command that reads a model input (issue 37, item 3).
//!
//! `verify`, `montecarlo`, `sensitivity`, `tip-radius`, `capture` and `charge` read the release
//! budget, the capture inputs and the charge inputs through [`resolve`] alone, so that they all
//! read the same file:
//!
//! 1. the file given with the command's flag (`--budget`, `--capture`, `--charge`);
//! 2. else the repository's copy (`models/release/budget.yaml`, ...) when the command runs from
//!    the repository's root (the path exists relative to the current directory: how `verify`
//!    has always found it);
//! 3. else the copy built into the binary (the same bytes as the repository's file at build
//!    time).
//!
//! Each command says which (the JSON output's `inputs` object, or the run's `run.inputs` for
//! `verify`; a line of the human output; a line on standard error when progress is shown) and
//! identifies it by the SHA-256 of the file's bytes (of the built-in copy's bytes for the
//! built-in one): the same hex string in every command for the same file.

use crate::error::CliError;
use geodesic_core::check::{InputFile, InputOrigin};
use std::path::Path;

/// A model input file that several commands read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelInput {
    /// The release Monte Carlo's uncertainty budget (`models/release/budget.yaml`).
    Budget,
    /// The capture inputs: xlim, drift time, state sources (`models/capture/capture.yaml`).
    Capture,
    /// The charge inputs: capacitances, contact voltage spread, release-tip geometry
    /// (`models/charge/charge.yaml`).
    Charge,
}

impl ModelInput {
    /// The flag that names another file.
    pub fn flag(self) -> &'static str {
        match self {
            ModelInput::Budget => "--budget",
            ModelInput::Capture => "--capture",
            ModelInput::Charge => "--charge",
        }
    }

    /// In words, for the human output.
    pub fn words(self) -> &'static str {
        match self {
            ModelInput::Budget => "release budget",
            ModelInput::Capture => "capture inputs",
            ModelInput::Charge => "charge inputs",
        }
    }

    /// The repository's copy, relative to the repository's root.
    pub fn repository_path(self) -> &'static str {
        match self {
            ModelInput::Budget => "models/release/budget.yaml",
            ModelInput::Capture => "models/capture/capture.yaml",
            ModelInput::Charge => "models/charge/charge.yaml",
        }
    }

    /// The plausible ranges of its parameters ([`crate::ranges`]).
    pub fn ranges(self) -> &'static [geodesic_core::pedigree::Range] {
        match self {
            ModelInput::Budget => crate::ranges::BUDGET,
            ModelInput::Capture => crate::ranges::CAPTURE,
            ModelInput::Charge => crate::ranges::CHARGE,
        }
    }

    /// The copy built into the binary.
    pub fn builtin(self) -> &'static str {
        match self {
            ModelInput::Budget => geodesic_release::budget::DEFAULT_BUDGET_YAML,
            ModelInput::Capture => geodesic_capture::DEFAULT_CAPTURE_YAML,
            ModelInput::Charge => geodesic_charge::DEFAULT_CHARGE_YAML,
        }
    }
}

/// Resolves a model input: `given` (its flag) if set, else the repository's copy when it exists
/// relative to the current directory, else the built-in copy. The file is read whole (at most
/// [`geodesic_core::fsio::MAX_YAML_BYTES`], UTF-8); the error is one line naming the flag and
/// the file. Every parameter's pedigree and plausible range are questioned
/// ([`crate::ranges`]): a value outside its range is one line `file:line: cause`.
pub fn resolve(input: ModelInput, given: Option<&Path>) -> Result<InputFile, CliError> {
    let f = resolve_file(input, given)?;
    crate::ranges::question(&f.text, &f.label, input.ranges()).map_err(CliError::bad)?;
    Ok(f)
}

fn resolve_file(input: ModelInput, given: Option<&Path>) -> Result<InputFile, CliError> {
    let read = |p: &Path, origin: InputOrigin| {
        let text = geodesic_core::fsio::read_text(p, geodesic_core::fsio::MAX_YAML_BYTES).map_err(
            |e| {
                let at = match e.line() {
                    0 => String::new(),
                    l => format!(":{l}"),
                };
                let by = match origin {
                    InputOrigin::Given => format!("{} ", input.flag()),
                    _ => String::new(),
                };
                CliError::bad(format!("{by}{}{at}: {}", p.display(), e.cause()))
            },
        )?;
        Ok(InputFile::new(p.display().to_string(), text).with_origin(origin))
    };
    match given {
        Some(p) => read(p, InputOrigin::Given),
        None => {
            let repo = Path::new(input.repository_path());
            if repo.is_file() {
                read(repo, InputOrigin::Repository)
            } else {
                Ok(InputFile::new(
                    format!("<built-in>/{}", input.repository_path()),
                    input.builtin(),
                )
                .with_origin(InputOrigin::BuiltIn))
            }
        }
    }
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
        for m in [ModelInput::Budget, ModelInput::Capture, ModelInput::Charge] {
            let path = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join(m.repository_path());
            let bytes = std::fs::read(&path).unwrap();
            let given = resolve(m, Some(&path)).unwrap();
            assert_eq!(given.origin, Some(InputOrigin::Given));
            assert_eq!(
                given.sha256,
                geodesic_core::hash::sha256_hex(&bytes),
                "{}",
                m.repository_path()
            );
            assert_eq!(
                geodesic_core::hash::sha256_hex(m.builtin().as_bytes()),
                given.sha256,
                "{}: the built-in copy differs from the file (rebuild)",
                m.repository_path()
            );
        }
    }

    #[test]
    fn a_missing_given_file_names_its_flag() {
        let e = resolve(ModelInput::Budget, Some(Path::new("no/such/budget.yaml")))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("--budget no/such/budget.yaml"), "{e}");
    }
}
