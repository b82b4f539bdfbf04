//! `sssbake bake`: the maps of every selected object, written whole or not
//! at all.

use crate::Failure;
use crate::asset_outputs::{BakeRecord, NewLayout};
use crate::progress::watch;
use crate::scene_options::SceneOptions;
use crate::staging::Staging;
use serde_json::json;
use sssbake::control::Control;
use sssbake::maps::{Output, margin_fill, render};
use sssbake::pipeline::{BakeError, prepare};
use sssbake::transport::kernel::Kernel;
use sssbake::transport::{Method, MethodSettings};
use sssbake_io::image_writer::{Precision, exr_bytes, png_bytes};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Options of `sssbake bake`.
#[derive(clap::Args)]
pub struct BakeArgs {
    #[command(flatten)]
    pub(crate) scene: SceneOptions,
    /// The folder for the maps (created if missing; not the input's own).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// The integrator.
    #[arg(long, default_value = "auto")]
    method: Method,
    /// The maps to write, comma-separated: subsurface, irradiance, diffuse,
    /// thickness, stretch, area.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "subsurface,irradiance,diffuse"
    )]
    pub(crate) outputs: Vec<Output>,
    /// Texels filled around each chart so filtering never reads black.
    #[arg(long, default_value_t = 8)]
    margin: u32,
    /// Write EXRs as 16-bit half floats instead of 32-bit.
    #[arg(long)]
    half: bool,
    /// Exposure of the PNG previews, in stops (the EXRs stay as baked).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    exposure: f32,
    /// Octree: the solid angle below which a node is taken whole.
    #[arg(long, default_value_t = 0.05)]
    octree_epsilon: f32,
    /// Importance: probes per texel.
    #[arg(long, default_value_t = 64)]
    samples: u32,
    /// Texture: Gaussians in the fit.
    #[arg(long, default_value_t = 6)]
    gaussians: usize,
    /// Replace maps already in the folder.
    #[arg(long)]
    force: bool,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
}

/// A file encoded and waiting to be written.
pub struct Encoded {
    /// Where it goes.
    pub path: PathBuf,
    /// Its bytes.
    pub bytes: Vec<u8>,
}

fn bake_failure(error: BakeError) -> Failure {
    Failure::Input(error.to_string())
}

/// A file-name-safe form of each object's name: characters outside
/// letters, digits and `-_.` become `_`, and names that then coincide
/// (ignoring case, as some file systems do) get `-2`, `-3`, … in order.
fn file_stems(names: &[&str]) -> Vec<String> {
    let mut taken = std::collections::HashSet::new();
    names
        .iter()
        .map(|name| {
            let safe: String = name
                .chars()
                .map(|c| {
                    if c.is_alphanumeric() || "-_.".contains(c) {
                        c
                    } else {
                        '_'
                    }
                })
                .collect();
            let mut stem = safe.clone();
            let mut n = 1;
            while !taken.insert(stem.to_lowercase()) {
                n += 1;
                stem = format!("{safe}-{n}");
            }
            stem
        })
        .collect()
}

