//! The fields of a geodesic requirement and the ReqIF attributes that supply them; the
//! conversions of values as other tools write them (IDs, methods, limits, numbers).

use super::{CHAPTER_NAME, DESCRIPTION, FOREIGN_ID, NAME, TEXT};
use geodesic_core::units::{Quantity, parse_quantity};

/// A field of a geodesic requirement that an attribute of the file can supply.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Field {
    /// `id`
    Id,
    /// `title`
    Title,
    /// `text`
    Text,
    /// `source`
    Source,
    /// `quantity`
    Quantity,
    /// `dimension`
    Dimension,
    /// `limit`
    Limit,
    /// `probability`
    Probability,
    /// `level` (ECSS verification level)
    Level,
    /// `stage` (ECSS verification stage)
    Stage,
    /// `spectrum.band`
    SpectrumBand,
    /// `spectrum.shape`
    SpectrumShape,
    /// `method`
    Method,
    /// `activity`
    Activity,
    /// `check`
    Check,
    /// `note`
    Note,
}

impl Field {
    /// Every field, in YAML order.
    pub const ALL: [Field; 16] = [
        Field::Id,
        Field::Title,
        Field::Text,
        Field::Source,
        Field::Quantity,
        Field::Dimension,
        Field::Limit,
        Field::Probability,
        Field::SpectrumBand,
        Field::SpectrumShape,
        Field::Level,
        Field::Stage,
        Field::Method,
        Field::Activity,
        Field::Check,
        Field::Note,
    ];

    /// The YAML key.
    pub fn name(self) -> &'static str {
        match self {
            Field::Id => "id",
            Field::Title => "title",
            Field::Text => "text",
            Field::Source => "source",
            Field::Quantity => "quantity",
            Field::Dimension => "dimension",
            Field::Limit => "limit",
            Field::Probability => "probability",
            Field::Level => "level",
            Field::Stage => "stage",
            Field::SpectrumBand => "spectrum-band",
            Field::SpectrumShape => "spectrum-shape",
            Field::Method => "method",
            Field::Activity => "activity",
            Field::Check => "check",
            Field::Note => "note",
        }
    }

    /// The field of a YAML key.
    pub fn parse(s: &str) -> Option<Field> {
        Field::ALL.into_iter().find(|f| f.name() == s)
    }

    /// The attribute names read for the field, first present wins (compared by [`norm`]).
    pub fn candidates(self) -> &'static [&'static str] {
        match self {
            Field::Id => &[
                FOREIGN_ID,
                "geodesic.ID",
                "ID",
                "Identifier",
                "PUID",
                "IE PUID",
                "Object Identifier",
                "Absolute Number",
                "Requirement ID",
                "Req ID",
                "Key",
                "Document Key",
                "Item ID",
            ],
            Field::Title => &[NAME, "geodesic.Title", "Title", "Name"],
            // the names tools give the statement: DOORS ("Object Text"), DOORS Next
            // ("Primary Text"), Polarion and Jama ("Description"), Codebeamer and Integrity
            // ("Text"), Enterprise Architect ("Notes"), and generic exports
            Field::Text => &[
                TEXT,
                "geodesic.Text",
                "Object Text",
                "Primary Text",
                "Text",
                "Requirement Text",
                "Statement",
                "Shall Statement",
                DESCRIPTION,
                "Description",
                "Notes",
                "Content",
                "Body",
            ],
            Field::Source => &["geodesic.Source", "Source"],
            Field::Quantity => &["geodesic.Quantity", "Quantity"],
            Field::Dimension => &["geodesic.Dimension", "Dimension"],
            Field::Limit => &["geodesic.Limit", "Limit"],
            Field::Probability => &["geodesic.Probability", "Probability"],
            Field::Level => &["geodesic.Level", "Verification Level"],
            Field::Stage => &["geodesic.Stage", "Verification Stage"],
            Field::SpectrumBand => &["geodesic.SpectrumBand", "Spectrum Band"],
            Field::SpectrumShape => &["geodesic.SpectrumShape", "Spectrum Shape"],
            Field::Method => &[
                "geodesic.Method",
                "Verification Method",
                "Verification Methods",
                "Method",
                "IE IVV Method",
            ],
            Field::Activity => &["geodesic.Activity", "Verification Activity", "Activity"],
            Field::Check => &["geodesic.Check"],
            Field::Note => &["geodesic.Note", "Note", "Comment", "Comments"],
        }
    }
}

impl Field {
    /// [`Field::candidates`], [`norm`]ed once.
    pub fn candidate_keys(self) -> &'static [String] {
        static KEYS: std::sync::OnceLock<Vec<Vec<String>>> = std::sync::OnceLock::new();
        let all = KEYS.get_or_init(|| {
            Field::ALL
                .iter()
                .map(|f| f.candidates().iter().map(|c| norm(c)).collect())
                .collect()
        });
        let i = Field::ALL
            .iter()
            .position(|f| *f == self)
            .expect("every field is in ALL");
        &all[i]
    }
}

