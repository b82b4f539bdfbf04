//! Running a manifest: each asset hashed, skipped when unchanged, else
//! baked into a hidden folder beside its own and swapped into place whole;
//! a failing asset does not stop the others; `jobs` assets at once, the
//! threads split between them.

use super::assemble::assemble_into;
use super::fingerprint::{Fingerprint, fingerprint};
use super::manifest::{Asset, Manifest};
use super::report::{
    AssetReport, BatchReport, Failure, Status, asset_report_path, batch_report_path,
};
use crate::atomic_write::write_atomically;
use crate::bake_to_folder;
use sssbake::control::Control;
use sssbake::{Error, plan};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// The record of an asset's bake, kept in its folder: the fingerprint its
/// inputs had.
pub const RECORD: &str = "sssbake-inputs.json";

/// How a batch runs.
#[derive(Clone, Debug, Default)]
pub struct BatchOptions {
    /// The output folder: `<out>/<asset>/` per asset, `<out>/reports/`,
    /// `<out>/batch.json`.
    pub out: PathBuf,
    /// Bake every asset even when unchanged.
    pub force: bool,
    /// Assets baked at once (at most one per thread); 0 is 1.
    pub jobs: usize,
    /// Only these assets (by name); every asset when empty. A run of some
    /// assets writes their reports but not the batch's.
    pub only: Vec<String>,
    /// Build each asset's folder from its objects' parts
    /// ([`super::parts`]) instead of baking it.
    pub assemble: bool,
}

/// Runs `manifest` as `options` say and writes the reports; `done` hears
/// of each asset as it ends. Errors only for what stops the whole batch
/// (an unknown asset name, an output folder that cannot be made).
pub fn run_batch(
    manifest: &Manifest,
    options: &BatchOptions,
    done: impl Fn(&AssetReport) + Sync,
) -> Result<BatchReport, Error> {
    let start = Instant::now();
    if let Some(unknown) = options
        .only
        .iter()
        .find(|n| !manifest.assets.iter().any(|a| &a.name == *n))
    {
        return Err(Error::field(
            "asset",
            format!(
                "{}: no asset `{unknown}` in the manifest",
                manifest.path.display()
            ),
        ));
    }
    let assets: Vec<&Asset> = manifest
        .assets
        .iter()
        .filter(|a| options.only.is_empty() || options.only.contains(&a.name))
        .collect();
    std::fs::create_dir_all(options.out.join("reports")).map_err(|e| {
        Error::output(
            options.out.display(),
            format!("cannot create the folder: {e}"),
        )
    })?;
    let cores = rayon::current_num_threads().max(1);
    let jobs = options.jobs.max(1).min(cores).min(assets.len().max(1));
    let threads_per_job = (cores / jobs).max(1);
    let next = AtomicUsize::new(0);
    let reports: Mutex<Vec<Option<AssetReport>>> = Mutex::new(vec![None; assets.len()]);
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads_per_job)
                    .build();
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(asset) = assets.get(i) else { break };
                    let report = match &pool {
                        Ok(pool) => pool.install(|| run_asset(asset, options)),
                        Err(_) => run_asset(asset, options),
                    };
                    let _ = write_report(&asset_report_path(&options.out, &asset.name), &report);
                    done(&report);
                    if let Ok(mut reports) = reports.lock() {
                        reports[i] = Some(report);
                    }
                }
            });
        }
    });
    let assets: Vec<AssetReport> = reports
        .into_inner()
        .unwrap_or_default()
        .into_iter()
        .flatten()
        .collect();
    let report = BatchReport {
        manifest: manifest.path.display().to_string(),
        out: options.out.display().to_string(),
        version: crate::VERSION.to_string(),
        jobs,
        threads_per_job,
        seconds: start.elapsed().as_secs_f64(),
        counts: BatchReport::count(&assets),
        assets,
    };
    if options.only.is_empty() {
        write_report(&batch_report_path(&options.out), &report)?;
    }
    Ok(report)
}

