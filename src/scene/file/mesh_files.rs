//! A mesh file's identity, however its path is spelled: what the `.scene` parser counts the
//! uses of a mesh by, and loads it once for.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// A mesh file's identity: its device and inode where it can be looked up, so that every
/// spelling of its path (`c.obj`, `./c.obj`, `d/../c.obj`, a link) is one mesh, loaded and
/// instanced once; else its path as joined (the load then names the problem).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(super) enum FileKey {
    Id(u64, u64),
    Path(PathBuf),
}

impl FileKey {
    pub(super) fn of(path: &Path) -> FileKey {
        #[cfg(unix)]
        if let Ok(meta) = std::fs::metadata(path) {
            use std::os::unix::fs::MetadataExt;
            return FileKey::Id(meta.dev(), meta.ino());
        }
        FileKey::Path(std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()))
    }
}

/// Each mesh path as written, with the file it names (looked up once per spelling).
#[derive(Default)]
pub(super) struct MeshFiles(HashMap<String, FileKey>);

impl MeshFiles {
    pub(super) fn key(&mut self, dir: &Path, path: &str) -> FileKey {
        if let Some(key) = self.0.get(path) {
            return key.clone();
        }
        let key = FileKey::of(&dir.join(path));
        self.0.insert(path.to_string(), key.clone());
        key
    }
}
