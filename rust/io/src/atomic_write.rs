//! Writing a file so that it either appears whole or not at all: written
//! under a hidden temporary name beside it, flushed, then renamed.

use std::io::Write;
use std::path::Path;

/// A new, empty hidden file `.<name>.<random>.<suffix>` beside `path`, on
/// the same file system so that renaming it into place is atomic; deleted
/// when dropped unless it is persisted.
pub fn hidden_beside(path: &Path, suffix: &str) -> std::io::Result<tempfile::NamedTempFile> {
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = path.file_name().map_or_else(
        || "output".to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    tempfile::Builder::new()
        .prefix(&format!(".{name}."))
        .suffix(&format!(".{suffix}"))
        .tempfile_in(folder)
}

/// Writes `bytes` to a hidden file beside `path`, flushed to disk, then
/// renames it into place; on any error the temporary file is removed and
/// `path` is untouched.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut file = hidden_beside(path, "partial")?;
    file.write_all(bytes)?;
    file.as_file().sync_all()?;
    file.persist(path).map(|_| ()).map_err(|e| e.error)
}
