//! Writing the files raylab makes ([`OutputFile`]): an output never destroys a file. It is written
//! to a temporary file in the destination's directory and renamed over the destination only when
//! complete, so an interrupted, killed or failed run leaves the previous file as it was. A killed
//! run's temporary file, `.NAME.raylab-PID-N.tmp`, is removed by a later write into that directory
//! once it is stale (not locked, this user's, unmodified for [`STALE_TEMP_AGE`]). A link is written
//! through, dangling or not (as the shell's `>` writes), except one that the kernel's
//! protected_symlinks rule would not follow. An output that is a file this process has read (the
//! scene, its meshes and material libraries, a view, rays, a script: compared by file identity, so
//! links and `./` paths are caught) is refused before anything is written, and so is an existing
//! FIFO, socket or directory.

use super::{is_device, kind, read_as, FileId, InputError};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

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
/// target is written (as the shell's `>` writes through one; `cp` would refuse it) and the
/// link kept. Refused: a link whose text names a directory (`newdir/`: the rename would fail
/// only after the work), and a link the kernel would not follow for `>` under
/// fs.protected_symlinks ([`protected_link`]): raylab follows links itself, so the kernel
/// never asks.
fn link_target(path: &Path) -> Result<PathBuf, InputError> {
    let mut target = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        let link = match target.symlink_metadata() {
            Ok(m) if m.file_type().is_symlink() => m,
            _ => return Ok(target),
        };
        if protected_link(&target, &link) {
            return Err(InputError::ProtectedLink {
                path: path.to_path_buf(),
                link: target,
            });
        }
        let next = std::fs::read_link(&target).map_err(|source| InputError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        if names_a_directory(&next) {
            return Err(InputError::LinkToDirectory {
                path: path.to_path_buf(),
                target: next,
            });
        }
        target = match target.parent() {
            Some(dir) => dir.join(next),
            None => next,
        };
    }
    Err(InputError::LinkLoop {
        path: path.to_path_buf(),
    })
}

/// The directory a path's last component is in (`.` for a bare name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// The effective user id of this process.
#[cfg(unix)]
fn effective_uid() -> u32 {
    rustix::process::geteuid().as_raw()
}

/// Whether the kernel's protected_symlinks rule forbids following `link` (with metadata
/// `meta`): it sits in a sticky, world-writable directory (/tmp) and is owned by neither
/// this user nor the directory's owner.
#[cfg(unix)]
fn protected_link(link: &Path, meta: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    let Ok(dir) = std::fs::metadata(parent_dir(link)) else {
        return false;
    };
    let sticky_and_shared = dir.mode() & 0o1002 == 0o1002;
    sticky_and_shared && meta.uid() != effective_uid() && meta.uid() != dir.uid()
}