/// Runs the command.
pub fn run(args: &BakeArgs) -> Result<(), Failure> {
    if args.outputs.is_empty() {
        return Err(Failure::Input("--outputs: name at least one map".into()));
    }
    if !args.exposure.is_finite() {
        return Err(Failure::Input(
            "--exposure: must be a number of stops".into(),
        ));
    }
    refuse_input_folder(&args.scene.input, &args.out)?;
    let loaded = args.scene.load()?;
    let mut outputs = args.outputs.clone();
    outputs.sort();
    outputs.dedup();
    let names: Vec<&str> = loaded.objects.iter().map(|(o, _)| o.as_str()).collect();
    let stems = file_stems(&names);
    let paths: Vec<(String, Output, PathBuf)> = loaded
        .objects
        .iter()
        .zip(&stems)
        .flat_map(|((object, _), object_stem)| {
            outputs.iter().flat_map(move |&output| {
                let stem = format!("{object_stem}_{}", output.name());
                let mut files =
                    vec![(object.clone(), output, args.out.join(format!("{stem}.exr")))];
                if output.is_colour() {
                    files.push((object.clone(), output, args.out.join(format!("{stem}.png"))));
                }
                files
            })
        })
        .collect();
    if !args.force
        && let Some((_, _, existing)) = paths.iter().find(|(_, _, p)| p.exists())
    {
        return Err(Failure::Output(format!(
            "{}: exists (use --force to replace it)",
            existing.display()
        )));
    }
    let quiet = args.json;
    let method_settings = MethodSettings {
        octree_epsilon: args.octree_epsilon,
        samples: args.samples,
        gaussians: args.gaussians,
        seed: args.scene.seed,
        ..MethodSettings::default()
    };
    let precision = if args.half {
        Precision::Half
    } else {
        Precision::Float
    };
    let mut staging = Staging::new(&args.out)?;
    let mut summaries = Vec::new();
    let mut layouts = BTreeMap::new();
    for ((object, assigned), stem) in loaded.objects.iter().zip(&stems) {
        let profile = assigned.profile.as_ref();
        let kernel = Kernel::new(profile, method_settings.d_max_epsilon);
        let control = Control::new();
        let start = Instant::now();
        let prepared = watch(&format!("{object}: lighting"), &control, quiet, || {
            prepare(
                &loaded.scene,
                object,
                loaded.lighting.clone(),
                &assigned.settings,
                &control,
            )
        })
        .map_err(bake_failure)?;
        let prepare_seconds = start.elapsed().as_secs_f64();
        let control = Control::new();
        let integration = watch(&format!("{object}: scattering"), &control, quiet, || {
            prepared.integrate(profile, &kernel, args.method, &method_settings, &control)
        })
        .map_err(bake_failure)?;
        let start = Instant::now();
        let fill = margin_fill(&prepared, args.margin);
        for (_, output, path) in paths.iter().filter(|(o, _, _)| o == object) {
            let mut image = render(
                &prepared,
                &integration.exitance,
                assigned.settings.eta,
                *output,
                &fill,
            );
            let bytes = if path.extension().is_some_and(|e| e == "png") {
                let scale = args.exposure.exp2();
                for texel in &mut image.texels {
                    *texel = texel.map(|v| v * scale);
                }
                png_bytes(&image)
            } else {
                exr_bytes(&image, precision)
            }
            .map_err(|e| Failure::Output(format!("{}: {e}", path.display())))?;
            staging.stage(path, &bytes)?;
        }
        if prepared.unwrapped {
            let layout = NewLayout {
                mesh: prepared.mesh.clone(),
                source_vertex: prepared.source_vertex.clone(),
            };
            layouts.insert(object.clone(), layout);
        }
        summaries.push(json!({
            "object": object,
            "stem": stem,
            "material": assigned.material.name,
            "material_source": assigned.source,
            "model": profile.model(),
            "texels": prepared.surfels.len(),
            "unwrapped": prepared.unwrapped,
            "method": integration.choice.method.name(),
            "reason": integration.choice.reason,
            "seconds": {
                "prepare": prepare_seconds,
                "integrate": integration.seconds,
                "maps": start.elapsed().as_secs_f64(),
            },
        }));
    }
    let mut notes = Vec::new();
    let record = BakeRecord {
        args,
        loaded: &loaded,
        summaries: &summaries,
        layouts: &layouts,
    };
    let maps: Vec<PathBuf> = staging.files().map(Path::to_path_buf).collect();
    let mut assets = record.gltf_copy(&mut notes)?;
    assets.extend(record.usd_layer(&maps, &mut notes)?);
    if !args.force
        && let Some(existing) = assets.iter().find(|e| e.path.exists())
    {
        return Err(Failure::Output(format!(
            "{}: exists (use --force to replace it)",
            existing.path.display()
        )));
    }
    let start = Instant::now();
    for asset in &assets {
        staging.stage(&asset.path, &asset.bytes)?;
    }
    let files: Vec<String> = staging.files().map(|p| p.display().to_string()).collect();
    staging.commit()?;
    let write_seconds = start.elapsed().as_secs_f64();
    let left_out: Vec<String> = loaded
        .scene
        .objects
        .iter()
        .filter(|o| !loaded.objects.iter().any(|(name, _)| *name == o.mesh.name))
        .map(|o| format!("object `{}`: not selected", o.mesh.name))
        .chain(notes)
        .collect();
    let scene_notes = &loaded.scene.notes;
    if args.json {
        let summary = json!({
            "scene": args.scene.input.display().to_string(),
            "resolution": args.scene.resolution,
            "objects": summaries,
            "files": files,
            "write_seconds": write_seconds,
            "left_out": left_out,
            "notes": scene_notes,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&summary).unwrap_or_default()
        );
    } else {
        for s in &summaries {
            println!(
                "{}: material `{}` ({}); {} texels, {} ({}); lit in {:.2} s, scattered in {:.2} s, maps in {:.2} s",
                s["object"].as_str().unwrap_or_default(),
                s["material"].as_str().unwrap_or_default(),
                s["material_source"].as_str().unwrap_or_default(),
                s["texels"],
                s["method"].as_str().unwrap_or_default(),
                s["reason"].as_str().unwrap_or_default(),
                s["seconds"]["prepare"].as_f64().unwrap_or_default(),
                s["seconds"]["integrate"].as_f64().unwrap_or_default(),
                s["seconds"]["maps"].as_f64().unwrap_or_default(),
            );
        }
        for note in scene_notes {
            println!("note: {note}");
        }
        for reason in &left_out {
            println!("left out {reason}");
        }
        println!(
            "wrote {} files to {} in {write_seconds:.2} s",
            files.len(),
            args.out.display()
        );
    }
    Ok(())
}

/// Refuses an output folder that is the input's own: a bake never writes
/// beside the asset it reads.
fn refuse_input_folder(input: &Path, out: &Path) -> Result<(), Failure> {
    let folder = input
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let same = match (folder.canonicalize(), out.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same {
        return Err(Failure::Input(format!(
            "--out {}: is the folder of the input {}; write the bake to another folder",
            out.display(),
            input.display()
        )));
    }
    Ok(())
}
