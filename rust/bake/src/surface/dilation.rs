//! Filling the texels around the layout's islands from the nearest covered
//! texel, so that filtering and mip-mapping never read empty texels.

use crate::mesh::Mesh;
use crate::surface::raster::barycentric;
use crate::surface::texels::{EMPTY, TexelSurfels};
use crate::surface::topology::{NONE, neighbours, welded_vertices};
use glam::{DVec2, Vec2};
use std::collections::VecDeque;

/// The widest blur, in texels either side; wider Gaussians are truncated.
pub const MAX_REACH: u32 = 512;

/// For every empty texel within `margin` texels (8-connected steps) of a
/// covered one: (that texel, the covered texel it copies), both as
/// y·N + x, found breadth-first so each copies from a nearest covered
/// texel. `index` is [`crate::TexelSurfels::index`].
pub fn dilation_offsets(index: &[u32], resolution: u32, margin: u32) -> Vec<(u32, u32)> {
    let n = resolution as i64;
    let mut source = vec![EMPTY; index.len()];
    let mut queue = VecDeque::new();
    for (texel, &surfel) in index.iter().enumerate() {
        if surfel != EMPTY {
            source[texel] = texel as u32;
            queue.push_back((texel as u32, 0u32));
        }
    }
    let mut offsets = Vec::new();
    while let Some((texel, steps)) = queue.pop_front() {
        if steps == margin {
            continue;
        }
        let (x, y) = (texel as i64 % n, texel as i64 / n);
        for (dx, dy) in [
            (-1, 0),
            (1, 0),
            (0, -1),
            (0, 1),
            (-1, -1),
            (1, -1),
            (-1, 1),
            (1, 1),
        ] {
            let (nx, ny) = (x + dx, y + dy);
            if nx < 0 || ny < 0 || nx >= n || ny >= n {
                continue;
            }
            let neighbour = (ny * n + nx) as usize;
            if source[neighbour] == EMPTY {
                source[neighbour] = source[texel as usize];
                offsets.push((neighbour as u32, source[texel as usize]));
                queue.push_back((neighbour as u32, steps + 1));
            }
        }
    }
    offsets
}

/// Like [`dilation_offsets`], but an empty texel just outside a chart edge
/// that is a UV seam copies the texel that continues the surface there:
/// the point beyond the edge is carried across it into the triangle on the
/// other side of the seam (keeping its position along the edge and its
/// distance from it, scaled by the two sides' UV lengths of the edge), and
/// the texel under it is used when covered. Elsewhere, and at open edges,
/// the nearest covered texel is kept.
pub fn seam_aware_offsets(
    mesh: &Mesh,
    uvs: &[Vec2],
    surfels: &TexelSurfels,
    margin: u32,
) -> Vec<(u32, u32)> {
    seam_aware_dilation(mesh, uvs, surfels, margin).offsets
}

/// [`seam_aware_offsets`], with which of its empty texels lie beyond an
/// open edge of the mesh.
#[derive(Clone)]
pub struct SeamAwareDilation {
    /// (empty texel, covered texel it copies), as [`seam_aware_offsets`].
    pub offsets: Vec<(u32, u32)>,
    /// Per offset: its empty texel lies beyond an open edge, where there
    /// is no surface, so light must not be read from it.
    pub open: Vec<bool>,
    /// Beyond the image itself, by side: whether the chart that reaches
    /// the image's edge at each row (x = 0 and x = N − 1) or column (y = 0
    /// and y = N − 1) ends there at an open edge of the mesh (else the
    /// surface continues, as across a seam the layout cut at the edge).
    pub open_beyond_image: ImageSides,
}

/// One flag per row for the left and right sides of an N × N image, one
/// per column for its bottom (y = 0) and top (y = N − 1).
#[derive(Clone, Debug, Default)]
pub struct ImageSides {
    /// x = 0, by row.
    pub left: Vec<bool>,
    /// x = N − 1, by row.
    pub right: Vec<bool>,
    /// y = 0, by column.
    pub bottom: Vec<bool>,
    /// y = N − 1, by column.
    pub top: Vec<bool>,
}

