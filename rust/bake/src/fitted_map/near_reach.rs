//! N's reach at each texel: [`super::NEAR_TEXELS`] of the texels about it,
//! not of the map's mean texel.
//!
//! N must reach a few texels every way, so that F (the rest) changes over
//! the lattice's cell and not from texel to texel. Where a map's texels
//! differ in size (the head's, as √area at 1024², from 0.15 mm at the 10th
//! percentile to 0.72 mm at the 99th), a reach of mean texels spans five
//! or more of the small ones, and those are where the light is least
//! smooth and N is summed most: on the head in skin1 at 4096², 65 sources
//! a target, where two of its own texels (this module's reach) hold 21.
//! The reach follows the texels' size, smoothly: M = N + F is exact for
//! any reach, but F is carried bilinearly between lattice texels, and a
//! reach that jumped between them (from one triangle's stretch to the
//! next) would put the jump of N into F.

use super::{MOST_STEP, NEAR_TEXELS};
use crate::surface::texels::TexelSurfels;
use rayon::prelude::*;

/// The longest step N's reach is counted in, in the map's mean texel
/// sides: a sliver stretched along a layout's pole (a hundred times longer
/// one way than the other) does not make N a sum over thousands of
/// sources a target.
const MOST_MEAN_SIDES: f32 = 4.0;

/// N's reach (mm) at each surfel of `surfels`: [`NEAR_TEXELS`] times the
/// longer step of the texels about it (mm per texel along u or v), the
/// mean over a block [`MOST_STEP`] texels each way read bilinearly
/// between the blocks' centres, so it is linear across a lattice's cell;
/// the step at most [`MOST_MEAN_SIDES`] mean texels.
pub(super) fn near_radii(surfels: &TexelSurfels) -> Vec<f32> {
    let n = surfels.resolution.max(1) as usize;
    let block = MOST_STEP as usize;
    let blocks = n.div_ceil(block);
    // Each block's mean step over its covered texels (NaN where none).
    let side: Vec<f32> = (0..blocks * blocks)
        .into_par_iter()
        .map(|b| {
            let (bx, by) = (b % blocks, b / blocks);
            let (mut sum, mut count) = (0.0f64, 0u32);
            for y in by * block..((by + 1) * block).min(n) {
                for x in bx * block..((bx + 1) * block).min(n) {
                    let i = surfels.index[x + y * n];
                    if let Some(s) = surfels.stretch.get(i as usize) {
                        let longer = s.max_element();
                        if longer.is_finite() && longer > 0.0 {
                            sum += f64::from(longer);
                            count += 1;
                        }
                    }
                }
            }
            if count == 0 {
                f32::NAN
            } else {
                (sum / f64::from(count)) as f32
            }
        })
        .collect();
    let mean_side = surfels.mean_side() as f32;
    surfels
        .texel
        .par_iter()
        .map(|&t| {
            let (x, y) = ((t as usize % n) as f32, (t as usize / n) as f32);
            // Block centres at (k + ½)·block − ½ texels.
            let at = |c: f32| ((c + 0.5) / block as f32 - 0.5).max(0.0);
            let (u, v) = (at(x), at(y));
            let (bx, by) = (u as usize, v as usize);
            let (fu, fv) = (u - bx as f32, v - by as f32);
            let (mut sum, mut weight) = (0.0f32, 0.0f32);
            for (dx, dy, w) in [
                (0, 0, (1.0 - fu) * (1.0 - fv)),
                (1, 0, fu * (1.0 - fv)),
                (0, 1, (1.0 - fu) * fv),
                (1, 1, fu * fv),
            ] {
                let (cx, cy) = ((bx + dx).min(blocks - 1), (by + dy).min(blocks - 1));
                let s = side[cx + cy * blocks];
                if s.is_finite() && w > 0.0 {
                    sum += w * s;
                    weight += w;
                }
            }
            let side = if weight > 0.0 {
                sum / weight
            } else {
                mean_side
            };
            (NEAR_TEXELS as f32 * side.min(MOST_MEAN_SIDES * mean_side)).max(0.0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::texels::unit_plane;
    use glam::Vec2;

    /// On a plane of unit texels the reach is NEAR_TEXELS everywhere; where
    /// the texels' step doubles across the map, the reach grows with it,
    /// linearly between the blocks' centres and never by more than their
    /// difference over a block from one texel to the next.
    #[test]
    fn the_reach_follows_the_texels_size_smoothly() {
        let mut plane = unit_plane(64);
        let even = near_radii(&plane);
        assert!(even.iter().all(|&r| (r - NEAR_TEXELS as f32).abs() < 1e-5));
        for (i, s) in plane.stretch.iter_mut().enumerate() {
            let x = plane.texel[i] % 64;
            *s = if x < 32 {
                Vec2::ONE
            } else {
                Vec2::new(2.0, 1.0)
            };
        }
        let graded = near_radii(&plane);
        let at = |x: u32, y: u32| {
            let i = plane.index[(x + 64 * y) as usize] as usize;
            graded[i]
        };
        let near = NEAR_TEXELS as f32;
        assert!((at(2, 10) - near).abs() < 1e-5);
        assert!((at(60, 10) - 2.0 * near).abs() < 1e-5);
        let steepest = (0..63)
            .map(|x| at(x + 1, 10) - at(x, 10))
            .fold(0.0f32, f32::max);
        assert!(steepest > 0.0 && steepest <= near / MOST_STEP as f32 + 1e-5);
        assert!((0..63).all(|x| at(x + 1, 10) >= at(x, 10) - 1e-6));
        // A sliver a hundred times longer than wide reaches no further than
        // MOST_MEAN_SIDES of the map's mean texels.
        for (i, s) in plane.stretch.iter_mut().enumerate() {
            if plane.texel[i] % 64 >= 32 {
                *s = Vec2::new(100.0, 1.0);
            }
        }
        let sliver = near_radii(&plane);
        let mean = plane.mean_side() as f32;
        let longest = sliver.iter().fold(0.0f32, |m, &r| m.max(r));
        assert!((longest - near * MOST_MEAN_SIDES * mean).abs() < 1e-4);
    }
}
