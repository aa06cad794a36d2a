//! Partial results of a sharded Monte Carlo run (`geodesic montecarlo --shard I/K --out
//! PART.json`) as JSON sealed with a SHA-256 checksum, and their strict reader used by
//! `geodesic merge` (and fuzzed by `geodesic-fuzz`).

use crate::montecarlo::{self, McResult};

/// Field of a partial result holding the SHA-256 (hex) of the rest of its JSON.
pub const CHECKSUM_KEY: &str = "sha256";

/// The JSON text of a partial result with the SHA-256 of its content (the JSON without the
/// checksum field) added, so that the reader detects any change to it.
pub fn sealed_json(r: &McResult) -> Result<Vec<u8>, String> {
    let mut v = serde_json::to_value(r).map_err(|e| e.to_string())?;
    let body = serde_json::to_vec(&v).map_err(|e| e.to_string())?;
    v[CHECKSUM_KEY] = serde_json::json!(geodesic_util::hash::sha256_hex(&body));
    serde_json::to_vec(&v).map_err(|e| e.to_string())
}

/// Largest |velocity| a partial result may hold [m/s]: the speed of light. No draw of the model
/// comes near it (they are of order um/s); the bound keeps every statistic of a merged run, in
/// um/s, finite.
pub const MAX_SPEED_M_S: f64 = 299_792_458.0;

/// Parses one partial result from its text (`file` names it in the error, which is one line),
/// refusing anything that is not exactly what `montecarlo --shard` wrote: malformed JSON, a
/// missing or wrong checksum, a count beyond its maximum, an empty shard, draws that are not
/// the shard's or a velocity that is not finite or beyond [`MAX_SPEED_M_S`].
pub fn parse_part(file: &str, text: &str) -> Result<McResult, String> {
    let mut v: serde_json::Value = serde_json::from_str(text).map_err(|e| {
        format!(
            "{file}:{}: not a geodesic montecarlo partial result: {}",
            e.line(),
            geodesic_util::text::clip(&e.to_string(), 200)
        )
    })?;
    let Some(obj) = v.as_object_mut() else {
        return Err(format!(
            "{file}: not a geodesic montecarlo partial result (not a JSON object)"
        ));
    };
    let Some(sum) = obj.remove(CHECKSUM_KEY) else {
        return Err(format!(
            "{file}: no `{CHECKSUM_KEY}` checksum (write partial results with this geodesic's montecarlo --shard)"
        ));
    };
    let body = serde_json::to_vec(&v).map_err(|e| format!("{file}: {e}"))?;
    if sum.as_str() != Some(geodesic_util::hash::sha256_hex(&body).as_str()) {
        return Err(format!(
            "{file}: checksum mismatch: the partial result was changed or damaged after it was written"
        ));
    }
    let r: McResult = serde_json::from_value(v).map_err(|e| {
        // serde quotes the offending input (an unknown variant, a field name): one line
        format!(
            "{file}: not a geodesic montecarlo partial result: {}",
            geodesic_util::text::clip(&e.to_string(), 200)
        )
    })?;
    let (i, k) = r.shard.unwrap_or((1, 1));
    montecarlo::check_size(r.n, Some(k)).map_err(|e| format!("{file}: {e}"))?;
    let expect = montecarlo::shard_range(r.n, i, k).map_err(|e| format!("{file}: {e}"))?;
    if r.v_m_s.is_empty() {
        return Err(format!("{file}: shard {i}/{k} holds no draws"));
    }
    if r.start != expect.start || r.v_m_s.len() != expect.len() {
        return Err(format!(
            "{file}: shard {i}/{k} holds {} draws from draw {}, expected draws {}..{}",
            r.v_m_s.len(),
            r.start,
            expect.start,
            expect.end
        ));
    }
    if let Some(j) = r
        .v_m_s
        .iter()
        .position(|x| !x.is_finite() || x.abs() > MAX_SPEED_M_S)
    {
        return Err(format!(
            "{file}: draw {} has a velocity {:e} m/s that is not finite or faster than light",
            r.start + j,
            r.v_m_s[j]
        ));
    }
    Ok(r)
}
