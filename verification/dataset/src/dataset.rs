//! Measurement datasets (interface.md): a YAML metadata file beside a CSV file, in the form a
//! lab delivers them.
//!
//! * `time_unit` (default `s`) and each channel's unit are any unit of
//!   [`geodesic_core::units`] of the right dimension; a channel names its CSV column when the
//!   header is not the channel's name (`x: {column: "TM displacement [nm]", unit: nm}`; the short
//!   form `x: m` means column `x`). Values are converted to SI; a power-of-ten unit (`ms`, `nm`)
//!   is applied to the number as written (its decimal exponent shifted), so that a record in
//!   `ms` and `nm` loads to the same bits as the same record in `s` and `m`.
//! * Lines of the CSV starting with `#` are comments. A row with an empty cell in a column the
//!   dataset uses (a missing value, also a row cut short) is skipped, counted and named in a
//!   warning; [`LoadOptions::strict`] refuses it instead.
//! * A sample far outside the envelope of its neighbours ([`wild_samples`]: a glitch no
//!   continuous signal makes) is excluded from the record the same way, said out loud, and
//!   refused under `strict`.
//! * Unknown keys are refused with file, line and the nearest valid key, as the requirement
//!   files are (serde's `deny_unknown_fields`); every other refusal names file and line and says
//!   what to write instead: malformed YAML, missing file or column, unknown or wrong-dimension
//!   unit, NaN or infinite cells, time not strictly increasing, a channel or known constant the
//!   scenario needs but lacks.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use geodesic_core::units::{Dim, parse_unit};
use geodesic_facility::Scenario;
use serde::{Deserialize, Serialize};
use serde_saphyr::Spanned;

use crate::error::FitError;

/// A loaded dataset, values in SI.
#[derive(Debug, Clone)]
pub struct Dataset {
    /// Path of the YAML file.
    pub yaml_path: PathBuf,
    /// The YAML file name as given on the command line (for JSON and reports).
    pub name: String,
    /// Scenario.
    pub scenario: Scenario,
    /// Free text.
    pub description: String,
    /// Sample times [s] from the trigger, strictly increasing.
    pub t: Vec<f64>,
    /// Channels, values in SI.
    pub channels: BTreeMap<String, Vec<f64>>,
    /// Channel units as written in the YAML.
    pub units: BTreeMap<String, String>,
    /// Known constants (`m` [kg], `E0` [V], ...).
    pub known: BTreeMap<String, f64>,
    /// 1-sigma white noise per channel from the YAML, in SI.
    pub noise: BTreeMap<String, f64>,
    /// Where each sample came from and what was left out (empty for a record made in memory).
    pub rows: Rows,
}

/// Where the samples of a dataset came from in its CSV, and what was left out of it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Rows {
    /// The CSV file as named in messages (empty for a record made in memory).
    pub file: String,
    /// CSV line (1-based) of each sample kept, in order; empty for a record made in memory.
    /// Meaningful only while it has one entry per sample ([`Dataset::line_of`]).
    pub lines: Vec<usize>,
    /// Comment lines (`#`) read past.
    pub comments: usize,
    /// Rows skipped for a missing value.
    pub skipped: Vec<Skipped>,
    /// Rows excluded as wild samples ([`wild_samples`]).
    pub wild: Vec<WildSample>,
    /// One-line warnings for the user (skipped rows, excluded samples).
    pub warnings: Vec<String>,
}

/// A row skipped because a cell the dataset uses is empty.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Skipped {
    /// CSV line (1-based).
    pub line: usize,
    /// The first empty column of the row (its CSV header).
    pub column: String,
}

/// A sample excluded from the record because it lies far outside its neighbours.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct WildSample {
    /// CSV line (1-based).
    pub line: usize,
    /// The channel.
    pub channel: String,
    /// Its time [s].
    pub t: f64,
    /// Its value [SI].
    pub value: f64,
    /// Its distance from the median of its neighbours [SI].
    pub deviation: f64,
    /// That distance over the channel's robust scale ([`wild_samples`]).
    pub robust_sigma: f64,
}

/// How strictly a dataset is read.
#[derive(Debug, Clone, Copy, Default)]
pub struct LoadOptions {
    /// Refuse a row with a missing value and a wild sample (exit 2) instead of skipping it
    /// with a warning.
    pub strict: bool,
}

/// A channel's unit: the short form `x: nm` (column `x`) or `x: {column: "...", unit: nm}`.
#[derive(Debug)]
struct ChannelSpec {
    column: Option<String>,
    unit: Option<String>,
}

const CHANNEL_KEYS: &[&str] = &["column", "unit"];

impl<'de> Deserialize<'de> for ChannelSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = ChannelSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a unit (`x: nm`) or `{column: NAME, unit: UNIT}`")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<ChannelSpec, E> {
                Ok(ChannelSpec {
                    column: None,
                    unit: Some(v.to_string()),
                })
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut m: A,
            ) -> Result<ChannelSpec, A::Error> {
                let mut out = ChannelSpec {
                    column: None,
                    unit: None,
                };
                while let Some(k) = m.next_key::<String>()? {
                    match k.as_str() {
                        "column" => out.column = Some(m.next_value()?),
                        "unit" => out.unit = Some(m.next_value()?),
                        _ => return Err(serde::de::Error::unknown_field(&k, CHANNEL_KEYS)),
                    }
                }
                Ok(out)
            }
        }
        d.deserialize_any(V)
    }
}

/// The keys of a dataset YAML (interface.md), in the order the format lists them.
pub const KEYS: &[&str] = &[
    "scenario",
    "description",
    "data",
    "time_column",
    "time_unit",
    "delimiter",
    "channels",
    "known",
    "noise",
];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Meta {
    scenario: Spanned<String>,
    #[serde(default)]
    description: Option<String>,
    data: Spanned<String>,
    #[serde(default)]
    time_column: Option<Spanned<String>>,
    #[serde(default)]
    time_unit: Option<Spanned<String>>,
    #[serde(default)]
    delimiter: Option<Spanned<String>>,
    channels: Spanned<BTreeMap<String, Spanned<ChannelSpec>>>,
    #[serde(default)]
    known: Option<Spanned<BTreeMap<String, Spanned<Number>>>>,
    #[serde(default)]
    noise: Option<BTreeMap<String, Spanned<Number>>>,
}

/// A number of the dataset YAML: bare (`0.089`, in SI for a known constant, in the channel's
/// unit for a noise figure) or with its unit (`89 g`, `0.8 nm`).
#[derive(Debug, Clone)]
enum Number {
    Bare(f64),
    Text(String),
}

