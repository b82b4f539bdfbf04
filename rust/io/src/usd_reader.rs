//! USD (.usda, .usdc, .usdz) through usd-core: no maintained Rust reader
//! builds with this toolchain, so `usd/read_stage.py` (embedded here) runs
//! in a Python with usd-core, chosen by $SSSBAKE_PYTHON (default
//! `python3`), and hands meshes and lights over as JSON. Units come from
//! the stage's metersPerUnit.

use crate::colour_texture::{self, ColourSpace};
use crate::usd_lights::{Writer, usd_light};
use crate::usd_material::{ShaderJson, TextureJson, material_hint};
use crate::{InputError, ReadOptions};
use glam::{Vec2, Vec3};
use serde::Deserialize;
use serde_json::Value;
use serde_path_to_error::Segment;
use sssbake::colour::{ColourTexture, UvTransform, Wrap};
use sssbake::{Mesh, Scene, SceneObject};
use std::path::Path;

/// `usd/read_stage.py`: run as a script by [`read_usd`], or loaded as a
/// module by a host that holds the stage in memory (the Python package),
/// whose `stage_json` output [`scene_from_json`] reads.
pub const READ_STAGE: &str = include_str!("../../../usd/read_stage.py");

/// What `usd/read_stage.py` prints: the reader's JSON contract. Keys the
/// script prints for people reading its output and the bake does not use
/// (`up_axis`, a mesh's `faces` and `subsets`) are ignored, as is any key
/// a newer script adds.
#[derive(Deserialize)]
struct StageJson {
    /// The stage's metersPerUnit; absent, `null` or not positive, USD's
    /// default of 0.01.
    meters_per_unit: Option<f64>,
    /// Every visible UsdGeomMesh.
    #[serde(default)]
    meshes: Vec<MeshJson>,
    /// Every visible UsdLux light.
    #[serde(default)]
    lights: Vec<LightJson>,
    /// The root layer's documentation string (Blender writes
    /// `Blender vX.Y.Z`).
    documentation: Option<String>,
}

/// One UsdGeomMesh, in world space and stage units.
#[derive(Deserialize)]
struct MeshJson {
    /// The object's name: the mesh prim's, or its parent Xform's when that
    /// holds only this mesh (as exporters such as Blender's write objects)
    /// [default: `mesh`].
    #[serde(default = "mesh_name")]
    name: String,
    /// The mesh prim's path.
    path: Option<String>,
    /// The points, transformed to world space (read wide, so a transform
    /// that overflows single precision is refused as a non-finite position
    /// of its object rather than as unreadable JSON).
    points: Vec<[f64; 3]>,
    /// For each face corner in face order, the point it uses
    /// (faceVertexIndices).
    #[serde(default)]
    corner_vertices: Vec<u32>,
    /// The faces fan-triangulated, as face-corner indices, counter-clockwise
    /// (already reversed for a mirroring transform or left-handed mesh).
    #[serde(default)]
    triangles: Vec<[u32; 3]>,
    /// The chosen st primvar per face corner; `null` when the mesh has none.
    uvs: Option<Vec<[f32; 2]>>,
    /// World-space unit normals per face corner; `null` when none are
    /// authored.
    normals: Option<Vec<[f32; 3]>>,
    /// The bound material's surface shader; `null` when nothing is bound.
    material: Option<ShaderJson>,
}

fn mesh_name() -> String {
    "mesh".into()
}

/// One UsdLux light with its world transform; sizes in stage units,
/// angles in degrees. Only the size of the light's own kind is present.
#[derive(Deserialize)]
pub(crate) struct LightJson {
    /// The prim's name [default: `light`].
    #[serde(default = "light_name")]
    pub(crate) name: String,
    /// The prim's type name (`SphereLight`, `DistantLight`, …).
    #[serde(rename = "type")]
    pub(crate) kind: Option<String>,
    /// inputs:intensity.
    pub(crate) intensity: f32,
    /// inputs:exposure, in stops.
    pub(crate) exposure: f32,
    /// inputs:color, linear [default: white].
    pub(crate) color: Option<[f32; 3]>,
    /// The light's origin in world space [default: the world origin].
    pub(crate) position: Option<[f32; 3]>,
    /// The light's −z axis in world space [default: −z].
    pub(crate) direction: Option<[f32; 3]>,
    /// The light's x axis in world space [default: x].
    pub(crate) tangent: Option<[f32; 3]>,
    /// inputs:normalize: the power does not depend on the size.
    #[serde(default)]
    pub(crate) normalize: bool,
    /// How much the world transform scales the light's x axis [default: 1].
    pub(crate) scale: Option<f32>,
    /// A SphereLight's, DiskLight's or CylinderLight's inputs:radius.
    pub(crate) radius: Option<f32>,
    /// A CylinderLight's inputs:length.
    pub(crate) length: Option<f32>,
    /// A CylinderLight's treatAsLine.
    pub(crate) treat_as_line: Option<bool>,
    /// A RectLight's inputs:width.
    pub(crate) width: Option<f32>,
    /// A RectLight's inputs:height.
    pub(crate) height: Option<f32>,
    /// A DistantLight's inputs:angle, degrees.
    pub(crate) angle: Option<f32>,
    /// A DomeLight's resolved inputs:texture:file; empty when it has none.
    pub(crate) texture: Option<String>,
    /// A DomeLight's inputs:texture:format [default: `automatic`].
    pub(crate) texture_format: Option<String>,
    /// inputs:diffuse, the light's multiplier on diffuse response
    /// [default: 1].
    pub(crate) diffuse: Option<f32>,
    /// A SphereLight's treatAsPoint.
    pub(crate) treat_as_point: Option<bool>,
    /// The ShapingAPI cone's half-angle, degrees, when one is authored.
    pub(crate) cone_angle: Option<f32>,
    /// The ShapingAPI cone's softness, in [0, 1].
    pub(crate) cone_softness: Option<f32>,
    /// inputs:colorTemperature, kelvin, when enableColorTemperature is on.
    pub(crate) color_temperature: Option<f32>,
}

