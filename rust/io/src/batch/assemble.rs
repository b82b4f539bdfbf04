//! An asset's folder built from its objects' parts ([`super::parts`]):
//! the parts' maps copied byte for byte, the summary put together from the
//! asset's plan and each part's numbers, and the look (the glTF copy or
//! the USD layer) written over every object, as a whole-asset bake writes
//! them. Refused, naming the asset and the object, when a part is
//! missing, failed or was baked from other inputs.

use super::fingerprint::Fingerprint;
use super::manifest::Asset;
use super::parts::{PARTS, PartReport, part_folder, parts_folder, read_part};
use super::report::Status;
use super::run::{RECORD, place};
use crate::assets::AssetRecord;
use crate::atomic_write::write_atomically;
use crate::folder::stage_assets;
use crate::look::{Emissive, emissive_png_name};
use crate::staging::Staging;
use sssbake::bake::ObjectSummary;
use sssbake::plan::ObjectPlan;
use sssbake::{Error, Summary, plan};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Builds `asset`'s folder from its parts in `out` (inputs `print`) in a
/// hidden folder, swaps it into place as `folder` and removes the parts.
pub(super) fn assemble_into(
    asset: &Asset,
    folder: &Path,
    out: &Path,
    print: &Fingerprint,
) -> Result<Summary, Error> {
    let (scene, request) = asset.options.load(&asset.scene)?;
    let plan = plan(&scene, &request)?;
    let parts: Vec<PartReport> = plan
        .objects
        .iter()
        .map(|object| usable_part(asset, object, out, print))
        .collect::<Result<_, _>>()?;
    let staged = tempfile::Builder::new()
        .prefix(&format!(".{}.partial-", asset.name))
        .tempdir_in(out)
        .map_err(|e| Error::output(out.display(), format!("cannot create a folder: {e}")))?;
    let mut staging = Staging::new(staged.path())?;
    let mut summary = Summary::new(&plan);
    let mut looks = Vec::new();
    for (object, part) in plan.objects.iter().zip(&parts) {
        let from = part_folder(out, &asset.name, &object.file_stem);
        for name in &part.maps {
            let bytes = read(asset, object, &from.join(name))?;
            staging.stage(&staged.path().join(name), &bytes)?;
        }
        if let Some(strength) = part.look_strength {
            let png = read(
                asset,
                object,
                &from.join(emissive_png_name(&object.file_stem)),
            )?;
            looks.push((object.name.clone(), Emissive { strength, png }));
        }
        summary.objects.push(ObjectSummary {
            plan: object.clone(),
            sources: part.sources,
            accuracy: part.accuracy.clone(),
            seconds: part.stages.clone(),
        });
    }
    let start = Instant::now();
    let written: Vec<PathBuf> = staging.files().map(Path::to_path_buf).collect();
    let record = AssetRecord {
        input: &asset.scene,
        out: staged.path(),
        uv_set: asset.options.uv_set.unwrap_or(0),
        objects: &scene.objects,
        summary: &summary,
        maps: &written,
        emissive: &looks,
        layer_writer: None,
    };
    let notes = stage_assets(&record, false, &mut staging)?;
    summary.files = staging.files().map(|p| p.display().to_string()).collect();
    staging.commit()?;
    summary.left_out.extend(notes);
    summary.write_seconds = start.elapsed().as_secs_f64();
    let record = serde_json::to_vec_pretty(print).unwrap_or_default();
    let record_path = staged.path().join(RECORD);
    write_atomically(&record_path, &record)
        .map_err(|e| Error::output(record_path.display(), format!("cannot write: {e}")))?;
    place(staged.keep(), folder)?;
    // The parts are in the folder now; a killed task's hidden leftovers go too.
    let _ = std::fs::remove_dir_all(parts_folder(out, &asset.name));
    let _ = std::fs::remove_dir(out.join(PARTS));
    Ok(summary)
}

/// The report of `object`'s part, when it was baked from the inputs of
/// `print`; else why not, naming the asset and the object.
fn usable_part(
    asset: &Asset,
    object: &ObjectPlan,
    out: &Path,
    print: &Fingerprint,
) -> Result<PartReport, Error> {
    let refused = |why: String| {
        Error::input(format!(
            "asset `{}`: object `{}`: {why}",
            asset.name, object.name
        ))
    };
    let Some(part) = read_part(out, &asset.name, &object.file_stem) else {
        return Err(refused(format!(
            "no part in {} (bake it with --asset {} --object {:?})",
            parts_folder(out, &asset.name).display(),
            asset.name,
            object.name
        )));
    };
    if part.status == Status::Failed {
        let why = part.error.map(|e| e.message).unwrap_or_default();
        return Err(refused(format!("its bake failed: {why}")));
    }
    if part.status != Status::Baked || part.hash.as_deref() != Some(print.hash.as_str()) {
        return Err(refused(format!(
            "its part was baked from other inputs (hash {}, the asset's now {}); bake it again",
            part.hash.as_deref().unwrap_or("none"),
            print.hash
        )));
    }
    Ok(part)
}

/// The bytes of a part's file, or an error naming the asset and object.
fn read(asset: &Asset, object: &ObjectPlan, path: &Path) -> Result<Vec<u8>, Error> {
    std::fs::read(path).map_err(|e| {
        Error::input(format!(
            "asset `{}`: object `{}`: cannot read its part's {}: {e}",
            asset.name,
            object.name,
            path.display()
        ))
    })
}
