//! The binary's error type: [`geodesic_verify::Error`] (every failure maps to an exit status
//! and a one-line cause; `main` prints `geodesic: <cause>` on standard error).

pub use geodesic_verify::error::{CmdResult, Error as CliError, InputKind};

/// A fit's error as the run's: bad input ([`InputKind::Invalid`]) at the fit error's file and
/// line, or a failed write ([`CliError::Io`] at its path); the fit error is kept as the source
/// of an input error and the message is unchanged.
pub fn from_fit(e: geodesic_fit::FitError) -> CliError {
    match &e {
        geodesic_fit::FitError::Input { file, line, .. } => {
            let (file, line) = (file.clone(), *line);
            CliError::input_from(InputKind::Invalid, e).in_file(file, line)
        }
        geodesic_fit::FitError::Write { path, .. } => {
            let path = path.clone();
            CliError::io(e).in_file(path, 0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_record_of_a_fit_is_an_input_error_at_its_file_and_line() {
        // a CSV whose time goes back at line 5, loaded through the fit library
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("r.csv"),
            "t,x\n0.0,1.0\n0.1,1.0\n0.2,1.0\n0.15,1.0\n0.3,1.0\n",
        )
        .unwrap();
        let yaml = dir.path().join("r.yaml");
        std::fs::write(&yaml, "data: r.csv\nchannel: x\nunit: m\n").unwrap();
        let e = from_fit(geodesic_fit::spectral::Series::load(&yaml).err().unwrap());
        let text = e.to_string();
        match &e {
            CliError::Input {
                kind: InputKind::Invalid,
                file: Some(f),
                line: Some(5),
                ..
            } => assert!(f.ends_with("r.csv"), "{f:?}"),
            other => panic!("{other:?}"),
        }
        // the fit's error is kept whole, and the message is the fit's
        let src = std::error::Error::source(&e).unwrap();
        assert_eq!(src.to_string(), text);
        assert!(src.downcast_ref::<geodesic_fit::FitError>().is_some());
    }
}
