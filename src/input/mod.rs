//! Reading the files a user names, and writing the ones raylab makes.
//!
//! Reading: only regular files are read (a FIFO, a device, a socket or a directory is refused
//! from its metadata, before anything opens it, so nothing blocks), and at most a cap of bytes
//! (read through a limit, so a file that grows meanwhile cannot run past it either).
//!
//! Writing: see the `output` module (an output never destroys a file).

pub(crate) mod output;

pub use output::{check_output, temp_owner, write_file, OutputFile, STALE_TEMP_AGE};

use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The default cap on one input file (OBJ, MTL, scene, rays, script): 1 GiB.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// The cap in force: [`MAX_INPUT_BYTES`], or `RAYLAB_MAX_INPUT_BYTES` where that is a number.
pub fn max_input_bytes() -> u64 {
    limit_from_env("RAYLAB_MAX_INPUT_BYTES", MAX_INPUT_BYTES)
}

/// The environment variables that set a limit ([`limit_from_env`]), with what they count.
pub const LIMIT_VARS: [(&str, &str); 4] = [
    ("RAYLAB_MAX_INPUT_BYTES", "bytes"),
    ("RAYLAB_MAX_TRIANGLES", "triangles"),
    ("RAYLAB_MAX_PLACEMENTS", "placements"),
    ("RAYLAB_MAX_TREE_ENTRIES", "scene tree entries"),
];

/// The number environment variable `var` holds, else `default`: the settable limits. (A value
/// that is not a whole number is refused by [`check_limit_vars`], which the binary calls
/// first.)
pub fn limit_from_env(var: &str, default: u64) -> u64 {
    std::env::var(var)
        .ok()
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(default)
}

/// Refuses a limit variable ([`LIMIT_VARS`]) that is set but is not a whole number, so a
/// mistyped limit is never silently replaced by the default.
pub fn check_limit_vars() -> Result<(), String> {
    for (var, unit) in LIMIT_VARS {
        if let Some(value) = std::env::var_os(var) {
            let text = value.to_string_lossy();
            if text.trim().parse::<u64>().is_err() {
                return Err(format!(
                    "{var}='{text}' is not a whole number of {unit} (0 to {})",
                    u64::MAX
                ));
            }
        }
    }
    Ok(())
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
    #[error(
        "{}: reports no size (as files under /proc and /sys do) and holds more than the \
         {limit} bytes read from such a file",
        path.display()
    )]
    Sizeless { path: PathBuf, limit: u64 },
    #[error("{}:{line}: not UTF-8 text", path.display())]
    NotText { path: PathBuf, line: usize },
    #[error("{}: {}", path.display(), NotText::Utf16)]
    Utf16 { path: PathBuf },
    #[error("{}: names a directory, not a file to write", path.display())]
    NotAFileName { path: PathBuf },
    // (It was "No such file or directory", naming neither.)
    #[error(
        "{}: there is no directory {} to write it in (make it first)",
        path.display(),
        dir.display()
    )]
    NoDirectory { path: PathBuf, dir: PathBuf },
    #[error("{}: too many levels of symbolic links", path.display())]
    LinkLoop { path: PathBuf },
    #[error(
        "{}: is a link to '{}', which names a directory, not a file to write",
        path.display(),
        target.display()
    )]
    LinkToDirectory { path: PathBuf, target: PathBuf },
    #[error(
        "{}: {} is a link in a sticky, world-writable directory owned by neither you nor the \
         directory's owner: refusing to write through it (as the kernel refuses `>` through \
         it where fs.protected_symlinks is set)",
        path.display(),
        link.display()
    )]
    ProtectedLink { path: PathBuf, link: PathBuf },
    #[error(
        "{}: is {}, which this run reads: refusing to overwrite an input",
        path.display(),
        input.display()
    )]
    IsInput { path: PathBuf, input: PathBuf },
}

/// A file's identity: the same file whatever path (link, `./`, hard link) names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct FileId(u64, u64);

impl FileId {
    #[cfg(unix)]
    fn of(meta: &std::fs::Metadata) -> Option<FileId> {
        use std::os::unix::fs::MetadataExt;
        Some(FileId(meta.dev(), meta.ino()))
    }

    #[cfg(not(unix))]
    fn of(_: &std::fs::Metadata) -> Option<FileId> {
        None
    }
}

/// Every regular file this process has read, with the path it was read by: an output never
/// replaces one of them.
static READ: Mutex<Vec<(FileId, PathBuf)>> = Mutex::new(Vec::new());

fn remember_read(path: &Path, meta: &std::fs::Metadata) {
    let Some(id) = FileId::of(meta) else { return };
    let mut read = READ.lock().unwrap_or_else(|e| e.into_inner());
    if !read.iter().any(|(known, _)| *known == id) {
        read.push((id, path.to_path_buf()));
    }
}

/// The input (as it was named when read) that `meta` is, if any. An input's path must still
/// name the same file: one deleted since may have left its identity to a new file.
fn read_as(meta: &std::fs::Metadata) -> Option<PathBuf> {
    let id = FileId::of(meta)?;
    let read = READ.lock().unwrap_or_else(|e| e.into_inner());
    let still = |p: &Path| std::fs::metadata(p).ok().and_then(|m| FileId::of(&m)) == Some(id);
    read.iter()
        .find(|(known, p)| *known == id && still(p))
        .map(|(_, p)| p.clone())
}

