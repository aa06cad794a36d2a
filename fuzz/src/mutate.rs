//! Byte-level and structure-aware mutations, deterministic for a given random stream.

use rand::{Rng, RngExt};

/// Largest input produced [bytes]; larger results are truncated.
pub const MAX_LEN: usize = 256 * 1024;

/// Tokens worth trying in every text format: non-finite and extreme numbers, YAML anchors,
/// aliases, tags and specials, quotes, XML declarations and entities, control characters.
pub const COMMON: &[&str] = &[
    "NaN",
    "nan",
    ".nan",
    ".NaN",
    "inf",
    "-inf",
    ".inf",
    "-.inf",
    "Infinity",
    "-Infinity",
    "1e308",
    "1e309",
    "-1e309",
    "1e-400",
    "-0",
    "-0.0",
    "0",
    "-1",
    "4294967296",
    "18446744073709551615",
    "18446744073709551616",
    "-9223372036854775809",
    "0x10",
    "1_000",
    "~",
    "null",
    "true",
    "&a",
    "*a",
    "&a [1]",
    "<<: *a",
    "!!binary",
    "!!float",
    "!!str",
    "!!int",
    "!!map",
    "!custom",
    "%YAML 1.2\n---\n",
    "---",
    "...",
    "? ",
    ": ",
    "- ",
    "|",
    ">",
    "{",
    "}",
    "[",
    "]",
    ",",
    "\"",
    "'",
    "\\",
    "\\u0000",
    "\\ud800",
    "\t",
    "\r",
    "\r\n",
    "\0",
    "\u{FEFF}",
    "\u{2028}",
    "µ",
    "°",
    "·",
    "^",
    "^-1",
    "^128",
    "/",
    "*",
    "e",
    "E",
    "+",
    "..",
    "<!DOCTYPE x [<!ENTITY a \"b\">]>",
    "&amp;",
    "&a;",
    "&#0;",
    "&#x110000;",
    "<![CDATA[",
    "]]>",
    "<?xml version=\"1.0\"?>",
    "<!--",
    "-->",
    "<",
    ">",
    "=",
    "#",
    "@",
];

/// Applies one to four random mutations to `input` (`others` are splice partners, `dict` the
/// format's own tokens).
pub fn mutate<R: Rng>(rng: &mut R, input: &[u8], others: &[Vec<u8>], dict: &[&str]) -> Vec<u8> {
    let mut v = input.to_vec();
    let n = 1 + rng.random_range(0..4usize);
    for _ in 0..n {
        one(rng, &mut v, others, dict);
        v.truncate(MAX_LEN);
    }
    v
}

fn pos<R: Rng>(rng: &mut R, len: usize) -> usize {
    rng.random_range(0..=len)
}

fn token<'a, R: Rng>(rng: &mut R, dict: &[&'a str]) -> &'a str {
    if !dict.is_empty() && rng.random_bool(0.6) {
        dict[rng.random_range(0..dict.len())]
    } else {
        COMMON[rng.random_range(0..COMMON.len())]
    }
}

/// Byte ranges of the lines of `v` (each without its `\n`).
fn lines(v: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for (i, b) in v.iter().enumerate() {
        if *b == b'\n' {
            out.push((start, i + 1));
            start = i + 1;
        }
    }
    if start < v.len() {
        out.push((start, v.len()));
    }
    out
}

/// Range of the "word" around `at`: the bytes between delimiters (space, punctuation).
fn word(v: &[u8], at: usize) -> (usize, usize) {
    let delim = |b: u8| b" \t\r\n,:;[]{}()<>=\"'/".contains(&b);
    let mut a = at.min(v.len());
    while a > 0 && !delim(v[a - 1]) {
        a -= 1;
    }
    let mut b = at.min(v.len());
    while b < v.len() && !delim(v[b]) {
        b += 1;
    }
    (a, b)
}

