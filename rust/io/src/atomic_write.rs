//! Writing a file so that it either appears whole or not at all.

use std::io::Write;
use std::path::{Path, PathBuf};

/// The hidden temporary name a file is written under before it is renamed
/// to `path`: `.<name>.<process id>.partial` in the same folder, so the
/// rename stays on one file system.
pub fn temporary_beside(path: &Path) -> Result<PathBuf, String> {
    let directory = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| format!("{}: not a file name", path.display()))?;
    Ok(directory.join(format!(
        ".{}.{}.partial",
        name.to_string_lossy(),
        std::process::id()
    )))
}

/// Writes `bytes` to [`temporary_beside`] `path`, flushed to disk; on any
/// error the temporary file is removed. Returns the temporary file's path.
pub fn write_temporary(path: &Path, bytes: &[u8]) -> Result<PathBuf, String> {
    let temporary = temporary_beside(path)?;
    let result = (|| {
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(bytes)?;
        file.sync_all()
    })();
    result.map(|()| temporary.clone()).map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        format!("{}: cannot write: {e}", path.display())
    })
}

/// Writes `bytes` to a temporary file beside `path`, then renames it into
/// place; on any error the temporary file is removed and `path` untouched.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let temporary = write_temporary(path, bytes)?;
    std::fs::rename(&temporary, path).map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        format!("{}: cannot write: {e}", path.display())
    })
}
