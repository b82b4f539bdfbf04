//! One object of a large asset baked alone into a part, so a farm can
//! spread an asset's objects over its workers: `<out>/.parts/<asset>/
//! <file_stem>/` holds the object's maps (and its look's glTF encoding),
//! `<out>/.parts/<asset>/<file_stem>.json` says how it went. The object's
//! bake reads the whole scene (its shadows and lights) and follows the
//! whole asset's plan, so its maps are the whole bake's, byte for byte.
//! [`super::assemble`] builds the asset's folder from its parts.

use super::fingerprint::fingerprint;
use super::manifest::{Asset, Manifest};
use super::report::{Failure, Status};
use super::run::{BatchOptions, place, recorded, write_report};
use crate::folder::stage_maps;
use crate::look::emissive_png_name;
use crate::staging::Staging;
use serde::{Deserialize, Serialize};
use sssbake::bake::{Accuracy, Seconds};
use sssbake::control::Control;
use sssbake::{Error, plan};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The hidden folder of every asset's parts in a batch's output folder.
pub const PARTS: &str = ".parts";

/// How the bake of one object of an asset went.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartReport {
    /// The asset's name in the manifest.
    pub asset: String,
    /// The object as asked for: its file stem or its name in the scene.
    pub object: String,
    /// `baked`; `skipped` when the asset's folder or this part is up to
    /// date; `failed` with `error`.
    pub status: Status,
    /// The content hash of the asset's inputs the part was baked from.
    pub hash: Option<String>,
    /// The maps' file names in the part's folder, in the order written.
    pub maps: Vec<String>,
    /// The look's emissive strength, for a glTF input (its encoding is
    /// the part's `<file_stem>_diffuse_emissive.png`).
    pub look_strength: Option<f32>,
    /// Sources the 3-D integrators gathered from.
    pub sources: usize,
    /// How far the object's exitance is from the exact sum.
    pub accuracy: Option<Accuracy>,
    /// Seconds per stage of the object's bake.
    pub stages: Seconds,
    /// Seconds this run spent on the part.
    pub seconds: f64,
    /// Why it failed.
    pub error: Option<Failure>,
}

/// The folder of asset `asset`'s parts in `out`.
pub fn parts_folder(out: &Path, asset: &str) -> PathBuf {
    out.join(PARTS).join(asset)
}

/// The folder of one object's part (by its file stem).
pub fn part_folder(out: &Path, asset: &str, file_stem: &str) -> PathBuf {
    parts_folder(out, asset).join(file_stem)
}

/// The report of one object's part (by its file stem).
pub fn part_report_path(out: &Path, asset: &str, file_stem: &str) -> PathBuf {
    parts_folder(out, asset).join(format!("{file_stem}.json"))
}

/// Bakes object `object` (its file stem, as [`super::farm_tasks`] lists
/// it, or its name) of asset `asset` of `manifest` into its part in
/// `options.out` and writes the part's report there (once the object is
/// known); errors only for an unknown asset or object.
pub fn bake_part(
    manifest: &Manifest,
    asset: &str,
    object: &str,
    options: &BatchOptions,
) -> Result<PartReport, Error> {
    let Some(asset) = manifest.assets.iter().find(|a| a.name == asset) else {
        return Err(Error::field(
            "asset",
            format!(
                "{}: no asset `{asset}` in the manifest",
                manifest.path.display()
            ),
        ));
    };
    let start = Instant::now();
    let mut report = PartReport {
        asset: asset.name.clone(),
        object: object.to_string(),
        status: Status::Failed,
        hash: None,
        maps: Vec::new(),
        look_strength: None,
        sources: 0,
        accuracy: None,
        stages: Seconds::default(),
        seconds: 0.0,
        error: None,
    };
    let mut report_path = None;
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        bake_object(asset, options, &mut report, &mut report_path)
    }));
    match outcome {
        Ok(Ok(status)) => report.status = status,
        Ok(Err(error)) => {
            if matches!(&error, Error::Setting { field, .. } if field == "object") {
                return Err(error);
            }
            report.error = Some(Failure::from(&error));
        }
        Err(panic) => report.error = Some(Failure::internal(panic)),
    }
    report.seconds = start.elapsed().as_secs_f64();
    if let Some(path) = report_path {
        write_report(&path, &report)?;
    }
    Ok(report)
}