#[cfg(not(unix))]
fn protected_link(_: &Path, _: &std::fs::Metadata) -> bool {
    false
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

/// How long a temporary file must have been left unmodified before a later write into its
/// directory may remove it (and only if it is this user's and unlocked: see the module's doc).
pub const STALE_TEMP_AGE: Duration = Duration::from_secs(60 * 60);

/// Removes the temporary files that runs killed while writing left in `dir`. A file is
/// removed only when all of these hold: its name is exactly a temporary file's
/// (`.NAME.raylab-PID-N.tmp`, [`temp_owner`]); it is a regular file, not a link; it belongs to
/// this user; it was last modified [`STALE_TEMP_AGE`] or more ago; and no process holds its
/// lock (each run holds an exclusive `flock` on every temporary file it writes until it is
/// renamed or removed, [`OutputFile::create`]). The pid in the name is not consulted: a
/// process in another pid namespace or on another host sharing the directory is not
/// visible in /proc.
fn remove_stale_temps(dir: &Path) {
    remove_temps_older_than(dir, STALE_TEMP_AGE);
}

#[cfg(unix)]
fn remove_temps_older_than(dir: &Path, age: Duration) {
    use std::os::unix::fs::{MetadataExt, OpenOptionsExt};
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let (me, now) = (effective_uid(), std::time::SystemTime::now());
    let stale = |m: &std::fs::Metadata| {
        let old = (m.modified().ok()).and_then(|t| now.duration_since(t).ok());
        m.file_type().is_file() && m.uid() == me && old.is_some_and(|old| old >= age)
    };
    for entry in entries.flatten() {
        if temp_owner(&entry.file_name()).is_none() {
            continue;
        }
        let path = entry.path();
        let Ok(meta) = path.symlink_metadata() else {
            continue;
        };
        if !stale(&meta) {
            continue;
        }
        // Opened without following a link or blocking (on a FIFO put there since), and
        // still the file looked at.
        let Ok(file) = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
            .open(&path)
        else {
            continue;
        };
        let same = file
            .metadata()
            .is_ok_and(|m| FileId::of(&m) == FileId::of(&meta) && stale(&m));
        if same && file.try_lock().is_ok() {
            let _ = std::fs::remove_file(&path);
        }
    }
}

#[cfg(not(unix))]
fn remove_temps_older_than(_: &Path, _: Duration) {}

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
        let dir = parent_dir(&target).to_path_buf();
        let name = (target.file_name())
            .unwrap_or(std::ffi::OsStr::new("output"))
            .to_owned();
        // (Only where the directory is surely missing: one that cannot be searched is not.)
        let missing = |e: &std::io::Error| {
            e.kind() == std::io::ErrorKind::NotFound && matches!(dir.try_exists(), Ok(false))
        };
        let (temp, file) = Self::open_temp(&dir, &name).map_err(|e| match missing(&e) {
            true => InputError::NoDirectory {
                path: path.to_path_buf(),
                dir: dir.clone(),
            },
            false => io(e),
        })?;
        Ok(OutputFile {
            path: path.to_path_buf(),
            target,
            temp: Some(temp),
            file: std::io::BufWriter::new(file),
        })
    }

    /// A new file `.NAME.raylab-PID-N.tmp` in `dir` ([`temp_name`]), created exclusively (mode
    /// 0666 less the umask) and locked (an exclusive `flock`, held while the file is open:
    /// until it is renamed or removed), once the stale ones of killed runs are removed. (Where
    /// the file system has no locks it is written unlocked: then no cleanup can lock it either,
    /// and none removes it.)
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
                Ok(file) => {
                    let _ = file.lock();
                    return Ok((temp, file));
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
    }

    /// The path the user named.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The temporary file being written (`None` for a device written in place).
    pub fn temp_path(&self) -> Option<&Path> {
        self.temp.as_deref()
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

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;
    use crate::input::read_text;
    use std::os::unix::fs::PermissionsExt;

    fn names(dir: &Path) -> Vec<String> {
        let mut n: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        n.sort();
        n
    }

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

    /// Sets a file's last modification `ago` back from now.
    fn age(path: &Path, ago: Duration) {
        let file = std::fs::File::options().write(true).open(path).unwrap();
        file.set_modified(std::time::SystemTime::now() - ago)
            .unwrap();
    }

    fn only_an_old_unlocked_temporary_file_of_this_user_is_removed() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let old = STALE_TEMP_AGE + Duration::from_secs(60);
        let temp = |what: &str, pid| temp_name(what.as_ref(), pid, 3).into_string().unwrap();
        // A live one: old, but its writer (here a handle of this test) holds its lock, as a
        // raylab in another pid namespace or on another host would.
        let live = temp("live.npy", 4_000_000);
        std::fs::write(d.join(&live), b"still writing").unwrap();
        age(&d.join(&live), old);
        let held = std::fs::File::open(d.join(&live)).unwrap();
        held.lock().unwrap();
        // A killed run's: old, unlocked.
        let stale = temp("stale.npy", std::process::id());
        std::fs::write(d.join(&stale), b"half").unwrap();
        age(&d.join(&stale), old);
        // Just made: unlocked yet (or on a file system without locks).
        let young = temp("young.npy", 4_000_001);
        std::fs::write(d.join(&young), b"new").unwrap();
        // Not a temporary file's name, or a link with one: never.
        for other in [
            ".notes.tmp",
            ".a.raylab-1.tmp",
            ".a.raylab-x-1.tmp",
            "b.raylab-1-1.tmp",
        ] {
            std::fs::write(d.join(other), b"the user's").unwrap();
            age(&d.join(other), old);
        }
        let link = temp("link.npy", 4_000_002);
        std::os::unix::fs::symlink(&stale, d.join(&link)).unwrap();
        assert_eq!(temp_owner(stale.as_ref()), Some(std::process::id()));
        write_file(&d.join("out.png"), b"x").unwrap();
        let mut kept = vec![
            ".a.raylab-1.tmp",
            ".a.raylab-x-1.tmp",
            ".notes.tmp",
            link.as_str(),
            live.as_str(),
            young.as_str(),
            "b.raylab-1-1.tmp",
            "out.png",
        ];
        kept.sort();
        assert_eq!(names(d), kept);
        // Its lock released (its writer killed), the live one is stale.
        drop(held);
        write_file(&d.join("out.png"), b"y").unwrap();
        assert!(!d.join(&live).exists());
        assert!(d.join(&young).exists());
    }

    fn a_temporary_file_is_locked_while_written() {
        let dir = tempfile::tempdir().unwrap();
        let mut out = OutputFile::create(&dir.path().join("a.png")).unwrap();
        out.write_all(b"png").unwrap();
        let temp = out.temp.clone().unwrap();
        age(&temp, STALE_TEMP_AGE * 2);
        let other = std::fs::File::open(&temp).unwrap();
        assert!(other.try_lock().is_err(), "locked by its writer");
        remove_stale_temps(dir.path());
        assert!(temp.exists());
        out.commit().unwrap();
        assert!(other.try_lock().is_ok(), "released once renamed");
        assert_eq!(names(dir.path()), ["a.png"]);
    }

    fn a_link_to_a_directorys_name_is_refused_before_any_work() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for (name, text) in [
            ("slash", "newdir/"),
            ("dot", "newdir/."),
            ("up", "newdir/.."),
        ] {
            std::os::unix::fs::symlink(text, d.join(name)).unwrap();
            let e = OutputFile::create(&d.join(name)).unwrap_err();
            assert!(
                matches!(e, InputError::LinkToDirectory { .. }),
                "{name}: {e}"
            );
            assert!(e.to_string().contains(text), "{e}");
        }
        // Through a second link too.
        std::os::unix::fs::symlink("slash", d.join("second")).unwrap();
        let e = OutputFile::create(&d.join("second")).unwrap_err();
        assert!(matches!(e, InputError::LinkToDirectory { .. }), "{e}");
        assert_eq!(names(d), ["dot", "second", "slash", "up"]);
    }

    fn a_link_in_a_sticky_shared_directory_is_followed_as_the_kernel_would() {
        let dir = tempfile::tempdir().unwrap();
        let sticky = dir.path().join("sticky");
        std::fs::create_dir(&sticky).unwrap();
        std::fs::set_permissions(&sticky, std::fs::Permissions::from_mode(0o1777)).unwrap();
        // This user's own link: followed.
        let mine = sticky.join("mine.png");
        std::os::unix::fs::symlink("mine-target.png", &mine).unwrap();
        write_file(&mine, b"png").unwrap();
        assert_eq!(
            std::fs::read(sticky.join("mine-target.png")).unwrap(),
            b"png"
        );
        if effective_uid() != 0 {
            println!("skipped: a link owned by another user needs root to make");
            return;
        }
        // Another user's (neither this user nor the directory's owner): refused.
        let theirs = sticky.join("theirs.png");
        std::os::unix::fs::symlink("/tmp/victim-of-a-link.png", &theirs).unwrap();
        std::os::unix::fs::lchown(&theirs, Some(54_321), Some(54_321)).unwrap();
        let e = write_file(&theirs, b"png").unwrap_err();
        assert!(matches!(e, InputError::ProtectedLink { .. }), "{e}");
        assert!(e.to_string().contains("sticky"), "{e}");
        assert!(!Path::new("/tmp/victim-of-a-link.png").exists());
        // The same link where the directory is not sticky: followed.
        std::fs::set_permissions(&sticky, std::fs::Permissions::from_mode(0o777)).unwrap();
        let inside = sticky.join("inside.png");
        std::os::unix::fs::symlink("inside-target.png", &inside).unwrap();
        std::os::unix::fs::lchown(&inside, Some(54_321), Some(54_321)).unwrap();
        write_file(&inside, b"png").unwrap();
        assert!(sticky.join("inside-target.png").exists());
        // Owned by the directory's owner: followed.
        std::fs::set_permissions(&sticky, std::fs::Permissions::from_mode(0o1777)).unwrap();
        std::os::unix::fs::chown(&sticky, Some(54_321), Some(54_321)).unwrap();
        std::fs::remove_file(sticky.join("inside-target.png")).unwrap();
        write_file(&inside, b"png").unwrap();
        assert!(sticky.join("inside-target.png").exists());
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[
        (
            "an_output_changes_nothing_until_committed_and_keeps_the_permissions",
            an_output_changes_nothing_until_committed_and_keeps_the_permissions,
        ),
        (
            "a_file_read_is_never_an_output_and_a_device_is_written_in_place",
            a_file_read_is_never_an_output_and_a_device_is_written_in_place,
        ),
        (
            "a_dangling_link_is_written_through_and_kept",
            a_dangling_link_is_written_through_and_kept,
        ),
        (
            "a_name_of_255_bytes_has_a_temporary_name_and_a_directory_name_is_refused",
            a_name_of_255_bytes_has_a_temporary_name_and_a_directory_name_is_refused,
        ),
        (
            "only_an_old_unlocked_temporary_file_of_this_user_is_removed",
            only_an_old_unlocked_temporary_file_of_this_user_is_removed,
        ),
        (
            "a_temporary_file_is_locked_while_written",
            a_temporary_file_is_locked_while_written,
        ),
        (
            "a_link_to_a_directorys_name_is_refused_before_any_work",
            a_link_to_a_directorys_name_is_refused_before_any_work,
        ),
        (
            "a_link_in_a_sticky_shared_directory_is_followed_as_the_kernel_would",
            a_link_in_a_sticky_shared_directory_is_followed_as_the_kernel_would,
        ),
    ];
}
