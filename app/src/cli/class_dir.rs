//! The class folder `raylab grade` reads: its submissions (and what is not one, named), what
//! a submission holds, and its copy, the one each of its runs works in.

use super::rubric::name_of;
use anyhow::{anyhow, bail, Result};
use raylab_app::one_line;
use std::path::{Path, PathBuf};

/// The submission directories of the class, in a class list's order ([`list_order`]). Every
/// other entry (a file, a broken link, a hidden directory such as `.git`, macOS's `__MACOSX`,
/// a suite `raylab suite export` wrote there) is named on stderr, so a submission handed in
/// as a file is not left out unseen.
pub(super) fn submissions(class: &Path) -> Result<Vec<PathBuf>> {
    let entries =
        std::fs::read_dir(class).map_err(|e| anyhow!("CLASS_DIR {}: {e}", class.display()))?;
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    // (As a class list reads: by bytes, "Zoë" came before "chloé", and "Élodie" after both.)
    paths.sort_by_cached_key(|p| (list_order(&name_of(p)), p.clone()));
    let mut dirs = Vec::new();
    for path in paths {
        let why = match () {
            _ if name_of(&path).starts_with('.') => "hidden",
            // (A class of zips: said how to grade them.)
            _ if !path.is_dir() && is_archive(&name_of(&path)) => {
                "an archive, not a directory (unpack each into a folder of its own)"
            }
            _ if !path.is_dir() => "not a directory",
            // (A class unzipped on a Mac holds one, graded as a student who crashed.)
            _ if name_of(&path) == "__MACOSX" => "macOS's zip metadata",
            // (A suite exported into the class's directory was graded as a student who
            // crashed.)
            _ if is_a_suite(&path) => "a suite (raylab suite export's files only)",
            _ => {
                dirs.push(path);
                continue;
            }
        };
        let shown = one_line(&path.display().to_string());
        eprintln!("warning: {shown}: {why}, so not a submission (not graded)");
    }
    if dirs.is_empty() {
        bail!(
            "{}: no submissions (a directory per submission)",
            class.display()
        );
    }
    Ok(dirs)
}

/// Whether `dir` holds an exported suite and nothing else: its families.txt, its README.md
/// and family directories each with its rays.txt. (A suite exported into the class's
/// directory was graded as a student who crashed; a student's directory that holds a copy of
/// families.txt beside its code is a submission.)
pub(super) fn is_a_suite(dir: &Path) -> bool {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return false;
    };
    let suite_file = |p: &Path| match name_of(p).as_str() {
        "families.txt" | "README.md" => p.is_file(),
        _ => p.join("rays.txt").is_file(),
    };
    dir.join("families.txt").is_file()
        && entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .all(|p| suite_file(&p))
}

/// Whether `dir` or a directory in it holds anything but directories (a file, a link, a
/// socket); one it cannot read counts as holding something, so the copy says why it failed.
pub(super) fn holds_a_file(dir: &Path) -> bool {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return true;
    };
    entries.into_iter().any(|entry| match entry {
        Ok(entry) if is_system_junk(&entry.file_name()) => false,
        Ok(entry) => match entry.file_type() {
            Ok(kind) if kind.is_dir() => holds_a_file(&entry.path()),
            _ => true,
        },
        Err(_) => true,
    })
}

/// What an operating system leaves in a folder it zips or shows, not a student: macOS's
/// `.DS_Store`, `__MACOSX/`, `Icon\r` and `._` files, Windows's `Thumbs.db` and `desktop.ini`.
/// (A folder of them alone was graded as 38 crashes, not as nothing handed in.)
fn is_system_junk(name: &std::ffi::OsStr) -> bool {
    // (Any case: Windows writes `thumbs.db` and `Desktop.ini` too; macOS a folder's `Icon\r`.)
    let name = name.to_string_lossy().to_lowercase();
    [
        "__macosx",
        ".ds_store",
        "thumbs.db",
        "desktop.ini",
        "icon\r",
    ]
    .contains(&&*name)
        || name.starts_with("._")
}

