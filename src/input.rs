//! Reading the files a user names, and checking the ones raylab writes: only regular files
//! are read (a FIFO, a device, a socket or a directory is refused from its metadata, before
//! anything opens it, so nothing blocks), and at most a cap of bytes (read through a limit, so
//! a file that grows meanwhile cannot run past it either). An existing output path that is a
//! FIFO, a socket or a directory is refused the same way.

use std::io::Read;
use std::path::{Path, PathBuf};

/// The default cap on one input file (OBJ, MTL, scene, rays, script): 1 GiB.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// The cap in force: [`MAX_INPUT_BYTES`], or `RAYLAB_MAX_INPUT_BYTES` where that is a number.
pub fn max_input_bytes() -> u64 {
    limit_from_env("RAYLAB_MAX_INPUT_BYTES", MAX_INPUT_BYTES)
}

/// The number environment variable `var` holds, else `default`: the settable limits.
pub fn limit_from_env(var: &str, default: u64) -> u64 {
    std::env::var(var)
        .ok()
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(default)
}

/// Why a file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: is {kind}, not a regular file", path.display())]
    NotRegular { path: PathBuf, kind: &'static str },
    #[error(
        "{}: {size} bytes is larger than the {limit}-byte limit for an input file \
         (RAYLAB_MAX_INPUT_BYTES sets another)",
        path.display()
    )]
    TooLarge {
        path: PathBuf,
        size: u64,
        limit: u64,
    },
    #[error("{}:{line}: not UTF-8 text", path.display())]
    NotText { path: PathBuf, line: usize },
}

/// Whether the path is a character or block device (/dev/null, /dev/zero).
fn is_device(meta: &std::fs::Metadata) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        t.is_char_device() || t.is_block_device()
    }
    #[cfg(not(unix))]
    {
        let _ = meta;
        false
    }
}

/// What a path that is not a regular file is.
fn kind(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if is_device(meta) {
        return "a device";
    }
    if t.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

/// The metadata of `path` if it is a regular file (following links).
fn regular(path: &Path) -> Result<std::fs::Metadata, InputError> {
    let meta = std::fs::metadata(path).map_err(|source| InputError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    match meta.is_file() {
        true => Ok(meta),
        false => Err(InputError::NotRegular {
            path: path.to_path_buf(),
            kind: kind(&meta),
        }),
    }
}

/// The bytes of regular file `path`, at most `limit` of them.
pub fn read_bytes(path: &Path, limit: u64) -> Result<Vec<u8>, InputError> {
    let meta = regular(path)?;
    let too_large = |size| InputError::TooLarge {
        path: path.to_path_buf(),
        size,
        limit,
    };
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    let io = |source| InputError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    match bytes.len() as u64 > limit {
        true => Err(too_large(bytes.len() as u64)),
        false => Ok(bytes),
    }
}

/// The UTF-8 text of regular file `path` (a leading byte-order mark dropped), at most
/// `limit` bytes.
pub fn read_text(path: &Path, limit: u64) -> Result<String, InputError> {
    let bytes = read_bytes(path, limit)?;
    let mut text = String::from_utf8(bytes).map_err(|e| InputError::NotText {
        path: path.to_path_buf(),
        line: 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count(),
    })?;
    if text.starts_with('\u{feff}') {
        text.drain(..3);
    }
    Ok(text)
}

/// Refuses an output path that exists as a FIFO, a socket or a directory (writing to a FIFO
/// would block until something reads it). A device such as /dev/null is written as usual.
pub fn check_output(path: &Path) -> Result<(), InputError> {
    match std::fs::metadata(path) {
        Ok(meta) if !meta.is_file() && !is_device(&meta) => Err(InputError::NotRegular {
            path: path.to_path_buf(),
            kind: kind(&meta),
        }),
        _ => Ok(()),
    }
}
