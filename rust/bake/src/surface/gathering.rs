//! A regular subset of an object's texels that stands for all of them
//! where a quantity varies slowly over the surface (the light an object
//! sends onto itself): computed at the subset and spread back to every
//! texel by distance on the surface.

use crate::control::{Cancelled, Control, parallel_fill};
use crate::layout::Layout;
use crate::surface::lattice::Lattice;
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
    every_nth_texel(layout, stride(layout.surfels.len(), target))
}

/// The texels `stride` apart along u and along v (every texel for 1).
pub fn every_nth_texel(layout: &Layout, stride: u32) -> Vec<u32> {
    let surfels = &layout.surfels;
    Lattice::new(surfels, stride)
        .surfels(surfels)
        .into_iter()
        .map(|s| s as u32)
        .collect()
}

/// Spreads values at the gathering texels to every texel: a weighted mean
/// ([`Spread::to_surfels`]) of the gathering texels within a few spacings
/// on the surface, facing the same way, in the same medium
/// ([`crate::surface::medium`]).
pub struct Spread<'a> {
    layout: &'a Layout,
    /// The gathering texels' positions, normals and pieces, by their place
    /// in the gathering list: a texel's candidates are read side by side,
    /// not each through its surfel.
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    pieces: Vec<Option<u32>>,
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
        let normals = gathering
            .iter()
            .map(|&s| surfels.normal[s as usize])
            .collect();
        let pieces = gathering
            .iter()
            .map(|&s| surfels.piece.get(s as usize).copied())
            .collect();
        let area: f64 = surfels.area.iter().map(|&a| f64::from(a.max(0.0))).sum();
        // Two spacings of the gathering texels: a dozen of them in reach.
        let spacing = (area / gathering.len().max(1) as f64).sqrt() as f32;
        let radius = (2.0 * spacing).max(f32::MIN_POSITIVE);
        Spread {
            layout,
            grid: Grid::new(&positions, radius),
            positions,
            normals,
            pieces,
            radius,
        }
    }

    /// `values`, one per gathering texel, spread to every surfel.
    pub fn to_surfels(
        &self,
        values: &[[f32; 3]],
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        let mut out = vec![[0.0f32; 3]; self.layout.surfels.len()];
        parallel_fill(&mut out, 1024, control, |s| self.spread_to(values, s))?;
        Ok(out)
    }

    /// `values`, one per gathering texel, spread to the surfels `at` alone
    /// (each as [`Self::to_surfels`] spreads to it).
    pub fn to_some(
        &self,
        values: &[[f32; 3]],
        at: &[u32],
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        let mut out = vec![[0.0f32; 3]; at.len()];
        parallel_fill(&mut out, 1024, control, |k| {
            self.spread_to(values, at[k] as usize)
        })?;
        Ok(out)
    }

    /// `values` spread to surfel `s`: twice as far where no gathering
    /// texel is near (a small chart).
    fn spread_to(&self, values: &[[f32; 3]], s: usize) -> [f32; 3] {
        self.mean_within(values, s, self.radius)
            .or_else(|| self.mean_within(values, s, 2.0 * self.radius))
            .unwrap_or([0.0; 3])
    }

    fn mean_within(&self, values: &[[f32; 3]], s: usize, radius: f32) -> Option<[f32; 3]> {
        let (mut sum, mut weight) = ([0.0f32; 3], 0.0f32);
        self.for_each_near(s, radius, |g, w| {
            for c in 0..3 {
                sum[c] += w * values[g][c];
            }
            weight += w;
        });
        (weight > 0.0).then(|| sum.map(|v| v / weight))
    }

    /// Each gathering texel within `radius` of surfel `s`, facing its way
    /// and in its medium: its index and its weight, falling smoothly to 0
    /// at the radius and with the cosine between their normals.
    fn for_each_near(&self, s: usize, radius: f32, mut visit: impl FnMut(usize, f32)) {
        let surfels = &self.layout.surfels;
        let (p, n) = (surfels.position[s], surfels.normal[s]);
        let piece = surfels.piece.get(s).copied();
        let r2 = radius * radius;
        self.grid.for_each_run(p, radius, |run| {
            for &g in &self.grid.order[run] {
                let g = g as usize;
                let d2 = (self.positions[g] - p).length_squared();
                let facing = self.normals[g].dot(n);
                if d2 >= r2 || facing <= 0.0 || self.pieces[g] != piece {
                    continue;
                }
                visit(g, (1.0 - d2 / r2).powi(2) * facing * facing);
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use crate::surface::texels::rasterize;
    use glam::Vec2;

    /// A 40 mm square in the z = 0 plane whose UVs fill the layout.
    fn square_layout(resolution: u32) -> Layout {
        let positions = [(0.0, 0.0), (40.0, 0.0), (40.0, 40.0), (0.0, 40.0)];
        let (mesh, _) = Mesh::new(
            "square",
            positions
                .iter()
                .map(|&(x, y)| Vec3::new(x, y, 0.0))
                .collect(),
            None,
            Some(
                positions
                    .iter()
                    .map(|&(x, y)| Vec2::new(x, y) / 40.0)
                    .collect(),
            ),
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap();
        let uvs = mesh.uvs.clone().unwrap();
        let surfels = rasterize(&mesh, &uvs, resolution);
        Layout {
            mesh,
            uvs,
            unwrapped: false,
            source_vertex: Vec::new(),
            surfels,
            relative_colour: Vec::new(),
            footprints: Default::default(),
        }
    }

    #[test]
    fn a_mean_carries_a_constant_and_a_piece_without_gathering_texels_gets_none() {
        let mut layout = square_layout(64);
        // A strip 6 mm wide is another piece of the mesh, and gathers none.
        let piece: Vec<u32> = layout
            .surfels
            .position
            .iter()
            .map(|p| u32::from(p.x < 6.0))
            .collect();
        layout.surfels.piece = piece;
        let gathering: Vec<u32> = every_nth_texel(&layout, 4)
            .into_iter()
            .filter(|&s| layout.surfels.piece[s as usize] == 0)
            .collect();
        let values = vec![[1.0f32, 2.0, 3.0]; gathering.len()];
        let spread = Spread::new(&layout, &gathering);
        let spread = spread.to_surfels(&values, &Control::default()).unwrap();
        for (v, &piece) in spread.iter().zip(&layout.surfels.piece) {
            match piece {
                1 => assert_eq!(*v, [0.0; 3]),
                _ => assert!((0..3).all(|c| (v[c] - values[0][c]).abs() < 1e-5), "{v:?}"),
            }
        }
    }
}
