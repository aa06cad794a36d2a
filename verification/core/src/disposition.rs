//! Dispositions of known non-compliances: an NCR (non-conformance report), a waiver or a request
//! for deviation (RFD), each with its reference, reason, owner, date and optional expiry,
//! kept in YAML (`verification/dispositions.yaml`) and shown in every report.
//!
//! A disposition does not change a verdict: a non-compliant requirement stays non-compliant.
//! It records that the non-compliance is known and owned, so that a CI gate against a baseline
//! fails on a *new* non-compliance or an *expired* disposition, not on a known one.
//!
//! ```yaml
//! dispositions:
//!   - requirement: CHG-Q
//!     kind: NCR            # NCR | waiver | RFD
//!     reference: NCR-GEO-001
//!     reason: "2-sigma charge 4.3 % above the 3e8 e the specification rounds to"
//!     owner: "charge analysis"
//!     date: 2026-11-23     # YYYY-MM-DD
//!     expires: 2027-06-30  # optional
//! ```

use crate::requirement::{LoadError, LoadKind, Origin, Requirements, origin_of, yaml_error};
use serde::{Deserialize, Serialize};
use serde_saphyr::Spanned;
use std::path::{Path, PathBuf};

/// Kind of disposition.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub enum DispositionKind {
    /// Non-conformance report.
    #[serde(rename = "NCR")]
    Ncr,
    /// Waiver.
    #[serde(rename = "waiver")]
    Waiver,
    /// Request for deviation.
    #[serde(rename = "RFD")]
    Rfd,
}

impl DispositionKind {
    /// As written in YAML and JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            DispositionKind::Ncr => "NCR",
            DispositionKind::Waiver => "waiver",
            DispositionKind::Rfd => "RFD",
        }
    }
}

/// A checked disposition.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Disposition {
    /// Requirement it applies to.
    #[serde(skip_serializing, default)]
    pub requirement: String,
    /// NCR, waiver or RFD.
    pub kind: DispositionKind,
    /// Document reference (`NCR-GEO-001`).
    pub reference: String,
    /// Why the non-compliance is accepted or how it is handled.
    pub reason: String,
    /// Who owns it.
    pub owner: String,
    /// Date raised, `YYYY-MM-DD`.
    pub date: String,
    /// Expiry date, `YYYY-MM-DD`, if any.
    pub expires: Option<String>,
    /// Whether it had expired on the day of the run.
    #[serde(default)]
    pub expired: bool,
    /// `file:line` where it is written.
    #[serde(default)]
    pub defined_at: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    dispositions: Vec<RawDisposition>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawDisposition {
    requirement: Spanned<String>,
    kind: Spanned<String>,
    reference: Spanned<String>,
    reason: String,
    owner: String,
    date: Spanned<String>,
    #[serde(default)]
    expires: Option<Spanned<String>>,
}

/// Days since 1970-01-01 of a `YYYY-MM-DD` date, if valid.
pub fn parse_date(s: &str) -> Option<i64> {
    let b = s.as_bytes();
    if b.len() != 10 || b[4] != b'-' || b[7] != b'-' {
        return None;
    }
    let y: i64 = s[0..4].parse().ok()?;
    let m: u32 = s[5..7].parse().ok()?;
    let d: u32 = s[8..10].parse().ok()?;
    if !(1..=12).contains(&m) || d == 0 {
        return None;
    }
    let leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    let dim = [
        31,
        if leap { 29 } else { 28 },
        31,
        30,
        31,
        30,
        31,
        31,
        30,
        31,
        30,
        31,
    ];
    if d > dim[(m - 1) as usize] {
        return None;
    }
    Some(days_from_civil(y, m, d))
}

/// Days since 1970-01-01 (proleptic Gregorian; H. Hinnant's algorithm).
pub fn days_from_civil(y: i64, m: u32, d: u32) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m as i64 + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d as i64 - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// `YYYY-MM-DD` of a day number since 1970-01-01.
pub fn civil_from_days(z: i64) -> String {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}")
}

/// Today's day number (UTC) since 1970-01-01.
pub fn today() -> i64 {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64);
    secs.div_euclid(86_400)
}

/// Loads and checks a dispositions file against the loaded requirements; `today` is the day
/// number of the run (see [`today`]) that decides [`Disposition::expired`]. With `strict`, a
/// disposition for a requirement that is not loaded is an error; without (the repository's
/// default file applied to a subset of the requirements), it is skipped.
pub fn load(
    path: &Path,
    reqs: &Requirements,
    today: i64,
    strict: bool,
) -> Result<Vec<Disposition>, LoadError> {
    let text = std::fs::read_to_string(path).map_err(|e| LoadError {
        origin: Origin {
            file: path.to_path_buf(),
            line: 1,
            column: 1,
        },
        kind: LoadKind::Unreadable,
        cause: format!("cannot read dispositions: {e}"),
    })?;
    from_str_with(&text, path, reqs, today, strict)
}

/// Parses and checks dispositions from text (`file` is used in messages only); a disposition
/// for a requirement that is not loaded is an error.
pub fn from_str(
    text: &str,
    file: &Path,
    reqs: &Requirements,
    today: i64,
) -> Result<Vec<Disposition>, LoadError> {
    from_str_with(text, file, reqs, today, true)
}

