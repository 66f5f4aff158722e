//! Reading the files a user names, and writing the ones raylab makes.
//!
//! Reading: only regular files are read (a FIFO, a device, a socket or a directory is refused
//! from its metadata, before anything opens it, so nothing blocks), and at most a cap of bytes
//! (read through a limit, so a file that grows meanwhile cannot run past it either).
//!
//! Writing ([`OutputFile`]): an output never destroys a file. It is written to a temporary
//! file in the destination's directory and renamed over the destination only when complete, so
//! an interrupted, killed or failed run leaves the previous file as it was (a killed run's
//! temporary file, `.NAME.raylab-PID-N.tmp`, is removed by the next write into that directory
//! once its process is gone). A link is written through, dangling or not. An output that is
//! a file this process has read (the scene, its meshes and material libraries, a view, rays, a
//! script: compared by file identity, so links and `./` paths are caught) is refused before
//! anything is written, and so is an existing FIFO, socket or directory.

use std::io::{Read, Write};
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
    #[error("{}: names a directory, not a file to write", path.display())]
    NotAFileName { path: PathBuf },
    #[error("{}: too many levels of symbolic links", path.display())]
    LinkLoop { path: PathBuf },
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
/// would block until something reads it), or that is a file this process has read. A device
/// such as /dev/null is written as usual.
pub fn check_output(path: &Path) -> Result<(), InputError> {
    if names_a_directory(path) {
        return Err(InputError::NotAFileName {
            path: path.to_path_buf(),
        });
    }
    match std::fs::metadata(path) {
        Ok(meta) if !meta.is_file() && !is_device(&meta) => Err(InputError::NotRegular {
            path: path.to_path_buf(),
            kind: kind(&meta),
        }),
        Ok(meta) => match read_as(&meta) {
            Some(input) => Err(InputError::IsInput {
                path: path.to_path_buf(),
                input,
            }),
            None => Ok(()),
        },
        Err(_) => Ok(()),
    }
}

/// Whether `path` can only name a directory: it ends with `/`, `/.` or `..` (`-o a.png/` was
/// refused only when the finished file was renamed to it). (`Path::components` hides a
/// trailing `/` or `/.`, so the bytes are read.)
fn names_a_directory(path: &Path) -> bool {
    let text = path.as_os_str().as_encoded_bytes();
    let last = text.rsplit(|&b| b == b'/').next().unwrap_or_default();
    matches!(last, b"" | b"." | b"..")
}

/// The most links followed from an output to the file it names (as the kernel's ELOOP).
const MAX_LINKS: usize = 40;

/// The file `path` names once its links are followed, existing or not: a dangling link's
/// target is written, as `cp` into a link would, and the link kept.
fn link_target(path: &Path) -> Result<PathBuf, InputError> {
    let mut target = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        let is_link = target
            .symlink_metadata()
            .is_ok_and(|m| m.file_type().is_symlink());
        if !is_link {
            return Ok(target);
        }
        let next = std::fs::read_link(&target).map_err(|source| InputError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        target = match target.parent() {
            Some(dir) => dir.join(next),
            None => next,
        };
    }
    Err(InputError::LinkLoop {
        path: path.to_path_buf(),
    })
}

/// The longest part of the destination's name kept in a temporary file's name, so that a
/// name of up to 255 bytes (NAME_MAX) still has a temporary name within it.
const TEMP_NAME_BYTES: usize = 64;

/// The temporary name of output `name`, number `n` of process `pid`: `.NAME.raylab-PID-N.tmp`,
/// NAME cut to [`TEMP_NAME_BYTES`].
fn temp_name(name: &std::ffi::OsStr, pid: u32, n: u64) -> std::ffi::OsString {
    let bytes = name.as_encoded_bytes();
    let cut = bytes.len().min(TEMP_NAME_BYTES);
    // (At a character boundary where the name is UTF-8.)
    let cut = match std::str::from_utf8(&bytes[..cut]) {
        Err(e) if e.error_len().is_none() => e.valid_up_to(),
        _ => cut,
    };
    let mut temp = std::ffi::OsString::from(".");
    temp.push(String::from_utf8_lossy(&bytes[..cut]).as_ref());
    temp.push(format!(".raylab-{pid}-{n}.tmp"));
    temp
}

