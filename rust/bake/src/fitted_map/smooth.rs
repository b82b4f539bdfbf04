//! Where the light entering is smooth over a lattice's cells: there N, a
//! sum over a texel's near neighbours, is as bilinear between the lattice
//! texels as the light is, and the whole map is carried, N and all.
//!
//! A texel's light is bilinear when it lies within a share of the light
//! carried bilinearly from the four lattice texels around it (on its own
//! surface). N at a texel reads the light of the texels within its reach
//! ([`super::near_reach`], a few of the texels about it), so a texel is
//! smooth when every texel within [`LAYOUT_REACH`] texels of it in the
//! layout is bilinear: away from a shadow's edge, a terminator, a chart's
//! edge (where a texel's neighbours in the layout are not its neighbours
//! on the surface) and texels so narrow that N reaches past the box.

use crate::surface::lattice::Lattice;
use crate::surface::texels::{EMPTY, TexelSurfels};
use rayon::prelude::*;

/// The box (texels each way in the layout) over which a texel's
/// neighbours must be bilinear: N reaches [`super::NEAR_TEXELS`] of the
/// texels about it on the surface, and a texel whose shorter side is
/// less than 1 / LAYOUT_REACH of N's reach there is never smooth.
pub(super) const LAYOUT_REACH: u32 = 5;

/// Per surfel, true where the light `light` (per surfel and channel)
/// within [`LAYOUT_REACH`] texels is within `share` of its bilinear mean
/// over the `lattice` texels around each, `alike(i, j)` saying lattice
/// texel j lies on texel i's surface, and N's reach (`near_radius`, mm
/// per surfel) within the box. Where the light is dim, within `share` of
/// a thousandth of its brightest.
pub(super) fn smooth_texels(
    surfels: &TexelSurfels,
    light: &[[f32; 3]],
    lattice: &Lattice,
    near_radius: &[f32],
    share: f32,
    alike: impl Fn(usize, usize) -> bool + Sync,
) -> Vec<bool> {
    let brightest = light.iter().fold([0.0f32; 3], |m, e| {
        [0, 1, 2].map(|c| if e[c] > m[c] { e[c] } else { m[c] })
    });
    let floor = brightest.map(|b| 1e-3 * b);
    // Texel by texel of the layout: 1 where its own light is bilinear.
    let n = surfels.resolution as usize;
    let bilinear: Vec<bool> = (0..n * n)
        .into_par_iter()
        .map(|t| {
            let i = surfels.index[t];
            if i == EMPTY {
                return false;
            }
            let i = i as usize;
            if surfels.stretch[i].min_element() * (LAYOUT_REACH as f32) < near_radius[i] {
                return false;
            }
            let Some(corners) = lattice.corners(surfels, i, |j| alike(i, j)) else {
                return false;
            };
            (0..3).all(|c| {
                let carried: f32 = corners.iter().map(|&(j, w)| w * light[j][c]).sum();
                (light[i][c] - carried).abs() <= share * carried.max(floor[c])
            })
        })
        .collect();
    let r = LAYOUT_REACH as usize;
    let all_within = |image: &[bool], t: usize, stride: usize, along: usize| {
        along >= r && along + r < n && (0..=2 * r).all(|k| image[t - r * stride + k * stride])
    };
    let rows: Vec<bool> = (0..n * n)
        .into_par_iter()
        .map(|t| all_within(&bilinear, t, 1, t % n))
        .collect();
    drop(bilinear);
    surfels
        .texel
        .par_iter()
        .map(|&t| all_within(&rows, t as usize, n, t as usize / n))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::texels::unit_plane as plane;
    use glam::Vec2;

    /// N's reach of two unit texels at every surfel.
    fn reach(surfels: &TexelSurfels) -> Vec<f32> {
        vec![2.0; surfels.len()]
    }

    fn smooth(surfels: &TexelSurfels, light: &[[f32; 3]]) -> Vec<bool> {
        let lattice = Lattice::new(surfels, 4);
        smooth_texels(surfels, light, &lattice, &reach(surfels), 0.005, |_, _| {
            true
        })
    }

    /// True for texels at least `LAYOUT_REACH` from the map's border.
    fn inside(n: u32, s: usize) -> bool {
        let (x, y) = (s as u32 % n, s as u32 / n);
        let r = LAYOUT_REACH;
        x >= r && y >= r && x + r < n && y + r < n
    }

    #[test]
    fn a_light_bilinear_over_the_map_is_smooth_away_from_its_border() {
        let surfels = plane(24);
        let light: Vec<[f32; 3]> = surfels
            .position
            .iter()
            .map(|p| [1.0 + 0.1 * p.x, 2.0 + 0.05 * p.y, 0.5])
            .collect();
        let smooth = smooth(&surfels, &light);
        for (s, &smooth) in smooth.iter().enumerate() {
            // The last lattice column and row (20) leave texels past them
            // without corners, and their neighbours with them.
            let (x, y) = (s as u32 % 24, s as u32 / 24);
            let cornered = x + LAYOUT_REACH <= 20 && y + LAYOUT_REACH <= 20;
            assert_eq!(smooth, inside(24, s) && cornered, "texel {s}");
        }
    }

    #[test]
    fn a_shadows_edge_an_empty_texel_and_small_texels_are_not_smooth() {
        let mut surfels = plane(40);
        let light: Vec<[f32; 3]> = surfels
            .position
            .iter()
            .map(|p| if p.x < 21.5 { [1.0; 3] } else { [0.2; 3] })
            .collect();
        let smooth = smooth(&surfels, &light);
        let at = |x: u32, y: u32| smooth[(y * 40 + x) as usize];
        // The edge lies between lattice columns 20 and 24: texels 21 to 23
        // are not bilinear, and neither is any texel within reach of them.
        let r = LAYOUT_REACH;
        assert!(!at(22, 10) && !at(21 - r, 10) && !at(23 + r, 10));
        assert!(at(20 - r, 10) && at(24 + r, 10));
        // An empty texel (off the lattice), and a texel whose sides are short against N's
        // reach, make their neighbourhoods rough.
        let even: Vec<[f32; 3]> = vec![[1.0; 3]; surfels.len()];
        surfels.index[21 * 40 + 21] = EMPTY;
        surfels.stretch[10 * 40 + 30] = Vec2::splat(0.1);
        let lattice = Lattice::new(&surfels, 4);
        let smooth = smooth_texels(
            &surfels,
            &even,
            &lattice,
            &reach(&surfels),
            0.005,
            |_, _| true,
        );
        let at = |x: u32, y: u32| smooth[(y * 40 + x) as usize];
        assert!(!at(21 + r, 21 - r) && !at(21 - r, 21) && at(20 - r, 21));
        assert!(!at(30, 10) && !at(30 - r, 10 + r) && at(30, 11 + r));
    }
}