/// The most a submission's files may hold in all, by their sizes (a sparse file's whole
/// size: its copy writes it all): raylab copies each submission to grade it, and a 20 GiB
/// sparse file, no disk at all in the class, took 83 s and 20 GiB of the temporary
/// directory's disk to copy.
const MAX_SUBMISSION_BYTES: u64 = 1 << 30;

/// Copies a submission: directories, files (with their permissions and modification times,
/// so `make` sees what it built as built) and links as links (never followed: a link to a
/// file the program's user cannot read stays unreadable); anything else is left out. Fails
/// before a file that would take the bytes `copied` so far past [`MAX_SUBMISSION_BYTES`].
pub(super) fn copy_tree(from: &Path, to: &Path, copied: &mut u64) -> std::io::Result<()> {
    std::fs::create_dir(to)?;
    for entry in std::fs::read_dir(from)? {
        let entry = entry?;
        let (source, target) = (entry.path(), to.join(entry.file_name()));
        let kind = entry.file_type()?;
        if kind.is_dir() {
            copy_tree(&source, &target, copied)?;
        } else if kind.is_file() {
            *copied = copied.saturating_add(entry.metadata()?.len());
            if *copied > MAX_SUBMISSION_BYTES {
                return Err(std::io::Error::other(format!(
                    "its files hold over {} GiB (at {}), more than a submission may: not \
                     copied to be graded",
                    MAX_SUBMISSION_BYTES >> 30,
                    source.display()
                )));
            }
            std::fs::copy(&source, &target)?;
            let modified = entry.metadata()?.modified()?;
            // (Opened to read: a read-only file, as git leaves its objects, keeps its time too.)
            std::fs::File::open(&target)?.set_modified(modified)?;
        } else if kind.is_symlink() {
            std::os::unix::fs::symlink(std::fs::read_link(&source)?, &target)?;
        }
    }
    Ok(())
}

/// How a class list orders a name: its letters without their accents and case (`Élodie`
/// among the e's, `chloé` before `Zoë`).
pub(super) fn list_order(name: &str) -> String {
    use unicode_normalization::{char::is_combining_mark, UnicodeNormalization};
    // (Letters that do not decompose, folded as a class list reads them: Ørjan among the o's.)
    let fold = |c: char| match c {
        'ø' | 'Ø' => "o",
        'æ' | 'Æ' => "ae",
        'œ' | 'Œ' => "oe",
        'ß' => "ss",
        'ł' | 'Ł' => "l",
        'đ' | 'Đ' => "d",
        'ı' => "i",
        _ => "",
    };
    let letters = name.nfd().filter(|c| !is_combining_mark(*c));
    let folded: String = letters
        .map(|c| match fold(c) {
            "" => c.to_string(),
            f => f.to_string(),
        })
        .collect();
    folded.to_lowercase()
}

/// The archives a submission holds where it holds nothing else (its system files aside): a
/// student who handed in `lab3.zip` crashed in every family, "can't open intersect.py".
pub(super) fn only_archives(dir: &Path) -> Option<Vec<String>> {
    let mut files = Vec::new();
    let mut dirs = vec![dir.to_path_buf()];
    while let Some(d) = dirs.pop() {
        for entry in std::fs::read_dir(&d).ok()?.flatten() {
            let name = entry.file_name();
            match entry.file_type() {
                _ if is_system_junk(&name) => {}
                Ok(kind) if kind.is_dir() => dirs.push(entry.path()),
                _ => files.push(name.to_string_lossy().into_owned()),
            }
        }
    }
    (!files.is_empty() && files.iter().all(|f| is_archive(f))).then_some(files)
}

/// Whether a file's name is an archive's (`lab3.zip`, `lab3.tar.gz`, …).
fn is_archive(name: &str) -> bool {
    const ARCHIVES: [&str; 7] = [".zip", ".tar", ".gz", ".tgz", ".xz", ".7z", ".rar"];
    ARCHIVES.iter().any(|a| name.to_lowercase().ends_with(a))
}
