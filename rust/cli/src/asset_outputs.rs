//! The assets a bake writes beside its maps: a glTF copy and a USD layer
//! that show each baked object's `diffuse` map. Objects that were unwrapped
//! take their new UVs along: a new mesh on their glTF node, a
//! `primvars:sssbake_st` on their USD mesh.

use crate::Failure;
use crate::bake_command::{BakeArgs, Encoded};
use crate::scene_options::Loaded;
use glam::{Mat3, Vec3};
use serde_json::{Value, json};
use sssbake::maps::Output;
use sssbake::{Mesh, SceneObject};
use sssbake_io::gltf_writer::{Baked, Geometry, gltf_copy};
use sssbake_io::usd_writer::{UsdBaked, usd_layer};
use std::collections::BTreeMap;

/// The layout of an object that was unwrapped, kept for the assets.
pub struct NewLayout {
    /// The unwrapped mesh (world space, mm) with its UVs.
    pub mesh: Mesh,
    /// The scene mesh's vertex each vertex copies.
    pub source_vertex: Vec<u32>,
}

/// What the asset writers read about the bake.
pub struct BakeRecord<'a> {
    /// The command's options.
    pub args: &'a BakeArgs,
    /// The scene and objects.
    pub loaded: &'a Loaded,
    /// One JSON summary per baked object (object, stem, material, …).
    pub summaries: &'a [Value],
    /// Unwrapped objects' layouts, by object name.
    pub layouts: &'a BTreeMap<String, NewLayout>,
}

impl BakeRecord<'_> {
    /// The baked objects an asset of the input's kind (`extensions`) shows,
    /// each with its summary; `None` when the input is of another kind or
    /// the diffuse map was not asked for.
    fn shown(
        &self,
        asset: &str,
        extensions: &[&str],
        notes: &mut Vec<String>,
    ) -> Option<Vec<(&SceneObject, &Value)>> {
        let input = &self.args.scene.input;
        let extension = input.extension()?.to_str()?.to_ascii_lowercase();
        if !extensions.contains(&extension.as_str()) {
            return None;
        }
        if !self.args.outputs.contains(&Output::Diffuse) {
            notes.push(format!(
                "{asset}: it shows the diffuse map, which was not asked for"
            ));
            return None;
        }
        let objects = &self.loaded.scene.objects;
        Some(
            self.summaries
                .iter()
                .filter_map(|s| {
                    let object = objects.iter().find(|o| o.mesh.name == s["object"])?;
                    Some((object, s))
                })
                .collect(),
        )
    }

    /// For a glTF input, a copy in which the baked objects show their
    /// `diffuse` map (see `sssbake_io::gltf_writer`).
    pub fn gltf_copy(&self, notes: &mut Vec<String>) -> Result<Vec<Encoded>, Failure> {
        let Some(objects) = self.shown("the glTF copy", &["gltf", "glb"], notes) else {
            return Ok(Vec::new());
        };
        let baked: Vec<Baked> = objects
            .into_iter()
            .filter_map(|(object, summary)| {
                let name = summary["object"].as_str()?;
                Some(Baked {
                    node: object.node?,
                    object: name.to_string(),
                    image: format!("{}_diffuse.png", summary["stem"].as_str()?),
                    uv_set: self.args.scene.uv_set,
                    geometry: self.layouts.get(name).map(|l| node_geometry(object, l)),
                })
            })
            .collect();
        let input = &self.args.scene.input;
        let files = gltf_copy(input, &baked)
            .map_err(|e| Failure::Input(format!("{}: {e}", input.display())))?;
        Ok(files
            .into_iter()
            .map(|(path, bytes)| Encoded {
                path: self.args.out.join(path),
                bytes,
            })
            .collect())
    }

    /// For a USD input, a layer over it that binds each baked object to a
    /// UsdPreviewSurface reading its `diffuse` map (see
    /// `sssbake_io::usd_writer`).
    pub fn usd_layer(
        &self,
        maps: &[std::path::PathBuf],
        notes: &mut Vec<String>,
    ) -> Result<Vec<Encoded>, Failure> {
        let extensions = ["usd", "usda", "usdc", "usdz"];
        let Some(objects) = self.shown("the USD layer", &extensions, notes) else {
            return Ok(Vec::new());
        };
        let mut baked = Vec::new();
        for (object, summary) in objects {
            let Some(prim) = &object.prim else { continue };
            let name = summary["object"].as_str().unwrap_or_default();
            let st = match self.layouts.get(name) {
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
            let stem = format!("{}_", summary["stem"].as_str().unwrap_or_default());
            baked.push(UsdBaked {
                object: name.to_string(),
                prim: prim.clone(),
                diffuse: format!("{stem}diffuse.png"),
                maps: maps
                    .iter()
                    .filter_map(|m| m.file_name()?.to_str().map(String::from))
                    .filter(|f| f.starts_with(&stem))
                    .collect(),
                attributes: json!({
                    "material": summary["material"],
                    "material_source": summary["material_source"],
                    "model": summary["model"],
                    "method": summary["method"],
                }),
                st,
            });
        }
        let settings = json!({
            "resolution": self.args.scene.resolution.to_string(),
            "version": env!("CARGO_PKG_VERSION"),
        });
        let input = &self.args.scene.input;
        let bytes = usd_layer(input, &self.args.out, &baked, settings)
            .map_err(|e| Failure::Input(format!("{}: {e}", input.display())))?;
        let stem = input
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        Ok(vec![Encoded {
            path: self.args.out.join(format!("{stem}_sssbake.usda")),
            bytes,
        }])
    }
}

/// The unwrapped mesh in its glTF node's frame and the file's units: the
/// inverse of the reader's node-to-world transform, with normals by the
/// transpose, winding restored for mirrored nodes, v flipped back down.
fn node_geometry(object: &SceneObject, layout: &NewLayout) -> Geometry {
    let to_world = object.local_to_world;
    let to_local = to_world.inverse();
    let linear = Mat3::from_mat4(to_world);
    let mirrored = linear.determinant() < 0.0;
    let mesh = &layout.mesh;
    let uvs = mesh.uvs.as_deref().unwrap_or_default();
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
            .map(|v| uvs.get(v).map_or([0.0, 0.0], |uv| [uv.x, 1.0 - uv.y]))
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
fn corner_uvs(object: &SceneObject, layout: &NewLayout) -> Option<Vec<[f32; 2]>> {
    let uvs = layout.mesh.uvs.as_deref()?;
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