/// Plans the whole asset, bakes `report.object` by that plan into a hidden
/// folder and moves it into place whole; fills `report` and says where
/// it goes once the object is known.
fn bake_object(
    asset: &Asset,
    options: &BatchOptions,
    report: &mut PartReport,
    report_path: &mut Option<PathBuf>,
) -> Result<Status, Error> {
    let out = &options.out;
    let print = fingerprint(&asset.scene, &asset.options);
    report.hash = Some(print.hash.clone());
    if !options.force && recorded(&out.join(&asset.name)).as_ref() == Some(&print) {
        return Ok(Status::Skipped);
    }
    let (scene, request) = asset.options.load(&asset.scene)?;
    let mut plan = plan(&scene, &request)?;
    // The file stem first: it is unique among the objects, a name may not be.
    let object = plan
        .objects
        .iter()
        .find(|o| o.file_stem == report.object)
        .or_else(|| plan.objects.iter().find(|o| o.name == report.object))
        .cloned();
    let Some(object) = object else {
        let names: Vec<&str> = plan.objects.iter().map(|o| o.file_stem.as_str()).collect();
        return Err(Error::field(
            "object",
            format!(
                "asset `{}` bakes no object `{}` (its objects: {})",
                asset.name,
                report.object,
                names.join(", ")
            ),
        ));
    };
    let stem = object.file_stem.clone();
    let folder = part_folder(out, &asset.name, &stem);
    if !options.force && folder.is_dir() && up_to_date(out, asset, &stem, &print.hash) {
        // Its report stays as the bake wrote it.
        return Ok(Status::Skipped);
    }
    *report_path = Some(part_report_path(out, &asset.name, &stem));
    plan.objects = vec![object];
    let parent = parts_folder(out, &asset.name);
    std::fs::create_dir_all(&parent)
        .map_err(|e| Error::output(parent.display(), format!("cannot create the folder: {e}")))?;
    let staged = tempfile::Builder::new()
        .prefix(&format!(".{stem}.partial-"))
        .tempdir_in(&parent)
        .map_err(|e| Error::output(parent.display(), format!("cannot create a folder: {e}")))?;
    let mut staging = Staging::new(staged.path())?;
    let folder_options = asset.options.folder(staged.path(), false);
    let control = Control::new();
    let (summary, looks) = stage_maps(
        &asset.scene,
        &scene,
        &plan,
        &folder_options,
        &control,
        &mut staging,
    )?;
    report.maps = staging
        .files()
        .filter_map(|p| Some(p.file_name()?.to_string_lossy().into_owned()))
        .collect();
    if let Some((_, look)) = looks.first() {
        staging.stage(&staged.path().join(emissive_png_name(&stem)), &look.png)?;
        report.look_strength = Some(look.strength);
    }
    staging.commit()?;
    if let Some(done) = summary.objects.first() {
        report.sources = done.sources;
        report.accuracy = done.accuracy.clone();
        report.stages = done.seconds.clone();
    }
    place(staged.keep(), &folder)?;
    Ok(Status::Baked)
}

/// Whether the part of `stem` was baked, from inputs of hash `hash`.
fn up_to_date(out: &Path, asset: &Asset, stem: &str, hash: &str) -> bool {
    read_part(out, &asset.name, stem)
        .is_some_and(|p| p.status == Status::Baked && p.hash.as_deref() == Some(hash))
}

/// The report of the part of `stem`, if there is a readable one.
pub fn read_part(out: &Path, asset: &str, stem: &str) -> Option<PartReport> {
    let bytes = std::fs::read(part_report_path(out, asset, stem)).ok()?;
    serde_json::from_slice(&bytes).ok()
}
