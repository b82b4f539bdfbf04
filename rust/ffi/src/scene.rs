//! A scene built up by the host: meshes as flat arrays, lights, a world.

use crate::errors::{Failure, SssbakeStatus, guarded, slice, text};
use crate::handles::{self, Handles};
use crate::lights::{SssbakeLight, light_from_host};
use glam::{Vec2, Vec3};
use sssbake::{Light, LightKind, Mesh, Scene, SceneObject};
use std::collections::HashMap;
use std::ffi::c_char;
use std::sync::{PoisonError, RwLock, RwLockReadGuard, RwLockWriteGuard, TryLockError};

/// The live scenes. A bake reads its scene under the lock, so adding to a
/// scene while it is baked is refused rather than raced.
pub(crate) static SCENES: Handles<RwLock<SssbakeScene>> = Handles::new(handles::SCENE);

/// A scene to read; a panic in an earlier call changed nothing it reads.
pub(crate) fn reading(scene: &RwLock<SssbakeScene>) -> RwLockReadGuard<'_, SssbakeScene> {
    scene.read().unwrap_or_else(PoisonError::into_inner)
}

/// The scene of `handle` to change, refused while a bake reads it.
fn changing<'a>(
    scene: &'a RwLock<SssbakeScene>,
) -> Result<RwLockWriteGuard<'a, SssbakeScene>, Failure> {
    match scene.try_write() {
        Ok(guard) => Ok(guard),
        Err(TryLockError::Poisoned(poisoned)) => Ok(poisoned.into_inner()),
        Err(TryLockError::WouldBlock) => Err(Failure::argument(
            "the scene is being baked: change it before or after the bake",
        )),
    }
}

/// A scene (opaque): built up by the host, or read from a file by
/// [`sssbake_scene_read`](crate::sssbake_scene_read).
pub struct SssbakeScene {
    pub(crate) scene: Scene,
    /// The file it was read from, kept so a bake into a folder can write
    /// the file's glTF copy or USD layer; `None` for a host's scene.
    pub(crate) file: Option<SceneFile>,
    /// Per object of a host's scene, the material index of each of its
    /// mesh's triangles (in the mesh's order); absent: all 0.
    pub(crate) face_materials: HashMap<String, Vec<u32>>,
}

/// Where a scene read from a file came from.
pub(crate) struct SceneFile {
    /// The glTF or USD file.
    pub(crate) path: std::path::PathBuf,
    /// The texture-coordinate set it was read with.
    pub(crate) uv_set: usize,
}

/// One mesh: `vertex_count` vertices with positions (x, y, z in scene
/// units, world space), optional unit normals and optional UVs (u, v with v
/// running up, as Blender's), and `index_count` indices, three per
/// triangle, counter-clockwise seen from outside; optionally each
/// triangle's material (an index into the materials given to
/// [`sssbake_bake_materials`](crate::sssbake_bake_materials)) and further
/// UV sets a base-colour image may read.
#[repr(C)]
pub struct SssbakeMesh {
    /// The object's name (UTF-8, NUL-terminated).
    pub name: *const c_char,
    /// 3 × `vertex_count` floats.
    pub positions: *const f32,
    /// 3 × `vertex_count` floats, or null to compute them.
    pub normals: *const f32,
    /// 2 × `vertex_count` floats, or null to unwrap.
    pub uvs: *const f32,
    /// Vertices.
    pub vertex_count: usize,
    /// `index_count` vertex indices.
    pub indices: *const u32,
    /// A multiple of 3.
    pub index_count: usize,
    /// `index_count` / 3 material indices, one per triangle, or null: every
    /// triangle has material 0.
    pub material_indices: *const u32,
    /// `texture_uv_count` × 2 × `vertex_count` floats: further UV sets, one
    /// after another, v running up; null when the count is 0. UV set 0 is
    /// `uvs` (the set baked into); these are sets 1 to `texture_uv_count`.
    pub texture_uvs: *const f32,
    /// UV sets in `texture_uvs`.
    pub texture_uv_count: usize,
}

impl Default for SssbakeMesh {
    /// No arrays and no name: a host fills what it has.
    fn default() -> Self {
        SssbakeMesh {
            name: std::ptr::null(),
            positions: std::ptr::null(),
            normals: std::ptr::null(),
            uvs: std::ptr::null(),
            vertex_count: 0,
            indices: std::ptr::null(),
            index_count: 0,
            material_indices: std::ptr::null(),
            texture_uvs: std::ptr::null(),
            texture_uv_count: 0,
        }
    }
}

/// Makes an empty scene whose units are `millimetres_per_unit` mm.
///
/// # Safety
/// `out` points to writable storage for a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_scene_new(
    millimetres_per_unit: f64,
    out: *mut *mut SssbakeScene,
) -> SssbakeStatus {
    guarded(|| {
        if out.is_null() {
            return Err(Failure::argument("out is null"));
        }
        if !(millimetres_per_unit.is_finite() && millimetres_per_unit > 0.0) {
            return Err(Failure::argument(format!(
                "millimetres per unit is {millimetres_per_unit}; it must be positive"
            )));
        }
        let scene = SssbakeScene {
            scene: Scene {
                source: "host scene".into(),
                millimetres_per_unit,
                ..Scene::default()
            },
            file: None,
            face_materials: HashMap::new(),
        };
        let handle = SCENES.issue(RwLock::new(scene))?;
        // SAFETY: checked non-null; the caller gives writable storage.
        unsafe { *out = handle };
        Ok(())
    })
}

