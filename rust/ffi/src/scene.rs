//! A scene built up by the host: meshes as flat arrays, lights, a world.

use crate::errors::{Failure, SssbakeStatus, guarded, slice, text};
use crate::handles::{self, Handles};
use crate::lights::{SssbakeLight, host_light};
use sssbake_host::{HostMesh, HostScene};
use std::ffi::c_char;
use std::ops::{Deref, DerefMut};
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
    pub(crate) host: HostScene,
}

impl Deref for SssbakeScene {
    type Target = HostScene;
    fn deref(&self) -> &HostScene {
        &self.host
    }
}

impl DerefMut for SssbakeScene {
    fn deref_mut(&mut self) -> &mut HostScene {
        &mut self.host
    }
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
        let scene = SssbakeScene {
            host: HostScene::new(millimetres_per_unit)?,
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
        // SAFETY: the caller's arrays hold the stated lengths.
        unsafe { with_host_mesh(mesh, |mesh| Ok(scene.add_mesh(mesh)?)) }
    })
}

/// Runs `then` with the library's view of the host's `mesh`: its arrays as
/// slices of the lengths it states.
///
/// # Safety
/// The mesh's arrays hold the lengths it states.
pub(crate) unsafe fn with_host_mesh<T>(
    mesh: &SssbakeMesh,
    then: impl FnOnce(&HostMesh) -> Result<T, Failure>,
) -> Result<T, Failure> {
    // SAFETY: forwarded from the caller.
    let name = unsafe { text(mesh.name, "mesh name") }?;
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
    let texture_uvs: Vec<&[f32]> = if n == 0 {
        vec![&[]; mesh.texture_uv_count]
    } else {
        extra.chunks_exact(2 * n).collect()
    };
    // SAFETY: forwarded from the caller.
    let indices = unsafe { slice(mesh.indices, mesh.index_count, &at("indices")) }?;
    if indices.len() % 3 != 0 {
        return Err(Failure::argument(at(&format!(
            "{} indices is not three per triangle",
            indices.len()
        ))));
    }
    let material_indices = if mesh.material_indices.is_null() {
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
    then(&HostMesh {
        name,
        positions,
        normals,
        uvs,
        indices,
        material_indices,
        texture_uvs: &texture_uvs,
    })
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
        Ok(scene.add_light(&host_light(light)?)?)
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
        Ok(scene.set_world([colour[0], colour[1], colour[2]], strength)?)
    })
}
