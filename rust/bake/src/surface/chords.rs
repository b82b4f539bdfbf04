//! How much body lies behind each texel, in every direction: the mean
//! length of the chords from the texel into the medium, and the slab
//! that has the same mean.
//!
//! One ray along the inward normal ([`super::opposite`]) sees a thin
//! part's thickness but not a body that is small sideways: a ball, a
//! nose's tip, the texels near a box's edge. Light entering there meets
//! the surface again sooner, and less of it is absorbed than in a slab as
//! thick as the normal's chord. Chords in many directions see it. Over
//! directions drawn by the cosine about the inward normal, a slab of
//! thickness t has chords t / cos θ; with each chord cut at `cap`, their
//! mean is E = 2t − t²/cap, so the slab with a body's mean E is
//! t = cap − √(cap·(cap − E)). A ball of radius a has chords 2a·cos θ,
//! mean 4a/3: about the slab of 2a/3.

use crate::surface::texels::{EMPTY, TexelSurfels};
use crate::walk::Enclosure;
use glam::Vec3;
use rayon::prelude::*;

/// Directions a texel's neighbourhood shares: strata of equal area of the
/// cosine-weighted hemisphere.
pub const DIRECTIONS: usize = 16;
/// Rays a texel casts: every fourth stratum, by its place in its 2 × 2
/// block of texels, so a block casts all of them.
pub const RAYS: usize = 4;

/// Per surfel, the thickness (mm) of the slab whose chords, cut at `cap`
/// mm, have the mean of the body's behind it; `cap` where every chord
/// reaches it (as thick as a half-space within the cap). The mean is over
/// the rays of the texel and its neighbours (3 × 3 texels, those on its
/// piece within three texels' length), [`DIRECTIONS`] strata in all.
pub fn equal_slabs(enclosure: &Enclosure, surfels: &TexelSurfels, cap: f32) -> Vec<f32> {
    let own: Vec<f32> = (0..surfels.len())
        .into_par_iter()
        .map(|s| mean_chord(enclosure, surfels, s, cap))
        .collect();
    (0..surfels.len())
        .into_par_iter()
        .map(|s| slab_of_mean_chord(neighbourhood_mean(surfels, &own, s), cap))
        .collect()
}

/// The thickness (mm) of the slab whose chords cut at `cap` have mean
/// `mean` ([module docs](self)); `cap` for a mean at or above it.
pub fn slab_of_mean_chord(mean: f32, cap: f32) -> f32 {
    if !(cap > 0.0 && mean.is_finite()) {
        return cap;
    }
    let mean = mean.clamp(0.0, cap);
    cap - (cap * (cap - mean)).sqrt()
}

/// The mean of `own` over surfel `s` and the covered texels around it on
/// its piece and near it on the surface.
fn neighbourhood_mean(surfels: &TexelSurfels, own: &[f32], s: usize) -> f32 {
    let n = surfels.resolution as i64;
    let texel = surfels.texel[s] as i64;
    let (x, y) = (texel % n, texel / n);
    let step = surfels.stretch[s].max_element();
    let near2 = (3.0 * step) * (3.0 * step);
    let (mut sum, mut count) = (0.0f32, 0u32);
    for dy in -1..=1 {
        for dx in -1..=1 {
            let (u, v) = (x + dx, y + dy);
            if !((0..n).contains(&u) && (0..n).contains(&v)) {
                continue;
            }
            let j = surfels.index[(v * n + u) as usize];
            if j == EMPTY {
                continue;
            }
            let j = j as usize;
            let joined = surfels.piece.get(j) == surfels.piece.get(s)
                && (surfels.position[j] - surfels.position[s]).length_squared() <= near2;
            if j == s || joined {
                sum += own[j];
                count += 1;
            }
        }
    }
    sum / count.max(1) as f32
}

/// The cosine-weighted mean of surfel `s`'s own [`RAYS`] chords into the
/// body, each cut at `cap`.
fn mean_chord(enclosure: &Enclosure, surfels: &TexelSurfels, s: usize, cap: f32) -> f32 {
    let inward = -surfels.normal[s].normalize_or_zero();
    if inward == Vec3::ZERO {
        return cap;
    }
    let (u, v) = inward.any_orthonormal_pair();
    let n = surfels.resolution.max(1);
    let texel = surfels.texel[s];
    let group = (texel % n % 2 + 2 * (texel / n % 2)) as usize;
    let mut sum = 0.0f32;
    for ray in 0..RAYS {
        // Equal areas of the unit disk, lifted to the hemisphere
        // (Malley): cosine-distributed about the inward normal.
        let stratum = group + RAYS * ray;
        let r2 = (stratum as f32 + 0.5) / DIRECTIONS as f32;
        let phi = std::f32::consts::TAU * (stratum as f32 * 0.618_034);
        let (sin_phi, cos_phi) = phi.sin_cos();
        let r = r2.sqrt();
        let direction = (u * (r * cos_phi) + v * (r * sin_phi) + inward * (1.0 - r2).sqrt())
            .normalize_or_zero();
        let chord = enclosure
            .first_hit(
                surfels.position[s],
                direction,
                cap,
                Some(surfels.triangle[s]),
            )
            .map_or(cap, |hit| hit.t.min(cap));
        sum += chord;
    }
    sum / RAYS as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slabs_mean_gives_back_its_thickness() {
        let cap = 20.0f32;
        for t in [0.5f32, 3.0, 10.0, 19.0] {
            let mean = 2.0 * t - t * t / cap;
            assert!((slab_of_mean_chord(mean, cap) - t).abs() < 1e-3 * t);
        }
        // Every chord at the cap: as thick as the cap. None at all: 0.
        assert_eq!(slab_of_mean_chord(cap, cap), cap);
        assert_eq!(slab_of_mean_chord(0.0, cap), 0.0);
        // Broken inputs stay defined.
        assert_eq!(slab_of_mean_chord(f32::NAN, cap), cap);
        assert_eq!(slab_of_mean_chord(1.0, 0.0), 0.0);
    }
}
