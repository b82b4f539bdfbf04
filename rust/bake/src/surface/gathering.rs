//! A regular subset of an object's texels that stands for all of them
//! where a quantity varies slowly over the surface (the light an object
//! sends onto itself): computed at the subset, spread back to every texel
//! by distance on the surface.

use crate::control::{Cancelled, Control, parallel_fill};
use crate::layout::Layout;
use crate::transport::sources::Grid;
use glam::Vec3;

/// Every how many texels along u and along v one gathers, for about
/// `target` of `texels` texels.
pub fn stride(texels: usize, target: usize) -> u32 {
    ((texels as f64 / target.max(1) as f64).sqrt().floor() as u32).max(1)
}

/// A regular subset of the texels, about `target` of them (every texel
/// when there are fewer): every k-th texel along u and along v.
pub fn gathering_texels(layout: &Layout, target: usize) -> Vec<u32> {
    let surfels = &layout.surfels;
    let stride = stride(surfels.len(), target);
    let n = surfels.resolution.max(1);
    (0..surfels.len() as u32)
        .filter(|&s| {
            let t = surfels.texel[s as usize];
            (t % n).is_multiple_of(stride) && (t / n).is_multiple_of(stride)
        })
        .collect()
}

/// Spreads values at the gathering texels to every texel: a weighted mean
/// of the gathering texels within a few spacings on the surface, facing
/// the same way, on the same piece of the mesh.
pub struct Spread<'a> {
    layout: &'a Layout,
    gathering: &'a [u32],
    positions: Vec<Vec3>,
    grid: Grid,
    radius: f32,
}

impl<'a> Spread<'a> {
    /// Spreads from `gathering` (surfels of `layout`).
    pub fn new(layout: &'a Layout, gathering: &'a [u32]) -> Self {
        let surfels = &layout.surfels;
        let positions: Vec<Vec3> = gathering
            .iter()
            .map(|&s| surfels.position[s as usize])
            .collect();
        let area: f64 = surfels.area.iter().map(|&a| f64::from(a.max(0.0))).sum();
        // Two spacings of the gathering texels: a dozen of them in reach.
        let spacing = (area / gathering.len().max(1) as f64).sqrt() as f32;
        let radius = (2.0 * spacing).max(f32::MIN_POSITIVE);
        Spread {
            layout,
            gathering,
            grid: Grid::new(&positions, radius),
            positions,
            radius,
        }
    }

    /// `values`, one per gathering texel, spread to every surfel.
    pub fn to_surfels(
        &self,
        values: &[[f32; 3]],
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        let surfels = &self.layout.surfels;
        let mut out = vec![[0.0f32; 3]; surfels.len()];
        parallel_fill(&mut out, 1024, control, |s| {
            // Twice as far where no gathering texel is near (a small chart).
            self.mean_within(values, s, self.radius)
                .or_else(|| self.mean_within(values, s, 2.0 * self.radius))
                .unwrap_or([0.0; 3])
        })?;
        Ok(out)
    }

    fn mean_within(&self, values: &[[f32; 3]], s: usize, radius: f32) -> Option<[f32; 3]> {
        let surfels = &self.layout.surfels;
        let (p, n) = (surfels.position[s], surfels.normal[s]);
        let piece = surfels.piece.get(s).copied();
        let (mut sum, mut weight) = ([0.0f32; 3], 0.0f32);
        let r2 = radius * radius;
        self.grid.for_each_run(p, radius, |run| {
            for &g in &self.grid.order[run] {
                let g = g as usize;
                let d2 = (self.positions[g] - p).length_squared();
                let at = self.gathering[g] as usize;
                let facing = surfels.normal[at].dot(n);
                if d2 >= r2 || facing <= 0.0 || surfels.piece.get(at).copied() != piece {
                    continue;
                }
                let w = (1.0 - d2 / r2).powi(2) * facing * facing;
                for c in 0..3 {
                    sum[c] += w * values[g][c];
                }
                weight += w;
            }
        });
        (weight > 0.0).then(|| sum.map(|v| v / weight))
    }
}
