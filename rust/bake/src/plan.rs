//! What a bake of a scene will do, and what it leaves out and why.

use crate::scene::Scene;
use crate::texels::rasterize;
use crate::topology::{TopologyReport, topology_report};
use crate::turk::point_count;
use crate::uv_analysis::analyse_uvs;
use std::time::Instant;

/// What the plan needs to know beyond the scene.
#[derive(Clone, Debug)]
pub struct PlanSettings {
    /// Objects to bake by name; all when empty.
    pub objects: Vec<String>,
    /// Texels per side of each object's maps.
    pub resolution: u32,
    /// Mean free path of the material, mm (sets the sample-point count).
    pub mean_free_path_mm: f64,
    /// Points per mean-free-path disk.
    pub point_multiplier: f64,
    /// Unwrap every object, even those whose UVs are usable.
    pub force_unwrap: bool,
    /// Texels between charts of an unwrap.
    pub padding: u32,
}

/// The plan for one object.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectPlan {
    /// Object name.
    pub name: String,
    /// Triangles with area.
    pub triangles: usize,
    /// Surface area, mm².
    pub area_mm2: f64,
    /// The surface's shape in words: parts, open edges, non-manifold edges.
    pub topology: String,
    /// The UV verdict in words.
    pub uv_verdict: String,
    /// Whether the mesh is unwrapped first.
    pub unwrap: bool,
    /// Seconds the unwrap took, when there was one.
    pub unwrap_seconds: Option<f64>,
    /// Texels the layout (after any unwrap) covers at the resolution.
    pub texels: usize,
    /// Surface area those texels stand for, mm².
    pub texel_area_mm2: f64,
    /// Sample points for the hierarchical integrator.
    pub points: usize,
    /// What the asset's material says, in words.
    pub material: String,
}

/// The plan for a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// Input file.
    pub source: String,
    /// Millimetres per scene unit.
    pub millimetres_per_unit: f64,
    /// Texels per side.
    pub resolution: u32,
    /// Objects to bake.
    pub objects: Vec<ObjectPlan>,
    /// Lights that light the bake, described.
    pub lights: Vec<String>,
    /// What is left out, each with its reason.
    pub left_out: Vec<String>,
}

/// Plans a bake of `scene`.
pub fn make_plan(scene: &Scene, settings: &PlanSettings) -> Result<Plan, String> {
    let selected = scene.select(&settings.objects)?;
    let mut left_out: Vec<String> = scene
        .objects
        .iter()
        .filter(|o| !selected.iter().any(|s| s.mesh.name == o.mesh.name))
        .map(|o| format!("object `{}`: not selected", o.mesh.name))
        .collect();
    left_out.extend(scene.notes.iter().cloned());
    let objects = selected
        .iter()
        .map(|object| {
            let mesh = &object.mesh;
            let report = analyse_uvs(mesh, None, settings.resolution);
            let shape = topology_report(mesh);
            let unwrap = settings.force_unwrap || !report.usable();
            let mut unwrap_seconds = None;
            let unwrapped;
            let layout = if unwrap {
                let start = Instant::now();
                unwrapped = crate::unwrap::unwrap(mesh, settings.resolution, settings.padding)
                    .map_err(|e| e.to_string())?;
                unwrap_seconds = Some(start.elapsed().as_secs_f64());
                &unwrapped
            } else {
                mesh
            };
            let uvs = layout.uvs.as_deref().unwrap_or_default();
            let surfels = rasterize(layout, uvs, settings.resolution);
            let (texels, texel_area_mm2) = (surfels.len(), surfels.total_area());
            let material = match &object.material {
                None => "none".to_string(),
                Some(m) if let Some(s) = &m.subsurface => {
                    format!("`{}`, subsurface from {}", m.name, s.from)
                }
                Some(m) if m.is_translucent() => format!("`{}`, translucent", m.name),
                Some(m) => format!("`{}`, opaque in the asset", m.name),
            };
            Ok(ObjectPlan {
                name: mesh.name.clone(),
                triangles: mesh.triangles.len(),
                area_mm2: mesh.area(),
                topology: describe(&shape),
                uv_verdict: report.verdict(),
                unwrap,
                unwrap_seconds,
                texels,
                texel_area_mm2,
                points: point_count(
                    mesh.area(),
                    settings.mean_free_path_mm,
                    settings.point_multiplier,
                ),
                material,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let mut lights = Vec::new();
    for light in &scene.lights {
        let power = light.intensity * light.color.iter().sum::<f32>();
        if power.is_nan() || power <= 0.0 {
            left_out.push(format!("light `{}`: gives no light", light.name));
            continue;
        }
        let kind = light.kind.name();
        lights.push(format!(
            "`{}`: {kind}, intensity {}",
            light.name, light.intensity
        ));
    }
    if lights.is_empty() {
        left_out.push("shadows and light transport: the scene has no lights (irradiance must come from an image)".into());
    }
    Ok(Plan {
        source: scene.source.clone(),
        millimetres_per_unit: scene.millimetres_per_unit,
        resolution: settings.resolution,
        objects,
        lights,
        left_out,
    })
}

/// "1 part, closed", or the parts and the edges that are open or shared by
/// more than two triangles.
fn describe(shape: &TopologyReport) -> String {
    let parts = if shape.parts == 1 {
        "1 part".to_string()
    } else {
        format!("{} parts", shape.parts)
    };
    let mut words = vec![parts];
    if shape.boundary_edges == 0 && shape.non_manifold_edges == 0 {
        words.push("closed".into());
    }
    if shape.boundary_edges > 0 {
        words.push(format!("{} open edges", shape.boundary_edges));
    }
    if shape.non_manifold_edges > 0 {
        words.push(format!(
            "{} non-manifold edges (treated as open)",
            shape.non_manifold_edges
        ));
    }
    words.join(", ")
}
