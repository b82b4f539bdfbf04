//! Filling the texels around the layout's islands from the nearest covered
//! texel, so that filtering and mip-mapping never read empty texels.

use crate::mesh::Mesh;
use crate::surface::raster::barycentric;
use crate::surface::texels::{EMPTY, TexelSurfels};
use crate::surface::topology::{NONE, neighbours, welded_vertices};
use glam::{DVec2, Vec2};
use std::collections::VecDeque;

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
    let n = surfels.resolution;
    let across = neighbours(mesh);
    let weld = welded_vertices(mesh);
    let uv = |t: u32, k: usize| uvs[mesh.triangles[t as usize][k] as usize].as_dvec2() * n as f64;
    dilation_offsets(&surfels.index, n, margin)
        .into_iter()
        .map(|(target, source)| {
            let t = surfels.triangle[surfels.index[source as usize] as usize];
            let centre = DVec2::new((target % n) as f64 + 0.5, (target / n) as f64 + 0.5);
            let corners = [uv(t, 0), uv(t, 1), uv(t, 2)];
            let Some(w) = barycentric(centre, &corners) else {
                return (target, source);
            };
            // The edge the centre lies beyond: opposite the most negative weight.
            let k = (0..3).min_by(|&a, &b| w[a].total_cmp(&w[b])).unwrap_or(0);
            let (a, b) = ((k + 1) % 3, (k + 2) % 3);
            let next = across[t as usize][a];
            if w[k] >= 0.0 || next == NONE {
                return (target, source);
            }
            let tri = mesh.triangles[t as usize];
            let next_tri = mesh.triangles[next as usize];
            let corner_in_next =
                |v: u32| (0..3).find(|&j| weld[next_tri[j] as usize] == weld[v as usize]);
            let (Some(na), Some(nb)) = (corner_in_next(tri[a]), corner_in_next(tri[b])) else {
                return (target, source);
            };
            let nc = 3 - na - nb;
            let (pa, pb) = (corners[a], corners[b]);
            let (qa, qb, qc) = (uv(next, na), uv(next, nb), uv(next, nc));
            let (edge, next_edge) = (pb - pa, qb - qa);
            if edge.length_squared() < 1e-24 || next_edge.length_squared() < 1e-24 {
                return (target, source);
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
            if carried.x < 0.0 || carried.y < 0.0 || carried.x >= n as f64 || carried.y >= n as f64
            {
                return (target, source);
            }
            let texel = carried.y as u32 * n + carried.x as u32;
            if surfels.index[texel as usize] != EMPTY {
                (target, texel)
            } else {
                (target, source)
            }
        })
        .collect()
}
