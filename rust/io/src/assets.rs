//! The assets a bake writes beside its maps: for a glTF input a copy, for
//! a USD input a layer over it, each showing every baked object's
//! `diffuse` map. Objects that were unwrapped take their new UVs along: a
//! new mesh on their glTF node, a `primvars:sssbake_st` on their USD mesh.

use crate::gltf_writer::{Baked, Geometry, gltf_copy};
use crate::usd_writer::{UsdBaked, usd_layer};
use glam::{Mat3, Vec3};
use serde_json::json;
use sssbake::bake::ObjectSummary;
use sssbake::pipeline::Layout;
use sssbake::{Error, Output, SceneObject, Summary};
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
}

/// A file to write: its final path and its bytes.
pub type AssetFile = (PathBuf, Vec<u8>);

/// The assets for `record`'s input kind (none for other kinds); `notes`
/// gains what could not be shown and why.
pub fn asset_files(record: &AssetRecord, notes: &mut Vec<String>) -> Result<Vec<AssetFile>, Error> {
    let extension = record
        .input
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let kind = match extension.as_str() {
        "gltf" | "glb" => "the glTF copy",
        "usd" | "usda" | "usdc" | "usdz" => "the USD layer",
        _ => return Ok(Vec::new()),
    };
    if !record.summary.outputs.contains(&Output::Diffuse) {
        notes.push(format!(
            "{kind}: it shows the diffuse map, which was not asked for"
        ));
        return Ok(Vec::new());
    }
    let input_error = |e: String| Error::input(e).in_file(record.input.display().to_string());
    if kind == "the glTF copy" {
        let files = gltf_copy(record.input, &gltf_objects(record)).map_err(input_error)?;
        Ok(files
            .into_iter()
            .map(|(path, bytes)| (record.out.join(path), bytes))
            .collect())
    } else {
        let baked = usd_objects(record, notes);
        let settings = json!({
            "resolution": record.summary.resolution.to_string(),
            "version": env!("CARGO_PKG_VERSION"),
        });
        let bytes = usd_layer(record.input, record.out, &baked, settings).map_err(input_error)?;
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

fn gltf_objects(record: &AssetRecord) -> Vec<Baked> {
    baked_objects(record)
        .filter_map(|(object, summary)| {
            Some(Baked {
                node: object.node?,
                object: summary.plan.name.clone(),
                image: format!("{}_diffuse.png", summary.plan.file_stem),
                uv_set: record.uv_set,
                geometry: new_layout(summary).map(|l| node_geometry(object, l)),
            })
        })
        .collect()
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
            diffuse: format!("{stem}diffuse.png"),
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