/// [`seam_aware_offsets`] and which of them lie beyond open edges.
pub fn seam_aware_dilation(
    mesh: &Mesh,
    uvs: &[Vec2],
    surfels: &TexelSurfels,
    margin: u32,
) -> SeamAwareDilation {
    let edges = EdgeLookup::new(mesh, uvs, surfels);
    let (offsets, open) = dilation_offsets(&surfels.index, surfels.resolution, margin)
        .into_iter()
        .map(|(target, source)| match edges.beyond(target, source) {
            Beyond::Seam(texel) => ((target, texel), false),
            Beyond::Open => ((target, source), true),
            Beyond::Unknown => ((target, source), false),
        })
        .unzip();
    let n = surfels.resolution;
    // The point one texel beyond the image from each edge texel.
    let side = |texel: &dyn Fn(u32) -> (u32, u32), outward: DVec2| -> Vec<bool> {
        (0..n)
            .map(|i| {
                let (x, y) = texel(i);
                let index = y * n + x;
                if surfels.index[index as usize] == EMPTY {
                    return false;
                }
                let centre = DVec2::new(x as f64 + 0.5, y as f64 + 0.5) + outward;
                matches!(edges.beyond_point(centre, index), Beyond::Open)
            })
            .collect()
    };
    let open_beyond_image = ImageSides {
        left: side(&|y| (0, y), DVec2::NEG_X),
        right: side(&|y| (n - 1, y), DVec2::X),
        bottom: side(&|x| (x, 0), DVec2::NEG_Y),
        top: side(&|x| (x, n - 1), DVec2::Y),
    };
    SeamAwareDilation {
        offsets,
        open,
        open_beyond_image,
    }
}

/// What lies beyond the chart edge between an empty texel and the covered
/// texel nearest to it.
enum Beyond {
    /// The surface continues across a seam, at this covered texel.
    Seam(u32),
    /// The mesh ends there.
    Open,
    /// Neither could be told (a corner, a degenerate edge, an empty texel
    /// across the seam).
    Unknown,
}

/// The mesh's edge adjacency and UVs in texels, for [`Beyond`].
struct EdgeLookup<'a> {
    mesh: &'a Mesh,
    uvs: &'a [Vec2],
    surfels: &'a TexelSurfels,
    across: Vec<[u32; 3]>,
    weld: Vec<u32>,
}

impl<'a> EdgeLookup<'a> {
    fn new(mesh: &'a Mesh, uvs: &'a [Vec2], surfels: &'a TexelSurfels) -> Self {
        EdgeLookup {
            mesh,
            uvs,
            surfels,
            across: neighbours(mesh),
            weld: welded_vertices(mesh),
        }
    }

    fn uv(&self, t: u32, k: usize) -> DVec2 {
        let n = self.surfels.resolution as f64;
        self.uvs[self.mesh.triangles[t as usize][k] as usize].as_dvec2() * n
    }

    /// What lies beyond the edge of `source`'s triangle that the empty
    /// texel `target` is outside of.
    fn beyond(&self, target: u32, source: u32) -> Beyond {
        let n = self.surfels.resolution;
        let centre = DVec2::new((target % n) as f64 + 0.5, (target / n) as f64 + 0.5);
        self.beyond_point(centre, source)
    }

