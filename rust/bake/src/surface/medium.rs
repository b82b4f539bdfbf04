//! Which pieces of a mesh one medium joins.
//!
//! Light scattered inside an object travels through its medium until it
//! meets the object's surface, any face of it, and leaves there: that is
//! the walk ([`crate::walk`]) and Cycles' Random Walk. Two closed pieces
//! with air between them never exchange light, however near. But pieces
//! that are not closed on their own often bound one medium together:
//! Suzanne's eyes are open domes plugging holes in the head, so light that
//! enters the face comes out through the eyes. Pieces that cross each
//! other, or one inside another, meet inside the medium too.
//!
//! So pieces are joined where light inside one reaches another: rays are
//! cast into the medium from a spread of each piece's triangles, and a
//! piece whose rays first meet another piece's faces often enough is one
//! medium with it. A ray from inside a closed piece meets that piece
//! again, whatever lies beyond, so closed pieces in air stay apart. The
//! test reads the winding: a piece turned inside out casts its rays into
//! the air.

use crate::irradiance::sequence::{basis, cosine_hemisphere, hammersley};
use crate::mesh::Mesh;
use crate::rays::RayScene;
use crate::surface::topology::{DisjointSets, triangle_pieces};
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::collections::HashMap;

/// Triangles of each piece rays are cast from, spread evenly over it.
const PROBED_TRIANGLES: usize = 1024;
/// Rays cast into the medium from each probed triangle.
const RAYS_PER_TRIANGLE: u32 = 4;
/// The share of a piece's rays that must meet another piece for the two
/// to be one medium: well above a ray slipping through a crack between
/// faces, well below what an opening onto another piece sends (Suzanne's
/// eyes send most of theirs into the head).
const JOINING_SHARE: f64 = 0.01;
/// Fewest rays meeting another piece that join them, however few were
/// cast.
const JOINING_RAYS: usize = 2;

/// At most how many rays [`medium_pieces`] casts for a mesh of `pieces`
/// pieces and `triangles` triangles (none for one piece): those cast into
/// the medium, and one a triangle to find those inside it.
pub fn planned_rays(pieces: usize, triangles: usize) -> f64 {
    if pieces <= 1 {
        return 0.0;
    }
    let into = triangles.min(pieces.saturating_mul(PROBED_TRIANGLES)) as f64;
    into * f64::from(RAYS_PER_TRIANGLE) + triangles as f64
}

/// The media of a mesh, by triangle.
#[derive(Clone, Debug, Default)]
pub struct Media {
    /// The medium each triangle belongs to (0, 1, … in the order of each
    /// medium's first triangle). Light scatters only between points of
    /// one medium.
    pub medium: Vec<u32>,
    /// The piece of the mesh ([`triangle_pieces`]) each triangle lies on,
    /// with [`INSIDE`] set where the triangle lies inside the medium,
    /// kept only where some medium joins several pieces (empty
    /// otherwise): light crossing from one piece of a medium to another
    /// must pass between their faces
    /// ([`crate::transport::through_medium::pieces_joined`]).
    pub piece: Vec<u32>,
}

/// Set on a triangle's piece ([`Media::piece`]) where the triangle, of a
/// piece set into the largest piece of its medium, lies inside the
/// medium: the ray along its outward normal first meets a face of the
/// mesh from within (the part of Suzanne's eye domes sunk beneath the
/// skin of the head). Medium lies on both its sides, so light reaches it
/// from either, not only from below its tangent plane. The largest piece
/// is never flagged: the few of its triangles that meet a dome from
/// behind, scattered over it, would split the octree's tree of it.
pub const INSIDE: u32 = 1 << 31;

