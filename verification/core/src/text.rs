//! Text of error messages.

/// `s` with its control characters escaped as Rust does (`\n`, `\r`, `\t`, `\u{1b}`), so that
/// input quoted in an error message keeps the message on one line.
///
/// ```
/// use geodesic_core::text::one_line;
/// assert_eq!(one_line("a\nb\tc µ"), "a\\nb\\tc µ");
/// ```
pub fn one_line(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        if c.is_control() || c == '\u{2028}' || c == '\u{2029}' {
            out.extend(c.escape_debug());
        } else {
            out.push(c);
        }
    }
    out
}