    /// What lies beyond the chart's edge between the covered texel
    /// `source` and the point `centre` (in texels, possibly outside the
    /// image): found by walking from the texel's centre towards the point,
    /// triangle by triangle while the chart continues (the edge crossed has
    /// the same UVs on both sides), to the first edge where it does not.
    fn beyond_point(&self, centre: DVec2, source: u32) -> Beyond {
        let n = self.surfels.resolution;
        let mut t = self.surfels.triangle[self.surfels.index[source as usize] as usize];
        let mut from = DVec2::new((source % n) as f64 + 0.5, (source / n) as f64 + 0.5);
        for _ in 0..32 {
            let corners = [self.uv(t, 0), self.uv(t, 1), self.uv(t, 2)];
            let (Some(w_to), Some(w_from)) =
                (barycentric(centre, &corners), barycentric(from, &corners))
            else {
                return Beyond::Unknown;
            };
            if w_to.iter().all(|&w| w >= 0.0) {
                return Beyond::Unknown;
            }
            // The edge the segment leaves through: where the first weight
            // falling below zero along it reaches zero.
            let Some((k, along)) = (0..3)
                .filter(|&k| w_to[k] < 0.0)
                .map(|k| (k, w_from[k].max(0.0) / (w_from[k].max(0.0) - w_to[k])))
                .min_by(|x, y| x.1.total_cmp(&y.1))
            else {
                return Beyond::Unknown;
            };
            let (a, b) = ((k + 1) % 3, (k + 2) % 3);
            let next = self.across[t as usize][a];
            let tri = self.mesh.triangles[t as usize];
            if next == NONE {
                // An edge whose ends weld into one point (a UV sphere's
                // pole) has nothing across it, but the surface goes on.
                return if self.weld[tri[a] as usize] == self.weld[tri[b] as usize] {
                    Beyond::Unknown
                } else {
                    Beyond::Open
                };
            }
            let next_tri = self.mesh.triangles[next as usize];
            let corner_in_next =
                |v: u32| (0..3).find(|&j| self.weld[next_tri[j] as usize] == self.weld[v as usize]);
            let (Some(na), Some(nb)) = (corner_in_next(tri[a]), corner_in_next(tri[b])) else {
                return Beyond::Unknown;
            };
            let same = |p: DVec2, q: DVec2| (p - q).length_squared() < 1e-12;
            if same(self.uv(next, na), corners[a]) && same(self.uv(next, nb), corners[b]) {
                from += (centre - from) * along;
                t = next;
                continue;
            }
            return self.carry(t, k, centre);
        }
        Beyond::Unknown
    }

    /// The covered texel on the far side of the UV seam along edge `k` of
    /// triangle `t` (opposite its corner k) that continues the surface to
    /// `centre`, which lies beyond that edge.
    fn carry(&self, t: u32, k: usize, centre: DVec2) -> Beyond {
        let (mesh, surfels) = (self.mesh, self.surfels);
        let n = surfels.resolution;
        let corners = [self.uv(t, 0), self.uv(t, 1), self.uv(t, 2)];
        let (a, b) = ((k + 1) % 3, (k + 2) % 3);
        let next = self.across[t as usize][a];
        let tri = mesh.triangles[t as usize];
        let next_tri = mesh.triangles[next as usize];
        let corner_in_next =
            |v: u32| (0..3).find(|&j| self.weld[next_tri[j] as usize] == self.weld[v as usize]);
        let (Some(na), Some(nb)) = (corner_in_next(tri[a]), corner_in_next(tri[b])) else {
            return Beyond::Unknown;
        };
        let nc = 3 - na - nb;
        let (pa, pb) = (corners[a], corners[b]);
        let (qa, qb, qc) = (self.uv(next, na), self.uv(next, nb), self.uv(next, nc));
        let (edge, next_edge) = (pb - pa, qb - qa);
        if edge.length_squared() < 1e-24 || next_edge.length_squared() < 1e-24 {
            return Beyond::Unknown;
        }
        let along = (centre - pa).dot(edge) / edge.length_squared();
        let beyond = (centre - pa).perp_dot(edge).abs() / edge.length();
        let inward = {
            let perp = next_edge.perp().normalize();
            if perp.dot(qc - qa) >= 0.0 {
                perp
            } else {
                -perp
            }
        };
        let carried =
            qa + next_edge * along + inward * beyond * (next_edge.length() / edge.length());
        if carried.x < 0.0 || carried.y < 0.0 || carried.x >= n as f64 || carried.y >= n as f64 {
            return Beyond::Unknown;
        }
        let texel = carried.y as u32 * n + carried.x as u32;
        if surfels.index[texel as usize] != EMPTY {
            Beyond::Seam(texel)
        } else {
            Beyond::Unknown
        }
    }
}
