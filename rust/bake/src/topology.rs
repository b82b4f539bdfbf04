//! Which triangle lies across each edge, with vertices welded by position so
//! that UV seams (split vertices) do not cut the surface apart.

use crate::mesh::Mesh;
use std::collections::HashMap;

/// Marks an edge with no triangle across it (a boundary).
pub const NONE: u32 = u32::MAX;

/// For every triangle and each of its edges (corner i to corner i + 1),
/// the triangle across that edge, or [`NONE`]. Non-manifold edges (three or
/// more triangles) are treated as boundaries.
pub fn neighbours(mesh: &Mesh) -> Vec<[u32; 3]> {
    let weld = welded_vertices(mesh);
    let mut edges: HashMap<(u32, u32), Vec<(u32, usize)>> = HashMap::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (weld[tri[e] as usize], weld[tri[(e + 1) % 3] as usize]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push((t as u32, e));
        }
    }
    let mut across = vec![[NONE; 3]; mesh.triangles.len()];
    for sharing in edges.values() {
        if let [(t0, e0), (t1, e1)] = sharing[..] {
            across[t0 as usize][e0] = t1;
            across[t1 as usize][e1] = t0;
        }
    }
    across
}

/// A canonical vertex per distinct position.
fn welded_vertices(mesh: &Mesh) -> Vec<u32> {
    let mut first: HashMap<[u32; 3], u32> = HashMap::new();
    mesh.positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            *first
                .entry(p.to_array().map(f32::to_bits))
                .or_insert(i as u32)
        })
        .collect()
}
