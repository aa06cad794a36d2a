//! Lab files as data-acquisition programs and spreadsheets write them (issue 52): each variant
//! of the public `tmmf-adhesion` record loads to the bits of the plain record (so it fits the
//! same), or is refused with a one-line cause naming file and line.

use super::*;

/// The public example `tmmf-adhesion` (YAML text naming `d.csv`, CSV text).
fn example() -> (String, String) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/examples");
    (
        std::fs::read_to_string(dir.join("tmmf-adhesion.yaml"))
            .unwrap()
            .replace("tmmf-adhesion.csv", "d.csv"),
        std::fs::read_to_string(dir.join("tmmf-adhesion.csv")).unwrap(),
    )
}

/// Loads `yaml` beside `csv` (written as bytes) in a fresh directory.
fn load(yaml: &str, csv: &[u8]) -> Result<Dataset, FitError> {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("d.csv"), csv).unwrap();
    let p = tmp.path().join("d.yaml");
    std::fs::write(&p, yaml).unwrap();
    Dataset::load(&p)
}

fn err(yaml: &str, csv: &[u8]) -> String {
    let e = load(yaml, csv).unwrap_err().to_string();
    assert!(!e.contains('\n'), "not one line: {e}");
    e
}

/// The same samples, bit for bit, at the same CSV lines; the same known constants and noise.
fn assert_same(a: &Dataset, b: &Dataset) {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.t), bits(&b.t), "time");
    for ch in ["x", "y"] {
        assert_eq!(bits(a.channel(ch)), bits(b.channel(ch)), "{ch}");
    }
    let vals = |m: &BTreeMap<String, f64>| {
        m.iter()
            .map(|(k, v)| (k.clone(), v.to_bits()))
            .collect::<Vec<_>>()
    };
    assert_eq!(vals(&a.known), vals(&b.known), "known");
    assert_eq!(vals(&a.noise), vals(&b.noise), "noise");
}

fn plain() -> Dataset {
    let (yaml, csv) = example();
    let d = load(&yaml, csv.as_bytes()).unwrap();
    assert!(d.rows.warnings.is_empty(), "{:?}", d.rows.warnings);
    d
}

/// A decimal number's text with its exponent shifted by `k` (the value times 10^k).
fn shifted(text: &str, k: i32) -> String {
    let (m, e) = text.split_once('e').unwrap();
    let e: i32 = e.parse().unwrap();
    let v: f64 = format!("{m}e{}", e + k).parse().unwrap();
    format!("{v}")
}

/// The example's CSV with time in ms and x, y in nm under `header`.
fn in_ms_nm(csv: &str, header: &str) -> String {
    let mut out = format!("{header}\n");
    for l in csv.lines().skip(1) {
        let c: Vec<&str> = l.split(',').collect();
        out += &format!(
            "{},{},{}\n",
            shifted(c[0], 3),
            shifted(c[1], 9),
            shifted(c[2], 9)
        );
    }
    out
}

#[test]
fn semicolons_and_tabs_are_detected_with_a_note_or_read_as_the_yaml_says() {
    let (yaml, csv) = example();
    let plain = plain();
    for (d, what) in [(";", "`;`"), ("\t", "tabs")] {
        let other = load(&yaml, csv.replace(',', d).as_bytes()).unwrap();
        assert_same(&other, &plain);
        assert_eq!(other.rows.lines, plain.rows.lines);
        let w = other.rows.warnings.join("\n");
        assert!(
            other.rows.warnings.len() == 1
                && w.contains("d.csv:1: note:")
                && w.contains(what)
                && w.contains("delimiter:"),
            "{w}"
        );
    }
    // said in the YAML: no note
    let said = yaml.replace("time_column: t\n", "time_column: t\ndelimiter: \";\"\n");
    let d = load(&said, csv.replace(',', ";").as_bytes()).unwrap();
    assert_same(&d, &plain);
    assert!(d.rows.warnings.is_empty(), "{:?}", d.rows.warnings);
    let tab = yaml.replace("time_column: t\n", "time_column: t\ndelimiter: tab\n");
    assert_same(
        &load(&tab, csv.replace(',', "\t").as_bytes()).unwrap(),
        &plain,
    );
    // a YAML that says `,` for a `;` file: the cause, not `time_column:`
    let comma = yaml.replace("time_column: t\n", "time_column: t\ndelimiter: \",\"\n");
    let e = err(&comma, csv.replace(',', ";").as_bytes());
    assert!(
        e.contains("d.csv:1:") && e.contains("delimiter: \";\"") && !e.contains("time_column"),
        "{e}"
    );
    let e = err(
        &yaml.replace("time_column: t\n", "time_column: t\ndelimiter: x\n"),
        csv.as_bytes(),
    );
    assert!(
        e.contains("d.yaml:5:") && e.contains("delimiter `x`"),
        "{e}"
    );
    // a `;` file with decimal commas: refused naming the cause
    let mut rows: Vec<String> = csv.lines().map(|l| l.replace(',', ";")).collect();
    rows[3] = rows[3].replacen('.', ",", 1);
    let e = err(&yaml, (rows.join("\n") + "\n").as_bytes());
    assert!(e.contains("d.csv:4:") && e.contains("decimal comma"), "{e}");
}