/// Frees a scene (null is allowed and frees nothing). A scene freed
/// already, never handed out, or a handle of another kind is refused with
/// [`SssbakeStatus::InvalidArgument`] and frees nothing. A bake running
/// with the scene on another thread keeps it until the bake returns.
#[unsafe(no_mangle)]
pub extern "C" fn sssbake_scene_free(scene: *mut SssbakeScene) -> SssbakeStatus {
    guarded(|| SCENES.free(scene, "scene"))
}

/// Adds a mesh; identical vertices (same position, normal and UV) are
/// shared, so a host may pass one vertex per triangle corner.
///
/// # Safety
/// `mesh` points to a mesh whose arrays hold the lengths it states (a
/// `scene` that is not a live scene is refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_scene_add_mesh(
    scene: *mut SssbakeScene,
    mesh: *const SssbakeMesh,
) -> SssbakeStatus {
    guarded(|| {
        let scene = SCENES.get(scene, "scene")?;
        let mut scene = changing(&scene)?;
        // SAFETY: the caller passes a valid mesh or null.
        let Some(mesh) = (unsafe { mesh.as_ref() }) else {
            return Err(Failure::argument("mesh is null"));
        };
        if let Some(file) = &scene.file {
            // The glTF copy or USD layer a folder bake writes follows the
            // file's objects; a mesh the file lacks would have no place there.
            return Err(Failure::argument(format!(
                "the scene was read from {}; meshes are added to a host's scene",
                file.path.display()
            )));
        }
        // SAFETY: the caller's arrays hold the stated lengths.
        let (object, face_materials) =
            unsafe { object_from_host(mesh, scene.scene.millimetres_per_unit) }?;
        if scene
            .scene
            .objects
            .iter()
            .any(|o| o.mesh.name == object.mesh.name)
        {
            return Err(Failure::argument(format!(
                "object `{}`: the scene has one of that name already",
                object.mesh.name
            )));
        }
        if let Some(face_materials) = face_materials {
            scene
                .face_materials
                .insert(object.mesh.name.clone(), face_materials);
        }
        scene.scene.objects.push(object);
        Ok(())
    })
}

