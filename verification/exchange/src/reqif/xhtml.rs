//! Plain text to ReqIF XHTML and back.
//!
//! geodesic's texts are plain: exported as one `xhtml:div`, a line break as `xhtml:br`. On
//! import, XHTML is read as a browser shows it: runs of white space collapse to one space,
//! `br` is a line break, block elements (`p`, `div`, `li`, headings, table rows) start a new
//! line, list items get a `- ` bullet, table cells are separated by ` | `; an image keeps its
//! alternative text (else `[image: SRC]`), an embedded object becomes `[object: DATA]` (its
//! content is the fallback shown when the object cannot be). So a text with two spaces in a row or leading spaces does not
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

/// The text of `node`'s content as a browser lays it out, before white space is collapsed
/// (depth first with a stack: XHTML nested arbitrarily deep cannot overflow it).
fn walk(node: roxmltree::Node, out: &mut String) {
    enum Step<'a, 'i> {
        Enter(roxmltree::Node<'a, 'i>),
        Push(&'static str),
    }
    let mut stack: Vec<Step> = node.children().rev().map(Step::Enter).collect();
    while let Some(step) = stack.pop() {
        let c = match step {
            Step::Push(s) => {
                out.push_str(s);
                continue;
            }
            Step::Enter(c) => c,
        };
        if c.is_text() {
            // a line break in the source is white space; only `br` and blocks break lines
            out.extend(
                c.text()
                    .unwrap_or("")
                    .chars()
                    .map(|ch| if ch.is_whitespace() { ' ' } else { ch }),
            );
            continue;
        }
        if !c.is_element() {
            continue;
        }
        let name = c.tag_name().name();
        let (before, after): (&'static str, &'static str) = match name {
            "br" => {
                out.push('\n');
                continue;
            }
            "img" => {
                match (c.attribute("alt"), c.attribute("src")) {
                    (Some(alt), _) if !alt.trim().is_empty() => out.push_str(alt),
                    (_, Some(src)) => out.push_str(&format!("[image: {src}]")),
                    _ => {}
                }
                continue;
            }
            // an embedded object (a picture, an OLE object, a PDF): a reference to its file;
            // its content is the fallback shown when the object cannot be, not more text
            "object" if c.attribute("data").is_some() => {
                out.push_str(&format!("[object: {}]", c.attribute("data").unwrap_or("")));
                continue;
            }
            "td" | "th" => ("", " | "),
            "li" => ("\n- ", "\n"),
            _ if is_block(name) => ("\n", "\n"),
            _ => ("", ""),
        };
        out.push_str(before);
        if !after.is_empty() {
            stack.push(Step::Push(after));
        }
        stack.extend(c.children().rev().map(Step::Enter));
    }
}

/// The `data` of every embedded object (`xhtml:object`, outermost only) in `node`.
pub fn xhtml_objects(node: roxmltree::Node) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack: Vec<roxmltree::Node> = node.children().collect();
    stack.reverse();
    while let Some(n) = stack.pop() {
        if !n.is_element() {
            continue;
        }
        if n.tag_name().name() == "object" && n.attribute("data").is_some() {
            out.push(n.attribute("data").unwrap_or_default().to_string());
            continue;
        }
        let mut kids: Vec<roxmltree::Node> = n.children().collect();
        kids.reverse();
        stack.extend(kids);
    }
    out
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

    #[test]
    fn embedded_objects_are_references() {
        let m = "<xhtml:div>See <xhtml:object data=\"f/spec.pdf\" type=\"application/pdf\">\
                 <xhtml:object data=\"f/icon.png\" type=\"image/png\">no viewer</xhtml:object>\
                 </xhtml:object> and <xhtml:img src=\"a.png\"/>.</xhtml:div>";
        assert_eq!(back(m), "See [object: f/spec.pdf] and [image: a.png].");
        let doc =
            format!("<THE-VALUE xmlns:xhtml=\"http://www.w3.org/1999/xhtml\">{m}</THE-VALUE>");
        let d = roxmltree::Document::parse(&doc).unwrap();
        assert_eq!(xhtml_objects(d.root_element()), ["f/spec.pdf"]);
    }
}