#[test]
fn a_unit_in_the_header_is_used_when_the_yaml_gives_none() {
    let (yaml, csv) = example();
    let plain = plain();
    // the record: `Time [ms]` named, no time_unit; before, read as seconds
    let named = yaml
        .replace("time_column: t\n", "time_column: Time [ms]\n")
        .replace("x: 8.000000e-10", "x: 0.8 nm")
        .replace("y: 3.000000e-09", "y: 3 nm")
        .replace(
            "  x: m\n  y: m\n",
            "  x: {column: \"x (nm)\"}\n  y: {column: y}\n",
        );
    let d = load(&named, in_ms_nm(&csv, "Time [ms],x (nm),y [nm]").as_bytes()).unwrap();
    assert_same(&d, &plain);
    assert_eq!(d.units["x"], "nm");
    assert!(d.rows.warnings.is_empty(), "{:?}", d.rows.warnings);
    // no time_column: `t` finds `t [ms]`; a short-form unit that agrees with the header
    let short = yaml
        .replace("time_column: t\n", "")
        .replace("x: 8.000000e-10", "x: 0.8 nm")
        .replace("y: 3.000000e-09", "y: 3 nm")
        .replace("  x: m\n  y: m\n", "  x: nm\n  y: {column: y}\n");
    let d = load(&short, in_ms_nm(&csv, "t [ms],x (nm),y (nm)").as_bytes()).unwrap();
    assert_same(&d, &plain);
    // a time column the YAML does not name: the refusal names it
    let e = err(&yaml, in_ms_nm(&csv, "Time [ms],x,y").as_bytes());
    assert!(
        e.contains("d.csv:1:") && e.contains("time_column: \"Time [ms]\""),
        "{e}"
    );
    // without any unit the channel is refused at its YAML line, naming both places
    let none = named.replace("  y: {column: y}\n", "  y: {column: tip}\n");
    let e = err(&none, in_ms_nm(&csv, "Time [ms],x (nm),tip").as_bytes());
    assert!(
        e.contains("d.yaml:") && e.contains("`y` has no unit") && e.contains("header"),
        "{e}"
    );
}

#[test]
fn a_header_that_contradicts_the_yaml_is_refused_naming_both() {
    let (yaml, csv) = example();
    let csv_ms = in_ms_nm(&csv, "Time [ms],x (nm),y (nm)");
    let said = yaml.replace("time_column: t\n", "time_column: Time [ms]\ntime_unit: s\n");
    let e = err(&said, csv_ms.as_bytes());
    assert!(
        e.contains("d.csv:1:")
            && e.contains("`Time [ms]`")
            && e.contains("d.yaml:5")
            && e.contains("`s`"),
        "{e}"
    );
    let ch = yaml
        .replace("time_column: t\n", "time_column: Time [ms]\n")
        .replace("  x: m\n", "  x: {column: \"x (nm)\", unit: um}\n");
    let e = err(&ch, csv_ms.as_bytes());
    assert!(
        e.contains("`x (nm)`") && e.contains("`um`") && e.contains("d.yaml:6"),
        "{e}"
    );
    // a header unit of the wrong dimension
    let e = err(
        &yaml.replace("time_column: t\n", "time_column: Time [V]\n"),
        csv.replacen("t,", "Time [V],", 1).as_bytes(),
    );
    assert!(
        e.contains("`Time [V]`") && e.contains("dimension voltage"),
        "{e}"
    );
}

