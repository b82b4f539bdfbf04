//! A regular subset of an object's texels that stands for all of them
//! where a quantity varies slowly over the surface (the light an object
//! sends onto itself): computed at the subset, spread back to every texel
//! by distance on the surface.

use crate::control::{Cancelled, Control, parallel_fill};
use crate::layout::Layout;
use crate::transport::sources::Grid;
use glam::{DMat3, DVec3, Vec3};

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

    /// `values`, one per gathering texel, fitted to every surfel: a
    /// weighted plane through the gathering texels around it in its
    /// tangent plane, so a field that changes linearly is carried exactly
    /// to the chart's edge, where a mean is pulled toward the inside. The
    /// fit stays within the values it is made from widened by half their
    /// range, and non-negative where they are; where they do not span the
    /// plane (a row of them, a small chart) it is their mean.
    pub fn fitted_to_surfels(
        &self,
        values: &[[f32; 3]],
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        let surfels = &self.layout.surfels;
        let mut out = vec![[0.0f32; 3]; surfels.len()];
        parallel_fill(&mut out, 1024, control, |s| {
            // A plane needs two rows of them, even at a chart's edge.
            self.fit_within(values, s, 1.5 * self.radius)
                .or_else(|| self.mean_within(values, s, 2.0 * self.radius))
                .unwrap_or([0.0; 3])
        })?;
        Ok(out)
    }

    /// The weighted plane fit at surfel `s` of the gathering texels within
    /// `radius`, or their mean where they do not span the plane.
    fn fit_within(&self, values: &[[f32; 3]], s: usize, radius: f32) -> Option<[f32; 3]> {
        let surfels = &self.layout.surfels;
        let (p, n) = (surfels.position[s], surfels.normal[s]);
        let (u, v) = n.any_orthonormal_pair();
        let piece = surfels.piece.get(s).copied();
        let r2 = radius * radius;
        // Normal equations of f ≈ c₀ + c₁a + c₂b, (a, b) in units of the
        // radius so the matrix stays well scaled.
        let mut normal = DMat3::ZERO;
        let mut rhs = [DVec3::ZERO; 3];
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        self.grid.for_each_run(p, radius, |run| {
            for &g in &self.grid.order[run] {
                let g = g as usize;
                let offset = self.positions[g] - p;
                let d2 = offset.length_squared();
                let at = self.gathering[g] as usize;
                let facing = surfels.normal[at].dot(n);
                if d2 >= r2 || facing <= 0.0 || surfels.piece.get(at).copied() != piece {
                    continue;
                }
                let w = f64::from((1.0 - d2 / r2).powi(2) * facing * facing);
                let x = DVec3::new(
                    1.0,
                    f64::from(offset.dot(u) / radius),
                    f64::from(offset.dot(v) / radius),
                );
                normal += DMat3::from_cols(x * (w * x.x), x * (w * x.y), x * (w * x.z));
                for c in 0..3 {
                    rhs[c] += x * (w * f64::from(values[g][c]));
                    lo[c] = lo[c].min(values[g][c]);
                    hi[c] = hi[c].max(values[g][c]);
                }
            }
        });
        let weight = normal.x_axis.x;
        if weight <= 0.0 {
            return None;
        }
        // Too few or too nearly in a row to fit a plane: their mean. The
        // determinant is the weight cubed times the variances' product
        // across the two directions, in units of the radius.
        const SPANNED: f64 = 1e-6;
        if normal.determinant() <= SPANNED * weight * weight * weight {
            return Some([0, 1, 2].map(|c| (rhs[c].x / weight) as f32));
        }
        // The plane may reach past the last row of gathering texels toward
        // a chart's edge, by half the values' range, and not below zero
        // where they are not: a fit never invents a swing.
        let inverse = normal.inverse();
        Some([0, 1, 2].map(|c| {
            let wider = 0.5 * (hi[c] - lo[c]);
            let floor = if lo[c] >= 0.0 { 0.0 } else { lo[c] - wider };
            ((inverse * rhs[c]).x as f32).clamp((lo[c] - wider).max(floor), hi[c] + wider)
        }))
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
        }
    }

    fn linear(p: Vec3) -> [f32; 3] {
        [1.0 + 0.05 * p.x, 2.0 - 0.02 * p.y, 3.0 + 0.01 * (p.x + p.y)]
    }

    #[test]
    fn a_fit_carries_a_linear_field_to_the_edges_and_a_mean_does_not() {
        let layout = square_layout(64);
        let gathering = gathering_texels(&layout, 256);
        assert!(gathering.len() < layout.surfels.len() / 8);
        let values: Vec<[f32; 3]> = gathering
            .iter()
            .map(|&s| linear(layout.surfels.position[s as usize]))
            .collect();
        let spread = Spread::new(&layout, &gathering);
        let control = Control::default();
        let fitted = spread.fitted_to_surfels(&values, &control).unwrap();
        let mean = spread.to_surfels(&values, &control).unwrap();
        let worst = |out: &[[f32; 3]]| {
            out.iter()
                .zip(&layout.surfels.position)
                .flat_map(|(v, &p)| {
                    let want = linear(p);
                    (0..3).map(move |c| ((v[c] - want[c]) / want[c]).abs())
                })
                .fold(0.0f32, f32::max)
        };
        // Past the last gathering texels, the corner reaches its bound.
        assert!(worst(&fitted) < 5e-3, "{}", worst(&fitted));
        let inside: Vec<[f32; 3]> = fitted
            .iter()
            .zip(&layout.surfels.position)
            .filter(|(_, p)| p.x > 4.0 && p.x < 34.0 && p.y > 4.0 && p.y < 34.0)
            .map(|(v, _)| *v)
            .collect();
        let inside_positions: Vec<Vec3> = layout
            .surfels
            .position
            .iter()
            .copied()
            .filter(|p| p.x > 4.0 && p.x < 34.0 && p.y > 4.0 && p.y < 34.0)
            .collect();
        for (v, p) in inside.iter().zip(&inside_positions) {
            let want = linear(*p);
            for c in 0..3 {
                assert!(
                    (v[c] - want[c]).abs() < 1e-4 * want[c],
                    "{v:?} {want:?} at {p}"
                );
            }
        }
        assert!(worst(&mean) > 0.01, "{}", worst(&mean));
    }

    #[test]
    fn a_fit_stays_near_the_values_it_is_made_from() {
        let layout = square_layout(64);
        let gathering = gathering_texels(&layout, 256);
        // A step: the fit across it overshoots neither side by more than
        // half the step, nor goes below zero.
        let values: Vec<[f32; 3]> = gathering
            .iter()
            .map(|&s| {
                let x = layout.surfels.position[s as usize].x;
                [if x < 20.0 { 0.0 } else { 1.0 }; 3]
            })
            .collect();
        let spread = Spread::new(&layout, &gathering);
        let fitted = spread
            .fitted_to_surfels(&values, &Control::default())
            .unwrap();
        assert!(
            fitted
                .iter()
                .flatten()
                .all(|v| (0.0..=1.5).contains(v) && v.is_finite())
        );
    }
}