impl<'de> Deserialize<'de> for Number {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = Number;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number, bare or with its unit (`0.089` or `89 g`)")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Number, E> {
                Ok(Number::Bare(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Number, E> {
                Ok(Number::Bare(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Number, E> {
                Ok(Number::Bare(v as f64))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Number, E> {
                Ok(Number::Text(v.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}

impl Number {
    /// The value in SI: a bare number times `bare_scale` (as [`to_si`] does with a cell), a
    /// number with a unit converted by that unit, which must be of dimension `dim` when given.
    /// `Err` is the cause, for a message.
    fn si(&self, bare_scale: f64, dim: Option<Dim>) -> Result<f64, String> {
        let bare = |text: &str, v: f64| to_si(text, v, bare_scale, power_of_ten(bare_scale));
        let text = match self {
            Number::Bare(v) => return Ok(bare(&format!("{v:e}"), *v)),
            Number::Text(t) => t.trim(),
        };
        let (q, unit) = geodesic_core::units::parse_quantity(text).map_err(|e| e.to_string())?;
        if unit.symbol.is_empty() {
            return Ok(bare(text, q.value / unit.scale));
        }
        if let Some(d) = dim
            && q.dim != d
        {
            return Err(format!(
                "`{}` is of dimension {}, expected {d}",
                geodesic_util::text::clip(text, 40),
                q.dim
            ));
        }
        // the number as written, its exponent shifted by a power-of-ten unit (`89 g` is the
        // bits of `0.089`)
        let num = text.replace('\u{03BC}', "µ");
        let num = num
            .trim_end()
            .strip_suffix(unit.symbol.as_str())
            .unwrap_or(text)
            .trim();
        Ok(match num.parse::<f64>() {
            Ok(v) => to_si(num, v, unit.scale, power_of_ten(unit.scale)),
            Err(_) => q.value,
        })
    }
}

fn line_of<T>(s: &Spanned<T>) -> usize {
    s.referenced.line() as usize
}

/// Dimension a channel of a scenario must have, if the scenario fixes it.
fn channel_dim(name: &str) -> Option<Dim> {
    match name {
        "x" | "y" => Some(Dim::LENGTH),
        "E" => Some(Dim::VOLTAGE),
        _ => None,
    }
}

/// The channels a scenario reads (interface.md): those it needs, then the optional ones.
pub(crate) fn scenario_channels(s: Scenario) -> &'static [&'static str] {
    s.channels()
}

/// The declared channels of `meta` (the dataset YAML `file`) as CSV columns: each a channel
/// of `scenario`, with a unit of its dimension when the YAML gives one (else the CSV header's,
/// [`Header::resolve`]); every channel the scenario needs declared.
fn channel_columns(file: &str, meta: &Meta, scenario: Scenario) -> Result<Vec<Column>, FitError> {
    let file = file.to_string();
    let known_channels = scenario_channels(scenario);
    // channels: unit, column
    let mut columns: Vec<Column> = Vec::new();
    for (ch, spec) in &meta.channels.value {
        let line = line_of(spec);
        if !known_channels.contains(&ch.as_str()) {
            return Err(FitError::input(
                &file,
                line,
                format!(
                    "channel `{}` is not one of scenario {} ({}){}; the CSV column goes under \
                     the channel: `{}: {{column: \"{}\", unit: ...}}`",
                    geodesic_util::text::clip(ch, 60),
                    scenario.name(),
                    known_channels.join(", "),
                    did_you_mean(ch, known_channels.iter().copied()),
                    nearest(ch, known_channels.iter().copied()).unwrap_or(known_channels[0]),
                    geodesic_util::text::clip(ch, 60)
                ),
            ));
        }
        let header = spec.value.column.clone().unwrap_or_else(|| ch.clone());
        let Some(u) = spec.value.unit.as_deref() else {
            // the unit of the CSV header (`x [nm]`), or a refusal once the header is read
            columns.push(Column {
                channel: ch.clone(),
                header,
                scale: 1.0,
                unit: None,
                dim: channel_dim(ch),
                line,
            });
            continue;
        };
        let unit = parse_unit(u.trim()).map_err(|e| {
            FitError::input(
                &file,
                line,
                format!(
                    "channel `{ch}`: {e}: write {} (docs/spec/interface.md)",
                    channel_hint(ch)
                ),
            )
        })?;
        if let Some(d) = channel_dim(ch)
            && unit.dim != d
        {
            return Err(FitError::input(
                &file,
                line,
                format!(
                    "channel `{ch}` has unit `{}` of dimension {}, expected {d}: write {}",
                    geodesic_util::text::clip(u, 40),
                    unit.dim,
                    channel_hint(ch)
                ),
            ));
        }
        columns.push(Column {
            channel: ch.clone(),
            header,
            scale: unit.scale,
            unit: Some(u.trim().to_string()),
            dim: channel_dim(ch),
            line,
        });
    }
    for need in scenario.required_channels() {
        if !columns.iter().any(|c| c.channel == *need) {
            let found = meta
                .channels
                .value
                .keys()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(", ");
            return Err(FitError::input(
                &file,
                line_of(&meta.channels),
                format!(
                    "scenario {} needs channel `{need}` under channels: (declared: {}); add \
                     `{need}: m` when the CSV column is named `{need}`, or `{need}: {{column: \
                     \"HEADER\", unit: m}}` to read it from the column HEADER",
                    scenario.name(),
                    if found.is_empty() {
                        "none".into()
                    } else {
                        found
                    }
                ),
            ));
        }
    }
    Ok(columns)
}

/// The known constants of `meta` (the dataset YAML `file`): those `scenario` uses, finite,
/// every one it needs present, masses and voltages positive.
fn known_constants(
    file: &str,
    meta: &Meta,
    scenario: Scenario,
) -> Result<BTreeMap<String, f64>, FitError> {
    let file = file.to_string();
    // known constants: those the scenario uses
    let known_line = meta.known.as_ref().map_or(1, line_of);
    let mut known = BTreeMap::new();
    let wanted = scenario.required_known();
    for (k, v) in meta.known.iter().flat_map(|m| m.value.iter()) {
        if !wanted.contains(&k.as_str()) {
            return Err(FitError::input(
                &file,
                line_of(v),
                format!(
                    "known constant `{}` is not one scenario {} uses ({}){}",
                    geodesic_util::text::clip(k, 60),
                    scenario.name(),
                    wanted.join(", "),
                    match nearest(k, wanted.iter().copied()).or_else(|| {
                        // the one constant the scenario needs is absent: a rename
                        let m = meta.known.as_ref().map(|m| &m.value);
                        match wanted {
                            [w] if m.is_some_and(|m| !m.contains_key(*w)) => Some(*w),
                            _ => None,
                        }
                    }) {
                        Some(n) => format!(": did you mean `{n}` ({})?", known_what(n)),
                        None => ": remove it".into(),
                    }
                ),
            ));
        }
        let si = v.value.si(1.0, known_dim(k)).map_err(|e| {
            FitError::input(
                &file,
                line_of(v),
                format!("known `{k}`: {e}: write {}", known_what(k)),
            )
        })?;
        if !si.is_finite() {
            return Err(FitError::input(
                &file,
                line_of(v),
                format!("known `{k}` is not a finite number: write its value in SI"),
            ));
        }
        known.insert(k.clone(), si);
    }
    for need in wanted {
        if !known.contains_key(*need) {
            return Err(FitError::input(
                &file,
                known_line,
                format!(
                    "scenario {} needs the known constant `{need}` ({}): add it under known:",
                    scenario.name(),
                    known_what(need)
                ),
            ));
        }
    }
    for (k, what) in [("m", "TM mass, kg"), ("E0", "electrode voltage, V")] {
        if let Some(v) = known.get(k).filter(|v| **v <= 0.0) {
            let line = meta
                .known
                .as_ref()
                .and_then(|m| m.value.get(k))
                .map_or(known_line, line_of);
            return Err(FitError::input(
                &file,
                line,
                format!("known `{k}` ({what}) must be positive, not {v}: write it in SI"),
            ));
        }
    }
    Ok(known)
}

/// The noise figures of `meta` (the dataset YAML `file`) [SI]: of declared channels, positive.
fn noise_figures(
    file: &str,
    meta: &Meta,
    columns: &[Column],
    units: &BTreeMap<String, String>,
) -> Result<BTreeMap<String, f64>, FitError> {
    let file = file.to_string();
    let mut noise = BTreeMap::new();
    for (ch, v) in meta.noise.iter().flatten() {
        let Some(c) = columns.iter().find(|c| &c.channel == ch) else {
            let declared: Vec<&str> = columns.iter().map(|c| c.channel.as_str()).collect();
            return Err(FitError::input(
                &file,
                line_of(v),
                format!(
                    "noise given for undeclared channel `{}` (channels: {}){}",
                    geodesic_util::text::clip(ch, 60),
                    declared.join(", "),
                    match nearest(ch, declared.iter().copied()) {
                        Some(n) => format!(": did you mean `{n}`?"),
                        None => ": remove it or declare the channel".into(),
                    }
                ),
            ));
        };
        let positive = || {
            FitError::input(
                &file,
                line_of(v),
                format!(
                    "noise of `{ch}` must be a positive number (1 sigma, in the channel's \
                     unit {} or with its own), or leave it out to have it estimated",
                    units[ch]
                ),
            )
        };
        // as the CSV's cells: the decimal written, its exponent shifted (exact)
        let si = v.value.si(c.scale, c.dim).map_err(|e| {
            FitError::input(
                &file,
                line_of(v),
                format!("noise of `{ch}`: {e}: write {}", channel_hint(ch)),
            )
        })?;
        if !(si.is_finite() && si > 0.0) {
            return Err(positive());
        }
        noise.insert(ch.clone(), si);
    }
    Ok(noise)
}

/// The time column's unit as written and its scale to seconds (`time_unit`; `None` when absent:
/// the header's unit, else seconds).
fn time_unit(file: &str, meta: &Meta) -> Result<Option<(String, f64)>, FitError> {
    let file = file.to_string();
    Ok(match &meta.time_unit {
        None => None,
        Some(u) => {
            let unit = parse_unit(u.value.trim()).map_err(|e| {
                FitError::input(
                    &file,
                    line_of(u),
                    format!("time_unit: {e}: write a time unit such as s, ms or us"),
                )
            })?;
            if unit.dim != Dim::TIME {
                return Err(FitError::input(
                    &file,
                    line_of(u),
                    format!(
                        "time_unit `{}` is of dimension {}, not a time: write s, ms or us",
                        geodesic_util::text::clip(&u.value, 40),
                        unit.dim
                    ),
                ));
            }
            Some((u.value.trim().to_string(), unit.scale))
        }
    })
}

/// The CSV's delimiter from the YAML's `delimiter:` (`None`: detected from the header).
fn delimiter_of(file: &str, meta: &Meta) -> Result<Option<u8>, FitError> {
    let Some(d) = &meta.delimiter else {
        return Ok(None);
    };
    let b = match d.value.as_str() {
        "," | "comma" => b',',
        ";" | "semicolon" => b';',
        "\t" | "\\t" | "tab" => b'\t',
        "|" => b'|',
        _ => {
            return Err(FitError::input(
                file,
                line_of(d),
                format!(
                    "delimiter `{}` is not one geodesic reads: write `delimiter: \",\"`, \
                     `\";\"`, `\"\\t\"` (a tab) or `\"|\"`, or leave it out to detect `;` and tabs",
                    short(&d.value)
                ),
            ));
        }
    };
    Ok(Some(b))
}

/// Refuses a table (of the CSV `csv`) too short to fit or without a sample after the trigger.
fn check_samples(csv: &str, table: &Table) -> Result<(), FitError> {
    let csv = csv.to_string();
    if table.t.len() < 10 {
        return Err(FitError::input(
            &csv,
            table.rows.lines.last().copied().unwrap_or(1),
            format!(
                "only {} samples{}: a fit needs at least 10 rows",
                table.t.len(),
                if table.rows.skipped.is_empty() {
                    String::new()
                } else {
                    format!(
                        " after skipping {} rows with a missing value",
                        table.rows.skipped.len()
                    )
                }
            ),
        ));
    }
    if !table.t.iter().any(|&v| v >= 0.0) {
        return Err(FitError::input(
            &csv,
            table.rows.lines.last().copied().unwrap_or(0),
            format!(
                "no sample at or after the trigger t = 0 (the last is at {:e} s): the time \
                 column is measured from the trigger; check `time_unit` and `time_column`",
                table.t.last().copied().unwrap_or(f64::NAN)
            ),
        ));
    }
    Ok(())
}

/// What a channel is, for messages.
fn channel_hint(name: &str) -> &'static str {
    match name {
        "x" => "a length such as m, um or nm",
        "y" => "a length such as m, um or nm",
        "E" => "a voltage such as V or mV",
        _ => "a unit",
    }
}

/// The candidate closest to `word`: equal but for case, or within a case-insensitive
/// Damerau-Levenshtein distance of a third of the longer word (one edit at least when both
/// have two characters or more, so that `x` never suggests `t`), if any.
pub fn nearest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let w = word.to_lowercase();
    candidates
        .into_iter()
        .map(|c| (strsim::damerau_levenshtein(&w, &c.to_lowercase()), c))
        .filter(|(d, c)| {
            let (a, b) = (w.chars().count(), c.chars().count());
            let min_edit = usize::from(a.min(b) >= 2);
            *d <= (a.max(b) / 3).max(min_edit)
        })
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// ` (did you mean `x`?)` when a candidate is near `word`, else empty.
fn did_you_mean<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    nearest(word, candidates).map_or(String::new(), |n| format!(": did you mean `{n}`?"))
}

/// The message of serde's `unknown field `K`, expected one of A, B` rewritten with the nearest
/// valid key and what to do; `None` for any other message.
fn unknown_key_message(msg: &str, what: &str) -> Option<String> {
    let rest = msg.split("unknown field `").nth(1)?;
    let (key, rest) = rest.split_once('`')?;
    let expected: Vec<String> = rest
        .split_once("expected")
        .map(|(_, e)| e.trim().trim_start_matches("one of").trim())
        .unwrap_or("")
        .split([','])
        .flat_map(|s| s.split(" or "))
        .map(|s| s.trim().trim_matches('`').to_string())
        .filter(|s| !s.is_empty())
        .collect();
    let hint = nearest(key, expected.iter().map(String::as_str));
    Some(match hint {
        Some(n) => format!(
            "unknown key `{}` in {what}: did you mean `{n}`? (valid keys: {})",
            geodesic_util::text::clip(key, 60),
            expected.join(", ")
        ),
        None => format!(
            "unknown key `{}` in {what}: remove it (valid keys: {})",
            geodesic_util::text::clip(key, 60),
            expected.join(", ")
        ),
    })
}

/// Reads a YAML file (size-limited) into `T`; a read or parse error is `file:line: cause`, an
/// unknown key names the nearest valid one.
pub fn read_yaml<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, FitError> {
    let file = path.display().to_string();
    let text = geodesic_util::fsio::read_text(path, geodesic_util::fsio::MAX_YAML_BYTES)
        .map_err(|e| FitError::input(&file, e.line(), format!("{}: check the path", e.cause())))?;
    let text = plain_text(text);
    if text
        .lines()
        .all(|l| l.trim().is_empty() || l.trim_start().starts_with('#'))
    {
        return Err(FitError::input(
            &file,
            1,
            "the file is empty (no YAML key): a dataset YAML names at least `scenario:`, \
             `data:` and `channels:` (docs/spec/interface.md)",
        ));
    }
    serde_saphyr::from_str(&text).map_err(|e| {
        let line = e.location().map_or(1, |l| (l.line() as usize).max(1));
        let msg = e.to_string();
        let first = msg.lines().next().unwrap_or("malformed YAML").to_string();
        let first = strip_location(&first);
        if let Some(m) = unknown_key_message(&first, "the dataset YAML") {
            return FitError::input(&file, line, m);
        }
        if let Some(f) = first.strip_prefix("missing field `") {
            let f = f.trim_end_matches('`');
            return FitError::input(
                &file,
                line,
                format!(
                    "the dataset YAML lacks `{f}:` (interface.md: scenario, data, channels are \
                     required): add it"
                ),
            );
        }
        FitError::input(
            &file,
            line,
            format!(
                "malformed YAML: {first}: check the indentation, the `key: value` form and the \
                 quoting of names with `:` or `#` near this line"
            ),
        )
    })
}

/// A serde-saphyr message without its `error: line N column M: ` prefix (the location is
/// printed by us).
fn strip_location(s: &str) -> String {
    let l = s.trim();
    let l = l.strip_prefix("error: ").unwrap_or(l);
    match l.find(": ") {
        Some(i) if l.starts_with("line ") => l[i + 2..].to_string(),
        _ => l.to_string(),
    }
}

/// A channel read from a CSV column.
#[derive(Clone)]
struct Column {
    /// The channel.
    channel: String,
    /// Its CSV header.
    header: String,
    /// SI per unit of the values as written (of `unit`; 1 until [`Header::resolve`] when the
    /// YAML gives no unit).
    scale: f64,
    /// The unit as the YAML writes it (`None`: none given, the header's is used).
    unit: Option<String>,
    /// The dimension the column must have, when the format fixes it.
    dim: Option<Dim>,
    /// The YAML line that declared it.
    line: usize,
}

/// `Some(k)` when `scale` is exactly `10^k`.
fn power_of_ten(scale: f64) -> Option<i32> {
    let k = scale.log10().round();
    if !(-300.0..=300.0).contains(&k) {
        return None;
    }
    let k = k as i32;
    (format!("1e{k}").parse::<f64>().ok() == Some(scale)).then_some(k)
}

/// A number of a CSV cell (`text`, parsed as `v`) in SI: `text` with its decimal exponent
/// shifted by `k` when the unit is `10^k` (the same bits as the number written in SI), else
/// `v * scale`.
fn to_si(text: &str, v: f64, scale: f64, pow10: Option<i32>) -> f64 {
    match pow10 {
        Some(0) => v,
        Some(k) => {
            let (mant, exp) = match text.find(['e', 'E']) {
                Some(i) => match text[i + 1..].parse::<i32>() {
                    Ok(e) => (&text[..i], e),
                    Err(_) => return v * scale,
                },
                None => (text, 0),
            };
            format!("{mant}e{}", exp.saturating_add(k))
                .parse()
                .unwrap_or(v * scale)
        }
        None => v * scale,
    }
}

impl Dataset {
    /// Loads the YAML at `path` and its CSV (missing values and wild samples skipped with a
    /// warning).
    pub fn load(path: &Path) -> Result<Dataset, FitError> {
        Dataset::load_with(path, LoadOptions::default())
    }

    /// CSV line of sample `i`, when the record was read from a CSV.
    pub fn line_of(&self, i: usize) -> Option<usize> {
        (self.rows.lines.len() == self.t.len())
            .then(|| self.rows.lines.get(i).copied())
            .flatten()
    }

    /// Loads the YAML at `path` and its CSV with `opts`.
    pub fn load_with(path: &Path, opts: LoadOptions) -> Result<Dataset, FitError> {
        let file = path.display().to_string();
        let meta: Meta = read_yaml(path)?;
        let scenario = Scenario::from_name(&meta.scenario.value).ok_or_else(|| {
            FitError::input(
                &file,
                line_of(&meta.scenario),
                format!(
                    "unknown scenario `{}`{}: write {}",
                    geodesic_util::text::clip(&meta.scenario.value, 60),
                    did_you_mean(&meta.scenario.value, geodesic_facility::scenario::names()),
                    geodesic_facility::scenario::names()
                        .iter()
                        .map(|n| format!("`scenario: {n}`"))
                        .collect::<Vec<_>>()
                        .join(" or ")
                ),
            )
        })?;
        let columns = channel_columns(&file, &meta, scenario)?;
        let known = known_constants(&file, &meta, scenario)?;
        let time_col = meta
            .time_column
            .as_ref()
            .map_or("t".to_string(), |s| s.value.clone());
        let time_unit = time_unit(&file, &meta)?;
        let delimiter = delimiter_of(&file, &meta)?;
        let csv_path = path
            .parent()
            .unwrap_or(Path::new("."))
            .join(&meta.data.value);
        let csv = csv_path.display().to_string();
        let spec = TableSpec {
            time: Column {
                channel: "time".into(),
                header: time_col,
                scale: time_unit.as_ref().map_or(1.0, |u| u.1),
                unit: time_unit.map(|u| u.0),
                dim: Some(Dim::TIME),
                line: meta
                    .time_unit
                    .as_ref()
                    .or(meta.time_column.as_ref())
                    .map_or(0, line_of),
            },
            channels: columns,
            missing: if opts.strict {
                Missing::Refuse
            } else {
                Missing::Skip
            },
            comments: true,
            header_units: true,
            delimiter,
            yaml: file.clone(),
            data_line: line_of(&meta.data),
        };
        let mut table = read_table(&csv_path, &spec)?;
        let units: BTreeMap<String, String> = table
            .columns
            .iter()
            .map(|c| (c.channel.clone(), c.unit.clone().unwrap_or_default()))
            .collect();
        let noise = noise_figures(&file, &meta, &table.columns, &units)?;
        check_samples(&csv, &table)?;
        // wild samples: excluded, or refused under --strict
        exclude_wild(&mut table, &spec, &noise, opts.strict)?;
        let mut rows = table.rows;
        if !rows.skipped.is_empty() {
            let n = rows.skipped.len();
            let first = &rows.skipped[0];
            rows.warnings.push(format!(
                "{csv}:{}: {n} row{} skipped for a missing value (first: an empty `{}`); \
                 fill the cells in, or pass --strict to refuse such a record",
                first.line,
                if n == 1 { "" } else { "s" },
                geodesic_util::text::clip(&first.column, 60)
            ));
        }
        let name = path
            .file_name()
            .map_or(file.clone(), |n| n.to_string_lossy().to_string());
        Ok(Dataset {
            yaml_path: path.to_path_buf(),
            name,
            scenario,
            description: meta.description.unwrap_or_default(),
            t: table.t,
            channels: table.channels,
            units,
            known,
            noise,
            rows,
        })
    }

    /// The values of a channel [SI].
    pub fn channel(&self, name: &str) -> &[f64] {
        &self.channels[name]
    }

    /// Stem of the YAML file name (`run-017` for `run-017.yaml`).
    pub fn stem(&self) -> String {
        self.yaml_path
            .file_stem()
            .map_or("dataset".into(), |s| s.to_string_lossy().to_string())
    }
}

fn known_what(k: &str) -> &'static str {
    match k {
        "m" => "the TM mock-up mass in kg, e.g. `m: 0.089` or `m: 89 g`",
        "E0" => "the initial electrode voltage in V, e.g. `E0: 120` or `E0: 120 V`",
        _ => "in SI",
    }
}

/// The dimension of a known constant, if the format fixes it.
fn known_dim(k: &str) -> Option<Dim> {
    match k {
        "m" => Some(Dim::MASS),
        "E0" => Some(Dim::VOLTAGE),
        _ => None,
    }
}

/// Largest magnitude of a sample in SI: squares and sums of squares of a whole record stay
/// finite (1e100^2 times a billion samples is far below the float maximum).
pub const MAX_ABS_SI: f64 = 1e100;

/// `s` cut to at most 80 characters for a one-line message.
fn short(s: &str) -> String {
    let one: String = s
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    if one.chars().count() > 80 {
        format!("{}...", one.chars().take(80).collect::<String>())
    } else {
        one
    }
}

/// A CSV's time column [s] and its named channels (values as written).
pub type Columns = (Vec<f64>, BTreeMap<String, Vec<f64>>);

/// Reads the time column and the named channels (scaled by nothing: values as written) of a
/// CSV, with the dataset format's checks (finite numbers, strictly increasing time, file and
/// line in every error; an empty cell refused, no comment lines); used by the spectral series
/// reader.
pub fn read_csv_columns(
    path: &Path,
    time_col: &str,
    channels: &BTreeMap<String, f64>,
) -> Result<Columns, FitError> {
    let spec = TableSpec {
        time: Column {
            channel: "time".into(),
            header: time_col.to_string(),
            scale: 1.0,
            unit: None,
            dim: None,
            line: 0,
        },
        channels: channels
            .keys()
            .map(|c| Column {
                channel: c.clone(),
                header: c.clone(),
                scale: 1.0,
                unit: None,
                dim: None,
                line: 0,
            })
            .collect(),
        missing: Missing::Refuse,
        comments: false,
        header_units: false,
        delimiter: Some(b','),
        yaml: String::new(),
        data_line: 0,
    };
    let t = read_table(path, &spec)?;
    Ok((t.t, t.channels))
}

/// What to do with an empty cell.
#[derive(Clone, Copy, PartialEq)]
enum Missing {
    /// Skip the row (counted).
    Skip,
    /// Refuse the file.
    Refuse,
}

struct TableSpec {
    time: Column,
    channels: Vec<Column>,
    missing: Missing,
    /// `#` lines are comments.
    comments: bool,
    /// A unit in a column's header (`Time [ms]`, `x (um)`) is used when the YAML gives none
    /// and checked against the YAML's.
    header_units: bool,
    /// The delimiter (`None`: `,`, or `;` or a tab when the header has no comma, with a note).
    delimiter: Option<u8>,
    /// The YAML that names the columns (empty: none), for messages.
    yaml: String,
    /// Its `data:` line.
    data_line: usize,
}

struct Table {
    t: Vec<f64>,
    channels: BTreeMap<String, Vec<f64>>,
    /// The channels' columns with their units resolved ([`Header::resolve`]).
    columns: Vec<Column>,
    rows: Rows,
}

/// Reads a CSV by its [`TableSpec`]: values in SI, checked.
fn read_table(path: &Path, spec: &TableSpec) -> Result<Table, FitError> {
    let file = path.display().to_string();
    let text = plain_text(read_csv_text(path, spec, &file)?);
    // the header's line: the first that is neither empty nor a comment
    let is_comment = |l: &str| spec.comments && l.starts_with('#');
    let Some(header_at) = text
        .lines()
        .position(|l| !(l.trim().is_empty() || is_comment(l)))
    else {
        return Err(FitError::input(
            &file,
            1,
            if text.trim().is_empty() {
                "the file is empty: a data file starts with a header line naming its columns, \
                 then one row per sample"
                    .to_string()
            } else {
                "the file has only comment lines and no header: the first line that is not a \
                 `#` comment names the columns"
                    .to_string()
            },
        ));
    };
    let header_text = text.lines().nth(header_at).unwrap_or("");
    let (delimiter, note) = detect_delimiter(spec, header_text, &file, header_at + 1);
    let body = uncommented(&text, spec.comments);
    let blank: Vec<bool> = body.lines().map(|l| l.trim().is_empty()).collect();
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(true)
        .delimiter(delimiter)
        .trim(csv::Trim::All)
        .from_reader(body.as_bytes());
    let headers = rdr
        .headers()
        .map_err(|e| {
            FitError::input(
                &file,
                header_at + 1,
                format!(
                    "bad header: {}: the first line that is not a `#` comment names the columns",
                    short(&e.to_string())
                ),
            )
        })?
        .clone();
    let header = Header {
        names: headers.iter().collect(),
        line: header_at + 1,
        text: &text,
        file: &file,
        spec,
        delimiter,
    };
    let it = header.index(&spec.time)?;
    let idx: Vec<usize> = spec
        .channels
        .iter()
        .map(|c| header.index(c))
        .collect::<Result<_, _>>()?;
    let resolved = header.resolve(it, &idx)?;
    let mut reading = Reading::new(&resolved, &file);
    if let Some(n) = note {
        reading.rows.warnings.push(n);
    }
    for rec in rdr.records() {
        let rec = rec.map_err(|e| {
            FitError::input(
                &file,
                record_line(e.position(), &blank),
                format!(
                    "malformed CSV row: {}: check the quotes of this row",
                    short(&e.to_string())
                ),
            )
        })?;
        reading.record(&rec, record_line(rec.position(), &blank), it, &idx)?;
    }
    Ok(reading.finish(&text))
}

/// A file's text as a program reads it: without the UTF-8 byte-order mark spreadsheet
/// programs write first, with `\n` line ends (a CRLF file's line numbers are those an editor
/// shows).
fn plain_text(text: String) -> String {
    let t = text.strip_prefix('\u{FEFF}').unwrap_or(&text);
    if t.contains('\r') {
        t.replace("\r\n", "\n")
    } else if t.len() == text.len() {
        text
    } else {
        t.to_string()
    }
}

/// The delimiter of a CSV whose header line (line `line` of `file`) is `header`: the YAML's,
/// else `,`, or `;` or a tab when the header has no comma but one of them, with a note saying
/// so.
fn detect_delimiter(
    spec: &TableSpec,
    header: &str,
    file: &str,
    line: usize,
) -> (u8, Option<String>) {
    if let Some(d) = spec.delimiter {
        return (d, None);
    }
    let found = if header.contains(',') {
        None
    } else if header.contains(';') {
        Some((b';', "`;`", "\";\""))
    } else if header.contains('\t') {
        Some((b'\t', "tabs", "\"\\t\""))
    } else {
        None
    };
    match found {
        None => (b',', None),
        Some((d, what, yaml)) => (
            d,
            Some(format!(
                "{file}:{line}: note: the header has no comma, its columns are separated by \
                 {what}: read so; write `delimiter: {yaml}` in the dataset YAML to say it"
            )),
        ),
    }
}

/// The CSV's text, a read error naming the file (or the YAML's `data:` line that names it).
fn read_csv_text(path: &Path, spec: &TableSpec, file: &str) -> Result<String, FitError> {
    geodesic_util::fsio::read_text(path, geodesic_util::fsio::MAX_CSV_BYTES).map_err(|e| {
        if spec.yaml.is_empty() {
            FitError::input(file, e.line(), format!("data file: {}", e.cause()))
        } else {
            FitError::input(
                &spec.yaml,
                spec.data_line,
                format!(
                    "data file {}: {}: `data:` is a path relative to the YAML file",
                    geodesic_util::text::clip(file, 120),
                    e.cause()
                ),
            )
        }
    })
}

/// With `comments`, `#` lines become empty lines, which the reader skips while counting them
/// (its own comment option loses the count: the lines of the records after a comment would be
/// off).
fn uncommented(text: &str, comments: bool) -> std::borrow::Cow<'_, str> {
    if comments && text.contains('#') {
        text.split_inclusive('\n')
            .map(|l| {
                if l.starts_with('#') {
                    &l[l.trim_end_matches(['\r', '\n']).len()..]
                } else {
                    l
                }
            })
            .collect::<String>()
            .into()
    } else {
        text.into()
    }
}

/// The line of a record: the reader gives the line it started from; past the empty and
/// comment lines (`blank`) it skipped, the record's own.
fn record_line(position: Option<&csv::Position>, blank: &[bool]) -> usize {
    let mut line = position.map_or(0, |p| p.line() as usize);
    while line > 0 && blank.get(line - 1).copied().unwrap_or(false) {
        line += 1;
    }
    line
}

/// A CSV's header, for finding the columns of a [`TableSpec`].
struct Header<'a> {
    names: Vec<&'a str>,
    /// Its line (1-based).
    line: usize,
    /// The CSV's text (the comment lines above the header are looked at).
    text: &'a str,
    file: &'a str,
    spec: &'a TableSpec,
    /// The delimiter the header was split with.
    delimiter: u8,
}

/// The name and unit of a header that ends in a unit in brackets or parentheses (`Time [ms]`,
/// `x (um)`, `tip [nm]`): `(name, unit text, unit)`; `None` when it has none or the bracket
/// holds no unit (`x (filtered)`).
fn header_unit(h: &str) -> Option<(&str, &str, geodesic_core::units::Unit)> {
    let h = h.trim();
    let close = h.chars().last()?;
    let open = match close {
        ']' => '[',
        ')' => '(',
        _ => return None,
    };
    let at = h.rfind(open)?;
    let inside = h[at + 1..h.len() - 1].trim();
    let unit = parse_unit(inside).ok()?;
    Some((h[..at].trim(), inside, unit))
}

impl Header<'_> {
    /// The index of column `c`: the header named so, else the one whose name before its unit
    /// is (`t` finds `t [ms]`); or an error that says how to name it.
    fn index(&self, c: &Column) -> Result<usize, FitError> {
        let (names, spec) = (&self.names, self.spec);
        let by_name = || {
            spec.header_units
                .then(|| {
                    names
                        .iter()
                        .position(|h| header_unit(h).is_some_and(|(n, _, _)| n == c.header))
                })
                .flatten()
        };
        let found = names.iter().position(|h| *h == c.header).or_else(by_name);
        found.ok_or_else(|| {
            let mut fix = match nearest(&c.header, names.iter().copied()) {
                Some(n) => format!("did you mean `{n}`? "),
                None => String::new(),
            };
            let used = char::from(self.delimiter);
            if let Some(other) = [',', ';', '\t', '|']
                .into_iter()
                .find(|d| *d != used && names.len() == 1 && names[0].contains(*d))
            {
                let (seen, yaml) = match other {
                    '\t' => ("tabs".to_string(), "\"\\t\"".to_string()),
                    d => (format!("`{d}`"), format!("\"{d}\"")),
                };
                return FitError::input(
                    self.file,
                    self.line,
                    format!(
                        "the header is one column ({}): its names are separated by {seen}, \
                         not `{}`: write `delimiter: {yaml}` in the dataset YAML{}",
                        geodesic_util::text::clip(names[0], 80),
                        if used == '\t' {
                            "\\t".to_string()
                        } else {
                            used.to_string()
                        },
                        if spec.delimiter.is_some() {
                            " (or remove `delimiter:` to detect it)"
                        } else {
                            ""
                        }
                    ),
                );
            }
            if spec.comments
                && self
                    .text
                    .lines()
                    .take(self.line.saturating_sub(1))
                    .filter_map(|l| l.strip_prefix('#'))
                    .any(|l| l.split(',').any(|h| h.trim() == c.header))
            {
                fix += "the header seems to be in a `#` comment line: remove its `#`; ";
            }
            // a time column the YAML does not name (`Time [ms]` for the default `t`)
            let time_like = names.iter().find(|h| {
                let name = header_unit(h).map_or(h.trim(), |(n, _, _)| n);
                matches!(name.to_lowercase().as_str(), "t" | "time")
            });
            fix += &if spec.yaml.is_empty() {
                "rename the column".to_string()
            } else if let (true, Some(h)) = (c.channel == "time", time_like) {
                format!("the time column seems to be `{h}`: set `time_column: \"{h}\"`")
            } else if c.channel == "time" {
                "set `time_column:` to the time column's header".to_string()
            } else {
                format!(
                    "name the column in the YAML: `{}: {{column: \"HEADER\", unit: ...}}`",
                    c.channel
                )
            };
            FitError::input(
                self.file,
                self.line,
                format!(
                    "no column `{}` in the header ({}): {fix}",
                    geodesic_util::text::clip(&c.header, 80),
                    geodesic_util::text::clip(&names.join(","), 200)
                ),
            )
        })
    }

    /// The spec with the unit of each column (the time at header index `it`, the channels at
    /// `idx`) settled: the YAML's, the header's when the YAML gives none (a contradiction
    /// between them refused naming both), seconds for a time column without either; a channel
    /// without either is refused.
    fn resolve(&self, it: usize, idx: &[usize]) -> Result<TableSpec, FitError> {
        let spec = self.spec;
        let mut out = TableSpec {
            time: self.resolve_column(&spec.time, self.names[it])?,
            channels: Vec::new(),
            missing: spec.missing,
            comments: spec.comments,
            header_units: spec.header_units,
            delimiter: spec.delimiter,
            yaml: spec.yaml.clone(),
            data_line: spec.data_line,
        };
        for (c, &i) in spec.channels.iter().zip(idx) {
            out.channels.push(self.resolve_column(c, self.names[i])?);
        }
        Ok(out)
    }

    /// Column `c` (headed `h`) with its unit settled ([`Header::resolve`]).
    fn resolve_column(&self, c: &Column, h: &str) -> Result<Column, FitError> {
        let spec = self.spec;
        let from_header = if spec.header_units {
            header_unit(h)
        } else {
            None
        };
        let yaml_at = || {
            if c.line > 0 {
                format!("{}:{}", spec.yaml, c.line)
            } else {
                spec.yaml.clone()
            }
        };
        let what = if c.channel == "time" {
            "`time_unit`".to_string()
        } else {
            format!("channel `{}`'s unit", c.channel)
        };
        let mut out = c.clone();
        match (&c.unit, from_header) {
            (Some(y), Some((_, hu_text, hu))) => {
                let same = hu.dim == parse_unit(y).map_or(hu.dim, |u| u.dim)
                    && ((hu.scale - c.scale) / c.scale).abs() < 1e-12;
                if !same {
                    return Err(FitError::input(
                        self.file,
                        self.line,
                        format!(
                            "column `{}` is in `{}` by its header, but the YAML ({}) gives \
                             {what} `{}`: make them agree, or remove the YAML's unit to use \
                             the header's",
                            short(h),
                            short(hu_text),
                            yaml_at(),
                            short(y)
                        ),
                    ));
                }
            }
            (None, Some((_, hu_text, hu))) => {
                if let Some(d) = c.dim.filter(|d| *d != hu.dim) {
                    return Err(FitError::input(
                        self.file,
                        self.line,
                        format!(
                            "column `{}` is in `{}` by its header, of dimension {}, but {} is \
                             a {}: correct the header, or give the unit in the YAML ({})",
                            short(h),
                            short(hu_text),
                            hu.dim,
                            if c.channel == "time" {
                                "the time".to_string()
                            } else {
                                format!("channel `{}`", c.channel)
                            },
                            d,
                            yaml_at()
                        ),
                    ));
                }
                out.scale = hu.scale;
                out.unit = Some(hu_text.to_string());
            }
            (Some(_), None) => {}
            (None, None) if c.channel == "time" || !spec.header_units => {}
            (None, None) => {
                return Err(FitError::input(
                    &spec.yaml,
                    c.line,
                    format!(
                        "channel `{}` has no unit, in the YAML or in its CSV header `{}`: add \
                         `unit:` ({}), or write it in the header (`{} [nm]`)",
                        c.channel,
                        short(h),
                        channel_hint(&c.channel),
                        c.channel
                    ),
                ));
            }
        }
        Ok(out)
    }
}

/// The rows of a [`TableSpec`] read so far, in SI.
struct Reading<'a> {
    spec: &'a TableSpec,
    file: &'a str,
    /// The power of ten of the time column's scale, and of each channel's.
    pow_t: Option<i32>,
    pows: Vec<Option<i32>>,
    t: Vec<f64>,
    vals: Vec<Vec<f64>>,
    rows: Rows,
    /// The channels' values of the row being read.
    row_vals: Vec<f64>,
}

impl<'a> Reading<'a> {
    fn new(spec: &'a TableSpec, file: &'a str) -> Self {
        Reading {
            spec,
            file,
            pow_t: power_of_ten(spec.time.scale),
            pows: spec
                .channels
                .iter()
                .map(|c| power_of_ten(c.scale))
                .collect(),
            t: Vec::new(),
            vals: vec![Vec::new(); spec.channels.len()],
            rows: Rows {
                file: file.to_string(),
                ..Rows::default()
            },
            row_vals: vec![0.0; spec.channels.len()],
        }
    }

