//! Content hashes for the reports: SHA-256 (the `sha2` crate) of input files and of the
//! requirement set, so that an auditor can tell which inputs produced a verdict.

use sha2::{Digest, Sha256};

/// SHA-256 of `bytes`, lower-case hex.
///
/// ```
/// assert_eq!(
///     geodesic_util::hash::sha256_hex(b"abc"),
///     "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
/// );
/// ```
pub fn sha256_hex(bytes: &[u8]) -> String {
    let d = Sha256::digest(bytes);
    d.iter().map(|b| format!("{b:02x}")).collect()
}

/// SHA-256 over several `(name, bytes)` parts, each framed by its name and length so that
/// moving bytes between parts changes the hash; the parts are hashed in the order given.
pub fn sha256_parts<'a>(parts: impl IntoIterator<Item = (&'a str, &'a [u8])>) -> String {
    let mut h = Sha256::new();
    for (name, bytes) in parts {
        h.update((name.len() as u64).to_le_bytes());
        h.update(name.as_bytes());
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(bytes);
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}
