//! Light a thin part receives through its rim.
//!
//! A thin texel's sum of its slab's profile over the real surface falls
//! short of the slab's total where the part ends within the profile's
//! reach: that share is light the slab would carry past the rim
//! ([`crate::transport::slab_profiles`]). Followed the other way (the walk
//! from the texel, reciprocal to light arriving there), it reaches the
//! rim's surface: the share F_dr the boundary reflects stays in the part
//! and leaves through its faces, which the texel's gain holds; the rest
//! leaves through the rim. Light arriving at the texel along those paths
//! therefore entered through the rim, and carries the rim's irradiance,
//! not the texel's: under a sun that lights the rim as it lights the face
//! the whole shortfall comes back, under one that grazes past it none.
//!
//! Where the rim lies is found by rays from the middle of the part's
//! thickness below the texel along its tangent plane: a surface met
//! within the slab's reach that faces sideways is the rim, and each
//! direction's share is the slab's light beyond that distance. A texel
//! whose sum misses under [`LEAST_SHARE`] of its slab's light seeks none.

use crate::prepared::Prepared;
use crate::surface::frame::own_frame;
use crate::surface::lattice::on_surface_of;
use crate::surface::opposite::surfel_under;
use crate::surface::texels::{EMPTY, TexelSurfels};
use crate::walk::Enclosure;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// The least share of its slab's light a thin texel's sum may miss for
/// its rim to be sought: light through the rim below it is under a
/// hundredth of the texel's.
pub const LEAST_SHARE: f64 = 0.01;
/// Directions in a thin texel's tangent plane sought for the rim.
const DIRECTIONS: usize = 8;
/// The most a thin texel's [`RimSights`] hold, bytes: where its entries
/// begin, and an entry per direction.
pub const BYTES_PER_TEXEL: usize =
    std::mem::size_of::<u32>() + DIRECTIONS * std::mem::size_of::<Sight>();
/// A surface met counts as the rim when its normal lies within this
/// cosine of the part's tangent plane (|n_met · n| below it): more face
/// than rim above it, as where the part curls round.
const SIDEWAYS: f32 = 0.7;

/// For each of a list of thin texels, the rim's texels its light comes in
/// through, each with its weight per channel: the texel's added exitance
/// (W/m²) is Σ weight × the irradiance entering there (W/m², after the
/// colour split). Held flat: a head at 4096² has millions of thin texels.
#[derive(Clone, Debug, Default)]
pub struct RimSights {
    /// Where each texel's entries begin in `entries`, and one past the last.
    start: Vec<u32>,
    /// One per direction that met the rim, texel after texel.
    entries: Vec<Sight>,
}

/// Where one ray met the rim, and its weight per channel. The light there
/// is the bilinear mean of the 2 × 2 texels about the point met: a rim a
/// few texels across is met on a boundary between texels as often as not
/// (its middle, where a thin part's rays run), and a single texel there
/// would turn with rounding (Suzanne's eyes in the add-on's bake and in
/// its glTF's moved by a tenth).
#[derive(Clone, Copy, Debug)]
struct Sight {
    /// The texel (y·N + x) at the lowest corner of the 2 × 2.
    corner: u32,
    /// The weights of the texels at (x, y), (x + 1, y), (x, y + 1) and
    /// (x + 1, y + 1), in 65535ths; 0 where a texel is empty or not on
    /// the rim's surface.
    blend: [u16; 4],
    weight: [f32; 3],
}

/// The offsets of [`Sight::blend`]'s texels from its corner.
const BLENDED: [(u32, u32); 4] = [(0, 0), (1, 0), (0, 1), (1, 1)];

impl RimSights {
    /// The light the rim brings texel `k` of the list under `entering`
    /// (the irradiance entering each surfel, W/m², after the colour
    /// split), W/m²; nothing for a texel past the list.
    pub fn light(
        &self,
        k: usize,
        surfels: &TexelSurfels,
        entering: impl Fn(usize) -> [f32; 3],
    ) -> [f64; 3] {
        let mut light = [0.0f64; 3];
        let (Some(&from), Some(&to)) = (self.start.get(k), self.start.get(k + 1)) else {
            return light;
        };
        let n = surfels.resolution;
        for sight in &self.entries[from as usize..to as usize] {
            for (&(dx, dy), &b) in BLENDED.iter().zip(&sight.blend) {
                let texel = (sight.corner + dx + dy * n) as usize;
                let Some(&s) = surfels.index.get(texel).filter(|_| b > 0) else {
                    continue;
                };
                let e = entering(s as usize);
                let share = f64::from(b) / f64::from(u16::MAX);
                for c in 0..3 {
                    light[c] += share * f64::from(sight.weight[c]) * f64::from(e[c]);
                }
            }
        }
        light
    }
}