/// The media of `mesh`: the pieces of [`triangle_pieces`], joined where
/// rays cast into one meet another (see the module's doc).
pub fn medium_pieces(mesh: &Mesh) -> Media {
    let pieces = triangle_pieces(mesh);
    let count = pieces.iter().max().map_or(0, |&last| last as usize + 1);
    if count <= 1 {
        return Media {
            medium: pieces,
            piece: Vec::new(),
        };
    }
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); count];
    for (t, &p) in pieces.iter().enumerate() {
        members[p as usize].push(t as u32);
    }
    let rays = RayScene::new(&[mesh]);
    let meetings: Vec<Vec<(u32, u32)>> = members
        .par_iter()
        .enumerate()
        .map(|(p, triangles)| meetings_from(mesh, &rays, &pieces, p as u32, triangles))
        .collect();
    let mut media = DisjointSets::new(count);
    for (p, met) in meetings.iter().enumerate() {
        for &(q, _) in met {
            media.join(p as u32, q);
        }
    }
    let medium = media.numbered(pieces.iter().copied());
    let media_count = medium.iter().max().map_or(0, |&last| last as usize + 1);
    if media_count == count {
        return Media {
            medium,
            piece: Vec::new(),
        };
    }
    // The largest piece of each medium holds the rest: only pieces set
    // into it are told inside or not.
    let mut largest: Vec<(usize, u32)> = vec![(0, u32::MAX); media_count];
    for (p, triangles) in members.iter().enumerate() {
        let m = medium[triangles[0] as usize] as usize;
        if triangles.len() > largest[m].0 {
            largest[m] = (triangles.len(), p as u32);
        }
    }
    let piece = pieces
        .par_iter()
        .enumerate()
        .map(|(t, &p)| {
            let host = largest[medium[t] as usize].1 == p;
            if !host && inside(mesh, &rays, t as u32) {
                p | INSIDE
            } else {
                p
            }
        })
        .collect();
    Media { medium, piece }
}

/// Whether triangle `t` lies inside the medium: the ray from its centroid
/// along its outward normal (by its winding) first meets a face from
/// behind, one facing the way the ray goes.
fn inside(mesh: &Mesh, rays: &RayScene, t: u32) -> bool {
    let [a, b, c] = mesh.triangles[t as usize].map(|v| mesh.positions[v as usize]);
    let Some(outward) = (b - a).cross(c - a).try_normalize() else {
        return false;
    };
    let skip = rays.scene_triangle(0, t);
    let centroid = (a + b + c) / 3.0;
    rays.closest_hit(centroid, outward, rays.epsilon(), f32::INFINITY, skip)
        .is_some_and(|hit| {
            let [a, b, c] =
                mesh.triangles[hit.triangle as usize].map(|v| mesh.positions[v as usize]);
            (b - a).cross(c - a).dot(outward) > 0.0
        })
}

/// The pieces that rays cast into the medium from piece `piece` (its
/// `triangles`) meet often enough to join it, with how many rays met each.
fn meetings_from(
    mesh: &Mesh,
    rays: &RayScene,
    pieces: &[u32],
    piece: u32,
    triangles: &[u32],
) -> Vec<(u32, u32)> {
    let stride = triangles.len().div_ceil(PROBED_TRIANGLES).max(1);
    let mut met: HashMap<u32, u32> = HashMap::new();
    let mut cast = 0usize;
    for &t in triangles.iter().step_by(stride) {
        let [a, b, c] = mesh.triangles[t as usize].map(|v| mesh.positions[v as usize]);
        let Some(inward) = (c - a).cross(b - a).try_normalize() else {
            continue;
        };
        let centroid = (a + b + c) / 3.0;
        let (u, v) = basis(inward);
        let skip = rays.scene_triangle(0, t);
        for i in 0..RAYS_PER_TRIANGLE {
            let local = cosine_hemisphere(hammersley(i, RAYS_PER_TRIANGLE, Vec2::splat(0.37)));
            let direction: Vec3 = (u * local.x + v * local.y + inward * local.z).normalize();
            cast += 1;
            let hit = rays.closest_hit(centroid, direction, rays.epsilon(), f32::INFINITY, skip);
            if let Some(hit) = hit {
                let other = pieces[hit.triangle as usize];
                if other != piece {
                    *met.entry(other).or_default() += 1;
                }
            }
        }
    }
    let needed = JOINING_RAYS.max((JOINING_SHARE * cast as f64).ceil() as usize);
    let mut joined: Vec<(u32, u32)> = met
        .into_iter()
        .filter(|&(_, n)| n as usize >= needed)
        .collect();
    joined.sort_unstable();
    joined
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_are_planned_only_for_several_pieces_and_bounded_per_piece() {
        assert_eq!(planned_rays(1, 10_000), 0.0);
        assert_eq!(planned_rays(2, 10), 50.0);
        // Each piece casts from at most PROBED_TRIANGLES of its triangles,
        // and one ray from every triangle.
        assert_eq!(planned_rays(3, 1_000_000), 3.0 * 1024.0 * 4.0 + 1e6);
        assert_eq!(
            planned_rays(usize::MAX, usize::MAX),
            usize::MAX as f64 * 5.0
        );
    }
}