/// Whether the path is a character or block device (/dev/null, /dev/zero).
pub(crate) fn is_device(meta: &std::fs::Metadata) -> bool {
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

/// The most bytes read from a regular file whose metadata gives no size (0), as the files
/// under /proc and /sys do: /proc/self/pagemap was read to the 1 GiB cap before its error.
pub const MAX_SIZELESS_BYTES: u64 = 1 << 20;

/// The bytes of regular file `path`, at most `limit` of them ([`MAX_SIZELESS_BYTES`] where its
/// metadata gives no size).
pub fn read_bytes(path: &Path, limit: u64) -> Result<Vec<u8>, InputError> {
    let meta = regular(path)?;
    let sizeless = meta.len() == 0 && limit > MAX_SIZELESS_BYTES;
    let limit = match sizeless {
        true => MAX_SIZELESS_BYTES,
        false => limit,
    };
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
    if let Ok(opened) = file.metadata() {
        remember_read(path, &opened);
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // (8 past the limit, not 1: /proc/self/pagemap refuses reads of other than whole 8-byte
    // entries.)
    let past = if sizeless { 8 } else { 1 };
    file.take(limit.saturating_add(past))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    match bytes.len() as u64 > limit {
        true if sizeless => Err(InputError::Sizeless {
            path: path.to_path_buf(),
            limit,
        }),
        true => Err(too_large(bytes.len() as u64)),
        false => Ok(bytes),
    }
}

/// The UTF-8 text of regular file `path` (a leading byte-order mark dropped, comment lines
/// of any bytes kept: [`text_of`]), at most `limit` bytes.
pub fn read_text(path: &Path, limit: u64) -> Result<String, InputError> {
    let mut text = text_of(read_bytes(path, limit)?).map_err(|why| match why {
        NotText::Utf16 => InputError::Utf16 {
            path: path.to_path_buf(),
        },
        NotText::Line(line) => InputError::NotText {
            path: path.to_path_buf(),
            line,
        },
    })?;
    if text.starts_with('\u{feff}') {
        text.drain(..3);
    }
    Ok(lone_cr_as_lf(text))
}

/// `text` with each line break written as a CR alone (classic Mac OS, some exporters) as LF:
/// read as it was, a file of them was one long line, every statement run together. CRLF
/// stays as it is.
pub fn lone_cr_as_lf(text: String) -> String {
    let bytes = text.as_bytes();
    let lone = |i: usize| bytes[i] == b'\r' && bytes.get(i + 1) != Some(&b'\n');
    match (0..bytes.len()).any(lone) {
        true => text.replace("\r\n", "\n").replace('\r', "\n"),
        false => text,
    }
}

/// Why bytes are not the text of a scene, rays or answers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum NotText {
    /// UTF-16 (a byte-order mark, or a NUL beside a first character of text), as Windows
    /// PowerShell's `>` writes.
    #[error("UTF-16 text (as Windows PowerShell's pipes and `>` write it), not UTF-8")]
    Utf16,
    /// This line (1-based) is not UTF-8 and not a comment.
    #[error("something that is not UTF-8 text (on line {0})")]
    Line(usize),
}

/// `bytes` as text, where a comment line (its first word starts with `#`) may hold any bytes:
/// it is skipped unread, so a comment written in Latin-1 does not refuse the file; its bytes
/// that are not UTF-8 become U+FFFD.
pub fn text_of(bytes: Vec<u8>) -> Result<String, NotText> {
    // (Without a byte-order mark: a first character of text beside a NUL; binary data that
    // starts with NUL was called UTF-16.)
    let utf16 = bytes.starts_with(&[0xff, 0xfe])
        || bytes.starts_with(&[0xfe, 0xff])
        || matches!(bytes[..], [0, b, ..] | [b, 0, ..]
            if b.is_ascii_graphic() || b.is_ascii_whitespace());
    if utf16 {
        return Err(NotText::Utf16);
    }
    lossy_where(bytes, |line| line.starts_with(b"#")).map_err(NotText::Line)
}

/// `bytes` as UTF-8 text, where a line `lossy` accepts (its bytes after leading blanks) may
/// hold any bytes, those not UTF-8 becoming U+FFFD; else the first line (1-based) that is not
/// UTF-8.
pub fn lossy_where(bytes: Vec<u8>, lossy: impl Fn(&[u8]) -> bool) -> Result<String, usize> {
    let bytes = match String::from_utf8(bytes) {
        Ok(text) => return Ok(text),
        Err(e) => e.into_bytes(),
    };
    let mut text = String::with_capacity(bytes.len());
    for (i, line) in bytes.split_inclusive(|&b| b == b'\n').enumerate() {
        match std::str::from_utf8(line) {
            Ok(line) => text.push_str(line),
            Err(_) if lossy(line.trim_ascii_start()) => {
                text.push_str(&String::from_utf8_lossy(line))
            }
            Err(_) => return Err(i + 1),
        }
    }
    Ok(text)
}
