//! Bounded reading of input files: only regular files, at most a stated size, and text that is
//! UTF-8 (a bad byte is reported at its line). A FIFO, `/dev/zero` or a directory given as an
//! input would otherwise block or allocate without end.

use std::io::Read;
use std::path::Path;

/// Largest CSV data file read [bytes] (1 GiB).
pub const MAX_CSV_BYTES: u64 = 1 << 30;
/// Largest YAML or JSON input file read [bytes] (16 MiB).
pub const MAX_YAML_BYTES: u64 = 16 << 20;

/// Why a file was not read. Display is one line without the file name (callers add it).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReadError {
    /// Opening or reading failed.
    #[error("cannot read: {0}")]
    Io(String),
    /// Not a regular file (FIFO, device, directory, socket).
    #[error("not a regular file ({0}); give a path to a regular file")]
    NotRegular(&'static str),
    /// Larger than the limit.
    #[error("file is larger than the limit of {limit} bytes")]
    TooLarge {
        /// The limit [bytes].
        limit: u64,
    },
    /// Not UTF-8 text.
    #[error("line {line}: invalid UTF-8 (byte 0x{byte:02x} at byte offset {offset})")]
    NotUtf8 {
        /// 1-based line of the first bad byte.
        line: usize,
        /// Byte offset of the first bad byte.
        offset: usize,
        /// The byte.
        byte: u8,
    },
}

impl ReadError {
    /// 1-based line the error is at (0: the whole file).
    pub fn line(&self) -> usize {
        match self {
            ReadError::NotUtf8 { line, .. } => *line,
            _ => 0,
        }
    }

    /// The cause without its line prefix.
    pub fn cause(&self) -> String {
        match self {
            ReadError::NotUtf8 { byte, offset, .. } => {
                format!("invalid UTF-8 (byte 0x{byte:02x} at byte offset {offset})")
            }
            other => other.to_string(),
        }
    }
}

fn kind_of(ft: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ft.is_fifo() {
            return "a FIFO";
        }
        if ft.is_char_device() {
            return "a character device";
        }
        if ft.is_block_device() {
            return "a block device";
        }
        if ft.is_socket() {
            return "a socket";
        }
    }
    if ft.is_dir() {
        "a directory"
    } else {
        "not a file"
    }
}

/// Reads the bytes of the regular file `path`, refusing anything larger than `limit` bytes.
pub fn read_bytes(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    let meta = std::fs::metadata(path).map_err(|e| ReadError::Io(e.to_string()))?;
    if !meta.is_file() {
        return Err(ReadError::NotRegular(kind_of(&meta.file_type())));
    }
    if meta.len() > limit {
        return Err(ReadError::TooLarge { limit });
    }
    let f = std::fs::File::open(path).map_err(|e| ReadError::Io(e.to_string()))?;
    // the file may grow after the check: never read more than limit + 1 bytes
    let mut out = Vec::with_capacity(meta.len() as usize);
    f.take(limit + 1)
        .read_to_end(&mut out)
        .map_err(|e| ReadError::Io(e.to_string()))?;
    if out.len() as u64 > limit {
        return Err(ReadError::TooLarge { limit });
    }
    Ok(out)
}

/// Converts bytes to text, naming the line of the first invalid UTF-8 byte.
pub fn utf8(bytes: Vec<u8>) -> Result<String, ReadError> {
    String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        let b = e.as_bytes();
        let line = 1 + b[..offset].iter().filter(|c| **c == b'\n').count();
        ReadError::NotUtf8 {
            line,
            offset,
            byte: b[offset],
        }
    })
}

/// Reads the regular file `path` as UTF-8 text of at most `limit` bytes.
pub fn read_text(path: &Path, limit: u64) -> Result<String, ReadError> {
    utf8(read_bytes(path, limit)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(tag: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("geodesic-fsio-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn refuses_non_regular_large_and_non_utf8() {
        let d = scratch("all");
        assert!(matches!(
            read_text(&d, 100),
            Err(ReadError::NotRegular("a directory"))
        ));
        #[cfg(unix)]
        assert!(matches!(
            read_text(Path::new("/dev/zero"), 100),
            Err(ReadError::NotRegular("a character device"))
        ));
        let f = d.join("big.txt");
        std::fs::write(&f, vec![b'a'; 200]).unwrap();
        assert_eq!(read_text(&f, 100), Err(ReadError::TooLarge { limit: 100 }));
        std::fs::write(&f, b"one\ntwo\nth\xffree\n").unwrap();
        let e = read_text(&f, 100).unwrap_err();
        assert_eq!(e.line(), 3, "{e}");
        assert!(e.to_string().starts_with("line 3: invalid UTF-8"), "{e}");
        std::fs::write(&f, "fine\n").unwrap();
        assert_eq!(read_text(&f, 100).unwrap(), "fine\n");
        let _ = std::fs::remove_dir_all(&d);
    }
}
