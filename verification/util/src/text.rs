//! Text of error messages.

/// `s` with its control characters escaped as Rust does (`\n`, `\r`, `\t`, `\u{1b}`), so that
/// input quoted in an error message keeps the message on one line.
///
/// ```
/// use geodesic_util::text::one_line;
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

/// [`one_line`] of `s`, cut after `max` characters with `…` and the count of what was left out,
/// for input echoed in an error message (a header line, a value) that may be arbitrarily long.
///
/// ```
/// use geodesic_util::text::clip;
/// assert_eq!(clip("ab\ncd", 10), "ab\\ncd");
/// assert_eq!(clip("abcdef", 3), "abc… (3 more characters)");
/// ```
pub fn clip(s: &str, max: usize) -> String {
    let n = s.chars().count();
    if n <= max {
        return one_line(s);
    }
    let head: String = s.chars().take(max).collect();
    format!("{}… ({} more characters)", one_line(&head), n - max)
}
