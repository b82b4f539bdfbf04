//! UV unwrapping with xatlas, for meshes whose UVs are missing or unusable.

use crate::mesh::Mesh;
use glam::Vec2;
use std::ffi::c_void;
// The xatlas library the shim calls is built and linked by this crate.
use xatlas_rs as _;

unsafe extern "C" {
    fn sssbake_unwrap(
        positions: *const f32,
        vertex_count: u32,
        indices: *const u32,
        index_count: u32,
        resolution: u32,
        padding: u32,
        texels_per_unit: f32,
        status: *mut i32,
    ) -> *mut c_void;
    fn sssbake_unwrap_sizes(
        handle: *const c_void,
        width: *mut u32,
        height: *mut u32,
        atlases: *mut u32,
        texels_per_unit: *mut f32,
        vertices: *mut u32,
        indices: *mut u32,
    );
    fn sssbake_unwrap_read(
        handle: *const c_void,
        atlas_index: *mut i32,
        uv: *mut f32,
        xref: *mut u32,
        indices: *mut u32,
    );
    fn sssbake_unwrap_free(handle: *mut c_void);
}

/// An unwrap that failed; names the object.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("object `{object}`: cannot unwrap: {reason}")]
pub struct UnwrapError {
    /// Object name.
    pub object: String,
    /// What went wrong.
    pub reason: String,
}

/// One xatlas run's result, copied out of the library.
struct Atlas {
    width: u32,
    height: u32,
    atlases: u32,
    texels_per_unit: f32,
    atlas_index: Vec<i32>,
    uv: Vec<f32>,
    xref: Vec<u32>,
    indices: Vec<u32>,
}

/// Unwraps `mesh` into one chart layout filling [0, 1]² for a
/// `resolution`² map with `padding` texels between charts. Charts are cut
/// and packed deterministically; vertices on seams are split. If the charts
/// do not fit one map at xatlas's scale, the scale shrinks until they do.
/// Faces xatlas cannot chart (degenerate slivers) keep no UV area.
pub fn unwrap(mesh: &Mesh, resolution: u32, padding: u32) -> Result<Mesh, UnwrapError> {
    unwrap_with_sources(mesh, resolution, padding).map(|(unwrapped, _)| unwrapped)
}

/// [`unwrap`], with the input vertex each new vertex copies (seams split
/// a vertex into several), so writers can carry the UVs back to the asset.
pub fn unwrap_with_sources(
    mesh: &Mesh,
    resolution: u32,
    padding: u32,
) -> Result<(Mesh, Vec<u32>), UnwrapError> {
    let error = |reason: String| UnwrapError {
        object: mesh.name.clone(),
        reason,
    };
    let resolution = resolution.max(8);
    let mut scale = 0.0f32;
    for _ in 0..24 {
        let atlas = run_xatlas(mesh, resolution, padding, scale).map_err(error)?;
        // Vertices of faces xatlas leaves out (degenerate ones) have atlas −1.
        if atlas.atlases <= 1 && atlas.atlas_index.iter().all(|&a| a <= 0) {
            return Ok((unwrapped_mesh(mesh, &atlas), atlas.xref));
        }
        scale = atlas.texels_per_unit * 0.8;
    }
    Err(error(format!("the charts do not fit a {resolution}² map")))
}

fn run_xatlas(
    mesh: &Mesh,
    resolution: u32,
    padding: u32,
    texels_per_unit: f32,
) -> Result<Atlas, String> {
    let positions: Vec<f32> = mesh.positions.iter().flat_map(|p| p.to_array()).collect();
    let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let mut status = 0i32;
    // SAFETY: the arrays outlive the call, their lengths are passed with
    // them, and every index is below the vertex count (Mesh guarantees it).
    let handle = unsafe {
        sssbake_unwrap(
            positions.as_ptr(),
            mesh.positions.len() as u32,
            indices.as_ptr(),
            indices.len() as u32,
            resolution,
            padding,
            texels_per_unit,
            &mut status,
        )
    };
    if handle.is_null() {
        return Err(format!("xatlas refused the mesh (status {status})"));
    }
    let (mut width, mut height, mut atlases, mut tpu, mut vertices, mut count) =
        (0, 0, 0, 0.0, 0, 0);
    // SAFETY: `handle` is a live atlas from `sssbake_unwrap`; the output
    // buffers are sized from the counts the library reports; it is freed once.
    unsafe {
        sssbake_unwrap_sizes(
            handle,
            &mut width,
            &mut height,
            &mut atlases,
            &mut tpu,
            &mut vertices,
            &mut count,
        );
        let mut atlas = Atlas {
            width,
            height,
            atlases,
            texels_per_unit: tpu,
            atlas_index: vec![0; vertices as usize],
            uv: vec![0.0; 2 * vertices as usize],
            xref: vec![0; vertices as usize],
            indices: vec![0; count as usize],
        };
        sssbake_unwrap_read(
            handle,
            atlas.atlas_index.as_mut_ptr(),
            atlas.uv.as_mut_ptr(),
            atlas.xref.as_mut_ptr(),
            atlas.indices.as_mut_ptr(),
        );
        sssbake_unwrap_free(handle);
        if atlas
            .xref
            .iter()
            .any(|&x| x as usize >= mesh.positions.len())
            || atlas.indices.iter().any(|&i| i >= vertices)
        {
            return Err("xatlas returned indices out of range".into());
        }
        atlas.width = atlas.width.max(1);
        atlas.height = atlas.height.max(1);
        Ok(atlas)
    }
}

fn unwrapped_mesh(mesh: &Mesh, atlas: &Atlas) -> Mesh {
    let size = Vec2::new(atlas.width as f32, atlas.height as f32);
    Mesh {
        name: mesh.name.clone(),
        positions: atlas
            .xref
            .iter()
            .map(|&x| mesh.positions[x as usize])
            .collect(),
        normals: atlas
            .xref
            .iter()
            .map(|&x| mesh.normals[x as usize])
            .collect(),
        uvs: Some(
            atlas
                .uv
                .chunks_exact(2)
                .map(|uv| Vec2::new(uv[0], uv[1]) / size)
                .collect(),
        ),
        triangles: atlas
            .indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
    }
}