    /// Reads record `rec` of CSV line `line` (the time in column `it`, the channels in `idx`):
    /// kept, skipped for an empty cell, or refused.
    fn record(
        &mut self,
        rec: &csv::StringRecord,
        line: usize,
        it: usize,
        idx: &[usize],
    ) -> Result<(), FitError> {
        let spec = self.spec;
        let mut empty: Option<&str> = None;
        let tv = self.cell(rec, line, it, &spec.time, self.pow_t)?;
        if tv.is_none() {
            empty = Some(&spec.time.header);
        }
        for (k, (c, &i)) in spec.channels.iter().zip(idx).enumerate() {
            match self.cell(rec, line, i, c, self.pows[k])? {
                Some(v) => self.row_vals[k] = v,
                None => {
                    empty.get_or_insert(&c.header);
                }
            }
        }
        if let Some(column) = empty {
            if spec.missing == Missing::Refuse {
                return Err(FitError::input(
                    self.file,
                    line,
                    if spec.yaml.is_empty() {
                        format!("empty cell in column `{column}`: fill it in")
                    } else {
                        format!(
                            "empty cell in column `{column}` (a missing value): fill it in, or \
                             run without --strict to skip the row with a warning"
                        )
                    },
                ));
            }
            self.rows.skipped.push(Skipped {
                line,
                column: column.to_string(),
            });
            return Ok(());
        }
        let tv = tv.expect("not empty");
        if let Some(&prev) = self.t.last()
            && tv <= prev
        {
            return Err(FitError::input(
                self.file,
                line,
                format!(
                    "time not strictly increasing ({tv:e} s after {prev:e} s): sort the rows by \
                     time and remove repeated samples"
                ),
            ));
        }
        self.t.push(tv);
        self.rows.lines.push(line);
        self.keep_values(line)
    }

