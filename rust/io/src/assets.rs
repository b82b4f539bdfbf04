//! The assets a bake writes beside its maps: for a glTF input a copy, for
//! a USD input a layer over it, each showing every baked object's look
//! (`crate::look`) as emission. Objects that were unwrapped take their new
//! UVs along: a new mesh on their glTF node, a `primvars:sssbake_st` on
//! their USD mesh.

use crate::folder::map_file_name;
use crate::gltf_writer::{Baked, Geometry, gltf_copy};
use crate::look::{Emissive, LOOK, emissive_png_name};
use crate::usd_reader::uv_primvars;
use crate::usd_writer::{LayerWriter, UsdBaked, usd_layer};
use glam::{Mat3, Vec3};
use serde_json::json;
use sssbake::bake::ObjectSummary;
use sssbake::layout::Layout;
use sssbake::{Error, SceneObject, Summary};
use std::path::{Path, PathBuf};

/// What the asset writers need to know about a finished bake.
pub struct AssetRecord<'a> {
    /// The input scene file.
    pub input: &'a Path,
    /// The folder the maps go to.
    pub out: &'a Path,
    /// The texture-coordinate set the objects were read with.
    pub uv_set: usize,
    /// The scene's objects.
    pub objects: &'a [SceneObject],
    /// The bake's summary.
    pub summary: &'a Summary,
    /// Every map written, by final path.
    pub maps: &'a [PathBuf],
    /// The look's emissive encoding per object name (for a glTF input).
    pub emissive: &'a [(String, Emissive)],
    /// Writes the USD layer in the caller's usd-core [a Python process].
    pub layer_writer: Option<&'a LayerWriter>,
}

/// A file to write: its final path and its bytes.
pub type AssetFile = (PathBuf, Vec<u8>);

/// The asset an input gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AssetKind {
    /// A copy of the glTF (.gltf or .glb).
    Gltf,
    /// A layer over the USD stage.
    Usd,
}

impl AssetKind {
    /// The asset for the input file `input`, by its extension; none for
    /// other kinds.
    pub fn of(input: &Path) -> Option<AssetKind> {
        let extension = input
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        match extension.as_str() {
            "gltf" | "glb" => Some(AssetKind::Gltf),
            "usd" | "usda" | "usdc" | "usdz" => Some(AssetKind::Usd),
            _ => None,
        }
    }

    fn name(self) -> &'static str {
        match self {
            AssetKind::Gltf => "the glTF copy",
            AssetKind::Usd => "the USD layer",
        }
    }
}

/// The assets for `record`'s input kind (none for other kinds); `notes`
/// gains what could not be shown and why.
pub fn asset_files(record: &AssetRecord, notes: &mut Vec<String>) -> Result<Vec<AssetFile>, Error> {
    let Some(kind) = AssetKind::of(record.input) else {
        return Ok(Vec::new());
    };
    if !record.summary.outputs.contains(&LOOK) {
        notes.push(format!(
            "{}: it shows the {LOOK} map, which was not asked for",
            kind.name()
        ));
        return Ok(Vec::new());
    }
    let input_error = |e: String| Error::input(e).in_file(record.input.display().to_string());
    match kind {
        AssetKind::Gltf => {
            let (baked, textures) = gltf_objects(record);
            let copy = gltf_copy(record.input, &baked).map_err(input_error)?;
            Ok(textures
                .into_iter()
                .chain(copy)
                .map(|(path, bytes)| (record.out.join(path), bytes))
                .collect())
        }
        AssetKind::Usd => {
            let baked = usd_objects(record, notes);
            let settings = json!({
                "resolution": record.summary.resolution.to_string(),
                "version": crate::VERSION,
            });
            let bytes = usd_layer(
                record.input,
                record.out,
                &baked,
                settings,
                &uv_primvars(record.uv_set),
                record.layer_writer,
            )
            .map_err(input_error)?;
            let stem = record
                .input
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            Ok(vec![(
                record.out.join(format!("{stem}_sssbake.usda")),
                bytes,
            )])
        }
    }
}

/// Each baked object with its scene object.
fn baked_objects<'a>(
    record: &'a AssetRecord,
) -> impl Iterator<Item = (&'a SceneObject, &'a ObjectSummary)> {
    record.summary.objects.iter().filter_map(|summary| {
        let object = record
            .objects
            .iter()
            .find(|o| o.mesh.name == summary.plan.name)?;
        Some((object, summary))
    })
}

/// The unwrapped layout of a baked object, if it was unwrapped.
fn new_layout(summary: &ObjectSummary) -> Option<&Layout> {
    Some(summary.plan.layout.as_ref()).filter(|l| l.unwrapped)
}

