//! A host's mesh unwrapped by the library's xatlas, the way a bake unwraps
//! an object whose UVs are unusable, with the UVs handed back per triangle
//! corner so the host keeps them as a UV map of its own.

use crate::errors::{Failure, SssbakeStatus, guarded, slice, text};
use crate::scene::SssbakeMesh;
use sssbake_host::unwrap_corners;

/// Unwraps `mesh` with xatlas into charts packed in [0, 1]² for a
/// `resolution`² map with `padding` texels between charts (a bake grows
/// each chart by its margin, so twice the margin keeps charts apart).
/// Only the positions and indices are read; vertices at one position are
/// joined, so a host may pass one vertex per triangle corner. On success
/// `uvs_out` holds the UV (u, v with v running up, as the mesh's `uvs`
/// would) of each index, 2 × `index_count` floats; a degenerate triangle
/// gets UVs with no area. `uvs_len` is the length of `uvs_out` in floats.
/// Every chart runs counter-clockwise in UV as its triangles do in 3-D
/// (xatlas may hand a chart back mirrored; it is mirrored again in place).
/// `charts_out`, unless null, gets each triangle's chart number
/// (`index_count` / 3 values): a host whose faces have more than three
/// corners sees there which triangles of a face were cut apart.
///
/// # Safety
/// `mesh` points to a mesh whose arrays hold the lengths it states;
/// `uvs_out` points to `uvs_len` writable floats; `charts_out` is null or
/// points to `index_count` / 3 writable values.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_unwrap(
    mesh: *const SssbakeMesh,
    resolution: u32,
    padding: u32,
    uvs_out: *mut f32,
    uvs_len: usize,
    charts_out: *mut u32,
) -> SssbakeStatus {
    guarded(|| {
        // SAFETY: the caller passes a valid mesh or null.
        let Some(mesh) = (unsafe { mesh.as_ref() }) else {
            return Err(Failure::argument("mesh is null"));
        };
        // SAFETY: forwarded from the caller.
        let name = unsafe { text(mesh.name, "mesh name") }?;
        let at = |what: &str| format!("object `{name}`: {what}");
        let n = mesh.vertex_count;
        // SAFETY: forwarded from the caller.
        let positions = unsafe { slice(mesh.positions, 3 * n, &at("positions")) }?;
        // SAFETY: forwarded from the caller.
        let indices = unsafe { slice(mesh.indices, mesh.index_count, &at("indices")) }?;
        if indices.is_empty() || !indices.len().is_multiple_of(3) {
            return Err(Failure::argument(at(&format!(
                "{} indices is not one or more triangles",
                indices.len()
            ))));
        }
        if uvs_len != 2 * indices.len() {
            return Err(Failure::argument(at(&format!(
                "uvs_len is {uvs_len}, but {} indices need {}",
                indices.len(),
                2 * indices.len()
            ))));
        }
        if uvs_out.is_null() {
            return Err(Failure::argument("uvs_out is null"));
        }
        let (uvs, charts) = unwrap_corners(name, positions, indices, resolution, padding)?;
        if !charts_out.is_null() {
            // SAFETY: checked non-null; the caller gives index_count / 3 values.
            let out = unsafe { std::slice::from_raw_parts_mut(charts_out, charts.len()) };
            out.copy_from_slice(&charts);
        }
        // SAFETY: checked non-null; the caller gives `uvs_len` writable floats.
        let out = unsafe { std::slice::from_raw_parts_mut(uvs_out, uvs_len) };
        out.copy_from_slice(&uvs);
        Ok(())
    })
}