/// The process that made temporary file `name` ([`temp_name`]), if it is one.
pub fn temp_owner(name: &std::ffi::OsStr) -> Option<u32> {
    let name = name.to_str()?;
    let rest = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (_, tail) = rest.rsplit_once(".raylab-")?;
    let (pid, n) = tail.split_once('-')?;
    n.parse::<u64>().ok()?;
    pid.parse().ok()
}

/// Removes the temporary files in `dir` whose process is gone (killed while writing): each is
/// named by its pid ([`temp_name`]), and a pid with no /proc entry has ended. Nothing is
/// removed where /proc is not there to ask.
fn remove_stale_temps(dir: &Path) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let Some(pid) = temp_owner(&entry.file_name()) else {
            continue;
        };
        let alive = Path::new("/proc").join(pid.to_string()).exists();
        if !alive && entry.file_type().is_ok_and(|t| t.is_file()) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// An output being written: a temporary file beside the destination, renamed over it by
/// [`OutputFile::commit`] once complete; dropped before that, it is removed and the
/// destination is untouched. A device (/dev/null) is written in place.
#[derive(Debug)]
pub struct OutputFile {
    /// The path the user named (for messages).
    path: PathBuf,
    /// Where the rename goes: the file a link points to, so the link is kept.
    target: PathBuf,
    /// The temporary file, `None` when writing a device in place.
    temp: Option<PathBuf>,
    file: std::io::BufWriter<std::fs::File>,
}

impl OutputFile {
    /// Checks `path` ([`check_output`]) and opens a temporary file in its directory, so an
    /// unwritable directory fails now, before any work, and nothing at `path` changes yet.
    pub fn create(path: &Path) -> Result<OutputFile, InputError> {
        check_output(path)?;
        let io = |source| InputError::Io {
            path: path.to_path_buf(),
            source,
        };
        if std::fs::metadata(path).is_ok_and(|m| is_device(&m)) {
            let file = std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(io)?;
            return Ok(OutputFile {
                path: path.to_path_buf(),
                target: path.to_path_buf(),
                temp: None,
                file: std::io::BufWriter::new(file),
            });
        }
        // Through a link (dangling or not): replace the file it names, keep the link.
        let target = link_target(path)?;
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let name = (target.file_name())
            .unwrap_or(std::ffi::OsStr::new("output"))
            .to_owned();
        let (temp, file) = Self::open_temp(&dir, &name).map_err(io)?;
        Ok(OutputFile {
            path: path.to_path_buf(),
            target,
            temp: Some(temp),
            file: std::io::BufWriter::new(file),
        })
    }

    /// A new file `.NAME.raylab-PID-N.tmp` in `dir` ([`temp_name`]), created exclusively (mode
    /// 0666 less the umask), once the stale ones of killed runs are removed.
    fn open_temp(dir: &Path, name: &std::ffi::OsStr) -> std::io::Result<(PathBuf, std::fs::File)> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static NEXT: AtomicU64 = AtomicU64::new(0);
        remove_stale_temps(dir);
        loop {
            let n = NEXT.fetch_add(1, Ordering::Relaxed);
            let temp = dir.join(temp_name(name, std::process::id(), n));
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&temp)
            {
                Ok(file) => return Ok((temp, file)),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
    }

    /// The path the user named.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes the file and renames it over the destination (keeping an existing file's
    /// permissions). The destination is checked again first: an input is never replaced.
    pub fn commit(mut self) -> Result<(), InputError> {
        let path = self.path.clone();
        let io = |source| InputError::Io {
            path: path.clone(),
            source,
        };
        self.file.flush().map_err(io)?;
        let Some(temp) = self.temp.take() else {
            return Ok(());
        };
        let result = check_output(&self.path).and_then(|()| {
            if let Ok(old) = std::fs::metadata(&self.target) {
                std::fs::set_permissions(&temp, old.permissions()).map_err(io)?;
            }
            std::fs::rename(&temp, &self.target).map_err(io)
        });
        if result.is_err() {
            let _ = std::fs::remove_file(&temp);
        }
        result
    }
}

impl Write for OutputFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file.write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if let Some(temp) = self.temp.take() {
            let _ = std::fs::remove_file(temp);
        }
    }
}