/// The attributes that name a heading: `ReqIF.ChapterName` (the standard, Polarion, ReqIF
/// Studio), DOORS' "Object Heading".
pub const HEADING_ATTRIBUTES: &[&str] = &[CHAPTER_NAME, "Object Heading"];

/// Attributes that are the tool's bookkeeping or geodesic's results, never a requirement's
/// text: not taken as the text when an object has none of [`Field::Text`]'s attributes, and
/// not listed as unmapped by the import's report.
pub const BOOKKEEPING: &[&str] = &[
    "ReqIF.ForeignCreatedBy",
    "ReqIF.ForeignCreatedOn",
    "ReqIF.ForeignModifiedBy",
    "ReqIF.ForeignModifiedOn",
    "ReqIF.ForeignCreatedThru",
    "ReqIF.ForeignDeleted",
    "ReqIF.Prefix",
    "ReqIF.Revision",
    "ReqIF.ChangeDescription",
    "Created By",
    "Created On",
    "Created Thru",
    "Last Modified By",
    "Last Modified On",
    "Modified By",
    "Modified On",
    "Author",
    "Owner",
    "Status",
    "Paragraph Style",
    "geodesic.LimitValue",
    "geodesic.Unit",
    "geodesic.Status",
    "geodesic.Basis",
    "geodesic.Value",
    "geodesic.Margin",
    "geodesic.CloseOut",
    "geodesic.Disposition",
    "geodesic.Remarks",
];

/// An attribute name as compared: without case, white space, `_` and `-`.
pub fn norm(s: &str) -> String {
    s.chars()
        .filter(|c| !c.is_whitespace() && *c != '_' && *c != '-')
        .flat_map(char::to_lowercase)
        .collect()
}

/// A geodesic requirement ID made from an identifier of another tool.
pub fn to_req_id(s: &str) -> String {
    let mut o = String::new();
    for c in s.chars() {
        if c.is_ascii_alphanumeric() {
            o.push(c.to_ascii_uppercase());
        } else if !o.ends_with('-') {
            o.push('-');
        }
    }
    let o = o.trim_matches('-').to_string();
    if o.is_empty() || o.starts_with(|c: char| c.is_ascii_digit()) {
        format!("REQ-{o}").trim_end_matches('-').to_string()
    } else {
        o
    }
}

/// A file name made from a family name (lower case, `-`).
pub fn slug(s: &str) -> String {
    let mut o = String::new();
    for c in s.chars() {
        if c.is_ascii_alphanumeric() {
            o.push(c.to_ascii_lowercase());
        } else if !o.ends_with('-') {
            o.push('-');
        }
    }
    o.trim_matches('-').to_string()
}

/// The ECSS-E-ST-10-02C method of a value as tools write it (of several, the first).
pub fn method_of(s: &str) -> Result<&'static str, String> {
    let first = s.split([',', ';', '/']).next().unwrap_or("").trim();
    let k: String = first
        .chars()
        .filter(char::is_ascii_alphanumeric)
        .flat_map(|c| c.to_lowercase())
        .collect();
    Ok(match k.as_str() {
        "test" | "t" | "testing" => "test",
        "analysis" | "a" | "simulation" | "similarity" => "analysis",
        "reviewofdesign" | "rod" | "r" | "review" | "designreview" => "review-of-design",
        "inspection" | "i" => "inspection",
        _ => {
            return Err(format!(
                "verification method `{}` is none of test, analysis, review-of-design, inspection (ECSS-E-ST-10-02C)",
                geodesic_util::text::clip(first, 80)
            ));
        }
    })
}

/// A number as tools write it in a string attribute: surrounding white space, a leading `+`,
/// a decimal comma (`0,5`; only when there is no point), thin or no-break spaces between
/// digit groups, and a trailing `%` (divided by 100). `None` when it is not a finite number.
pub fn lenient_number(s: &str) -> Option<f64> {
    let t = s.trim();
    let (t, scale) = match t.strip_suffix('%') {
        Some(r) => (r.trim_end(), 0.01),
        None => (t, 1.0),
    };
    let t = t.strip_prefix('+').unwrap_or(t);
    let mut cleaned: String = t
        .chars()
        .filter(|c| !matches!(c, '\u{2009}' | '\u{202f}' | '\u{a0}' | '_'))
        .collect();
    if !cleaned.contains('.') && cleaned.matches(',').count() == 1 {
        cleaned = cleaned.replace(',', ".");
    }
    let v: f64 = cleaned.parse().ok()?;
    let v = v * scale;
    v.is_finite().then_some(v)
}