/// Reads the host's arrays into an object, sharing identical vertices and
/// leaving out triangles without area, with each kept triangle's material
/// index when the host gives them.
///
/// # Safety
/// The mesh's arrays hold the lengths it states.
unsafe fn object_from_host(
    mesh: &SssbakeMesh,
    scale: f64,
) -> Result<(SceneObject, Option<Vec<u32>>), Failure> {
    // SAFETY: forwarded from the caller.
    let name = unsafe { text(mesh.name, "mesh name") }?.to_string();
    let n = mesh.vertex_count;
    let at = |what: &str| format!("object `{name}`: {what}");
    // No array of 3 floats per vertex can be that long: refused before a
    // length wraps around.
    if n.checked_mul(3 * std::mem::size_of::<f32>())
        .is_none_or(|b| b > isize::MAX as usize)
    {
        return Err(Failure::argument(at(&format!(
            "vertex_count {n} is too large"
        ))));
    }
    // SAFETY: forwarded from the caller.
    let positions = unsafe { slice(mesh.positions, 3 * n, &at("positions")) }?;
    let normals = if mesh.normals.is_null() {
        None
    } else {
        // SAFETY: forwarded from the caller.
        Some(unsafe { slice(mesh.normals, 3 * n, &at("normals")) }?)
    };
    let uvs = if mesh.uvs.is_null() {
        None
    } else {
        // SAFETY: forwarded from the caller.
        Some(unsafe { slice(mesh.uvs, 2 * n, &at("uvs")) }?)
    };
    let extra_len = mesh
        .texture_uv_count
        .checked_mul(2 * n)
        .ok_or_else(|| Failure::argument(at("texture_uv_count is too large")))?;
    // SAFETY: forwarded from the caller.
    let extra = unsafe { slice(mesh.texture_uvs, extra_len, &at("texture_uvs")) }?;
    if extra.iter().any(|c| !c.is_finite()) {
        return Err(Failure::argument(at(
            "texture_uvs hold a value that is not finite",
        )));
    }
    // SAFETY: forwarded from the caller.
    let indices = unsafe { slice(mesh.indices, mesh.index_count, &at("indices")) }?;
    if indices.len() % 3 != 0 {
        return Err(Failure::argument(at(&format!(
            "{} indices is not three per triangle",
            indices.len()
        ))));
    }
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(Failure::input(at(&format!("index {bad} but {n} vertices"))));
    }
    let face_materials = if mesh.material_indices.is_null() {
        None
    } else {
        // SAFETY: forwarded from the caller.
        Some(unsafe {
            slice(
                mesh.material_indices,
                indices.len() / 3,
                &at("material_indices"),
            )
        }?)
    };
    // Share vertices equal bit for bit in every attribute.
    let mut shared: HashMap<Vec<u32>, u32> = HashMap::new();
    let mut remap = Vec::with_capacity(n);
    let (mut p, mut nr, mut uv) = (Vec::new(), Vec::new(), Vec::new());
    let mut sets: Vec<Vec<Vec2>> = vec![Vec::new(); mesh.texture_uv_count];
    for v in 0..n {
        let position = Vec3::from_slice(&positions[3 * v..3 * v + 3]);
        let normal = normals.map_or(Vec3::ZERO, |s| Vec3::from_slice(&s[3 * v..3 * v + 3]));
        let coord = uvs.map_or(Vec2::ZERO, |s| Vec2::from_slice(&s[2 * v..2 * v + 2]));
        let texture_coord = |k: usize| Vec2::from_slice(&extra[2 * (k * n + v)..][..2]);
        let mut key: Vec<u32> = [
            position.x, position.y, position.z, normal.x, normal.y, normal.z, coord.x, coord.y,
        ]
        .map(f32::to_bits)
        .to_vec();
        for k in 0..sets.len() {
            key.extend(texture_coord(k).to_array().map(f32::to_bits));
        }
        let index = *shared.entry(key).or_insert_with(|| {
            p.push(position * scale as f32);
            nr.push(normal);
            uv.push(coord);
            for (k, set) in sets.iter_mut().enumerate() {
                set.push(texture_coord(k));
            }
            (p.len() - 1) as u32
        });
        remap.push(index);
    }
    // Triangles without area are left out here (Mesh::new would drop them)
    // so that the material indices stay in step with the mesh's triangles.
    let mut kept_materials = Vec::new();
    let triangles = indices
        .chunks_exact(3)
        .enumerate()
        .map(|(f, t)| (f, [t[0], t[1], t[2]].map(|i| remap[i as usize])))
        .filter(|&(_, t)| sssbake::mesh::triangle_area(&p, t) > 0.0)
        .map(|(f, t)| {
            if let Some(m) = face_materials {
                kept_materials.push(m[f]);
            }
            t
        })
        .collect();
    let uvs = uvs.map(|_| uv);
    let (mesh, _) = Mesh::new(&name, p, normals.map(|_| nr), uvs.clone(), triangles)
        .map_err(|e| Failure::input(e.to_string()))?;
    // UV set 0 is the baked one, so texture sets keep their numbers even
    // on a mesh without it.
    let uv_sets = if sets.is_empty() {
        uvs.into_iter().collect()
    } else {
        std::iter::once(uvs.unwrap_or_default())
            .chain(sets)
            .collect()
    };
    let object = SceneObject {
        mesh,
        uv_sets,
        ..SceneObject::default()
    };
    Ok((object, face_materials.map(|_| kept_materials)))
}

/// Adds a light in the host's units (see [`SssbakeLight`]).
///
/// # Safety
/// `light` points to a light (a `scene` that is not a live scene is
/// refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_scene_add_light(
    scene: *mut SssbakeScene,
    light: *const SssbakeLight,
) -> SssbakeStatus {
    guarded(|| {
        let scene = SCENES.get(scene, "scene")?;
        let mut scene = changing(&scene)?;
        // SAFETY: the caller passes a light or null.
        let Some(light) = (unsafe { light.as_ref() }) else {
            return Err(Failure::argument("light is null"));
        };
        let converted = light_from_host(light, scene.scene.millimetres_per_unit)?;
        scene.scene.lights.push(converted);
        Ok(())
    })
}

/// Sets a uniform world: `colour` (3 floats, linear) × `strength`, a
/// radiance in W/(m²·sr) as Blender's Background shader gives it.
///
/// # Safety
/// `colour` points to 3 floats (a `scene` that is not a live scene is
/// refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_scene_set_world(
    scene: *mut SssbakeScene,
    colour: *const f32,
    strength: f32,
) -> SssbakeStatus {
    guarded(|| {
        let scene = SCENES.get(scene, "scene")?;
        let mut scene = changing(&scene)?;
        // SAFETY: the caller passes 3 floats.
        let colour = unsafe { slice(colour, 3, "world colour") }?;
        if !(strength.is_finite() && strength >= 0.0)
            || colour.iter().any(|c| !c.is_finite() || *c < 0.0)
        {
            return Err(Failure::argument(format!(
                "world colour {colour:?} × strength {strength}: both must be finite and non-negative"
            )));
        }
        scene
            .scene
            .lights
            .retain(|l| !matches!(l.kind, LightKind::Environment { .. }));
        if strength > 0.0 && colour.iter().any(|&c| c > 0.0) {
            scene.scene.lights.push(Light {
                name: "World".into(),
                kind: LightKind::Environment { texture: None },
                color: [colour[0], colour[1], colour[2]],
                intensity: strength,
                position: Vec3::ZERO,
                direction: Vec3::NEG_Z,
                tangent: Vec3::X,
                casts_shadow: true,
            });
        }
        Ok(())
    })
}
