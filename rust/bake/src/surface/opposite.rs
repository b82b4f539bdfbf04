//! Where the object ends behind each texel: the face a ray along the
//! inward normal leaves the medium through, how far that is, and the texel
//! that holds it. A thin part (an ear, a shell, a leaf) is then a pair of
//! texels a small thickness apart, which the local slab
//! ([`crate::transport::local_slab`]) couples.

use crate::surface::texels::{EMPTY, TexelSurfels};
use crate::walk::Enclosure;
use glam::Vec2;
use rayon::prelude::*;

/// The face behind one texel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Opposite {
    /// Distance along the inward normal to where the medium ends, mm.
    pub thickness: f32,
    /// The surfel of the texel covering that point.
    pub surfel: u32,
}

/// For every surfel, the face behind it, when a ray along its inward
/// normal meets a face of the same medium within `reach` mm, at a point
/// some texel covers; `None` where the medium goes on beyond `reach`, the
/// ray meets nothing or another medium, or lands where no texel is (a mesh
/// open below the texel is a half-space there). Any face met ends the
/// medium, whichever way it faces, as it ends the walk and Cycles' Random
/// Walk: a face turned towards the ray is a piece set into this one (the
/// rim of Suzanne's eye domes, sunk a few millimetres into the head), and
/// the skin above it is a layer that thick, not a half-space. The reach
/// bounds each ray: a part thicker than the profile's reach is a
/// half-space to every reader, and most rays into a head would otherwise
/// cross all of it (half the time at 4096²).
pub fn opposites(
    enclosure: &Enclosure,
    surfels: &TexelSurfels,
    reach: f32,
) -> Vec<Option<Opposite>> {
    (0..surfels.len())
        .into_par_iter()
        .map(|s| opposite_of(enclosure, surfels, s, reach))
        .collect()
}

fn opposite_of(
    enclosure: &Enclosure,
    surfels: &TexelSurfels,
    s: usize,
    reach: f32,
) -> Option<Opposite> {
    let inward = -surfels.normal[s].normalize_or_zero();
    if inward == glam::Vec3::ZERO {
        return None;
    }
    let hit = enclosure.first_hit(
        surfels.position[s],
        inward,
        reach,
        Some(surfels.triangle[s]),
    )?;
    let surfel = surfel_under(surfels, enclosure.uv_at(hit.triangle, hit.uv))?;
    let same_piece = surfels
        .piece
        .get(s)
        .is_none_or(|&p| surfels.piece.get(surfel as usize) == Some(&p));
    (same_piece && hit.t.is_finite()).then_some(Opposite {
        thickness: hit.t,
        surfel,
    })
}

/// The surfel of the texel under `uv`, or of its nearest covered
/// neighbour when that texel is empty (a point on a chart's very edge).
pub(crate) fn surfel_under(surfels: &TexelSurfels, uv: Vec2) -> Option<u32> {
    let n = surfels.resolution as i64;
    if n == 0 || !uv.is_finite() {
        return None;
    }
    let (x, y) = (
        (uv.x * n as f32).floor() as i64,
        (uv.y * n as f32).floor() as i64,
    );
    let ring = [(0, 0), (1, 0), (-1, 0), (0, 1), (0, -1)];
    ring.iter()
        .map(|(dx, dy)| (x + dx, y + dy))
        .filter(|&(x, y)| (0..n).contains(&x) && (0..n).contains(&y))
        .map(|(x, y)| surfels.index[(y * n + x) as usize])
        .find(|&i| i != EMPTY)
}
