#!/usr/bin/env python3
"""docs/guide-report.md followed as written: its `format_type!` block goes into
verification/report/src/formats.rs, one line into `formats()`, and the report crate's tests run
with it plus a test that renders the example report and checks the new file's content (every
requirement's line). The files are restored afterwards, pass or fail."""
import re
import subprocess
import sys
from pathlib import Path

root = Path(__file__).resolve().parent.parent
guide = (root / "docs/guide-report.md").read_text()
blocks = re.findall(r"```rust\n(.*?)```", guide, re.S)
snippet = next(b for b in blocks if "format_type!(" in b)
snippet = "\n".join(l[3:] if l.startswith("   ") else l for l in snippet.splitlines())
name = re.search(r"format_type!\(\s*(\w+),\s*\"([^\"]+)\"", snippet)
ty, file = name.group(1), name.group(2)
line = re.search(r"One line in `formats\(\)`: `([^`]+)`", guide).group(1)
path = root / "verification/report/src/formats.rs"
original = path.read_text()
try:
    s = original.replace("/// Every report format, in the order they are written.",
                         snippet.strip() + "\n\n/// Every report format, in the order they are written.", 1)
    s = s.replace("        Box::new(BaselineDiffMarkdown),\n",
                  "        Box::new(BaselineDiffMarkdown),\n        " + line + "\n", 1)
    s = s.replace("#[cfg(test)]\nmod tests {", f"""#[cfg(test)]
mod tests {{
    #[test]
    fn guide_report_example_renders_every_requirement() {{
        let r = crate::testutil::report(1.3, 6.0);
        let input = super::RenderInput {{ report: &r, diff: None, json: "{{}}", dir: std::path::Path::new(".") }};
        let f = super::formats().into_iter().find(|f| f.file() == "{file}").expect("registered");
        let text = String::from_utf8(f.render(&input).unwrap().unwrap()).unwrap();
        assert_eq!(text.lines().count(), r.matrix.requirements.len(), "{{text}}");
        for row in &r.matrix.requirements {{
            assert!(text.contains(&row.id), "{{text}}");
        }}
    }}
""", 1)
    path.write_text(s)
    out = subprocess.run(["cargo", "test", "--release", "-p", "geodesic-report", "--lib", "formats"],
                         cwd=root, capture_output=True, text=True)
    print(out.stdout[-3000:], out.stderr[-3000:])
    ok = out.returncode == 0 and "guide_report_example_renders_every_requirement ... ok" in out.stdout
    print(f"guide-report: {ty} ({file}) {'registered and rendered' if ok else 'FAILED'}")
    sys.exit(0 if ok else 1)
finally:
    path.write_text(original)
