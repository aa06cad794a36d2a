//! Grayscale frames: PGM (P2 plain and P5 raw, 8 or 16 bit, several images concatenated in
//! one file) and PNG (8 or 16-bit gray, via the `png` crate), a folder of frames sorted by name
//! or one multi-frame PGM file.

use crate::ImageError;
use std::path::{Path, PathBuf};

/// One grayscale frame, rows from the top of the image to its bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Largest gray level of the format (255 for 8 bit, 65535 for 16 bit, or the PGM maxval).
    pub maxval: u16,
    /// Gray levels, row-major, `height * width`, the first row the top of the image.
    pub data: Vec<u16>,
}

impl Frame {
    /// Gray level at column `c` and row `r` counted from the top.
    pub fn at(&self, c: usize, r: usize) -> f64 {
        f64::from(self.data[r * self.width + c])
    }

    /// The frame as a binary PGM (P5; 16 bit big-endian when `maxval > 255`).
    pub fn to_pgm(&self) -> Vec<u8> {
        let mut out = format!("P5\n{} {}\n{}\n", self.width, self.height, self.maxval).into_bytes();
        for &v in &self.data {
            if self.maxval > 255 {
                out.extend_from_slice(&v.to_be_bytes());
            } else {
                out.push(v as u8);
            }
        }
        out
    }
}

/// Largest accepted frame side [pixels]: a high-speed camera frame is tens to a few thousand
/// pixels; the bound keeps a corrupt header from allocating gigabytes.
pub const MAX_SIDE: usize = 16_384;

/// Reads every image of a PGM file (P2 or P5; several images may follow each other).
pub fn read_pgm(file: &Path, bytes: &[u8]) -> Result<Vec<Frame>, ImageError> {
    let mut frames = Vec::new();
    let mut pos = 0usize;
    loop {
        // skip whitespace between images
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if pos >= bytes.len() {
            break;
        }
        let k = frames.len();
        let err = |cause: String| ImageError::new(file, 0, format!("frame {k}: {cause}"));
        let magic = bytes.get(pos..pos + 2).unwrap_or(&[]);
        let raw = match magic {
            b"P5" => true,
            b"P2" => false,
            _ => {
                return Err(err(format!(
                    "not a grayscale PGM image (magic {:?}, expected P5 or P2)",
                    String::from_utf8_lossy(magic)
                )));
            }
        };
        pos += 2;
        let mut header = [0usize; 3];
        for (i, h) in header.iter_mut().enumerate() {
            *h = pgm_number(bytes, &mut pos)
                .ok_or_else(|| err(format!("truncated or malformed header (field {})", i + 1)))?;
        }
        let [w, h, maxval] = header;
        if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE {
            return Err(err(format!(
                "size {w} x {h} is outside 1..{MAX_SIDE} pixels"
            )));
        }
        if maxval == 0 || maxval > 65_535 {
            return Err(err(format!("maxval {maxval} is outside 1..65535")));
        }
        let n = w * h;
        let mut data = Vec::with_capacity(n);
        if raw {
            // exactly one whitespace byte after maxval
            pos += 1;
            let bpp = if maxval > 255 { 2 } else { 1 };
            let need = n * bpp;
            let body = bytes.get(pos..pos + need).ok_or_else(|| {
                err(format!(
                    "truncated: {} bytes of pixels, {need} expected for {w} x {h} at {} bit",
                    bytes.len().saturating_sub(pos),
                    8 * bpp
                ))
            })?;
            for c in body.chunks_exact(bpp) {
                let v = if bpp == 2 {
                    u16::from_be_bytes([c[0], c[1]])
                } else {
                    u16::from(c[0])
                };
                data.push(v);
            }
            pos += need;
        } else {
            for i in 0..n {
                let v = pgm_number(bytes, &mut pos).ok_or_else(|| {
                    err(format!("truncated: {i} of {n} gray levels of a plain PGM"))
                })?;
                data.push(v.min(65_536) as u16);
            }
        }
        if let Some(v) = data.iter().find(|&&v| usize::from(v) > maxval) {
            return Err(err(format!("gray level {v} above the maxval {maxval}")));
        }
        frames.push(Frame {
            width: w,
            height: h,
            maxval: maxval as u16,
            data,
        });
    }
    if frames.is_empty() {
        return Err(ImageError::new(file, 0, "no image in the file"));
    }
    Ok(frames)
}

