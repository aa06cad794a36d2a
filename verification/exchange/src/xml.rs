//! A small XML writer: escaping and indentation for one fixed document shape.

/// Escapes a double-quoted attribute value: `&`, `<`, `>`, `"`, `'`, and tab, line feed and carriage
/// return as character references (so that attribute normalisation keeps them). Characters XML
/// 1.0 does not allow (C0 controls other than those) are replaced by U+FFFD so that the output
/// is always well-formed.
/// `'` is written `&#x27;` as Python's html.escape writes it (the reqif package, ReqIF Studio).
/// geodesic's one escaping: [`geodesic_util::escape`].
pub fn escape(s: &str) -> String {
    geodesic_util::escape::with(s, &geodesic_util::escape::XML_ATTRIBUTE)
}

/// Escapes element content: `&`, `<`, `>` only (quotes stay as they are, as ReqIF tools write
/// them).
pub fn escape_text(s: &str) -> String {
    geodesic_util::escape::with(s, &geodesic_util::escape::XML_TEXT)
}

/// Escapes XHTML text: `&`, `<`, `>`, `"` and `'` (as Python's `html.escape`, which the
/// `reqif` package uses to write XHTML, so that its passthrough keeps the file unchanged).
pub fn escape_xhtml(s: &str) -> String {
    geodesic_util::escape::with(s, &geodesic_util::escape::XHTML)
}

/// An indenting writer of elements (two spaces a level).
#[derive(Default)]
pub struct Writer {
    out: String,
    depth: usize,
}

impl Writer {
    /// A writer that starts with the XML declaration.
    pub fn new() -> Self {
        Writer {
            out: "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n".into(),
            depth: 0,
        }
    }

    /// A writer of a fragment that starts at `depth` levels of indentation.
    pub fn fragment(depth: usize) -> Self {
        Writer {
            out: String::new(),
            depth,
        }
    }

    fn indent(&mut self) {
        for _ in 0..self.depth {
            self.out.push_str("  ");
        }
    }

    fn tag(&mut self, name: &str, attrs: &[(&str, &str)], close: bool) {
        self.indent();
        self.out.push('<');
        self.out.push_str(name);
        for (k, v) in attrs {
            self.out.push(' ');
            self.out.push_str(k);
            self.out.push_str("=\"");
            self.out.push_str(&escape(v));
            self.out.push('"');
        }
        self.out.push_str(if close { "/>\n" } else { ">\n" });
    }

    /// Opens `<name attrs>` on its own line.
    pub fn open(&mut self, name: &str, attrs: &[(&str, &str)]) {
        self.tag(name, attrs, false);
        self.depth += 1;
    }

    /// Closes `</name>`.
    pub fn close(&mut self, name: &str) {
        self.depth -= 1;
        self.indent();
        self.out.push_str("</");
        self.out.push_str(name);
        self.out.push_str(">\n");
    }

    /// `<name attrs/>`.
    pub fn empty(&mut self, name: &str, attrs: &[(&str, &str)]) {
        self.tag(name, attrs, true);
    }

    /// `<name>text</name>` on one line.
    pub fn text(&mut self, name: &str, text: &str) {
        self.raw(name, &escape_text(text));
    }

    /// `<name>markup</name>` on one line; `markup` must be well-formed XML already.
    pub fn raw(&mut self, name: &str, markup: &str) {
        self.indent();
        self.out.push('<');
        self.out.push_str(name);
        self.out.push('>');
        self.out.push_str(markup);
        self.out.push_str("</");
        self.out.push_str(name);
        self.out.push_str(">\n");
    }

    /// The document.
    pub fn finish(self) -> String {
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup_and_controls() {
        assert_eq!(
            escape("a<b & \"c\" 'd'>"),
            "a&lt;b &amp; &quot;c&quot; &#x27;d&#x27;&gt;"
        );
        assert_eq!(escape("x\ny\u{1}"), "x&#10;y\u{FFFD}");
        assert_eq!(escape_text("a<b & \"c\"\n"), "a&lt;b &amp; \"c\"\n");
    }
}