/// As [`from_str`]; without `strict`, dispositions for requirements that are not loaded are
/// skipped (every other error still counts).
pub fn from_str_with(
    text: &str,
    file: &Path,
    reqs: &Requirements,
    today: i64,
    strict: bool,
) -> Result<Vec<Disposition>, LoadError> {
    let file: PathBuf = file.to_path_buf();
    let raw: RawFile = serde_saphyr::from_str(text).map_err(|e| yaml_error(&file, &e))?;
    let mut out: Vec<Disposition> = Vec::new();
    for r in raw.dispositions {
        let err = |s: &Spanned<String>, cause: String| LoadError {
            origin: origin_of(&file, s),
            kind: LoadKind::Invalid,
            cause,
        };
        let id = r.requirement.value.trim().to_string();
        let known = reqs.get(&id).is_some();
        if !known && strict {
            return Err(err(
                &r.requirement,
                format!("disposition for unknown requirement `{id}`"),
            )
            .with_kind(LoadKind::UnknownId));
        }
        if let Some(prev) = out.iter().find(|d| d.requirement == id) {
            return Err(err(
                &r.requirement,
                format!(
                    "second disposition for {id} (first at {}); keep one per requirement",
                    prev.defined_at
                ),
            ));
        }
        let kind = match r.kind.value.trim() {
            "NCR" => DispositionKind::Ncr,
            "waiver" => DispositionKind::Waiver,
            "RFD" => DispositionKind::Rfd,
            other => {
                return Err(err(
                    &r.kind,
                    format!("unknown disposition kind `{other}` (NCR, waiver or RFD)"),
                ));
            }
        };
        if r.reference.value.trim().is_empty() {
            return Err(err(&r.reference, "empty reference".into()));
        }
        let date = r.date.value.trim().to_string();
        let Some(day) = parse_date(&date) else {
            return Err(err(&r.date, format!("`{date}` is not a date (YYYY-MM-DD)")));
        };
        let (expires, expired) = match &r.expires {
            Some(e) => {
                let text = e.value.trim().to_string();
                let Some(d) = parse_date(&text) else {
                    return Err(err(e, format!("`{text}` is not a date (YYYY-MM-DD)")));
                };
                if d < day {
                    return Err(err(
                        e,
                        format!("expires {text} before it was raised ({date})"),
                    ));
                }
                (Some(text), d < today)
            }
            None => (None, false),
        };
        let at = origin_of(&file, &r.requirement);
        if !known {
            continue;
        }
        out.push(Disposition {
            requirement: id,
            kind,
            reference: r.reference.value.trim().to_string(),
            reason: r.reason.trim().to_string(),
            owner: r.owner.trim().to_string(),
            date,
            expires,
            expired,
            defined_at: format!("{}:{}", at.file.display(), at.line),
        });
    }
    Ok(out)
}

/// The dispositions of `text` that name a requirement not in `reqs` (a renamed or removed
/// requirement, or one outside a subset), one line each: `NCR NCR-GEO-002 (file:line) names
/// FAC-ADH-CAL, which is not loaded`. Empty when the text does not parse (the loader says why).
pub fn unmatched(text: &str, file: &Path, reqs: &Requirements) -> Vec<String> {
    let Ok(raw) = serde_saphyr::from_str::<RawFile>(text) else {
        return Vec::new();
    };
    raw.dispositions
        .iter()
        .filter(|r| reqs.get(r.requirement.value.trim()).is_none())
        .map(|r| {
            let at = origin_of(file, &r.requirement);
            format!(
                "{} {} ({}:{}) names {}, which is not loaded: it applies to nothing in this run",
                r.kind.value.trim(),
                r.reference.value.trim(),
                at.file.display(),
                at.line,
                r.requirement.value.trim()
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reqs() -> Requirements {
        let t = "family: f
requirements:
  - id: A-ONE
    title: a
    text: shall
    source: s
    quantity: q
    dimension: velocity
    limit: <= 5 um/s
    method: analysis
    activity: mc
";
        Requirements::from_sources(&[(PathBuf::from("f.yaml"), t.into())]).unwrap()
    }

    const OK: &str = "dispositions:
  - requirement: A-ONE
    kind: waiver
    reference: W-1
    reason: known
    owner: me
    date: 2026-01-01
    expires: 2026-06-30
";

    #[test]
    fn loads_and_expires() {
        let r = reqs();
        let before = parse_date("2026-06-30").unwrap();
        let d = from_str(OK, Path::new("d.yaml"), &r, before).unwrap();
        assert_eq!(d[0].kind, DispositionKind::Waiver);
        assert!(!d[0].expired);
        assert_eq!(d[0].defined_at, "d.yaml:2");
        let d = from_str(OK, Path::new("d.yaml"), &r, before + 1).unwrap();
        assert!(d[0].expired);
    }

    #[test]
    fn bad_entries_name_file_and_line() {
        let r = reqs();
        let cases = [
            (OK.replace("A-ONE", "B-TWO"), ":2:", "unknown requirement"),
            (
                OK.replace("waiver", "excuse"),
                ":3:",
                "unknown disposition kind",
            ),
            (OK.replace("2026-01-01", "2026-02-30"), ":7:", "not a date"),
            (
                OK.replace("2026-06-30", "2025-06-30"),
                ":8:",
                "before it was raised",
            ),
            (
                OK.replace("owner: me", "owner: me\n    colour: red"),
                ":",
                "unknown field",
            ),
        ];
        for (text, at, cause) in cases {
            let e = from_str(&text, Path::new("d.yaml"), &r, 0)
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with("d.yaml") && e.contains(at) && e.contains(cause),
                "{e}"
            );
            assert_eq!(e.lines().count(), 1, "{e}");
        }
    }

    #[test]
    fn civil_round_trip() {
        for z in [-800_000_i64, -1, 0, 1, 19_000, 20_415, 2_000_000] {
            assert_eq!(parse_date(&civil_from_days(z)), Some(z));
        }
        assert_eq!(civil_from_days(0), "1970-01-01");
        assert_eq!(parse_date("2000-02-29"), Some(11_016));
        assert_eq!(parse_date("1900-02-29"), None);
    }
}