fn light_name() -> String {
    "light".into()
}

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
    let uv_set = uv_primvars(options.uv_set).join(",");
    let stdout =
        crate::python::run_script(READ_STAGE, [path.as_os_str(), uv_set.as_ref()], "read it")
            .map_err(error)?;
    // Straight into the contract's structs; the output is parsed a second
    // time, as plain JSON, only to name the object an error is in.
    let mut json = serde_json::Deserializer::from_slice(&stdout);
    let stage = stage_json(&mut json, || serde_json::from_slice(&stdout).ok())
        .and_then(|stage| json.end().map(|()| stage).map_err(not_json))
        .map_err(error)?;
    scene_from_stage(stage, &file, options)
}

/// Builds the scene from the reader's JSON: the shape `usd/read_stage.py`
/// prints, spelt out field by field on this module's `StageJson`, `MeshJson`
/// and `LightJson` (and `usd_material`'s `ShaderJson`). A field of the wrong
/// type is an error naming the object or light and the field's path.
pub fn scene_from_json(
    value: &Value,
    file: &str,
    options: &ReadOptions,
) -> Result<Scene, InputError> {
    let stage = stage_json(value, || Some(value.clone())).map_err(|message| InputError {
        file: file.to_string(),
        message,
    })?;
    scene_from_stage(stage, file, options)
}

fn not_json(error: serde_json::Error) -> String {
    format!("the USD reader's output is not JSON: {error}")
}

/// The reader's output as its contract, or what does not fit it and where.
/// `value` gives the output as plain JSON, to look up names with.
fn stage_json<'de, D>(
    deserializer: D,
    value: impl FnOnce() -> Option<Value>,
) -> Result<StageJson, String>
where
    D: serde::Deserializer<'de, Error = serde_json::Error>,
{
    serde_path_to_error::deserialize(deserializer).map_err(|e| {
        if e.inner().is_syntax() || e.inner().is_eof() {
            return not_json(e.into_inner());
        }
        misfit(&e, value().as_ref())
    })
}

/// A field that does not fit the contract, said the way the rest of the
/// reader speaks: "object `Head`: points[2]: invalid length 2, …" for a
/// mesh's or light's field, the bare path for the stage's own.
fn misfit(error: &serde_path_to_error::Error<serde_json::Error>, value: Option<&Value>) -> String {
    let segments: Vec<&Segment> = error.path().iter().collect();
    let (who, rest) = match segments[..] {
        [Segment::Map { key }, Segment::Seq { index }, ref rest @ ..]
            if key == "meshes" || key == "lights" =>
        {
            let kind = if key == "meshes" { "object" } else { "light" };
            let name = value
                .and_then(|v| v[key.as_str()][*index]["name"].as_str())
                .map_or_else(|| format!("at {key}[{index}]"), |n| format!("`{n}`"));
            (Some(format!("{kind} {name}")), rest)
        }
        ref all => (None, all),
    };
    let mut field = String::new();
    for segment in rest {
        if !field.is_empty() && !matches!(segment, Segment::Seq { .. }) {
            field.push('.');
        }
        field.push_str(&segment.to_string());
    }
    // The path says where; the column in the script's one-line output adds
    // nothing a reader can use.
    let inner = error.inner();
    let mut what = inner.to_string();
    let position = format!(" at line {} column {}", inner.line(), inner.column());
    if let Some(stripped) = what.strip_suffix(&position) {
        what.truncate(stripped.len());
    }
    let parts: Vec<String> = [who, (!field.is_empty()).then_some(field)]
        .into_iter()
        .flatten()
        .chain([what])
        .collect();
    parts.join(": ")
}

