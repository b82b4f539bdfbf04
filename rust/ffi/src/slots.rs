//! An object whose faces carry several materials (Blender's material
//! slots): one bake of the whole object per material, each texel taken from
//! the bake of the material of the face it lies on.
//!
//! So a texel shows its own material's subsurface light, as if the whole
//! object were of that material: light that enters a face of another
//! material and crosses the boundary under the surface is scattered by the
//! texel's material, not by the one it entered. Faces of a material without
//! subsurface ([`SSSBAKE_MATERIAL_NONE`]) are left out: their texels stay
//! empty.

use crate::bake::{SssbakeProgress, SssbakeSettings, UserData, request_from_host, watched};
use crate::errors::{Failure, text};
use crate::material::{
    SSSBAKE_MATERIAL_NONE, SssbakeMaterial, assignment_from_host, texture_from_host,
};
use crate::scene::SssbakeScene;
use serde_json::{Value, json};
use sssbake::control::Control;
use sssbake::image::Image;
use sssbake::{BakedObject, Output};
use std::borrow::Cow;
use std::sync::atomic::AtomicI32;

/// Marks a texel no bake owns.
const NO_PART: u32 = u32::MAX;

/// The bakes of one object, one per material its faces use, and which bake
/// each texel shows.
pub(crate) struct Composite {
    /// One bake per material that scatters.
    parts: Vec<BakedObject>,
    /// Per texel (row-major, y growing with v), the index into `parts` of
    /// the bake it shows, or [`NO_PART`].
    owner: Vec<u32>,
}

impl Composite {
    /// Texels per side.
    pub(crate) fn resolution(&self) -> u32 {
        self.parts[0].prepared.surfels.resolution
    }

    /// Map `output`, rows top to bottom: each texel from its owner's bake,
    /// black where no bake owns it.
    pub(crate) fn render(&self, output: Output) -> Result<Image, sssbake::Error> {
        if let [only] = self.parts.as_slice()
            && self.owner.iter().all(|&o| o == 0)
        {
            return only.render(output);
        }
        let images = self
            .parts
            .iter()
            .map(|p| p.render(output))
            .collect::<Result<Vec<_>, _>>()?;
        let n = self.resolution() as usize;
        let mut texels = vec![[0.0f32; 3]; n * n];
        for (t, &owner) in self.owner.iter().enumerate() {
            if owner != NO_PART {
                // Texel row y runs up with v; image rows run down.
                let at = (n - 1 - t / n) * n + t % n;
                texels[at] = images[owner as usize].texels[at];
            }
        }
        Ok(Image {
            width: n,
            height: n,
            texels,
        })
    }

    /// Whether texel `t` (row-major, y growing with v) holds a value: covered
    /// or filled by a bake that owns it.
    pub(crate) fn covered(&self) -> Vec<bool> {
        let covered = self.parts[0].covered();
        covered
            .iter()
            .zip(&self.owner)
            .map(|(&c, &o)| c && o != NO_PART)
            .collect()
    }
}