/// Writes `bytes` to `path` through an [`OutputFile`]: all of them, or nothing changes.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), InputError> {
    let mut out = OutputFile::create(path)?;
    out.write_all(bytes).map_err(|source| InputError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    out.commit()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    fn names(dir: &Path) -> Vec<String> {
        let mut n: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        n.sort();
        n
    }

    #[test]
    fn an_output_changes_nothing_until_committed_and_keeps_the_permissions() {
        let dir = tempfile::tempdir().unwrap();
        let dest = dir.path().join("a.png");
        std::fs::write(&dest, b"old").unwrap();
        std::fs::set_permissions(&dest, std::fs::Permissions::from_mode(0o640)).unwrap();
        let mut out = OutputFile::create(&dest).unwrap();
        out.write_all(b"new, longer").unwrap();
        out.flush().unwrap();
        assert_eq!(std::fs::read(&dest).unwrap(), b"old");
        assert_eq!(names(dir.path()).len(), 2, "the temporary file beside it");
        drop(out);
        assert_eq!(std::fs::read(&dest).unwrap(), b"old");
        assert_eq!(names(dir.path()), ["a.png"]);
        let mut out = OutputFile::create(&dest).unwrap();
        out.write_all(b"new, longer").unwrap();
        out.commit().unwrap();
        assert_eq!(std::fs::read(&dest).unwrap(), b"new, longer");
        let mode = std::fs::metadata(&dest).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o640);
        assert_eq!(names(dir.path()), ["a.png"]);
    }

    #[test]
    fn a_file_read_is_never_an_output_and_a_device_is_written_in_place() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in.scene");
        std::fs::write(&input, b"tri 0 0 0 1 0 0 0 1 0\n").unwrap();
        let other = dir.path().join("other.png");
        assert!(check_output(&input).is_ok(), "not read yet");
        read_text(&input, 1 << 20).unwrap();
        let e = OutputFile::create(&input).unwrap_err();
        assert!(matches!(e, InputError::IsInput { .. }), "{e}");
        assert!(write_file(&other, b"x").is_ok());
        let mut null = OutputFile::create(Path::new("/dev/null")).unwrap();
        null.write_all(b"nothing").unwrap();
        null.commit().unwrap();
        assert!(Path::new("/dev/null").exists());
    }

    #[test]
    fn a_dangling_link_is_written_through_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("link.png");
        std::os::unix::fs::symlink("target.png", &link).unwrap();
        write_file(&link, b"png").unwrap();
        assert!(link.symlink_metadata().unwrap().file_type().is_symlink());
        assert_eq!(
            std::fs::read(dir.path().join("target.png")).unwrap(),
            b"png"
        );
        let looped = dir.path().join("loop.png");
        std::os::unix::fs::symlink("loop.png", &looped).unwrap();
        let e = write_file(&looped, b"x").unwrap_err();
        assert!(matches!(e, InputError::LinkLoop { .. }), "{e}");
    }

    #[test]
    fn a_name_of_255_bytes_has_a_temporary_name_and_a_directory_name_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let long = dir.path().join(format!("a{}.png", "é".repeat(125)));
        assert_eq!(long.file_name().unwrap().len(), 255);
        write_file(&long, b"x").unwrap();
        assert_eq!(std::fs::read(&long).unwrap(), b"x");
        for bad in ["a.png/", "a.png/.", ".."] {
            let e = OutputFile::create(&dir.path().join(bad)).unwrap_err();
            assert!(matches!(e, InputError::NotAFileName { .. }), "{bad}: {e}");
        }
        assert_eq!(names(dir.path()).len(), 1);
    }

    #[test]
    fn a_killed_runs_temporary_file_is_removed_by_the_next_write() {
        let dir = tempfile::tempdir().unwrap();
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        let name = |pid| temp_name("out.t.npy".as_ref(), pid, 3);
        assert_eq!(temp_owner(&name(dead)), Some(dead));
        std::fs::write(dir.path().join(name(dead)), b"half").unwrap();
        std::fs::write(dir.path().join(name(std::process::id())), b"live").unwrap();
        std::fs::write(dir.path().join(".other.tmp"), b"not ours").unwrap();
        write_file(&dir.path().join("out.png"), b"x").unwrap();
        let live = name(std::process::id()).into_string().unwrap();
        assert_eq!(names(dir.path()), [".other.tmp", live.as_str(), "out.png"]);
    }
}
