//! An object whose faces carry several materials (Blender's material
//! slots): one bake of the whole object per material, each texel taken from
//! the bake of the material of the face it lies on.
//!
//! So a texel shows its own material's subsurface light, as if the whole
//! object were of that material: light that enters a face of another
//! material and crosses the boundary under the surface is scattered by the
//! texel's material, not by the one it entered. Faces of a material without
//! subsurface ([`HostMaterialKind::NoSubsurface`]) are left out: their
//! texels stay empty.

use crate::material::{HostMaterial, HostMaterialKind};
use crate::scene::HostScene;
use serde_json::{Value, json};
use sssbake::control::Control;
use sssbake::image::Image;
use sssbake::{BakeRequest, BakedObject, Error, Output, Summary};
use std::borrow::Cow;

/// How a door runs each part of a bake: with its own progress reports and
/// cancel, part `part` of `parts` equal parts of the call.
pub trait PartRunner {
    /// The door's error, which a library error becomes.
    type Error: From<Error>;

    /// Runs `work` with a [`Control`] the door watches (reporting its
    /// fraction and cancelling it when asked); a cancel that came during
    /// the work fails the part even when the work finished.
    fn run<T: Send>(
        &mut self,
        part: (usize, usize),
        work: impl FnOnce(&Control) -> Result<T, Error> + Send,
    ) -> Result<T, Self::Error>;
}

/// Marks a texel no bake owns.
const NO_PART: u32 = u32::MAX;

/// The bakes of one object, one per material its faces use, and which bake
/// each texel shows.
pub struct Composite {
    /// One bake per material that scatters.
    parts: Vec<BakedObject>,
    /// Per texel (row-major, y growing with v), the index into `parts` of
    /// the bake it shows, or [`NO_PART`].
    owner: Vec<u32>,
}

impl Composite {
    /// Texels per side.
    pub fn resolution(&self) -> u32 {
        self.parts[0].prepared.surfels.resolution
    }

    /// Map `output`, rows top to bottom: each texel from its owner's bake,
    /// black where no bake owns it.
    pub fn render(&self, output: Output) -> Result<Image, Error> {
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

    /// Map `output` into `pixels` (4 floats a texel) as a host's image:
    /// RGBA rows from v = 0 up (Blender's and OpenGL's order), alpha 1 on
    /// covered and filled texels, 0 elsewhere. `pixels` holds 4·N² floats.
    pub fn write_rgba(&self, output: Output, pixels: &mut [f32]) -> Result<(), Error> {
        let image = self.render(output)?;
        let n = self.resolution() as usize;
        let covered = self.covered();
        // Image rows run down; texel rows (and the host's) run up with v.
        for y in 0..n {
            let row = &image.texels[(n - 1 - y) * n..(n - y) * n];
            for (x, texel) in row.iter().enumerate() {
                let at = 4 * (y * n + x);
                pixels[at..at + 3].copy_from_slice(texel);
                pixels[at + 3] = if covered[y * n + x] { 1.0 } else { 0.0 };
            }
        }
        Ok(())
    }

    /// Whether texel `t` (row-major, y growing with v) holds a value: covered
    /// or filled by a bake that owns it.
    pub fn covered(&self) -> Vec<bool> {
        let covered = self.parts[0].covered();
        covered
            .iter()
            .zip(&self.owner)
            .map(|(&c, &o)| c && o != NO_PART)
            .collect()
    }
}

/// Bakes `object` of `scene` with `materials` and the rest of `request`
/// (its objects and materials are set here), each face with the material
/// its index names (all with material 0 when the mesh gives none or one
/// material is given), and returns the composite and its summary as JSON:
/// `sssbake bake --json`'s for this object, with `materials` listing each
/// material the faces use when there are several.
pub fn bake_materials<R: PartRunner>(
    scene: &HostScene,
    object: &str,
    materials: &[HostMaterial],
    request: &BakeRequest,
    runner: &mut R,
) -> Result<(Composite, Value), R::Error> {
    let index = scene
        .scene
        .objects
        .iter()
        .position(|o| o.mesh.name == object)
        .ok_or_else(|| Error::input(format!("no object named `{object}`")))?;
    if materials.is_empty() {
        return Err(Error::field(
            "materials",
            format!("object `{object}`: no material was given"),
        )
        .into());
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
        return Err(Error::field(
            "materials",
            format!(
                "object `{object}`: triangle {face} has material {m}, but {} materials were given",
                materials.len()
            ),
        )
        .into());
    }
    let mut used: Vec<u32> = faces.to_vec();
    used.sort_unstable();
    used.dedup();
    let baked: Vec<u32> = used
        .iter()
        .copied()
        .filter(|&m| !matches!(materials[m as usize].kind, HostMaterialKind::NoSubsurface))
        .collect();
    if baked.is_empty() {
        return Err(Error::input(format!(
            "object `{object}`: none of its faces has a material with subsurface to bake"
        ))
        .into());
    }
    let uv_set_count = scene.scene.objects[index].uv_sets.len();
    let mut parts = Vec::with_capacity(baked.len());
    let mut summaries = Vec::with_capacity(baked.len());
    for (share, &m) in baked.iter().enumerate() {
        let material = &materials[m as usize];
        let mut request = request.clone();
        request.objects = vec![object.to_string()];
        request.materials = material.assignment(scene.scene.millimetres_per_unit)?;
        let texture = material.texture(object, uv_set_count)?;
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
        let (mut objects, summary): (Vec<BakedObject>, Summary) =
            runner.run((share, baked.len()), |control| {
                let plan = sssbake::plan(host_scene, &request)?;
                sssbake::bake(host_scene, &plan, control)
            })?;
        let part = objects
            .pop()
            .ok_or_else(|| Error::input(format!("no object named `{object}`")))?;
        parts.push(part);
        summaries.push(serde_json::to_value(&summary).unwrap_or_default());
    }
    let owner = texel_owners(&parts[0], &faces, &baked);
    let names: Vec<String> = used
        .iter()
        .map(|&m| {
            materials[m as usize]
                .name
                .map_or_else(|| format!("material {m}"), str::to_string)
        })
        .collect();
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
