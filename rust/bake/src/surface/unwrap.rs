//! UV unwrapping with xatlas, for meshes whose UVs are missing or unusable.

use crate::mesh::Mesh;
use glam::Vec2;
use sssbake_xatlas::{Atlas, Options};

/// An unwrap that failed; names the object.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("object `{object}`: cannot unwrap: {reason}")]
pub struct UnwrapError {
    /// Object name.
    pub object: String,
    /// What went wrong.
    pub reason: String,
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
    let positions: Vec<f32> = mesh.positions.iter().flat_map(|p| p.to_array()).collect();
    let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    // First at xatlas's own estimate of the scale that fills the map.
    let mut texels_per_unit = None;
    for _ in 0..24 {
        let options = Options {
            resolution,
            padding,
            texels_per_unit,
        };
        let atlas = sssbake_xatlas::unwrap(&positions, &indices, &options)
            .map_err(|e| error(e.to_string()))?;
        // Vertices of faces xatlas leaves out (degenerate ones) are in no atlas.
        if atlas.atlas_count <= 1
            && atlas
                .vertices
                .iter()
                .all(|v| matches!(v.atlas_index, None | Some(0)))
        {
            let sources = atlas.vertices.iter().map(|v| v.xref).collect();
            return Ok((unwrapped_mesh(mesh, &atlas), sources));
        }
        // A scale that is no longer positive hands the estimate back to xatlas.
        texels_per_unit = Some(atlas.texels_per_unit * 0.8).filter(|&t| t > 0.0 && t.is_finite());
    }
    Err(error(format!("the charts do not fit a {resolution}² map")))
}

fn unwrapped_mesh(mesh: &Mesh, atlas: &Atlas) -> Mesh {
    let size = Vec2::new(atlas.width.max(1) as f32, atlas.height.max(1) as f32);
    Mesh {
        name: mesh.name.clone(),
        positions: atlas
            .vertices
            .iter()
            .map(|v| mesh.positions[v.xref as usize])
            .collect(),
        normals: atlas
            .vertices
            .iter()
            .map(|v| mesh.normals[v.xref as usize])
            .collect(),
        uvs: Some(
            atlas
                .vertices
                .iter()
                .map(|v| Vec2::from(v.uv) / size)
                .collect(),
        ),
        triangles: atlas
            .indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
    }
}
