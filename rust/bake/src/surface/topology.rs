//! Which triangle lies across each edge, with vertices welded by position so
//! that UV seams (split vertices) do not cut the surface apart; and what
//! that says about the mesh (parts, boundaries, non-manifold edges).

use crate::fast_hash::FastHash;
use crate::mesh::Mesh;
use std::collections::HashMap;

/// Marks an edge with no triangle across it (a boundary).
pub const NONE: u32 = u32::MAX;

/// The shape of a mesh's surface.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TopologyReport {
    /// Separate pieces (triangles joined through shared edges).
    pub parts: usize,
    /// Edges with one triangle.
    pub boundary_edges: usize,
    /// Edges with three or more triangles.
    pub non_manifold_edges: usize,
}

/// Each welded edge and the (triangle, edge index) pairs that use it.
fn edges(mesh: &Mesh) -> HashMap<(u32, u32), Vec<(u32, usize)>, FastHash> {
    let weld = welded_vertices(mesh);
    let mut edges: HashMap<(u32, u32), Vec<(u32, usize)>, FastHash> =
        HashMap::with_capacity_and_hasher(mesh.triangles.len() * 2, FastHash::default());
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (weld[tri[e] as usize], weld[tri[(e + 1) % 3] as usize]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push((t as u32, e));
        }
    }
    edges
}

/// For every triangle and each of its edges (corner i to corner i + 1),
/// the triangle across that edge, or [`NONE`]. Non-manifold edges (three or
/// more triangles) are treated as boundaries.
pub fn neighbours(mesh: &Mesh) -> Vec<[u32; 3]> {
    let mut across = vec![[NONE; 3]; mesh.triangles.len()];
    for sharing in edges(mesh).values() {
        if let [(t0, e0), (t1, e1)] = sharing[..] {
            across[t0 as usize][e0] = t1;
            across[t1 as usize][e1] = t0;
        }
    }
    across
}

/// Counts the mesh's parts, boundary edges and non-manifold edges.
pub fn topology_report(mesh: &Mesh) -> TopologyReport {
    let mut report = TopologyReport::default();
    for sharing in edges(mesh).values() {
        match sharing.len() {
            1 => report.boundary_edges += 1,
            2 => {}
            _ => report.non_manifold_edges += 1,
        }
    }
    report.parts = triangle_pieces(mesh)
        .iter()
        .max()
        .map_or(0, |&last| last as usize + 1);
    report
}

/// The piece each triangle belongs to (0, 1, … in the order of each
/// piece's first triangle): triangles are of one piece when a chain of
/// shared edges (welded by position, non-manifold ones included) joins
/// them. Pieces that bound one medium together, or cross, are joined into
/// one by [`crate::surface::medium::medium_pieces`], which light stays in.
pub fn triangle_pieces(mesh: &Mesh) -> Vec<u32> {
    let mut sets = DisjointSets::new(mesh.triangles.len());
    for sharing in edges(mesh).values() {
        for pair in sharing.windows(2) {
            sets.join(pair[0].0, pair[1].0);
        }
    }
    sets.numbered(0..mesh.triangles.len() as u32)
}

/// Items joined into sets (union–find with path halving).
pub(crate) struct DisjointSets {
    parent: Vec<u32>,
}

impl DisjointSets {
    /// `count` items, each alone.
    pub(crate) fn new(count: usize) -> Self {
        DisjointSets {
            parent: (0..count as u32).collect(),
        }
    }

    fn root(&mut self, mut i: u32) -> u32 {
        while self.parent[i as usize] != i {
            self.parent[i as usize] = self.parent[self.parent[i as usize] as usize];
            i = self.parent[i as usize];
        }
        i
    }

    /// Puts `a` and `b` in one set.
    pub(crate) fn join(&mut self, a: u32, b: u32) {
        let (a, b) = (self.root(a), self.root(b));
        self.parent[a as usize] = b;
    }

    /// The set of each of `items`, numbered 0, 1, … in the order each set
    /// first appears.
    pub(crate) fn numbered(&mut self, items: impl Iterator<Item = u32>) -> Vec<u32> {
        let mut number_of_root = vec![u32::MAX; self.parent.len()];
        let mut sets = 0u32;
        items
            .map(|i| {
                let r = self.root(i) as usize;
                if number_of_root[r] == u32::MAX {
                    number_of_root[r] = sets;
                    sets += 1;
                }
                number_of_root[r]
            })
            .collect()
    }
}

/// A canonical vertex per distinct position.
pub(crate) fn welded_vertices(mesh: &Mesh) -> Vec<u32> {
    let mut first: HashMap<[u32; 3], u32, FastHash> =
        HashMap::with_capacity_and_hasher(mesh.positions.len(), FastHash::default());
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
