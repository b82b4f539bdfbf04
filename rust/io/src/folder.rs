//! A bake written into a folder: every planned map of every object as a
//! linear EXR (and an sRGB PNG preview for colour maps), and the input's
//! glTF copy or USD layer, all staged and renamed into place together.

use crate::assets::{AssetKind, AssetRecord, asset_files};
use crate::image_writer::{Precision, exr_bytes, png_bytes};
use crate::look::{Emissive, LOOK, emissive};
use crate::staging::Staging;
use crate::usd_writer::LayerWriter;
use rayon::prelude::*;
use sssbake::control::Control;
use sssbake::{Error, Plan, Scene, Summary, bake_each};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One output's files, (path, bytes), and its glTF emissive encoding when
/// it is the look of a glTF input.
type EncodedOutput<'a> = (Vec<(&'a Path, Vec<u8>)>, Option<Emissive>);

/// How a bake is written.
#[derive(Clone, Debug)]
pub struct FolderOptions {
    /// The folder (made if missing; never the input's own).
    pub out: PathBuf,
    /// Replace files already there.
    pub force: bool,
    /// EXR sample precision.
    pub precision: Precision,
    /// Exposure of the PNG previews, stops (the EXRs stay as baked).
    pub exposure: f32,
    /// The texture-coordinate set the scene was read with.
    pub uv_set: usize,
    /// Writes a USD input's layer in the caller's usd-core (for a stage
    /// held in memory) [a Python process reads the input's file].
    pub layer_writer: Option<LayerWriter>,
}

impl Default for FolderOptions {
    fn default() -> Self {
        FolderOptions {
            out: PathBuf::new(),
            force: false,
            precision: Precision::Float,
            exposure: 0.0,
            uv_set: 0,
            layer_writer: None,
        }
    }
}

/// Bakes `plan` of `scene` (read from `input`) into `options.out`; the
/// summary lists the files written.
pub fn bake_to_folder(
    input: &Path,
    scene: &Scene,
    plan: &Plan,
    options: &FolderOptions,
    control: &Control,
) -> Result<Summary, Error> {
    check_exposure(options)?;
    refuse_input_folder(input, &options.out)?;
    let maps = map_paths(plan, &options.out);
    refuse_existing(maps.iter().map(|(_, _, p)| p.as_path()), options.force)?;
    let mut staging = Staging::new(&options.out)?;
    let (mut summary, looks) = stage_maps(input, scene, plan, options, control, &mut staging)?;
    let start = Instant::now();
    let written: Vec<PathBuf> = staging.files().map(Path::to_path_buf).collect();
    let record = AssetRecord {
        input,
        out: &options.out,
        uv_set: options.uv_set,
        objects: &scene.objects,
        summary: &summary,
        maps: &written,
        emissive: &looks,
        layer_writer: options.layer_writer.as_ref(),
    };
    let notes = stage_assets(&record, options.force, &mut staging)?;
    summary.files = staging.files().map(|p| p.display().to_string()).collect();
    staging.commit()?;
    summary.left_out.extend(notes);
    summary.write_seconds = start.elapsed().as_secs_f64();
    Ok(summary)
}

