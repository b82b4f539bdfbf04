//! USD (.usda, .usdc, .usdz) through usd-core: no maintained Rust reader
//! builds with this toolchain, so `usd/read_stage.py` (embedded here) runs
//! in a Python with usd-core, chosen by $SSSBAKE_PYTHON (default
//! `python3`), and hands meshes and lights over as JSON. Units come from
//! the stage's metersPerUnit.

use crate::{InputError, ReadOptions};
use glam::{Vec2, Vec3};
use serde_json::Value;
use sssbake::{Light, LightKind, Mesh, Scene, SceneObject};
use std::path::Path;

const READ_STAGE: &str = include_str!("../../../usd/read_stage.py");

/// Reads a USD stage.
pub fn read_usd(path: &Path, options: &ReadOptions) -> Result<Scene, InputError> {
    let file = path.display().to_string();
    let error = |message: String| InputError {
        file: file.clone(),
        message,
    };
    if !path.is_file() {
        return Err(error("cannot read: no such file".into()));
    }
    let uv_set = if options.uv_set == 0 {
        String::new()
    } else {
        format!("st{}", options.uv_set)
    };
    let stdout =
        crate::python::run_script(READ_STAGE, [path.as_os_str(), uv_set.as_ref()], "read it")
            .map_err(error)?;
    let value: Value = serde_json::from_slice(&stdout)
        .map_err(|e| error(format!("the USD reader's output is not JSON: {e}")))?;
    scene_from_json(&value, &file, options)
}

/// Builds the scene from the reader's JSON (see `usd/read_stage.py`).
pub fn scene_from_json(
    value: &Value,
    file: &str,
    options: &ReadOptions,
) -> Result<Scene, InputError> {
    let error = |message: String| InputError {
        file: file.to_string(),
        message,
    };
    let meters_per_unit = value["meters_per_unit"]
        .as_f64()
        .filter(|m| *m > 0.0)
        .unwrap_or(0.01);
    let scale = options.unit_scale.unwrap_or(meters_per_unit * 1000.0);
    let mut scene = Scene {
        source: file.to_string(),
        millimetres_per_unit: scale,
        ..Default::default()
    };
    for mesh in value["meshes"].as_array().into_iter().flatten() {
        let name = mesh["name"].as_str().unwrap_or("mesh").to_string();
        let points =
            vec3s(&mesh["points"]).map_err(|m| error(format!("object `{name}`: points {m}")))?;
        let corners: Vec<u32> = mesh["corner_vertices"]
            .as_array()
            .into_iter()
            .flatten()
            .map(|v| v.as_u64().unwrap_or(u64::MAX) as u32)
            .collect();
        if let Some(bad) = corners.iter().find(|&&c| c as usize >= points.len()) {
            return Err(error(format!(
                "object `{name}`: a face refers to point {bad}, but there are {} points",
                points.len()
            )));
        }
        // One vertex per face corner, so per-corner UVs and normals stay exact.
        let positions: Vec<Vec3> = corners
            .iter()
            .map(|&c| points[c as usize] * scale as f32)
            .collect();
        let triangles: Vec<[u32; 3]> = mesh["triangles"]
            .as_array()
            .into_iter()
            .flatten()
            .map(|t| [0, 1, 2].map(|k| t[k].as_u64().unwrap_or(u64::MAX) as u32))
            .collect();
        let uvs = mesh["uvs"].as_array().map(|a| {
            a.iter()
                .map(|uv| Vec2::new(num(&uv[0]), num(&uv[1])))
                .collect::<Vec<_>>()
        });
        let normals = match &mesh["normals"] {
            Value::Array(_) => Some(
                vec3s(&mesh["normals"])
                    .map_err(|m| error(format!("object `{name}`: normals {m}")))?,
            ),
            _ => None,
        };
        if triangles.is_empty() {
            scene
                .notes
                .push(format!("object `{name}`: has no faces and is left out"));
            continue;
        }
        let (mesh_out, warnings) = Mesh::new(&name, positions, normals, uvs.clone(), triangles)
            .map_err(|e| error(e.to_string()))?;
        if warnings.degenerate_triangles > 0 {
            scene.notes.push(format!(
                "object `{name}`: {} zero-area triangles left out",
                warnings.degenerate_triangles
            ));
        }
        if uvs.is_none() {
            scene.notes.push(format!(
                "object `{name}`: has no st primvar; it will be unwrapped"
            ));
        }
        let material =
            crate::usd_material::usd_material(&mesh["material"], scale).map(|(hint, notes)| {
                scene.notes.extend(notes);
                hint
            });
        scene.objects.push(SceneObject {
            mesh: mesh_out,
            uv_sets: uvs.into_iter().collect(),
            material,
            node: None,
            local_to_world: glam::Mat4::IDENTITY,
            prim: mesh["path"].as_str().map(String::from),
        });
    }
    for light in value["lights"].as_array().into_iter().flatten() {
        let Some((kind, normalizing_area_m2)) = usd_light_kind(light, scale) else {
            scene.notes.push(format!(
                "light `{}`: a {} is not a kind sssbake bakes; left out",
                light["name"].as_str().unwrap_or("light"),
                light["type"].as_str().unwrap_or("light of no type")
            ));
            continue;
        };
        let exposure = num(&light["exposure"]);
        let mut intensity = num(&light["intensity"]) * exposure.exp2();
        if light["normalize"].as_bool() == Some(true) && normalizing_area_m2 > 0.0 {
            intensity /= normalizing_area_m2;
        } else if let LightKind::Point { radius_mm } | LightKind::Spot { radius_mm, .. } = kind {
            // A sphere of radiance L shines π r² L watts per steradian.
            let r_m = radius_mm * 1e-3;
            intensity *= std::f32::consts::PI * r_m * r_m;
        }
        let color = light["color"]
            .as_array()
            .map_or([1.0; 3], |c| [0, 1, 2].map(|k| num(&c[k])));
        let direction = vec3(&light["direction"]).unwrap_or(Vec3::NEG_Z);
        scene.lights.push(Light {
            name: light["name"].as_str().unwrap_or("light").to_string(),
            kind,
            color,
            intensity,
            position: vec3(&light["position"]).unwrap_or(Vec3::ZERO) * scale as f32,
            direction: direction.normalize_or(Vec3::NEG_Z),
            tangent: vec3(&light["tangent"]).map_or(Vec3::X, |t| t.normalize_or(Vec3::X)),
        });
    }
    scene.objects.sort_by(|a, b| a.mesh.name.cmp(&b.mesh.name));
    Ok(scene)
}

