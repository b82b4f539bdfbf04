//! A bake's files, written under hidden temporary names as they are made
//! and renamed into place together at the end: the outputs appear all at
//! once or not at all, and no more than one map is held in memory.
//!
//! Replacing is all or nothing too. Before the renames, each file about
//! to be replaced gets a second name (a hard link, so it never leaves its
//! own path); if any rename fails, the files already placed are put back
//! from those names (or removed, where there was none before), so a failed
//! `--force` bake leaves the previous outputs as they were.

use crate::atomic_write::hidden_beside;
use sssbake::Error;
use std::io::Write;
use std::path::{Path, PathBuf};
use tempfile::TempPath;

/// Files staged in an output folder, not yet in place.
pub struct Staging {
    out: PathBuf,
    created_folder: bool,
    /// (temporary, final) per file, in the order staged.
    staged: Vec<(TempPath, PathBuf)>,
    committed: bool,
}

impl Staging {
    /// Stages into `out`, made if missing (and removed again if nothing is
    /// committed).
    pub fn new(out: &Path) -> Result<Self, Error> {
        let created_folder = !out.exists();
        std::fs::create_dir_all(out)
            .map_err(|e| Error::output(out.display(), format!("cannot create the folder: {e}")))?;
        Ok(Staging {
            out: out.to_path_buf(),
            created_folder,
            staged: Vec::new(),
            committed: false,
        })
    }

    /// Writes `bytes` for `path` under a hidden temporary name beside it,
    /// flushed to disk.
    pub fn stage(&mut self, path: &Path, bytes: &[u8]) -> Result<(), Error> {
        let cannot =
            |e: std::io::Error| Error::output(path.display(), format!("cannot write: {e}"));
        let mut file = hidden_beside(path, "partial").map_err(cannot)?;
        file.write_all(bytes).map_err(cannot)?;
        file.as_file().sync_all().map_err(cannot)?;
        self.staged
            .push((file.into_temp_path(), path.to_path_buf()));
        Ok(())
    }

    /// The final paths of the files staged so far.
    pub fn files(&self) -> impl Iterator<Item = &Path> {
        self.staged.iter().map(|(_, path)| path.as_path())
    }

    /// Renames every staged file into place; on an error puts back what it
    /// replaced, removes what it added and every temporary file.
    pub fn commit(self) -> Result<(), Error> {
        self.commit_with(|from, to| std::fs::rename(from, to))
    }

    /// [`Staging::commit`] with the rename given (tests fail it on purpose).
    fn commit_with(
        mut self,
        mut rename: impl FnMut(&Path, &Path) -> std::io::Result<()>,
    ) -> Result<(), Error> {
        let mut previous: Vec<(PathBuf, TempPath)> = Vec::new();
        for (_, path) in &self.staged {
            if path.exists() {
                let backup = second_name(path)
                    .map_err(|e| Error::output(path.display(), format!("cannot keep: {e}")))?;
                previous.push((path.clone(), backup));
            }
        }
        let staged = std::mem::take(&mut self.staged);
        let mut placed: Vec<PathBuf> = Vec::new();
        for (temporary, path) in staged {
            if let Err(e) = rename(&temporary, &path) {
                for done in &placed {
                    match previous.iter().find(|(p, _)| p == done) {
                        Some((_, backup)) => {
                            let _ = std::fs::rename(backup, done);
                        }
                        None => {
                            let _ = std::fs::remove_file(done);
                        }
                    }
                }
                return Err(Error::output(path.display(), format!("cannot write: {e}")));
            }
            // Renamed: the temporary name is gone, so nothing to delete.
            let _ = temporary.keep();
            placed.push(path);
        }
        if let Ok(folder) = std::fs::File::open(&self.out) {
            let _ = folder.sync_all();
        }
        self.committed = true;
        drop(previous);
        remove_leftovers(&placed);
        Ok(())
    }
}