/// A decimal number of a PGM header or plain body, skipping whitespace and `#` comments.
fn pgm_number(bytes: &[u8], pos: &mut usize) -> Option<usize> {
    loop {
        while *pos < bytes.len() && bytes[*pos].is_ascii_whitespace() {
            *pos += 1;
        }
        if bytes.get(*pos) == Some(&b'#') {
            while *pos < bytes.len() && bytes[*pos] != b'\n' {
                *pos += 1;
            }
            continue;
        }
        break;
    }
    let start = *pos;
    let mut v: usize = 0;
    while *pos < bytes.len() && bytes[*pos].is_ascii_digit() {
        v = v
            .checked_mul(10)?
            .checked_add(usize::from(bytes[*pos] - b'0'))?;
        *pos += 1;
        if *pos - start > 9 {
            return None;
        }
    }
    (*pos > start).then_some(v)
}

/// Reads a grayscale PNG (8 or 16 bit; colour and palette images are refused: the camera
/// records gray levels, and a conversion would change the thresholds' meaning).
pub fn read_png(file: &Path, bytes: &[u8]) -> Result<Frame, ImageError> {
    let err = |cause: String| ImageError::new(file, 0, cause);
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::IDENTITY);
    let mut reader = decoder
        .read_info()
        .map_err(|e| err(format!("not a readable PNG: {e}")))?;
    let info = reader.info();
    let (w, h) = (info.width as usize, info.height as usize);
    if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE {
        return Err(err(format!(
            "size {w} x {h} is outside 1..{MAX_SIDE} pixels"
        )));
    }
    if info.color_type != png::ColorType::Grayscale {
        return Err(err(format!(
            "colour type {:?}: only grayscale frames are accepted (convert to 8 or 16-bit gray)",
            info.color_type
        )));
    }
    let depth = info.bit_depth;
    let bits: u32 = match depth {
        png::BitDepth::Eight => 8,
        png::BitDepth::Sixteen => 16,
        other => {
            return Err(err(format!(
                "bit depth {other:?}: only 8 and 16-bit gray frames are accepted"
            )));
        }
    };
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| err("image too large".to_string()))?;
    let mut buf = vec![0u8; size];
    let out = reader
        .next_frame(&mut buf)
        .map_err(|e| err(format!("damaged PNG data: {e}")))?;
    let line = out.line_size;
    let mut data = Vec::with_capacity(w * h);
    for r in 0..h {
        let row = &buf[r * line..r * line + line];
        if bits == 16 {
            data.extend(
                row.chunks_exact(2)
                    .take(w)
                    .map(|c| u16::from_be_bytes([c[0], c[1]])),
            );
        } else {
            data.extend(row.iter().take(w).map(|&v| u16::from(v)));
        }
    }
    Ok(Frame {
        width: w,
        height: h,
        maxval: if bits == 16 { 65_535 } else { 255 },
        data,
    })
}

/// Reads one image file by its extension (`.pgm`, `.pnm`, `.png`; case-insensitive).
pub fn read_file(path: &Path) -> Result<Vec<Frame>, ImageError> {
    let bytes =
        std::fs::read(path).map_err(|e| ImageError::new(path, 0, format!("cannot read: {e}")))?;
    match extension(path).as_deref() {
        Some("png") => Ok(vec![read_png(path, &bytes)?]),
        Some("pgm") | Some("pnm") => read_pgm(path, &bytes),
        _ => Err(ImageError::new(
            path,
            0,
            "not a frame file: the extension must be .pgm, .pnm or .png",
        )),
    }
}

fn extension(p: &Path) -> Option<String> {
    p.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
}

/// A frame sequence: the frames in order and the file each came from.
#[derive(Debug, Clone)]
pub struct Sequence {
    /// The frames.
    pub frames: Vec<Frame>,
    /// The file of each frame.
    pub sources: Vec<PathBuf>,
}