fn num(v: &Value) -> f32 {
    v.as_f64().unwrap_or(f64::NAN) as f32
}

fn vec3(v: &Value) -> Option<Vec3> {
    let a = v.as_array().filter(|a| a.len() == 3)?;
    Some(Vec3::new(num(&a[0]), num(&a[1]), num(&a[2])))
}

fn vec3s(v: &Value) -> Result<Vec<Vec3>, String> {
    v.as_array()
        .ok_or_else(|| "are missing".to_string())?
        .iter()
        .map(|p| vec3(p).ok_or_else(|| "have an entry that is not three numbers".to_string()))
        .collect()
}

/// A UsdLux light's kind with its size in mm, and the area (m²) its
/// `normalize` divides by; `None` for kinds not baked.
fn usd_light_kind(light: &Value, scale: f64) -> Option<(LightKind, f32)> {
    // The light's own transform scales its size; absent, it is 1.
    let own = num(&light["scale"]);
    let scale = scale as f32
        * if own.is_finite() && own > 0.0 {
            own
        } else {
            1.0
        };
    let size = |key: &str| (num(&light[key]) * scale).max(0.0);
    let radius_mm = size("radius");
    let disk_m2 = std::f32::consts::PI * (radius_mm * 1e-3).powi(2);
    Some(match light["type"].as_str().unwrap_or("") {
        "DistantLight" => (
            LightKind::Directional {
                angle: num(&light["angle"]).to_radians().max(0.0),
            },
            0.0,
        ),
        "SphereLight" => (LightKind::Point { radius_mm }, 4.0 * disk_m2),
        "DiskLight" => (LightKind::Disk { radius_mm }, disk_m2),
        "RectLight" => {
            let (width_mm, height_mm) = (size("width"), size("height"));
            (
                LightKind::Rectangle {
                    width_mm,
                    height_mm,
                },
                width_mm * height_mm * 1e-6,
            )
        }
        "DomeLight" => (
            LightKind::Environment {
                texture: light["texture"]
                    .as_str()
                    .filter(|t| !t.is_empty())
                    .map(String::from),
            },
            0.0,
        ),
        _ => return None,
    })
}