/// Removes the hidden temporary and backup names of `paths` that a killed
/// earlier bake left beside them (a process killed mid-write cannot remove
/// its own): `.<name>.<random>.partial` and `.<name>.<random>.previous`.
fn remove_leftovers(paths: &[PathBuf]) {
    for path in paths {
        let (Some(folder), Some(name)) = (path.parent(), path.file_name()) else {
            continue;
        };
        let prefix = format!(".{}.", name.to_string_lossy());
        let Ok(entries) = std::fs::read_dir(folder) else {
            continue;
        };
        for entry in entries.flatten() {
            let file_name = entry.file_name();
            let file_name = file_name.to_string_lossy();
            let ours = file_name.starts_with(&prefix)
                && (file_name.ends_with(".partial") || file_name.ends_with(".previous"));
            if ours && entry.file_type().is_ok_and(|t| t.is_file()) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// A second, hidden name for the existing file `path` (deleted when
/// dropped): a hard link, or a copy where links are not supported.
fn second_name(path: &Path) -> std::io::Result<TempPath> {
    let backup = hidden_beside(path, "previous")?.into_temp_path();
    std::fs::remove_file(&backup)?;
    if std::fs::hard_link(path, &backup).is_err() {
        std::fs::copy(path, &backup)?;
    }
    Ok(backup)
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed && self.created_folder {
            // The temporary files go with `staged`; then the folder is empty.
            self.staged.clear();
            let _ = std::fs::remove_dir(&self.out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hidden_files(folder: &Path) -> Vec<String> {
        std::fs::read_dir(folder)
            .unwrap()
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|n| n.starts_with('.'))
            .collect()
    }

    #[test]
    fn a_replacement_that_fails_at_its_last_file_keeps_the_previous_files() {
        let folder = tempfile::tempdir().unwrap();
        let names = ["a.exr", "b.exr", "c.png"];
        for name in &names[..2] {
            std::fs::write(folder.path().join(name), format!("old {name}")).unwrap();
        }
        let mut staging = Staging::new(folder.path()).unwrap();
        for name in names {
            staging
                .stage(&folder.path().join(name), format!("new {name}").as_bytes())
                .unwrap();
        }
        let mut renames = 0;
        let result = staging.commit_with(|from, to| {
            renames += 1;
            if to.ends_with("c.png") {
                Err(std::io::Error::other("the disk is full"))
            } else {
                std::fs::rename(from, to)
            }
        });
        assert!(matches!(result, Err(Error::Output { .. })));
        assert_eq!(renames, 3, "it failed at the last file");
        for name in &names[..2] {
            let text = std::fs::read_to_string(folder.path().join(name)).unwrap();
            assert_eq!(text, format!("old {name}"));
        }
        assert!(!folder.path().join("c.png").exists(), "nothing new stays");
        assert_eq!(hidden_files(folder.path()), Vec::<String>::new());
    }

    #[test]
    fn a_commit_removes_what_a_killed_bake_left_of_its_files_and_nothing_else() {
        let folder = tempfile::tempdir().unwrap();
        let out = folder.path();
        let left = [".map.exr.Xy12ab.partial", ".map.exr.Qw34cd.previous"];
        let kept = [
            ".other.exr.Zz99zz.partial",
            ".map.exr.notes",
            "map.exr.partial",
        ];
        for name in left.iter().chain(&kept) {
            std::fs::write(out.join(name), b"x").unwrap();
        }
        let mut staging = Staging::new(out).unwrap();
        staging.stage(&out.join("map.exr"), b"new").unwrap();
        staging.commit().unwrap();
        for name in left {
            assert!(!out.join(name).exists(), "{name}");
        }
        for name in kept {
            assert!(out.join(name).exists(), "{name}");
        }
        assert_eq!(std::fs::read(out.join("map.exr")).unwrap(), b"new");
    }

    #[test]
    fn a_commit_replaces_every_file_and_leaves_no_temporary_name() {
        let folder = tempfile::tempdir().unwrap();
        std::fs::write(folder.path().join("a.exr"), "old").unwrap();
        let mut staging = Staging::new(folder.path()).unwrap();
        staging.stage(&folder.path().join("a.exr"), b"new").unwrap();
        staging
            .stage(&folder.path().join("b.exr"), b"new b")
            .unwrap();
        staging.commit().unwrap();
        assert_eq!(
            std::fs::read_to_string(folder.path().join("a.exr")).unwrap(),
            "new"
        );
        assert_eq!(
            std::fs::read_to_string(folder.path().join("b.exr")).unwrap(),
            "new b"
        );
        assert_eq!(hidden_files(folder.path()), Vec::<String>::new());
    }

    #[test]
    fn two_stagings_of_one_path_in_one_process_do_not_collide() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("a.exr");
        let mut first = Staging::new(folder.path()).unwrap();
        let mut second = Staging::new(folder.path()).unwrap();
        first.stage(&path, b"first").unwrap();
        second.stage(&path, b"second").unwrap();
        drop(first);
        second.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "second");
    }

    #[test]
    fn an_abandoned_staging_removes_its_files_and_the_folder_it_made() {
        let parent = tempfile::tempdir().unwrap();
        let out = parent.path().join("new");
        let mut staging = Staging::new(&out).unwrap();
        staging.stage(&out.join("a.exr"), b"x").unwrap();
        drop(staging);
        assert!(!out.exists());
    }
}