/// The batch report of `manifest` from the asset reports in `out` (as a
/// farm's tasks left them), written to `out/batch.json`.
pub fn collect_reports(
    manifest: &Manifest,
    out: &Path,
    seconds: f64,
) -> Result<BatchReport, Error> {
    let assets: Vec<AssetReport> = manifest
        .assets
        .iter()
        .map(|asset| {
            let path = asset_report_path(out, &asset.name);
            std::fs::read(&path)
                .ok()
                .and_then(|bytes| serde_json::from_slice::<AssetReport>(&bytes).ok())
                .unwrap_or_else(|| AssetReport {
                    name: asset.name.clone(),
                    scene: asset.scene.display().to_string(),
                    status: Status::Missing,
                    folder: out.join(&asset.name).display().to_string(),
                    files: Vec::new(),
                    seconds: 0.0,
                    hash: None,
                    error: Some(Failure {
                        kind: "missing".into(),
                        message: format!("{}: no report (the asset was not run)", path.display()),
                    }),
                    summary: None,
                })
        })
        .collect();
    let report = BatchReport {
        manifest: manifest.path.display().to_string(),
        out: out.display().to_string(),
        version: crate::VERSION.to_string(),
        jobs: 0,
        threads_per_job: 0,
        seconds,
        counts: BatchReport::count(&assets),
        assets,
    };
    write_report(&batch_report_path(out), &report)?;
    Ok(report)
}

/// Hashes, skips or bakes one asset; never panics.
fn run_asset(asset: &Asset, options: &BatchOptions) -> AssetReport {
    let start = Instant::now();
    let folder = options.out.join(&asset.name);
    let mut report = AssetReport {
        name: asset.name.clone(),
        scene: asset.scene.display().to_string(),
        status: Status::Failed,
        folder: folder.display().to_string(),
        files: Vec::new(),
        seconds: 0.0,
        hash: None,
        error: None,
        summary: None,
    };
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let print = fingerprint(&asset.scene, &asset.options);
        report.hash = Some(print.hash.clone());
        if !options.force && recorded(&folder).as_ref() == Some(&print) {
            report.files = files_in(&folder);
            return Ok(Status::Skipped);
        }
        refuse_input_inside(&folder, &print)?;
        let summary = if options.assemble {
            assemble_into(asset, &folder, &options.out, &print)?
        } else {
            bake_into(asset, &folder, &options.out, &print)?
        };
        report.files = files_in(&folder);
        report.summary = serde_json::to_value(&summary).ok();
        Ok(Status::Baked)
    }));
    match outcome {
        Ok(Ok(status)) => report.status = status,
        Ok(Err(error)) => report.error = Some(Failure::from(&error)),
        Err(panic) => report.error = Some(Failure::internal(panic)),
    }
    report.seconds = start.elapsed().as_secs_f64();
    report
}

/// Bakes `asset` into a hidden folder in `out`, records `print` there and
/// swaps it into place as `folder`.
fn bake_into(
    asset: &Asset,
    folder: &Path,
    out: &Path,
    print: &Fingerprint,
) -> Result<sssbake::Summary, Error> {
    let staging = tempfile::Builder::new()
        .prefix(&format!(".{}.partial-", asset.name))
        .tempdir_in(out)
        .map_err(|e| Error::output(out.display(), format!("cannot create a folder: {e}")))?;
    let (scene, request) = asset.options.load(&asset.scene)?;
    let plan = plan(&scene, &request)?;
    let control = Control::new();
    let folder_options = asset.options.folder(staging.path(), false);
    let summary = bake_to_folder(&asset.scene, &scene, &plan, &folder_options, &control)?;
    let record = serde_json::to_vec_pretty(print).unwrap_or_default();
    let record_path = staging.path().join(RECORD);
    write_atomically(&record_path, &record)
        .map_err(|e| Error::output(record_path.display(), format!("cannot write: {e}")))?;
    place(staging.keep(), folder)?;
    Ok(summary)
}

/// Moves the finished folder `staged` to `folder`, replacing what was
/// there: the old folder is moved aside first and removed after, so
/// `folder` holds one bake's files or none, never a mix. If the move
/// fails the old folder comes back.
pub(super) fn place(staged: PathBuf, folder: &Path) -> Result<(), Error> {
    let cannot = |e: std::io::Error| {
        let _ = std::fs::remove_dir_all(&staged);
        Error::output(
            folder.display(),
            format!("cannot move the bake into place: {e}"),
        )
    };
    if !folder.exists() {
        return std::fs::rename(&staged, folder).map_err(cannot);
    }
    let name = folder.file_name().unwrap_or_default().to_string_lossy();
    let parent = folder.parent().unwrap_or(Path::new("."));
    let aside = tempfile::Builder::new()
        .prefix(&format!(".{name}.previous-"))
        .tempdir_in(parent)
        .map_err(cannot)?
        .keep();
    // The empty directory is there to reserve the name; a rename onto an
    // empty directory replaces it.
    if let Err(e) = std::fs::rename(folder, &aside) {
        let _ = std::fs::remove_dir(&aside);
        return Err(cannot(e));
    }
    if let Err(e) = std::fs::rename(&staged, folder) {
        let _ = std::fs::rename(&aside, folder);
        return Err(cannot(e));
    }
    let _ = std::fs::remove_dir_all(&aside);
    Ok(())
}