    /// The row's channel values appended, each checked to stay well inside the float range:
    /// values near the largest float overflow once in SI (or in any sum of squares
    /// downstream).
    fn keep_values(&mut self, line: usize) -> Result<(), FitError> {
        let spec = self.spec;
        for (k, v) in self.row_vals.iter().enumerate() {
            if v.abs() > MAX_ABS_SI {
                let c = &spec.channels[k];
                return Err(FitError::input(
                    self.file,
                    line,
                    format!(
                        "channel `{}` (column `{}`) is {v:e} in SI, beyond the supported \
                         magnitude {MAX_ABS_SI:e}: check the value and the channel's unit{}",
                        c.channel,
                        c.header,
                        if c.line > 0 {
                            format!(" ({}:{})", spec.yaml, c.line)
                        } else {
                            String::new()
                        }
                    ),
                ));
            }
            self.vals[k].push(*v);
        }
        Ok(())
    }

    /// Cell `i` of `rec` (column `c`, its scale a power of ten `pow` when exact) in SI:
    /// `Ok(None)` when empty (a missing value); not a finite number is refused.
    fn cell(
        &self,
        rec: &csv::StringRecord,
        line: usize,
        i: usize,
        c: &Column,
        pow: Option<i32>,
    ) -> Result<Option<f64>, FitError> {
        let skip = self.spec.missing == Missing::Skip;
        let s = rec.get(i).unwrap_or("");
        if s.is_empty() {
            return Ok(None);
        }
        let v: f64 = s.parse().map_err(|_| {
            FitError::input(
                self.file,
                line,
                if s.contains(',') && s.replace(',', ".").parse::<f64>().is_ok() {
                    format!(
                        "`{}` in column `{}` has a decimal comma: export the record with a `.` \
                         decimal point (`{}`)",
                        short(s),
                        c.header,
                        short(&s.replace(',', "."))
                    )
                } else if s.starts_with('"') {
                    format!(
                        "`{}` in column `{}` is not a number (unbalanced quote?): write a \
                         plain or scientific number",
                        short(s),
                        c.header
                    )
                } else {
                    format!(
                        "`{}` in column `{}` is not a number: write a plain or scientific \
                         number with a `.` decimal point{}",
                        short(s),
                        c.header,
                        if skip {
                            ", or leave the cell empty for a missing value"
                        } else {
                            ""
                        }
                    )
                },
            )
        })?;
        if !v.is_finite() {
            return Err(FitError::input(
                self.file,
                line,
                format!(
                    "`{}` in column `{}` is not a finite number: correct it{}",
                    short(s),
                    c.header,
                    if skip {
                        ", or leave the cell empty to skip the row (a missing value)"
                    } else {
                        ""
                    }
                ),
            ));
        }
        Ok(Some(to_si(s, v, c.scale, pow)))
    }

