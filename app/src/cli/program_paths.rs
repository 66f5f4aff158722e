//! The files a `grade --program` command names outside the submissions: a teacher's wrapper
//! named by a path relative to where raylab runs (the command runs in each submission's copy,
//! where it is not), by its bare name (looked up on the PATH alone), or under `~` (each
//! program's HOME is its own directory), or one the programs cannot read (they run as other
//! users). Each made every submission crash with a shell's "not found" or "Permission
//! denied", the grading run through, so each is refused before any program runs. Only a
//! simple command is read so (words, no `cd`, `;`, `&&`, `|`, `#`, `$`, quotes within words):
//! in any other a word may never be run where it reads (`cd lab3 && ./x.py`, a comment), and
//! a refusal there was false.

use anyhow::{bail, Result};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

/// Refuses a simple `--program` that names a file the submissions' runs cannot reach: a
/// relative path to a file here that no submission holds, a path under `~` that is the
/// teacher's, or (`as_others`: the programs run as other users, `who` says which) an absolute
/// one those users cannot run (the command: [`command_word`]) or read (an argument).
pub(super) fn check_program_paths(
    template: &str,
    submissions: &[PathBuf],
    as_others: Option<&str>,
) -> Result<()> {
    let Some(words) = simple_words(template) else {
        return Ok(());
    };
    let home = std::env::var_os("HOME").map(PathBuf::from);
    let command = command_word(&words);
    // (Not where the command sets its own PATH: `env PATH=/opt/grader run.sh` finds it there.)
    let own_path = words[..command].iter().any(|w| w.starts_with("PATH="));
    if let (Some(&word), false) = (words.get(command), own_path) {
        refuse_bare_name_here(word, as_others.is_some())?;
        if let Some(who) = as_others {
            warn_of_another_command(word, who)?;
        }
    }
    for (k, word) in words.iter().enumerate() {
        if let (Some(rest), Some(home)) = (word.strip_prefix("~/"), &home) {
            let yours = home.join(rest);
            if yours.is_file() {
                bail!(
                    "--program: {word}: ~ is each program's own directory (its HOME), not \
                     yours: name it by its absolute path, {}",
                    yours.display()
                );
            }
            continue;
        }
        // (A bare name is a path only as an interpreter's script: `make -s run` names a
        // target, which a file here may share.)
        let script =
            k == command + 1 && INTERPRETERS.contains(&words[command]) && !word.starts_with('-');
        if !word.contains('/') && !script {
            continue;
        }
        let path = Path::new(word);
        let here = path.is_file();
        // (A `..` leaves the copy, which no submission's own file is then.)
        let outside = path
            .components()
            .any(|c| c == std::path::Component::ParentDir);
        let held = !outside && submissions.iter().any(|s| s.join(path).exists());
        if path.is_relative() && here && !held {
            let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
            bail!(
                "--program: {word} is a file here, but the command runs in each submission's \
                 copy, and no submission holds it: a wrapper of yours is named by its absolute \
                 path, {} (a program of the students' is elsewhere in their folders: look \
                 where)",
                absolute.display()
            );
        }
        let Some(who) = as_others else { continue };
        if path.is_absolute() && here {
            // (Through links, the file itself: a link in /usr/local/bin to a file in /root
            // passed.)
            let real = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
            let (needs, what, letters) = needs(&real, k == command);
            let mode = std::fs::metadata(&real).map_or(0, |m| m.permissions().mode());
            let dirs = [path, &real].map(|p| p.parent().unwrap_or(Path::new("/")));
            let closed = !dirs.iter().all(|d| super::access::open_to_others(d));
            if closed || mode & needs != needs {
                bail!(
                    "--program: {word}: the programs run as {who}, other users to it, who \
                     cannot {what} it: `chmod o+{letters}` it and `o+x` the directories above \
                     it"
                );
            }
        }
    }
    Ok(())
}