/// The glTF copy's baked objects and their emissive textures, by file name.
fn gltf_objects(record: &AssetRecord) -> (Vec<Baked>, Vec<AssetFile>) {
    let mut baked = Vec::new();
    let mut textures = Vec::new();
    for (object, summary) in baked_objects(record) {
        let name = &summary.plan.name;
        let (Some(node), Some((_, look))) =
            (object.node, record.emissive.iter().find(|(n, _)| n == name))
        else {
            continue;
        };
        let image = emissive_png_name(&summary.plan.file_stem);
        textures.push((PathBuf::from(&image), look.png.clone()));
        baked.push(Baked {
            node,
            object: name.clone(),
            image,
            strength: look.strength,
            uv_set: record.uv_set,
            geometry: new_layout(summary).map(|l| node_geometry(object, l)),
        });
    }
    (baked, textures)
}

fn usd_objects(record: &AssetRecord, notes: &mut Vec<String>) -> Vec<UsdBaked> {
    let mut baked = Vec::new();
    for (object, summary) in baked_objects(record) {
        let Some(prim) = &object.prim else { continue };
        let name = &summary.plan.name;
        let st = match new_layout(summary) {
            None => None,
            Some(layout) => match corner_uvs(object, layout) {
                Some(st) => Some(st),
                None => {
                    notes.push(format!(
                        "object `{name}` from the USD layer: the unwrap split a polygon \
                         between charts, which one value per face corner cannot hold"
                    ));
                    continue;
                }
            },
        };
        let stem = format!("{}_", summary.plan.file_stem);
        let plan = &summary.plan;
        baked.push(UsdBaked {
            object: name.clone(),
            prim: prim.clone(),
            emission: map_file_name(&plan.file_stem, LOOK, "exr"),
            maps: record
                .maps
                .iter()
                .filter_map(|m| m.file_name()?.to_str().map(String::from))
                .filter(|f| f.starts_with(&stem))
                .collect(),
            attributes: json!({
                "material": plan.material.name,
                "material_source": plan.material.source,
                "model": plan.material.model,
                "method": plan.integrator.as_ref().map(|i| i.method.name()),
            }),
            st,
        });
    }
    baked
}

/// The unwrapped mesh in its glTF node's frame and the file's units: the
/// inverse of the reader's node-to-world transform, with normals by the
/// transpose, winding restored for mirrored nodes, v flipped back down.
fn node_geometry(object: &SceneObject, layout: &Layout) -> Geometry {
    let to_world = object.local_to_world;
    let to_local = to_world.inverse();
    let linear = Mat3::from_mat4(to_world);
    let mirrored = linear.determinant() < 0.0;
    let mesh = &layout.mesh;
    Geometry {
        positions: mesh
            .positions
            .iter()
            .map(|&p| to_local.transform_point3(p).to_array())
            .collect(),
        normals: mesh
            .normals
            .iter()
            .map(|&n| {
                (linear.transpose() * n)
                    .try_normalize()
                    .unwrap_or(Vec3::Z)
                    .to_array()
            })
            .collect(),
        uvs: (0..mesh.positions.len())
            .map(|v| {
                layout
                    .uvs
                    .get(v)
                    .map_or([0.0, 0.0], |uv| [uv.x, 1.0 - uv.y])
            })
            .collect(),
        indices: mesh
            .triangles
            .iter()
            .flat_map(|&[a, b, c]| if mirrored { [a, c, b] } else { [a, b, c] })
            .collect(),
    }
}

/// The unwrapped UVs per face corner of a USD mesh (whose reader made one
/// vertex per corner), or `None` when a corner took two different UVs.
/// Corners of faces left out (degenerate ones) get (0, 0).
fn corner_uvs(object: &SceneObject, layout: &Layout) -> Option<Vec<[f32; 2]>> {
    let uvs = &layout.uvs;
    let mut st: Vec<Option<[f32; 2]>> = vec![None; object.mesh.positions.len()];
    for &vertex in layout.mesh.triangles.iter().flatten() {
        let corner = *layout.source_vertex.get(vertex as usize)? as usize;
        let uv = uvs.get(vertex as usize)?.to_array();
        match st.get_mut(corner)? {
            Some(seen) if (seen[0] - uv[0]).abs() + (seen[1] - uv[1]).abs() > 1e-6 => {
                return None;
            }
            slot => *slot = Some(uv),
        }
    }
    Some(st.into_iter().map(|uv| uv.unwrap_or([0.0, 0.0])).collect())
}