#[test]
fn crlf_bom_and_comments_keep_the_bits_and_the_line_numbers() {
    let (yaml, csv) = example();
    let plain = plain();
    let crlf = csv.replace('\n', "\r\n");
    let d = load(&yaml, crlf.as_bytes()).unwrap();
    assert_same(&d, &plain);
    assert_eq!(d.rows.lines, plain.rows.lines);
    // a bad cell is named at the line an editor shows, CRLF or not
    let mut rows: Vec<&str> = csv.lines().collect();
    rows[700] = "-6.5e-04,NaN,0";
    for eol in ["\n", "\r\n"] {
        let e = err(&yaml, (rows.join(eol) + eol).as_bytes());
        assert!(e.contains("d.csv:701:"), "{eol:?}: {e}");
    }
    // a byte-order mark before a comment, before the header, and before the YAML
    for head in ["\u{FEFF}# exported by the DAQ\r\n", "\u{FEFF}"] {
        let text = format!("{head}{crlf}");
        let d = load(&format!("\u{FEFF}{yaml}"), text.as_bytes()).unwrap();
        assert_same(&d, &plain);
        assert!(d.rows.warnings.is_empty(), "{:?}", d.rows.warnings);
        let shift = usize::from(head.contains('#'));
        assert_eq!(d.line_of(0), Some(2 + shift));
    }
}

#[test]
fn known_constants_and_noise_take_units() {
    let (yaml, csv) = example();
    let plain = plain();
    let with = yaml
        .replace("m: 8.900000e-02", "m: 89 g")
        .replace("x: 8.000000e-10", "x: 0.8 nm")
        .replace("y: 3.000000e-09", "y: 3e-3 um");
    let d = load(&with, csv.as_bytes()).unwrap();
    assert_same(&d, &plain);
    let e = err(&yaml.replace("m: 8.900000e-02", "m: 89 V"), csv.as_bytes());
    assert!(
        e.contains("d.yaml:9:") && e.contains("`m`") && e.contains("dimension voltage"),
        "{e}"
    );
    let e = err(
        &yaml.replace("m: 8.900000e-02", "m: 89 grm"),
        csv.as_bytes(),
    );
    assert!(e.contains("d.yaml:9:") && e.contains("unknown unit"), "{e}");
    let e = err(&yaml.replace("x: 8.000000e-10", "x: 1 s"), csv.as_bytes());
    assert!(
        e.contains("d.yaml:11:") && e.contains("noise of `x`"),
        "{e}"
    );
}

#[test]
fn an_empty_file_is_said_to_be_empty() {
    let (yaml, csv) = example();
    for empty in ["", "\u{FEFF}", "\r\n\r\n"] {
        let e = err(&yaml, empty.as_bytes());
        assert!(
            e.contains("d.csv:1:") && e.contains("the file is empty"),
            "{e}"
        );
        let e = err(empty, csv.as_bytes());
        assert!(
            e.contains("d.yaml:1:") && e.contains("the file is empty"),
            "{e}"
        );
    }
    let e = err(&yaml, b"# only a comment\n");
    assert!(e.contains("only comment lines"), "{e}");
}

#[test]
fn an_unknown_unit_gets_a_suggestion() {
    let (yaml, csv) = example();
    let e = err(&yaml.replace("  y: m\n", "  y: mircon\n"), csv.as_bytes());
    assert!(
        e.contains("d.yaml:7:") && e.contains("did you mean `micron`"),
        "{e}"
    );
    let with = yaml
        .replace("  x: m\n", "  x: microns\n")
        .replace("x: 8.000000e-10", "x: 8e-4");
    let x: Vec<String> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            format!("{},{},{}", c[0], shifted(c[1], 6), c[2])
        })
        .collect();
    let d = load(&with, format!("t,x,y\n{}\n", x.join("\n")).as_bytes()).unwrap();
    assert_same(&d, &plain());
}