/// Builds the scene from the reader's output read into its contract.
fn scene_from_stage(
    stage: StageJson,
    file: &str,
    options: &ReadOptions,
) -> Result<Scene, InputError> {
    let error = |message: String| InputError {
        file: file.to_string(),
        message,
    };
    let meters_per_unit = stage.meters_per_unit.filter(|m| *m > 0.0).unwrap_or(0.01);
    let scale = options.unit_scale.unwrap_or(meters_per_unit * 1000.0);
    let mut scene = Scene {
        source: file.to_string(),
        millimetres_per_unit: scale,
        ..Default::default()
    };
    for mesh in stage.meshes {
        let name = mesh.name;
        let points: Vec<Vec3> = mesh
            .points
            .into_iter()
            .map(|p| glam::DVec3::from(p).as_vec3())
            .collect();
        let corners = mesh.corner_vertices;
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
        let triangles = mesh.triangles;
        let uvs: Option<Vec<Vec2>> = mesh
            .uvs
            .map(|uvs| uvs.into_iter().map(Vec2::from).collect());
        let normals: Option<Vec<Vec3>> = mesh
            .normals
            .map(|normals| normals.into_iter().map(Vec3::from).collect());
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
        let mut uv_sets: Vec<Vec<Vec2>> = uvs.into_iter().collect();
        let mut colour_texture = None;
        let material = mesh
            .material
            .as_ref()
            .and_then(|m| material_hint(m, scale))
            .map(|(hint, notes, texture)| {
                scene.notes.extend(notes);
                colour_texture = texture.map(|(input, texture)| {
                    usd_colour_texture(&hint.name, input, texture, file, &mut uv_sets)
                });
                hint
            });
        scene.objects.push(SceneObject {
            mesh: mesh_out,
            uv_sets,
            colour_texture,
            material,
            node: None,
            local_to_world: glam::Mat4::IDENTITY,
            prim: mesh.path,
        });
    }
    let writer = Writer::of(stage.documentation.as_deref());
    for light in &stage.lights {
        if let Some(light) = usd_light(light, scale, writer, &mut scene.notes).map_err(error)? {
            scene.lights.push(light);
        }
    }
    scene.objects.sort_by(|a, b| a.mesh.name.cmp(&b.mesh.name));
    Ok(scene)
}

/// A UsdUVTexture driving `input` of material `material`, read: its file
/// (relative to the stage's folder when the resolver left it relative),
/// decoded by `sourceColorSpace` (`auto`: sRGB for integer images, linear
/// for float ones), with its wrap, scale and bias, the UsdTransform2d before
/// it, and its primvar (added to `uv_sets` when it is not the bake's).
fn usd_colour_texture(
    material: &str,
    input: String,
    texture: TextureJson,
    stage_file: &str,
    uv_sets: &mut Vec<Vec<Vec2>>,
) -> ColourTexture {
    let path = Path::new(stage_file)
        .parent()
        .unwrap_or(Path::new("."))
        .join(&texture.file);
    let space = match texture.source_colour_space.as_str() {
        "sRGB" => ColourSpace::Srgb,
        "raw" => ColourSpace::Raw,
        _ => ColourSpace::Auto,
    };
    let decoded = if texture.file.is_empty() {
        Err("the texture names no file".to_string())
    } else {
        colour_texture::read(&path, space)
    };
    let colour_space = match (&decoded, space) {
        (Ok((_, used)), ColourSpace::Auto) => format!("auto: {used}"),
        _ => space.name().to_string(),
    };
    let primvar = texture.primvar.clone().unwrap_or_else(|| "st".into());
    let uv_set = match (texture.uvs, texture.missing) {
        (_, true) => usize::MAX,
        (Some(uvs), false) => {
            uv_sets.push(uvs.into_iter().map(Vec2::from).collect());
            uv_sets.len() - 1
        }
        (None, false) => 0,
    };
    let wrap = |mode: &str| match mode {
        "black" => Wrap::Black,
        "clamp" => Wrap::Clamp,
        "mirror" => Wrap::Mirror,
        _ => Wrap::Repeat,
    };
    ColourTexture {
        material: material.to_string(),
        input,
        file: path.display().to_string(),
        image: decoded.map(|(image, _)| image),
        colour_space,
        uv_set,
        uv_set_name: format!("primvar `{primvar}`"),
        transform: texture.transform.map(|t| UvTransform::Usd {
            translation: Vec2::from(t.translation),
            rotation_degrees: t.rotation,
            scale: Vec2::from(t.scale),
        }),
        wrap: [wrap(&texture.wrap_s), wrap(&texture.wrap_t)],
        nearest: false,
        scale: texture.scale.unwrap_or([1.0; 3]),
        bias: texture.bias.unwrap_or([0.0; 3]),
    }
}

/// The primvars a mesh's texture coordinates are read from for the
/// texture-coordinate set `uv_set`, the first a mesh has: set 0 is `st`
/// (or the names other exporters use), set N is `stN`. The USD layer's
/// materials read the same one.
pub fn uv_primvars(uv_set: usize) -> Vec<String> {
    if uv_set == 0 {
        ["st", "UVMap", "uv", "st0"].map(String::from).to_vec()
    } else {
        vec![format!("st{uv_set}")]
    }
}