    /// The table read, with the count of `text`'s comment lines.
    fn finish(self, text: &str) -> Table {
        let mut rows = self.rows;
        rows.comments = text
            .lines()
            .filter(|l| self.spec.comments && l.starts_with('#'))
            .count();
        Table {
            t: self.t,
            columns: self.spec.channels.clone(),
            channels: self
                .spec
                .channels
                .iter()
                .zip(self.vals)
                .map(|(c, v)| (c.channel.clone(), v))
                .collect(),
            rows,
        }
    }
}

/// Neighbours of a sample [`wild_samples`] compares it with (five on each side; at the ends
/// the ten nearest).
const NEIGHBOURS: usize = 10;
/// Neighbours left out at each end of their sorted values when taking their spread: a glitch
/// of up to this many samples (plus the sample itself) cannot widen it.
const TRIM: usize = 3;
/// A wild sample is this many times the channel's robust scale from its neighbours' median...
pub const WILD_ROBUST_SIGMA: f64 = 20.0;
/// ...and this many times the spread of its neighbours (their range without the three lowest
/// and the three highest): outside any curve its neighbours trace.
pub const WILD_SPREAD: f64 = 10.0;

/// For each sample of `v`: its deviation from the median of its [`NEIGHBOURS`] and their
/// spread (their range without the [`TRIM`] lowest and highest). Empty when `v` has no more
/// samples than [`NEIGHBOURS`]. A glitch of up to four samples moves neither: each of its
/// samples has at most three glitched neighbours.
pub fn local_deviation(v: &[f64]) -> Vec<(f64, f64)> {
    let n = v.len();
    if n <= NEIGHBOURS {
        return Vec::new();
    }
    let half = NEIGHBOURS / 2;
    let mut buf = [0.0; NEIGHBOURS];
    (0..n)
        .map(|i| {
            let start = i.saturating_sub(half).min(n - NEIGHBOURS - 1);
            let mut k = 0;
            for (j, &x) in v.iter().enumerate().skip(start).take(NEIGHBOURS + 1) {
                if j != i {
                    buf[k] = x;
                    k += 1;
                }
            }
            let m = geodesic_util::stats::median(&mut buf[..k]);
            // buf is sorted now: the spread without the extremes
            let spread = buf[k - 1 - TRIM] - buf[TRIM];
            (v[i] - m, spread)
        })
        .collect()
}

/// [`local_deviation`] of `v` sampled at times `t` [s]. On a grid (every interval within 1e-6
/// of the first) the same, bit for bit. On irregular stamps (jitter, gaps) each sample of the
/// window (the sample and its neighbours) is first carried back from its stamp to the window's
/// straight grid (from its first to its last stamp) along the neighbours' local slope, the
/// median of the slopes of five disjoint pairs of neighbours (a wild neighbour spoils one
/// pair): the neighbours' median by index takes a steep signal between uneven stamps for a
/// deviation (a retraction's residual at the start of its stroke, stamps jittered by sd 10 %
/// of the step, read 8.3 robust sigma off and was set aside as a wild sample). Only the
/// displacement is carried, a tenth of a step for such jitter, so a corner of the signal (a
/// trigger) moves the figure by little; at the record's ends, whose neighbours are on one side,
/// the neighbours are carried to the sample's stamp. `t` shorter than `v`:
/// [`local_deviation`].
pub fn local_deviation_at(t: &[f64], v: &[f64]) -> Vec<(f64, f64)> {
    let n = v.len();
    if n <= NEIGHBOURS || t.len() < n {
        return local_deviation(v);
    }
    let h0 = t[1] - t[0];
    let regular = t[..n]
        .windows(2)
        .all(|w| ((w[1] - w[0]) - h0).abs() <= 1e-6 * h0.abs());
    if regular {
        return local_deviation(v);
    }
    let half = NEIGHBOURS / 2;
    let mut idx = [0usize; NEIGHBOURS];
    let mut buf = [0.0; NEIGHBOURS];
    (0..n)
        .map(|i| {
            let start = i.saturating_sub(half).min(n - NEIGHBOURS - 1);
            let mut k = 0;
            for j in start..start + NEIGHBOURS + 1 {
                if j != i {
                    idx[k] = j;
                    k += 1;
                }
            }
            // slopes of the pairs (first, sixth), (second, seventh), ...
            let mut slopes = [0.0; NEIGHBOURS / 2];
            for (p, sl) in slopes.iter_mut().enumerate() {
                let (a, b) = (idx[p], idx[p + half]);
                let dt = t[b] - t[a];
                *sl = if dt > 0.0 { (v[b] - v[a]) / dt } else { 0.0 };
            }
            let slope = geodesic_util::stats::median(&mut slopes);
            let slope = if slope.is_finite() { slope } else { 0.0 };
            // each sample's displacement from the window's straight grid (its first and last
            // stamps), carried along the slope; at the record's ends, where the neighbours
            // are all on one side, the whole way to the sample's stamp (the index's median
            // lags a steep signal by half the window there)
            let (a, b) = (start, start + NEIGHBOURS);
            let step = (t[b] - t[a]) / NEIGHBOURS as f64;
            let centred = start + half == i;
            let moved = |j: usize| {
                let to = if centred {
                    t[a] + (j - a) as f64 * step
                } else {
                    t[i]
                };
                v[j] - slope * (t[j] - to)
            };
            for (x, &j) in buf.iter_mut().zip(&idx[..k]) {
                *x = moved(j);
            }
            let m = geodesic_util::stats::median(&mut buf[..k]);
            let spread = buf[k - 1 - TRIM] - buf[TRIM];
            (moved(i) - m, spread)
        })
        .collect()
}

/// The robust scale of local deviations: 1.4826 times their median absolute value (the
/// standard deviation for Gaussian noise).
pub fn robust_scale(dev: &[(f64, f64)]) -> f64 {
    if dev.is_empty() {
        return 0.0;
    }
    let mut a: Vec<f64> = dev.iter().map(|(d, _)| d.abs()).collect();
    let mid = a.len() / 2;
    a.select_nth_unstable_by(mid, f64::total_cmp);
    1.4826 * a[mid]
}

/// The samples of `v` that no continuous signal explains: farther from the median of their ten
/// neighbours than [`WILD_ROBUST_SIGMA`] times the channel's robust scale (the median absolute
/// deviation from the neighbours, floored at `floor` [SI] and at the channel's quantum, its
/// smallest step between samples) and than [`WILD_SPREAD`] times the neighbours' own spread.
/// A smooth signal, however steep or oscillating, stays within its neighbours' envelope (a
/// peak sampled six times per period lies one spread off their median; a step, half of one);
/// Gaussian noise never reaches 20 sigma. Glitches of one to four adjacent samples are found.
/// Returns (index, deviation, deviation over the scale).
pub fn wild_samples(v: &[f64], floor: f64) -> Vec<(usize, f64, f64)> {
    let dev = local_deviation(v);
    if dev.is_empty() {
        return Vec::new();
    }
    let quantum = v
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min);
    let quantum = if quantum.is_finite() { quantum } else { 0.0 };
    let s = robust_scale(&dev).max(floor).max(quantum);
    dev.iter()
        .enumerate()
        .filter(|(_, (d, spread))| {
            d.abs() > WILD_ROBUST_SIGMA * s && d.abs() > WILD_SPREAD * spread
        })
        .map(|(i, (d, _))| (i, *d, if s > 0.0 { d.abs() / s } else { f64::INFINITY }))
        .collect()
}

