//! The position and the one-line cause of a serde-saphyr error: every YAML loader of geodesic
//! reports `file:line[:column]: cause` from these.

/// A YAML error's position (1-based, when the parser knows it) and its cause on one line,
/// without the position serde-saphyr repeats in its message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct YamlError {
    /// 1-based line.
    pub line: Option<u64>,
    /// 1-based column.
    pub column: Option<u64>,
    /// The cause, one line.
    pub cause: String,
}

/// The position and cause of `e`.
pub fn yaml_error(e: &serde_saphyr::Error) -> YamlError {
    let loc = e.location();
    YamlError {
        line: loc.map(|l| l.line()),
        column: loc.map(|l| l.column()),
        cause: cause(&e.to_string()),
    }
}

/// The first non-empty line of a serde-saphyr message without its `error: line N column M: `
/// prefix (`invalid YAML` if the message is empty).
///
/// ```
/// use geodesic_util::yaml::cause;
/// assert_eq!(cause("error: line 3 column 7: unknown field `x`\n more"), "unknown field `x`");
/// assert_eq!(cause("error: invalid type"), "invalid type");
/// ```
pub fn cause(message: &str) -> String {
    let first = message
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("invalid YAML");
    let first = first.strip_prefix("error: ").unwrap_or(first);
    match first.find(": ") {
        Some(i) if first.starts_with("line ") => first[i + 2..].to_string(),
        _ => first.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn position_and_cause_of_a_parse_error() {
        #[derive(Debug, serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        #[allow(dead_code)]
        struct T {
            a: f64,
        }
        let e = serde_saphyr::from_str::<T>("a: 1\nb: 2\n").unwrap_err();
        let y = yaml_error(&e);
        assert_eq!(y.line, Some(2), "{y:?}");
        assert!(
            y.cause.contains("unknown field") || y.cause.contains('b'),
            "{y:?}"
        );
        assert!(!y.cause.starts_with("line "), "{y:?}");
        assert_eq!(cause(""), "invalid YAML");
    }
}
