//! Requirement IDs a user typed: the nearest loaded ones when one is unknown.

use crate::error::Error;
use geodesic_core::Requirements;

/// One line for an ID that is not loaded: the nearest IDs (Damerau-Levenshtein distance,
/// case-insensitive), or how to list them all.
pub fn unknown_id(what: &str, id: &str, reqs: &Requirements) -> Error {
    let ids: Vec<&str> = reqs.items.iter().map(|r| r.id.as_str()).collect();
    let near = nearest_ids(id, &ids);
    if near.is_empty() {
        Error::unknown_id(format!(
            "{what}{id}: no such requirement among the {} loaded (`geodesic requirements list` lists them)",
            ids.len()
        ))
    } else {
        Error::unknown_id(format!(
            "{what}{id}: no such requirement; nearest: {}",
            near.join(", ")
        ))
    }
}

/// Up to three loaded IDs nearest to `word`: those at the smallest edit distance, if it is at
/// most a third of the word's length (at least 2), else the IDs that contain it or that it
/// contains.
pub fn nearest_ids(word: &str, ids: &[&str]) -> Vec<String> {
    let w = word.trim().to_uppercase();
    let mut scored: Vec<(usize, &str)> = ids
        .iter()
        .map(|id| (strsim::damerau_levenshtein(&w, &id.to_uppercase()), *id))
        .collect();
    scored.sort();
    let close = (w.chars().count() / 3).max(2);
    let best: Vec<String> = scored
        .iter()
        .filter(|(d, _)| *d <= close)
        .take(3)
        .map(|(_, id)| id.to_string())
        .collect();
    if !best.is_empty() || w.is_empty() {
        return best;
    }
    ids.iter()
        .filter(|id| {
            let u = id.to_uppercase();
            u.contains(&w) || w.contains(&u)
        })
        .take(3)
        .map(|s| s.to_string())
        .collect()
}
