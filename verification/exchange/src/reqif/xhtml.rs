//! Plain text to ReqIF XHTML and back.
//!
//! geodesic's texts are plain: exported as one `xhtml:div`, a line break as `xhtml:br`. On
//! import, XHTML is read as a browser shows it: runs of white space collapse to one space,
//! `br` is a line break, block elements (`p`, `div`, `li`, headings, table rows) start a new
//! line, list items get a `- ` bullet, table cells are separated by ` | `; images and objects
//! keep their alternative text. So a text with two spaces in a row or leading spaces does not
//! survive a round trip through XHTML (none of geodesic's requirements has one).

use crate::xml::escape_xhtml;

/// `<xhtml:div>text</xhtml:div>`, a line break as `<xhtml:br/>`.
pub fn text_to_xhtml(text: &str) -> String {
    let lines: Vec<String> = text.split('\n').map(escape_xhtml).collect();
    format!("<xhtml:div>{}</xhtml:div>", lines.join("<xhtml:br/>"))
}

fn is_block(name: &str) -> bool {
    matches!(
        name,
        "p" | "div"
            | "li"
            | "ul"
            | "ol"
            | "h1"
            | "h2"
            | "h3"
            | "h4"
            | "h5"
            | "h6"
            | "tr"
            | "table"
            | "blockquote"
            | "pre"
            | "dl"
            | "dt"
            | "dd"
            | "address"
            | "hr"
    )
}

fn walk(node: roxmltree::Node, out: &mut String) {
    for c in node.children() {
        if c.is_text() {
            // a line break in the source is white space; only `br` and blocks break lines
            out.extend(
                c.text()
                    .unwrap_or("")
                    .chars()
                    .map(|ch| if ch.is_whitespace() { ' ' } else { ch }),
            );
        } else if c.is_element() {
            let name = c.tag_name().name();
            match name {
                "br" => out.push('\n'),
                "img" | "object" => {
                    if let Some(alt) = c.attribute("alt").or_else(|| c.attribute("name")) {
                        out.push_str(alt);
                    }
                    walk(c, out);
                }
                "td" | "th" => {
                    walk(c, out);
                    out.push_str(" | ");
                }
                _ if is_block(name) => {
                    out.push('\n');
                    if name == "li" {
                        out.push_str("- ");
                    }
                    walk(c, out);
                    out.push('\n');
                }
                _ => walk(c, out),
            }
        }
    }
}

/// The text a reader sees in the XHTML content of `node` (a `THE-VALUE` element).
pub fn xhtml_to_text(node: roxmltree::Node) -> String {
    let mut raw = String::new();
    walk(node, &mut raw);
    // collapse white space within lines, keep the line structure, drop empty lines
    let mut lines: Vec<String> = Vec::new();
    for l in raw.split('\n') {
        let words: Vec<&str> = l.split_whitespace().collect();
        let mut s = words.join(" ");
        while s.ends_with(" |") {
            s.truncate(s.len() - 2);
        }
        if !s.is_empty() {
            lines.push(s);
        }
    }
    lines.join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn back(markup: &str) -> String {
        let doc =
            format!("<THE-VALUE xmlns:xhtml=\"http://www.w3.org/1999/xhtml\">{markup}</THE-VALUE>");
        let d = roxmltree::Document::parse(&doc).unwrap();
        xhtml_to_text(d.root_element())
    }

    #[test]
    fn plain_text_survives() {
        for t in [
            "The GPRM shall release the TM with |X'| < 5 um/s & more.",
            "line one\nline two",
            "±200 µm, \"quoted\", <tag>",
        ] {
            assert_eq!(back(&text_to_xhtml(t)), t);
        }
    }

    #[test]
    fn reads_rich_text_as_a_reader_sees_it() {
        let m = "<xhtml:div>\n  <xhtml:p>The   TM <xhtml:b>shall</xhtml:b> be\n released.</xhtml:p>\
                 <xhtml:ul><xhtml:li>first</xhtml:li><xhtml:li>second</xhtml:li></xhtml:ul>\
                 <xhtml:table><xhtml:tr><xhtml:td>a</xhtml:td><xhtml:td>b</xhtml:td></xhtml:tr></xhtml:table>\
                 </xhtml:div>";
        assert_eq!(
            back(m),
            "The TM shall be released.\n- first\n- second\na | b"
        );
    }
}