/// Refuses an asset folder that holds one of the asset's own inputs (an
/// asset named as its scene's folder, baked into the folder above it), or
/// that a batch did not make: replacing it would remove what is there.
fn refuse_input_inside(folder: &Path, print: &Fingerprint) -> Result<(), Error> {
    let Ok(folder) = folder.canonicalize() else {
        return Ok(());
    };
    let inside = print.files.iter().find(|file| {
        Path::new(file)
            .canonicalize()
            .is_ok_and(|file| file.starts_with(&folder))
    });
    if let Some(file) = inside {
        return Err(Error::output(
            folder.display(),
            format!("holds the asset's input {file}; bake the batch into another --out"),
        ));
    }
    // A batch replaces only folders it made (or empty ones).
    let empty = std::fs::read_dir(&folder).is_ok_and(|mut entries| entries.next().is_none());
    if !empty && !folder.join(RECORD).exists() {
        return Err(Error::output(
            folder.display(),
            format!("exists without a {RECORD}: not a batch's folder, so it is left alone"),
        ));
    }
    Ok(())
}

/// The fingerprint recorded in `folder` by its last bake, if any.
pub(super) fn recorded(folder: &Path) -> Option<Fingerprint> {
    let bytes = std::fs::read(folder.join(RECORD)).ok()?;
    serde_json::from_slice(&bytes).ok()
}

/// The files in `folder`, sorted, without hidden ones.
pub(super) fn files_in(folder: &Path) -> Vec<String> {
    let mut files: Vec<String> = std::fs::read_dir(folder)
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
        .map(|e| e.path().display().to_string())
        .collect();
    files.sort();
    files
}

/// Writes `report` as pretty JSON to `path`, whole or not at all.
pub(super) fn write_report(path: &Path, report: &impl serde::Serialize) -> Result<(), Error> {
    let bytes = serde_json::to_vec_pretty(report)
        .map_err(|e| Error::output(path.display(), format!("cannot write: {e}")))?;
    write_atomically(path, &bytes)
        .map_err(|e| Error::output(path.display(), format!("cannot write: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(folder: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(folder)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_placed_folder_replaces_the_old_one_whole_and_leaves_nothing_aside() {
        let out = tempfile::tempdir().unwrap();
        let folder = out.path().join("head");
        std::fs::create_dir(&folder).unwrap();
        std::fs::write(folder.join("old_only.exr"), "old").unwrap();
        std::fs::write(folder.join("both.exr"), "old").unwrap();
        let staged = out.path().join(".head.partial-1");
        std::fs::create_dir(&staged).unwrap();
        std::fs::write(staged.join("both.exr"), "new").unwrap();
        place(staged.clone(), &folder).unwrap();
        assert_eq!(
            names(&folder),
            ["both.exr"],
            "no file of the old bake stays"
        );
        assert_eq!(
            std::fs::read_to_string(folder.join("both.exr")).unwrap(),
            "new"
        );
        assert_eq!(names(out.path()), ["head"], "nothing left aside");
    }

    #[test]
    fn a_folder_that_cannot_be_placed_keeps_the_old_one() {
        let out = tempfile::tempdir().unwrap();
        let folder = out.path().join("head");
        std::fs::create_dir(&folder).unwrap();
        std::fs::write(folder.join("a.exr"), "old").unwrap();
        let missing = out.path().join(".head.partial-gone");
        let error = place(missing, &folder).unwrap_err();
        assert!(matches!(error, Error::Output { .. }), "{error}");
        assert_eq!(
            std::fs::read_to_string(folder.join("a.exr")).unwrap(),
            "old"
        );
        assert_eq!(names(out.path()), ["head"]);
    }
}