/// Refuses a command named without a `/` that is a file here and not on the programs' PATH
/// (`run.sh {scene} {rays}` for ./run.sh): the shell looks such a name up on the PATH alone,
/// so every submission crashed "not found". (`others`: the programs run as other users,
/// whose PATH keeps only the directories every user may search.)
fn refuse_bare_name_here(word: &str, others: bool) -> Result<()> {
    if word.contains('/') || SHELL_WORDS.contains(&word) || !Path::new(word).is_file() {
        return Ok(());
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    let path = match others {
        true => super::access::searchable_path(&path),
        false => path,
    };
    if on_path(word, &path, 0).is_some() {
        return Ok(());
    }
    let absolute = std::path::absolute(word).unwrap_or_else(|_| PathBuf::from(word));
    bail!(
        "--program: {word} is a file here, but a command named without a `/` is looked up on \
         the programs' PATH, where it is not (every submission would crash \"not found\"): \
         name it by its absolute path, {}",
        absolute.display()
    );
}

/// Warns where a command named without a `/` is another file on the programs' PATH (which
/// keeps only the directories every user may search) than on raylab's, and refuses one on
/// raylab's PATH but not on theirs: `python3`, a pyenv shim under /root with numpy for
/// `check`, was /usr/bin/python3 without it for every submission, each crashing "No module
/// named 'numpy'".
fn warn_of_another_command(word: &str, who: &str) -> Result<()> {
    if word.contains('/') || SHELL_WORDS.contains(&word) {
        return Ok(());
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    // (Theirs, a file others may run: a shim of mode 700 in an open directory is not.)
    let theirs = on_path(word, &super::access::searchable_path(&path), 0o001);
    let (yours, theirs) = (on_path(word, &path, 0o111), theirs);
    match (yours, theirs) {
        (Some(yours), None) => bail!(
            "--program: {word} is {} on your PATH, which the programs, run as {who}, cannot \
             run (its directory or it closed to them): on theirs it is not found (every \
             submission would crash): name one every user may run by its absolute path",
            yours.display()
        ),
        (Some(yours), Some(theirs)) if yours != theirs => eprintln!(
            "warning: --program: {word} is {} on your PATH, but the programs run as {who}, who \
             cannot run it (its directory or it closed to them): they run {} (its modules or \
             version may differ from the one `raylab check` runs: name one every user may run \
             by its absolute path)",
            yours.display(),
            theirs.display()
        ),
        _ => {}
    }
    Ok(())
}

/// Where the shell finds command `word` on `path` (a PATH): the first file of that name whose
/// mode has one of `bits` (0: any file).
fn on_path(word: &str, path: &std::ffi::OsStr, bits: u32) -> Option<PathBuf> {
    std::env::split_paths(path)
        .map(|dir| dir.join(word))
        .find(|file| {
            file.metadata()
                .is_ok_and(|m| m.is_file() && (bits == 0 || m.permissions().mode() & bits != 0))
        })
}

/// The shell's own commands and words, which run whatever files share their names.
const SHELL_WORDS: &[&str] = &[
    "!", ".", ":", "[", "alias", "bg", "break", "case", "cd", "command", "continue", "do", "done",
    "echo", "elif", "else", "esac", "eval", "exec", "exit", "export", "false", "fg", "fi", "for",
    "getopts", "hash", "if", "jobs", "kill", "local", "printf", "pwd", "read", "readonly",
    "return", "set", "shift", "test", "then", "times", "trap", "true", "type", "ulimit", "umask",
    "unalias", "unset", "until", "wait", "while",
];

/// Which of `words` the shell runs: the first after variable assignments (`X=1`), `exec`
/// and `env` with its assignments (`env X=1 /opt/w.sh` runs /opt/w.sh). After an `env`
/// option (`env -i /opt/w.sh`) the option is taken for the command, the file for an argument:
/// a refusal missed, never a false one.
fn command_word(words: &[&str]) -> usize {
    let assignment = |w: &str| {
        w.split_once('=').is_some_and(|(name, _)| {
            name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        })
    };
    (words.iter())
        .position(|w| !assignment(w) && *w != "exec" && *w != "env")
        .unwrap_or(0)
}

/// Commands whose first argument is a script they read: `python3 mine.py` with mine.py here
/// and in no submission is the teacher's file.
const INTERPRETERS: &[&str] = &[
    "sh", "bash", "dash", "python", "python3", "node", "ruby", "perl",
];

/// The permission bits others need on `path`, the word for them and their `chmod` letters:
/// a command run (`run`) needs x, and r as well unless it is a compiled program (ELF: a
/// script's interpreter, or the shell, reads it); an argument, r.
fn needs(path: &Path, run: bool) -> (u32, &'static str, &'static str) {
    use std::io::Read;
    let mut head = [0u8; 4];
    let compiled = std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok()
        && &head == b"\x7fELF";
    match (run, compiled) {
        (true, false) => (0o005, "run", "rx"),
        (true, true) => (0o001, "run", "x"),
        (false, _) => (0o004, "read", "r"),
    }
}

/// The words of a simple command, the placeholders left out (so `{` counts as special), each
/// taken out of the quotes that wrap it whole: `None` where the shell could run a word
/// elsewhere than where it reads, or not at all.
fn simple_words(template: &str) -> Option<Vec<&str>> {
    let special = |c: char| ";&|#$`()<>{}\\*?[\n".contains(c);
    let mut words = Vec::new();
    for word in template.split_whitespace() {
        let bare = match word.as_bytes() {
            [q @ (b'\'' | b'"'), .., r] if q == r => &word[1..word.len() - 1],
            _ => word,
        };
        if bare == "{scene}" || bare == "{rays}" {
            continue;
        }
        if bare.contains(special) || bare.contains(['\'', '"']) || bare == "cd" {
            return None;
        }
        words.push(bare);
    }
    Some(words)
}