/// Removes the wild samples of every channel from `table` (or refuses the first under
/// `strict`), recording them and a warning.
fn exclude_wild(
    table: &mut Table,
    spec: &TableSpec,
    noise: &BTreeMap<String, f64>,
    strict: bool,
) -> Result<(), FitError> {
    let csv = table.rows.file.clone();
    let mut drop = vec![false; table.t.len()];
    let mut found: Vec<WildSample> = Vec::new();
    for c in &spec.channels {
        let v = &table.channels[&c.channel];
        let floor = noise.get(&c.channel).copied().unwrap_or(0.0);
        for (i, d, z) in wild_samples(v, floor) {
            let w = WildSample {
                line: table.rows.lines[i],
                channel: c.channel.clone(),
                t: table.t[i],
                value: v[i],
                deviation: d,
                robust_sigma: z,
            };
            if strict {
                return Err(FitError::input(
                    csv.clone(),
                    w.line,
                    format!(
                        "`{}` = {:e} (SI) lies {} robust sigma off its neighbours (a wild sample): \
                         correct it or leave the cell empty; without --strict it is excluded with \
                         a warning",
                        c.header,
                        w.value,
                        fmt_sig(z)
                    ),
                ));
            }
            drop[i] = true;
            found.push(w);
        }
    }
    if found.is_empty() {
        return Ok(());
    }
    found.sort_by_key(|w| w.line);
    let keep = |v: &mut Vec<f64>| {
        let mut k = 0;
        v.retain(|_| {
            k += 1;
            !drop[k - 1]
        });
    };
    keep(&mut table.t);
    for v in table.channels.values_mut() {
        keep(v);
    }
    let mut k = 0;
    table.rows.lines.retain(|_| {
        k += 1;
        !drop[k - 1]
    });
    let list: Vec<String> = found
        .iter()
        .take(5)
        .map(|w| {
            format!(
                "line {} ({} = {:e}, {} robust sigma off its neighbours)",
                w.line,
                w.channel,
                w.value,
                fmt_sig(w.robust_sigma)
            )
        })
        .collect();
    table.rows.warnings.push(format!(
        "{}:{}: {} wild sample{} excluded from the fit: {}{}; correct or delete {}, or pass \
         --strict to refuse the record",
        csv.clone(),
        found[0].line,
        found.len(),
        if found.len() == 1 { "" } else { "s" },
        list.join(", "),
        if found.len() > 5 { ", ..." } else { "" },
        if found.len() == 1 {
            "that row"
        } else {
            "those rows"
        }
    ));
    table.rows.wild = found;
    Ok(())
}

/// `v` with four significant digits: plain between 1e-3 and 1e5, else scientific.
pub fn fmt_sig(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        let dec = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.dec$}")
    } else {
        format!("{v:.3e}")
    }
}

#[cfg(test)]
mod daq_tests;
#[cfg(test)]
mod tests;