/// Bakes `object` of `scene` with `materials`, each face with the material
/// its index names (all with material 0 when the mesh gives none), and
/// returns the composite and its summary as JSON.
pub(crate) fn bake_materials(
    scene: &SssbakeScene,
    object: &str,
    materials: &[SssbakeMaterial],
    settings: &SssbakeSettings,
    progress: SssbakeProgress,
    user: &UserData,
    cancel: Option<&AtomicI32>,
) -> Result<(Composite, Value), Failure> {
    let index = scene
        .scene
        .objects
        .iter()
        .position(|o| o.mesh.name == object)
        .ok_or_else(|| Failure::input(format!("no object named `{object}`")))?;
    if materials.is_empty() {
        return Err(Failure::argument(format!(
            "object `{object}`: no material was given"
        )));
    }
    let faces: Cow<[u32]> = match scene.face_materials.get(object) {
        Some(faces) if materials.len() > 1 => Cow::Borrowed(faces),
        _ => Cow::Owned(vec![0; scene.scene.objects[index].mesh.triangles.len()]),
    };
    if let Some((face, &m)) = faces
        .iter()
        .enumerate()
        .find(|&(_, &m)| m as usize >= materials.len())
    {
        return Err(Failure::argument(format!(
            "object `{object}`: triangle {face} has material {m}, but {} materials were given",
            materials.len()
        )));
    }
    let mut used: Vec<u32> = faces.to_vec();
    used.sort_unstable();
    used.dedup();
    let baked: Vec<u32> = used
        .iter()
        .copied()
        .filter(|&m| materials[m as usize].kind != SSSBAKE_MATERIAL_NONE)
        .collect();
    if baked.is_empty() {
        return Err(Failure::input(format!(
            "object `{object}`: none of its faces has a material with subsurface to bake"
        )));
    }
    let uv_set_count = scene.scene.objects[index].uv_sets.len();
    let mut parts = Vec::with_capacity(baked.len());
    let mut summaries = Vec::with_capacity(baked.len());
    for (share, &m) in baked.iter().enumerate() {
        let material = &materials[m as usize];
        let mut request = request_from_host(settings, true)?;
        request.objects = vec![object.to_string()];
        // SAFETY: the caller's material pointers are valid (sssbake_bake's contract).
        request.materials =
            unsafe { assignment_from_host(material, scene.scene.millimetres_per_unit) }?;
        // SAFETY: as above.
        let texture = unsafe { texture_from_host(material, object, uv_set_count) }?;
        let with_texture;
        let host_scene = match texture {
            Some(texture) => {
                let mut copy = scene.scene.clone();
                copy.objects[index].colour_texture = Some(texture);
                with_texture = copy;
                &with_texture
            }
            None => &scene.scene,
        };
        let control = Control::new();
        let (mut objects, summary) = watched(
            &control,
            progress,
            user,
            cancel,
            (share, baked.len()),
            || {
                let plan = sssbake::plan(host_scene, &request)?;
                sssbake::bake(host_scene, &plan, &control)
            },
        )?;
        control.check().map_err(sssbake::Error::from)?;
        let part = objects
            .pop()
            .ok_or_else(|| Failure::input(format!("no object named `{object}`")))?;
        parts.push(part);
        summaries.push(serde_json::to_value(&summary).unwrap_or_default());
    }
    let owner = texel_owners(&parts[0], &faces, &baked);
    let names = used
        .iter()
        .map(|&m| {
            let name = materials[m as usize].name;
            if name.is_null() {
                Ok(format!("material {m}"))
            } else {
                // SAFETY: the caller's strings are NUL-terminated.
                unsafe { text(name, "material name") }.map(str::to_string)
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    let summary = combined_summary(summaries, &owner, &used, &baked, &names);
    Ok((Composite { parts, owner }, summary))
}

/// Per texel, the index into the baked materials of the material of the
/// face it lies on (a filled margin texel takes its source's).
fn texel_owners(first: &BakedObject, faces: &[u32], baked: &[u32]) -> Vec<u32> {
    let surfels = &first.prepared.surfels;
    let n = surfels.resolution as usize;
    let mut owner = vec![NO_PART; n * n];
    for (&t, &triangle) in surfels.texel.iter().zip(&surfels.triangle) {
        let material = faces[triangle as usize];
        owner[t as usize] = baked
            .iter()
            .position(|&b| b == material)
            .map_or(NO_PART, |p| p as u32);
    }
    for &(to, from) in first.fill() {
        owner[to as usize] = owner[from as usize];
    }
    owner
}

/// One summary for the composite: that of the material owning the most
/// texels, with `materials` listing each material the faces use (its plan
/// and colour when baked, its texels, a note when left out).
fn combined_summary(
    mut summaries: Vec<Value>,
    owner: &[u32],
    used: &[u32],
    baked: &[u32],
    names: &[String],
) -> Value {
    if used.len() == 1 {
        return summaries.pop().unwrap_or_default();
    }
    let texels = |part: u32| owner.iter().filter(|&&o| o == part).count();
    let main = (0..baked.len() as u32)
        .max_by_key(|&p| texels(p))
        .unwrap_or(0);
    let rows: Vec<Value> = used
        .iter()
        .zip(names)
        .map(|(&m, name)| match baked.iter().position(|&b| b == m) {
            Some(p) => {
                let object = &summaries[p]["objects"][0];
                json!({
                    "index": m,
                    "name": name,
                    "material": object["material"],
                    "colour": object["colour"],
                    "accuracy": object["accuracy"],
                    "texels": texels(p as u32),
                })
            }
            None => json!({
                "index": m,
                "name": name,
                "material": null,
                "texels": 0,
                "note": "no subsurface: its faces are left out, their texels empty",
            }),
        })
        .collect();
    let left_out = used.len() - baked.len();
    let mut summary = summaries.swap_remove(main as usize);
    summary["objects"][0]["materials"] = Value::Array(rows);
    if left_out > 0
        && let Some(notes) = summary["notes"].as_array_mut()
    {
        notes.push(json!(format!(
            "{left_out} of the object's {} materials have no subsurface; their faces are left out",
            used.len()
        )));
    }
    summary
}