/// Reads a folder of PGM or PNG frames (sorted by name; other files ignored) or one
/// multi-frame PGM file. Every frame must have the first one's size and maxval; in a folder
/// whose names end in a frame number, a gap in the numbers is a missing frame.
pub fn load_sequence(path: &Path) -> Result<Sequence, ImageError> {
    let mut frames = Vec::new();
    let mut sources = Vec::new();
    if path.is_dir() {
        let rd = std::fs::read_dir(path)
            .map_err(|e| ImageError::new(path, 0, format!("cannot read the folder: {e}")))?;
        let mut files: Vec<PathBuf> = rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.is_file() && matches!(extension(p).as_deref(), Some("pgm" | "pnm" | "png"))
            })
            .collect();
        files.sort();
        if files.is_empty() {
            return Err(ImageError::new(
                path,
                0,
                "no .pgm, .pnm or .png frame in the folder",
            ));
        }
        check_numbering(path, &files)?;
        for f in &files {
            for fr in read_file(f)? {
                frames.push(fr);
                sources.push(f.clone());
            }
        }
    } else {
        for fr in read_file(path)? {
            frames.push(fr);
            sources.push(path.to_path_buf());
        }
    }
    let first = &frames[0];
    for (k, f) in frames.iter().enumerate() {
        if (f.width, f.height) != (first.width, first.height) {
            return Err(ImageError::new(
                &sources[k],
                0,
                format!(
                    "frame {k} is {} x {} pixels, the first frame {} x {}",
                    f.width, f.height, first.width, first.height
                ),
            ));
        }
        if f.maxval != first.maxval {
            return Err(ImageError::new(
                &sources[k],
                0,
                format!(
                    "frame {k} has gray levels up to {}, the first frame up to {} (bit depth changed)",
                    f.maxval, first.maxval
                ),
            ));
        }
    }
    Ok(Sequence { frames, sources })
}

/// When every name ends in a number (`retraction00012.pgm`), the numbers must be consecutive.
fn check_numbering(dir: &Path, files: &[PathBuf]) -> Result<(), ImageError> {
    let nums: Vec<Option<u64>> = files
        .iter()
        .map(|f| {
            let stem = f.file_stem()?.to_string_lossy().into_owned();
            let digits: String = stem
                .chars()
                .rev()
                .take_while(|c| c.is_ascii_digit())
                .collect();
            let digits: String = digits.chars().rev().collect();
            if digits.is_empty() || digits.len() > 18 {
                None
            } else {
                digits.parse().ok()
            }
        })
        .collect();
    if nums.iter().any(|n| n.is_none()) {
        return Ok(());
    }
    let mut nums: Vec<(u64, &PathBuf)> = nums.into_iter().flatten().zip(files).collect();
    nums.sort();
    for w in nums.windows(2) {
        if w[1].0 == w[0].0 {
            return Err(ImageError::new(
                dir,
                0,
                format!(
                    "frames {} and {} carry the same number {}",
                    w[0].1.display(),
                    w[1].1.display(),
                    w[0].0
                ),
            ));
        }
        if w[1].0 != w[0].0 + 1 {
            return Err(ImageError::new(
                dir,
                0,
                format!(
                    "missing frame: {} is followed by {} (numbers {} to {} absent)",
                    w[0].1.display(),
                    w[1].1.display(),
                    w[0].0 + 1,
                    w[1].0 - 1
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pgm_plain_raw_16_bit_and_concatenated() {
        let f = Path::new("x.pgm");
        let p2 = b"P2\n# c\n3 2\n255\n0 1 2\n3 4 255\n";
        let fr = read_pgm(f, p2).unwrap();
        assert_eq!(fr[0].data, vec![0, 1, 2, 3, 4, 255]);
        let a = Frame {
            width: 2,
            height: 1,
            maxval: 1000,
            data: vec![7, 999],
        };
        let mut two = a.to_pgm();
        two.extend(a.to_pgm());
        let fr = read_pgm(f, &two).unwrap();
        assert_eq!(fr.len(), 2);
        assert_eq!(fr[1], a);
        let e = read_pgm(f, &a.to_pgm()[..10]).unwrap_err().to_string();
        assert!(e.contains("x.pgm") && e.contains("truncated"), "{e}");
        let e = read_pgm(f, b"P6\n1 1\n255\n000").unwrap_err().to_string();
        assert!(e.contains("not a grayscale PGM"), "{e}");
        let e = read_pgm(f, b"P2 1 1 10 11").unwrap_err().to_string();
        assert!(e.contains("above the maxval"), "{e}");
    }
}