/// The 2 × 2 texels about `uv` that lie on the surface of surfel `met`
/// (the texel under it), with their bilinear weights by the texels'
/// centres, renormalized over those: (corner texel, weights in 65535ths).
fn blend_about(surfels: &TexelSurfels, uv: Vec2, met: u32) -> Option<(u32, [u16; 4])> {
    let n = surfels.resolution;
    let at = uv * n as f32 - Vec2::splat(0.5);
    let corner = at
        .floor()
        .clamp(Vec2::ZERO, Vec2::splat(n.saturating_sub(2) as f32));
    let along = (at - corner).clamp(Vec2::ZERO, Vec2::ONE);
    let (x, y) = (corner.x as u32, corner.y as u32);
    let mut weights = [0.0f32; 4];
    for (w, &(dx, dy)) in weights.iter_mut().zip(&BLENDED) {
        let Some(&s) = surfels.index.get(((y + dy) * n + x + dx) as usize) else {
            continue;
        };
        if s != EMPTY && on_surface_of(surfels, met as usize, s as usize) {
            let wx = if dx == 0 { 1.0 - along.x } else { along.x };
            let wy = if dy == 0 { 1.0 - along.y } else { along.y };
            *w = wx * wy;
        }
    }
    let total: f32 = weights.iter().sum();
    (total > 0.0 && total.is_finite()).then(|| {
        let blend = weights.map(|w| (w / total * f32::from(u16::MAX)).round() as u16);
        (y * n + x, blend)
    })
}

/// A thin texel as the rim sees it.
#[derive(Clone, Copy, Debug)]
pub struct RimTexel {
    /// The texel.
    pub texel: usize,
    /// The part's thickness there, mm.
    pub thickness: f32,
    /// How far its slab's light reaches, mm: the rim is sought no farther.
    pub reach: f32,
    /// Per channel, the light per unit irradiance entering through the
    /// rim: the boundary's share 1 − F_dr of the slab's total the texel's
    /// sum misses, the share that passes the rim.
    pub through_rim: [f32; 3],
}

/// For each of `texels`, where its rim lies within its reach and how much
/// of its light enters there: the rim's texels met and their weights,
/// each direction weighed by `beyond(thickness, distance)`, the share per
/// channel of the slab's light beyond that distance (mm), the weights
/// summing to the texel's `through_rim`. Empty where no rim is met (the
/// shortfall is then the part curving away, and light does not come back
/// that way).
pub fn rim_sights(
    prepared: &Prepared,
    texels: &[RimTexel],
    beyond: &(impl Fn(f32, f32) -> [f32; 3] + Sync),
) -> RimSights {
    let enclosure = Enclosure::new(&prepared.mesh, &prepared.uvs);
    let surfels = &prepared.surfels;
    let each: Vec<Vec<Sight>> = texels
        .par_iter()
        .map(|t| {
            if t.through_rim.iter().all(|&m| m <= 0.0) {
                return Vec::new();
            }
            let normal = surfels.normal[t.texel].normalize_or_zero();
            if normal == Vec3::ZERO {
                return Vec::new();
            }
            let middle = surfels.position[t.texel] - normal * (0.5 * t.thickness);
            // The surface's own frame, not the world's axes: eight rays meet
            // a rim's few texels by chance, and a frame from the world's axes
            // turned them with the file's convention.
            let (u, v) = own_frame(&prepared.mesh, surfels.triangle[t.texel], normal);
            let mut met = Vec::with_capacity(DIRECTIONS);
            for k in 0..DIRECTIONS {
                let angle = std::f32::consts::TAU * k as f32 / DIRECTIONS as f32;
                let direction = u * angle.cos() + v * angle.sin();
                let Some(hit) = enclosure.first_hit(middle, direction, t.reach, None) else {
                    continue;
                };
                let facing = enclosure.facet_normal(hit.triangle);
                // Leaving the medium through a face that looks sideways.
                if facing.dot(direction) <= 0.0 || facing.dot(normal).abs() >= SIDEWAYS {
                    continue;
                }
                let uv = enclosure.uv_at(hit.triangle, hit.uv);
                let blended = surfel_under(surfels, uv).and_then(|s| blend_about(surfels, uv, s));
                if let Some((corner, blend)) = blended {
                    met.push((corner, blend, beyond(t.thickness, hit.t)));
                }
            }
            let total: [f32; 3] = [0, 1, 2].map(|c| met.iter().map(|(_, _, w)| w[c]).sum());
            met.into_iter()
                .map(|(corner, blend, w)| {
                    let weight = [0, 1, 2].map(|c| {
                        let share = t.through_rim[c] * w[c] / total[c];
                        if share.is_finite() {
                            share.max(0.0)
                        } else {
                            0.0
                        }
                    });
                    Sight {
                        corner,
                        blend,
                        weight,
                    }
                })
                .collect()
        })
        .collect();
    let mut start = Vec::with_capacity(each.len() + 1);
    start.push(0);
    for sight in &each {
        start.push(start.last().copied().unwrap_or(0) + sight.len() as u32);
    }
    RimSights {
        start,
        entries: each.into_iter().flatten().collect(),
    }
}
