//! A bake's files, written under temporary names as they are made and
//! renamed into place together at the end: the outputs appear all at once
//! or not at all, and no more than one map is held in memory.

use crate::Failure;
use sssbake_io::atomic_write::write_temporary;
use std::path::{Path, PathBuf};

/// Files staged in an output folder, not yet in place.
pub struct Staging {
    out: PathBuf,
    created_folder: bool,
    /// (temporary, final) per file, in the order staged.
    staged: Vec<(PathBuf, PathBuf)>,
    committed: bool,
}

impl Staging {
    /// Stages into `out`, made if missing (and removed again if nothing is
    /// committed).
    pub fn new(out: &Path) -> Result<Self, Failure> {
        let created_folder = !out.exists();
        std::fs::create_dir_all(out).map_err(|e| {
            Failure::Output(format!("{}: cannot create the folder: {e}", out.display()))
        })?;
        Ok(Staging {
            out: out.to_path_buf(),
            created_folder,
            staged: Vec::new(),
            committed: false,
        })
    }

    /// Writes `bytes` for `path` under a hidden temporary name beside it.
    pub fn stage(&mut self, path: &Path, bytes: &[u8]) -> Result<(), Failure> {
        let temporary = write_temporary(path, bytes).map_err(Failure::Output)?;
        self.staged.push((temporary, path.to_path_buf()));
        Ok(())
    }

    /// The final paths of the files staged so far.
    pub fn files(&self) -> impl Iterator<Item = &Path> {
        self.staged.iter().map(|(_, path)| path.as_path())
    }

    /// Renames every staged file into place; on an error removes those
    /// already placed and every temporary file.
    pub fn commit(mut self) -> Result<(), Failure> {
        let mut placed = Vec::new();
        for (temporary, path) in &self.staged {
            if let Err(e) = std::fs::rename(temporary, path) {
                for done in placed {
                    let _ = std::fs::remove_file(done);
                }
                return Err(Failure::Output(format!(
                    "{}: cannot write: {e}",
                    path.display()
                )));
            }
            placed.push(path);
        }
        self.committed = true;
        Ok(())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if self.committed {
            return;
        }
        for (temporary, _) in &self.staged {
            let _ = std::fs::remove_file(temporary);
        }
        if self.created_folder {
            let _ = std::fs::remove_dir(&self.out);
        }
    }
}