/// Bakes every object of `plan` and stages its maps in `staging` (paths
/// in `options.out`), one object at a time; returns the summary and, for
/// a glTF input, each object's look encoded for the copy.
pub fn stage_maps(
    input: &Path,
    scene: &Scene,
    plan: &Plan,
    options: &FolderOptions,
    control: &Control,
    staging: &mut Staging,
) -> Result<(Summary, Vec<(String, Emissive)>), Error> {
    check_exposure(options)?;
    let maps = map_paths(plan, &options.out);
    // The glTF copy shows the look through its own emissive encoding.
    let encode_look = AssetKind::of(input) == Some(AssetKind::Gltf);
    let mut looks = Vec::new();
    let summary = bake_each(scene, plan, control, |object| {
        let mine: Vec<&(String, sssbake::Output, PathBuf)> =
            maps.iter().filter(|(n, _, _)| n == object.name()).collect();
        let mut outputs: Vec<sssbake::Output> = mine.iter().map(|(_, o, _)| *o).collect();
        outputs.dedup();
        // Each output is rendered once and encoded into its files; the
        // outputs side by side (the encoders are serial), which holds one
        // image per output at most, as the plan's memory estimate counts.
        let encoded: Vec<EncodedOutput> = outputs
            .par_iter()
            .map(|&output| {
                let (pngs, exrs): (Vec<&Path>, Vec<&Path>) = mine
                    .iter()
                    .filter(|(_, o, _)| *o == output)
                    .map(|(_, _, path)| path.as_path())
                    .partition(|p| p.extension().is_some_and(|e| e == "png"));
                let mut image = object.render(output)?;
                let mut files = Vec::new();
                let mut look = None;
                for path in exrs {
                    if encode_look && output == LOOK {
                        look =
                            Some(emissive(&image).map_err(|e| Error::output(path.display(), e))?);
                    }
                    let bytes = exr_bytes(&image, options.precision)
                        .map_err(|e| Error::output(path.display(), e))?;
                    files.push((path, bytes));
                }
                // The previews last: they scale the image by the exposure.
                let scale = options.exposure.exp2();
                for texel in &mut image.texels {
                    *texel = texel.map(|v| v * scale);
                }
                for path in pngs {
                    let bytes = png_bytes(&image).map_err(|e| Error::output(path.display(), e))?;
                    files.push((path, bytes));
                }
                Ok((files, look))
            })
            .collect::<Result<_, Error>>()?;
        for (files, look) in encoded {
            if let Some(look) = look {
                looks.push((object.name().to_string(), look));
            }
            for (path, bytes) in files {
                staging.stage(path, &bytes)?;
            }
        }
        Ok(())
    })?;
    Ok((summary, looks))
}

/// Stages the assets of `record` (the glTF copy or USD layer) in
/// `staging`, refusing files already there unless `force`; returns what
/// the assets could not show and why.
pub fn stage_assets(
    record: &AssetRecord,
    force: bool,
    staging: &mut Staging,
) -> Result<Vec<String>, Error> {
    let mut notes = Vec::new();
    let assets = asset_files(record, &mut notes)?;
    refuse_existing(assets.iter().map(|(p, _)| p.as_path()), force)?;
    for (path, bytes) in &assets {
        staging.stage(path, bytes)?;
    }
    Ok(notes)
}

fn check_exposure(options: &FolderOptions) -> Result<(), Error> {
    if !options.exposure.is_finite() {
        return Err(Error::field("exposure", "must be a number of stops"));
    }
    Ok(())
}

/// (object, output, path) of every map `plan` makes in `out`: an EXR per
/// output and a PNG per colour output.
pub fn map_paths(plan: &Plan, out: &Path) -> Vec<(String, sssbake::Output, PathBuf)> {
    let mut paths = Vec::new();
    for object in &plan.objects {
        for &output in &plan.outputs {
            let file = |extension| out.join(map_file_name(&object.file_stem, output, extension));
            paths.push((object.name.clone(), output, file("exr")));
            if output.is_colour() {
                paths.push((object.name.clone(), output, file("png")));
            }
        }
    }
    paths
}

/// The file name of map `output` of the object whose file-name-safe name
/// is `file_stem`: `<file_stem>_<output>.<extension>`.
pub fn map_file_name(file_stem: &str, output: sssbake::Output, extension: &str) -> String {
    format!("{file_stem}_{}.{extension}", output.name())
}

fn refuse_existing<'a>(
    mut paths: impl Iterator<Item = &'a Path>,
    force: bool,
) -> Result<(), Error> {
    match paths.find(|p| p.exists()) {
        Some(existing) if !force => Err(Error::output(
            existing.display(),
            "exists (use --force to replace it)",
        )),
        _ => Ok(()),
    }
}

/// Refuses an output folder that is the input's own: a bake never writes
/// beside the asset it reads. (A stage only in memory has no folder.)
fn refuse_input_folder(input: &Path, out: &Path) -> Result<(), Error> {
    if !input.is_file() {
        return Ok(());
    }
    let folder = input
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let same = match (folder.canonicalize(), out.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same {
        return Err(Error::field(
            "out",
            format!(
                "{} is the folder of the input {}; write the bake to another folder",
                out.display(),
                input.display()
            ),
        ));
    }
    Ok(())
}
