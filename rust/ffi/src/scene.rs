//! A scene built up by the host: meshes as flat arrays, lights, a world.

use crate::errors::{Failure, SssbakeStatus, guarded, slice, text};
use crate::lights::{SssbakeLight, light_from_host};
use glam::{Vec2, Vec3};
use sssbake::{Light, LightKind, Mesh, Scene, SceneObject};
use std::collections::HashMap;
use std::ffi::c_char;

/// A scene (opaque): built up by the host, or read from a file by
/// [`sssbake_scene_read`](crate::sssbake_scene_read).
pub struct SssbakeScene {
    pub(crate) scene: Scene,
    /// The file it was read from, kept so a bake into a folder can write
    /// the file's glTF copy or USD layer; `None` for a host's scene.
    pub(crate) file: Option<SceneFile>,
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
/// triangle, counter-clockwise seen from outside.
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
        };
        // SAFETY: checked non-null; the caller gives writable storage.
        unsafe { *out = Box::into_raw(Box::new(scene)) };
        Ok(())
    })
}

/// Frees a scene (null is allowed).
///
/// # Safety
/// `scene` came from [`sssbake_scene_new`] or
/// [`sssbake_scene_read`](crate::sssbake_scene_read) and is not used again.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_scene_free(scene: *mut SssbakeScene) {
    if !scene.is_null() {
        // SAFETY: made by Box::into_raw when the scene was made, freed once.
        drop(unsafe { Box::from_raw(scene) });
    }
}

/// Adds a mesh; identical vertices (same position, normal and UV) are
/// shared, so a host may pass one vertex per triangle corner.
///
/// # Safety
/// `scene` is a live scene; `mesh` points to a mesh whose arrays hold the
/// lengths it states.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_scene_add_mesh(
    scene: *mut SssbakeScene,
    mesh: *const SssbakeMesh,
) -> SssbakeStatus {
    guarded(|| {
        // SAFETY: the caller passes a live scene and a valid mesh or null.
        let (scene, mesh) = unsafe { (scene.as_mut(), mesh.as_ref()) };
        let (Some(scene), Some(mesh)) = (scene, mesh) else {
            return Err(Failure::argument("scene or mesh is null"));
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
        let object = unsafe { object_from_host(mesh, scene.scene.millimetres_per_unit) }?;
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
        scene.scene.objects.push(object);
        Ok(())
    })
}

/// Reads the host's arrays into an object, sharing identical vertices.
///
/// # Safety
/// The mesh's arrays hold the lengths it states.
unsafe fn object_from_host(mesh: &SssbakeMesh, scale: f64) -> Result<SceneObject, Failure> {
    // SAFETY: forwarded from the caller.
    let name = unsafe { text(mesh.name, "mesh name") }?.to_string();
    let n = mesh.vertex_count;
    let at = |what: &str| format!("object `{name}`: {what}");
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
    // Share vertices equal bit for bit.
    let mut shared: HashMap<[u32; 8], u32> = HashMap::new();
    let mut remap = Vec::with_capacity(n);
    let (mut p, mut nr, mut uv) = (Vec::new(), Vec::new(), Vec::new());
    for v in 0..n {
        let position = Vec3::from_slice(&positions[3 * v..3 * v + 3]);
        let normal = normals.map_or(Vec3::ZERO, |s| Vec3::from_slice(&s[3 * v..3 * v + 3]));
        let coord = uvs.map_or(Vec2::ZERO, |s| Vec2::from_slice(&s[2 * v..2 * v + 2]));
        let key = [
            position.x, position.y, position.z, normal.x, normal.y, normal.z, coord.x, coord.y,
        ]
        .map(f32::to_bits);
        let index = *shared.entry(key).or_insert_with(|| {
            p.push(position * scale as f32);
            nr.push(normal);
            uv.push(coord);
            (p.len() - 1) as u32
        });
        remap.push(index);
    }
    let triangles = indices
        .chunks_exact(3)
        .map(|t| {
            [
                remap[t[0] as usize],
                remap[t[1] as usize],
                remap[t[2] as usize],
            ]
        })
        .collect();
    let uvs = uvs.map(|_| uv);
    let (mesh, _) = Mesh::new(&name, p, normals.map(|_| nr), uvs.clone(), triangles)
        .map_err(|e| Failure::input(e.to_string()))?;
    Ok(SceneObject {
        mesh,
        uv_sets: uvs.into_iter().collect(),
        ..SceneObject::default()
    })
}

/// Adds a light in the host's units (see [`SssbakeLight`]).
///
/// # Safety
/// `scene` is a live scene; `light` points to a light.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_scene_add_light(
    scene: *mut SssbakeScene,
    light: *const SssbakeLight,
) -> SssbakeStatus {
    guarded(|| {
        // SAFETY: the caller passes a live scene and a light or null.
        let (scene, light) = unsafe { (scene.as_mut(), light.as_ref()) };
        let (Some(scene), Some(light)) = (scene, light) else {
            return Err(Failure::argument("scene or light is null"));
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
/// `scene` is a live scene; `colour` points to 3 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_scene_set_world(
    scene: *mut SssbakeScene,
    colour: *const f32,
    strength: f32,
) -> SssbakeStatus {
    guarded(|| {
        // SAFETY: the caller passes a live scene or null.
        let Some(scene) = (unsafe { scene.as_mut() }) else {
            return Err(Failure::argument("scene is null"));
        };
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