/// The comparison and the SI quantity of a limit as written (`<= 5 um/s`). A decimal comma
/// (`<= 7,5 um/s`) is read as a point: the returned text is then the corrected one.
pub fn parse_limit(s: &str) -> Result<(Quantity, String, Option<String>), String> {
    let t = s.trim();
    match parse_limit_exact(t) {
        Ok((q, d)) => Ok((q, d, None)),
        Err(e) => {
            // `<= 7,5 um/s`: the number with a decimal comma, as many locales write it
            let fixed = decimal_comma_fixed(t);
            match fixed.as_deref().map(parse_limit_exact) {
                Some(Ok((q, d))) => Ok((q, d, fixed)),
                _ => Err(e),
            }
        }
    }
}

fn decimal_comma_fixed(t: &str) -> Option<String> {
    let chars: Vec<char> = t.chars().collect();
    let mut out = String::with_capacity(t.len());
    let mut changed = false;
    for (i, &c) in chars.iter().enumerate() {
        let digit_before = i > 0 && chars[i - 1].is_ascii_digit();
        let digit_after = chars.get(i + 1).is_some_and(|d| d.is_ascii_digit());
        if c == ',' && digit_before && digit_after {
            out.push('.');
            changed = true;
        } else {
            out.push(c);
        }
    }
    (changed && !t.contains('.')).then_some(out)
}

fn parse_limit_exact(t: &str) -> Result<(Quantity, String), String> {
    for sym in ["<=", "≤", ">=", "≥", "<", ">"] {
        if let Some(rest) = t.strip_prefix(sym) {
            // an amplitude spectral density limit (`... Hz^-1/2`): the dimension is that of the
            // quantity whose spectrum is bounded
            let stripped = geodesic_core::spectrum::strip_asd_unit(rest.trim());
            let rest = stripped.as_deref().unwrap_or(rest);
            let clipped = geodesic_util::text::clip(t, 80);
            let (q, _) =
                parse_quantity(rest.trim()).map_err(|e| format!("limit `{clipped}`: {e}"))?;
            let dim = q.dim.name().ok_or_else(|| {
                format!("limit `{clipped}`: its unit has no dimension geodesic names")
            })?;
            return Ok((q, dim.to_string()));
        }
    }
    Err(format!(
        "limit `{}` must start with <=, <, >= or > (e.g. `<= 5 um/s`)",
        geodesic_util::text::clip(t, 80)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_from_other_tools() {
        assert_eq!(to_req_id("REL-GPRM-VEL"), "REL-GPRM-VEL");
        assert_eq!(to_req_id("LOREM-818"), "LOREM-818");
        assert_eq!(to_req_id("sys_req 12"), "SYS-REQ-12");
        assert_eq!(to_req_id("42"), "REQ-42");
        assert_eq!(to_req_id("_3a15c15b-8af5"), "REQ-3A15C15B-8AF5");
        assert_eq!(to_req_id("--"), "REQ");
    }

    #[test]
    fn methods_as_tools_write_them() {
        assert_eq!(method_of("Test").unwrap(), "test");
        assert_eq!(method_of("A").unwrap(), "analysis");
        assert_eq!(method_of("Review of Design").unwrap(), "review-of-design");
        assert_eq!(method_of("RoD").unwrap(), "review-of-design");
        assert_eq!(method_of("Inspection, Test").unwrap(), "inspection");
        assert!(
            method_of("Demonstration")
                .unwrap_err()
                .contains("Demonstration")
        );
    }

    #[test]
    fn numbers_as_strings() {
        assert_eq!(lenient_number(" 0.5 "), Some(0.5));
        assert_eq!(lenient_number("+1.5E+01"), Some(15.0));
        assert_eq!(lenient_number("0,5"), Some(0.5));
        assert_eq!(lenient_number("50 %"), Some(0.5));
        assert_eq!(lenient_number("1\u{a0}000.5"), Some(1000.5));
        assert_eq!(
            lenient_number("1,000.5"),
            None,
            "a thousands comma is not a decimal"
        );
        assert_eq!(lenient_number("NaN"), None);
        assert_eq!(lenient_number("1e999"), None);
        assert_eq!(lenient_number("abc"), None);
    }

    #[test]
    fn limits_with_a_decimal_comma_are_read() {
        let (q, d, fixed) = parse_limit("<= 7,5 um/s").unwrap();
        assert!((q.value - 7.5e-6).abs() < 1e-18);
        assert_eq!(d, "velocity");
        assert_eq!(fixed.as_deref(), Some("<= 7.5 um/s"));
        let (_, _, fixed) = parse_limit("<= 7.5 um/s").unwrap();
        assert!(fixed.is_none());
        assert!(
            parse_limit("7.5 um/s")
                .unwrap_err()
                .contains("must start with")
        );
    }
}