fn one<R: Rng>(rng: &mut R, v: &mut Vec<u8>, others: &[Vec<u8>], dict: &[&str]) {
    let len = v.len();
    match rng.random_range(0..16u32) {
        0 if len > 0 => {
            let i = rng.random_range(0..len);
            v[i] ^= 1 << rng.random_range(0..8u32);
        }
        1 if len > 0 => {
            let i = rng.random_range(0..len);
            v[i] = rng.random();
        }
        2 => {
            let i = pos(rng, len);
            let k = 1 + rng.random_range(0..4usize);
            for _ in 0..k {
                let b: u8 = if rng.random_bool(0.5) {
                    b" \n:-{}[]\"'.0123456789eE+&*!#<>/"[rng.random_range(0..31usize)]
                } else {
                    rng.random()
                };
                v.insert(i, b);
            }
        }
        3 if len > 0 => {
            let a = rng.random_range(0..len);
            let b = (a + 1 + rng.random_range(0..64usize)).min(len);
            v.drain(a..b);
        }
        4 if len > 0 => {
            let a = rng.random_range(0..len);
            let b = (a + 1 + rng.random_range(0..256usize)).min(len);
            let chunk = v[a..b].to_vec();
            let at = pos(rng, len);
            v.splice(at..at, chunk);
        }
        5 if !others.is_empty() => {
            let o = &others[rng.random_range(0..others.len())];
            let cut = pos(rng, len);
            let from = pos(rng, o.len());
            v.truncate(cut);
            v.extend_from_slice(&o[from..]);
        }
        6 | 7 => {
            let t = token(rng, dict).as_bytes().to_vec();
            let at = pos(rng, len);
            v.splice(at..at, t);
        }
        8 | 9 => {
            // replace a word (a number, a key, a unit) by a token
            let t = token(rng, dict).as_bytes().to_vec();
            let (a, b) = word(v, pos(rng, len));
            v.splice(a..b, t);
        }
        10 => {
            let mut out = Vec::with_capacity(len + len / 16);
            for &b in v.iter() {
                if b == b'\n' {
                    out.push(b'\r');
                }
                out.push(b);
            }
            *v = out;
        }
        11 => {
            let bom = "\u{FEFF}".as_bytes();
            v.splice(0..0, bom.iter().copied());
        }
        12 => {
            let bad: &[&[u8]] = &[
                b"\xff",
                b"\xc3",
                b"\xed\xa0\x80",
                b"\xf4\x90\x80\x80",
                b"\xe2\x82",
            ];
            let b = bad[rng.random_range(0..bad.len())];
            let at = pos(rng, len);
            v.splice(at..at, b.iter().copied());
        }
        13 => {
            // deep nesting
            let depth = 1 + rng.random_range(0..2000usize);
            let (open, close): (&[u8], &[u8]) = match rng.random_range(0..5u32) {
                0 => (b"[", b"]"),
                1 => (b"{\"a\":", b"}"),
                2 => (b"- ", b""),
                3 => (b"<a>", b"</a>"),
                _ => (b"(", b")"),
            };
            let at = pos(rng, len);
            let mut ins = open.repeat(depth);
            ins.extend_from_slice(b"1");
            ins.extend_from_slice(&close.repeat(depth));
            v.splice(at..at, ins);
        }
        14 => {
            // long string or repeated chunk
            let at = pos(rng, len);
            let n = 1 + rng.random_range(0..20_000usize);
            let b = if rng.random_bool(0.5) { b'a' } else { b'9' };
            v.splice(at..at, std::iter::repeat_n(b, n));
        }
        _ => {
            // line operations: duplicate, delete or swap lines
            let ls = lines(v);
            if ls.is_empty() {
                return;
            }
            let (a0, a1) = ls[rng.random_range(0..ls.len())];
            match rng.random_range(0..3u32) {
                0 => {
                    let l = v[a0..a1].to_vec();
                    v.splice(a0..a0, l);
                }
                1 => {
                    v.drain(a0..a1);
                }
                _ => {
                    let (b0, b1) = ls[rng.random_range(0..ls.len())];
                    if b0 > a1 {
                        let la = v[a0..a1].to_vec();
                        let lb = v[b0..b1].to_vec();
                        v.splice(b0..b1, la);
                        v.splice(a0..a1, lb);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn deterministic_for_a_seed_and_bounded() {
        let seed = b"a: 1\nb: [2, 3]\n".to_vec();
        let run = |s: u64| {
            let mut rng = ChaCha8Rng::seed_from_u64(s);
            (0..500)
                .map(|_| mutate(&mut rng, &seed, std::slice::from_ref(&seed), &["x"]))
                .collect::<Vec<_>>()
        };
        let a = run(7);
        assert_eq!(a, run(7));
        assert_ne!(a, run(8));
        assert!(a.iter().all(|m| m.len() <= MAX_LEN));
        assert!(a.iter().any(|m| m != &seed));
    }
}
