//! `sssbake plan`: what a bake of a scene would do, and what it leaves out.

use crate::Failure;
use crate::material_choice;
use serde_json::json;
use sssbake::plan::{Plan, PlanSettings, make_plan};
use sssbake::transport::MethodSettings;
use sssbake::transport::choice::{Choice, choose};
use sssbake::transport::kernel::Kernel;
use sssbake_io::{ReadOptions, read_scene};
use sssbake_profile::model::{Model, build_profile};
use std::path::PathBuf;

/// Options of `sssbake plan`.
#[derive(clap::Args)]
pub struct PlanArgs {
    /// The scene: .gltf or .glb.
    input: PathBuf,
    /// An object to bake (repeat for more) [default: every object].
    #[arg(long = "object", value_name = "NAME")]
    objects: Vec<String>,
    /// Texels per side of each map.
    #[arg(long, default_value_t = 1024)]
    resolution: u32,
    /// The texture-coordinate set to bake into.
    #[arg(long, default_value_t = 0)]
    uv_set: usize,
    /// Millimetres per scene unit, overriding the file's units.
    #[arg(long)]
    unit_scale: Option<f64>,
    /// The material (sets the sample-point count) [default: skin1].
    #[arg(long, conflicts_with = "material")]
    preset: Option<String>,
    /// A TOML material file.
    #[arg(long)]
    material: Option<PathBuf>,
    /// Unwrap every object with xatlas, even where the UVs are usable.
    #[arg(long)]
    unwrap: bool,
    /// Texels between the charts of an unwrap.
    #[arg(long, default_value_t = 4)]
    margin: u32,
    /// Sample points per disk of one mean free path.
    #[arg(long, default_value_t = 1.0)]
    points_per_disk: f64,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs the command.
pub fn run(args: &PlanArgs) -> Result<(), Failure> {
    if !(1..=16384).contains(&args.resolution) {
        return Err(Failure::Input(format!(
            "--resolution: {} must be between 1 and 16384",
            args.resolution
        )));
    }
    if let Some(s) = args.unit_scale.filter(|s| !(s.is_finite() && *s > 0.0)) {
        return Err(Failure::Input(format!(
            "--unit-scale: {s} must be a positive number of millimetres"
        )));
    }
    if !(args.points_per_disk.is_finite() && args.points_per_disk > 0.0) {
        return Err(Failure::Input(format!(
            "--points-per-disk: {} must be positive",
            args.points_per_disk
        )));
    }
    let preset = args
        .preset
        .as_deref()
        .or(args.material.is_none().then_some("skin1"));
    let material = material_choice::load(preset, args.material.as_deref())?;
    let options = ReadOptions {
        uv_set: args.uv_set,
        unit_scale: args.unit_scale,
    };
    let scene = read_scene(&args.input, &options).map_err(|e| Failure::Input(e.to_string()))?;
    let settings = PlanSettings {
        objects: args.objects.clone(),
        resolution: args.resolution,
        mean_free_path_mm: material.finest_mean_free_path_mm(),
        point_multiplier: args.points_per_disk,
        force_unwrap: args.unwrap,
        padding: args.margin,
    };
    let plan = make_plan(&scene, &settings).map_err(Failure::Input)?;
    let profile = build_profile(&material, Model::default_for(&material), 6)
        .map_err(|e| Failure::Input(e.to_string()))?;
    let kernel = Kernel::new(profile.as_ref(), MethodSettings::default().d_max_epsilon);
    let choices: Vec<Choice> = plan
        .objects
        .iter()
        .map(|o| {
            let mean_area = o.texel_area_mm2 / o.texels.max(1) as f64;
            choose(o.texels, mean_area, kernel.d_max as f64, kernel.transmits())
        })
        .collect();
    let text = if args.json {
        format!(
            "{}\n",
            serde_json::to_string_pretty(&plan_json(&plan, &material.name, &choices))
                .unwrap_or_default()
        )
    } else {
        plan_text(&plan, &material.name, settings.mean_free_path_mm, &choices)
    };
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
    Ok(())
}

fn plan_text(plan: &Plan, material: &str, mean_free_path: f64, choices: &[Choice]) -> String {
    let mut text = format!(
        "scene {}: {} mm per unit, maps of {}² texels, material {material} (ℓ = {mean_free_path:.3} mm)\n",
        plan.source, plan.millimetres_per_unit, plan.resolution
    );
    for (o, choice) in plan.objects.iter().zip(choices) {
        text += &format!(
            "object `{}`: {} triangles, {:.1} mm²\n",
            o.name, o.triangles, o.area_mm2
        );
        text += &format!("  surface: {}\n  UVs: {}\n", o.topology, o.uv_verdict);
        if let Some(seconds) = o.unwrap_seconds {
            text += &format!("  unwrap: yes, with xatlas ({seconds:.2} s)\n");
        }
        text += &format!(
            "  texels: {} covering {:.1} mm²\n",
            o.texels, o.texel_area_mm2
        );
        text += &format!(
            "  sample points: {}\n  asset material: {}\n",
            o.points, o.material
        );
        text += &format!(
            "  integrator (auto): {}: {}\n",
            choice.method, choice.reason
        );
    }
    text += &format!(
        "lights: {}\n",
        if plan.lights.is_empty() {
            "none".into()
        } else {
            plan.lights.join("; ")
        }
    );
    for reason in &plan.left_out {
        text += &format!("leaves out {reason}\n");
    }
    text
}

fn plan_json(plan: &Plan, material: &str, choices: &[Choice]) -> serde_json::Value {
    json!({
        "source": plan.source,
        "millimetres_per_unit": plan.millimetres_per_unit,
        "resolution": plan.resolution,
        "material": material,
        "objects": plan.objects.iter().zip(choices).map(|(o, choice)| json!({
            "name": o.name,
            "triangles": o.triangles,
            "area_mm2": o.area_mm2,
            "topology": o.topology,
            "uv_verdict": o.uv_verdict,
            "unwrap": o.unwrap,
            "unwrap_seconds": o.unwrap_seconds,
            "texels": o.texels,
            "texel_area_mm2": o.texel_area_mm2,
            "points": o.points,
            "asset_material": o.material,
            "integrator": choice.method.name(),
            "integrator_reason": choice.reason,
        })).collect::<Vec<_>>(),
        "lights": plan.lights,
        "left_out": plan.left_out,
    })
}
