//! Escaping text for XML, HTML and SVG: one implementation ([`with`]) and the rule sets the
//! outputs use. Each rule set keeps the bytes its output has always had (JUnit and HTML write
//! `&apos;`, ReqIF writes `&#x27;` as Python's `html.escape` does so that a passthrough keeps a
//! file unchanged, an SVG label escapes only `&`, `<` and `>`).

/// What [`with`] escapes besides `&`, `<` and `>` (always escaped).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rules {
    /// `"` as `&quot;`.
    pub quot: bool,
    /// `'` as this reference, if any.
    pub apos: Option<&'static str>,
    /// Tab and line feed as `&#9;` and `&#10;` (attribute normalisation keeps them).
    pub tab_lf: bool,
    /// Carriage return as `&#13;`.
    pub cr: bool,
    /// C0 controls other than tab, line feed and carriage return, and U+FFFE, U+FFFF (which
    /// XML 1.0 does not allow) replaced by U+FFFD, so that the output is always well-formed.
    pub controls: bool,
}

/// Markup text and attributes of the JUnit XML and the HTML report: `&`, `<`, `>`, `"` and
/// `'` (as `&apos;`).
pub const MARKUP: Rules = Rules {
    quot: true,
    apos: Some("&apos;"),
    tab_lf: false,
    cr: false,
    controls: false,
};

/// Text drawn in an SVG (`<text>` content): `&`, `<` and `>` only.
pub const TEXT: Rules = Rules {
    quot: false,
    apos: None,
    tab_lf: false,
    cr: false,
    controls: false,
};

/// A double-quoted XML attribute value (ReqIF): `&`, `<`, `>`, `"`, `'` (as `&#x27;`), tab,
/// line feed and carriage return as character references, disallowed controls replaced.
pub const XML_ATTRIBUTE: Rules = Rules {
    quot: true,
    apos: Some("&#x27;"),
    tab_lf: true,
    cr: true,
    controls: true,
};

/// XML element content (ReqIF): `&`, `<`, `>` and carriage return; quotes stay as they are, as
/// ReqIF tools write them; disallowed controls replaced.
pub const XML_TEXT: Rules = Rules {
    quot: false,
    apos: None,
    tab_lf: false,
    cr: true,
    controls: true,
};

/// XHTML text (ReqIF rich text): as Python's `html.escape` (`&`, `<`, `>`, `"`, `'` as
/// `&#x27;`) plus carriage return; disallowed controls replaced.
pub const XHTML: Rules = Rules {
    quot: true,
    apos: Some("&#x27;"),
    tab_lf: false,
    cr: true,
    controls: true,
};

/// `s` escaped by `rules`.
///
/// ```
/// use geodesic_util::escape::{with, MARKUP, XML_ATTRIBUTE};
/// assert_eq!(with("a<'b'>&", &MARKUP), "a&lt;&apos;b&apos;&gt;&amp;");
/// assert_eq!(with("'\n\u{1}", &XML_ATTRIBUTE), "&#x27;&#10;\u{FFFD}");
/// ```
pub fn with(s: &str, rules: &Rules) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' if rules.quot => o.push_str("&quot;"),
            '\'' if rules.apos.is_some() => o.push_str(rules.apos.unwrap_or_default()),
            '\t' if rules.tab_lf => o.push_str("&#9;"),
            '\n' if rules.tab_lf => o.push_str("&#10;"),
            '\r' if rules.cr => o.push_str("&#13;"),
            '\t' | '\n' | '\r' => o.push(c),
            c if rules.controls && ((c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}') => {
                o.push('\u{FFFD}')
            }
            c => o.push(c),
        }
    }
    o
}

/// [`with`] [`MARKUP`]: text or attribute of the JUnit XML and the HTML report.
pub fn markup(s: &str) -> String {
    with(s, &MARKUP)
}

/// [`with`] [`TEXT`]: text drawn in an SVG.
pub fn text(s: &str) -> String {
    with(s, &TEXT)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_rule_set_as_its_output_writes_it() {
        let s = "a<b & \"c\" 'd'>\t\n\r\u{1}\u{FFFF}";
        assert_eq!(
            markup(s),
            "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;\t\n\r\u{1}\u{FFFF}"
        );
        assert_eq!(text(s), "a&lt;b &amp; \"c\" 'd'&gt;\t\n\r\u{1}\u{FFFF}");
        assert_eq!(
            with(s, &XML_ATTRIBUTE),
            "a&lt;b &amp; &quot;c&quot; &#x27;d&#x27;&gt;&#9;&#10;&#13;\u{FFFD}\u{FFFD}"
        );
        assert_eq!(
            with(s, &XML_TEXT),
            "a&lt;b &amp; \"c\" 'd'&gt;\t\n&#13;\u{FFFD}\u{FFFD}"
        );
        assert_eq!(
            with(s, &XHTML),
            "a&lt;b &amp; &quot;c&quot; &#x27;d&#x27;&gt;\t\n&#13;\u{FFFD}\u{FFFD}"
        );
    }
}
