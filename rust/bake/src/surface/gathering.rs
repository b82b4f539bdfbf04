//! A regular subset of an object's texels that stands for all of them
//! where a quantity varies slowly over the surface (the light an object
//! sends onto itself, the sums of the kernel's weights under a unit
//! light): computed at the subset, spread or fitted back to every texel by
//! distance on the surface.

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
    every_nth_texel(layout, stride(layout.surfels.len(), target))
}

/// The texels `stride` apart along u and along v (every texel for 1).
pub fn every_nth_texel(layout: &Layout, stride: u32) -> Vec<u32> {
    let surfels = &layout.surfels;
    let stride = stride.max(1);
    let n = surfels.resolution.max(1);
    (0..surfels.len() as u32)
        .filter(|&s| {
            let t = surfels.texel[s as usize];
            (t % n).is_multiple_of(stride) && (t / n).is_multiple_of(stride)
        })
        .collect()
}

/// Spreads values at the gathering texels to every texel: a weighted mean
/// ([`Spread::to_surfels`]) or a weighted plane
/// ([`Spread::fitted_to_surfels`]) of the gathering texels within a few
/// spacings on the surface, facing the same way, in the same medium
/// ([`crate::surface::medium`]).
pub struct Spread<'a> {
    layout: &'a Layout,
    gathering: &'a [u32],
    positions: Vec<Vec3>,
    grid: Grid,
    radius: f32,
}

/// The least variance (in units of the fit's radius squared) of the
/// gathering texels' offsets along any direction of the tangent plane for
/// a plane to be fitted through them: a standard deviation of a tenth of
/// the radius, about a third of their spacing. A single row has none.
const SPANNED: f64 = 1e-2;

/// The least eigenvalue of the weighted covariance of the offsets whose
/// moments (weight, first and second, as the normal equations hold them)
/// are `moments`.
fn least_spread(moments: &DMat3) -> f64 {
    let weight = moments.x_axis.x;
    let (a, b) = (moments.x_axis.y / weight, moments.x_axis.z / weight);
    let aa = moments.y_axis.y / weight - a * a;
    let bb = moments.z_axis.z / weight - b * b;
    let ab = moments.y_axis.z / weight - a * b;
    let (trace, determinant) = (aa + bb, aa * bb - ab * ab);
    0.5 * (trace - (trace * trace - 4.0 * determinant).max(0.0).sqrt())
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
    /// range, and above half the least of them where none is negative;
    /// where they do not span the plane (a row of them, a thin strip) it is
    /// their mean. `None` for a surfel with no gathering texel of its medium
    /// facing its way within reach (a part or a chart smaller than the
    /// spacing): the caller finds its value itself.
    pub fn fitted_to_surfels(
        &self,
        values: &[[f32; 3]],
        control: &Control,
    ) -> Result<Vec<Option<[f32; 3]>>, Cancelled> {
        let surfels = &self.layout.surfels;
        let mut out = vec![None; surfels.len()];
        parallel_fill(&mut out, 1024, control, |s| {
            // A plane needs two rows of them, even at a chart's edge.
            self.fit_within(values, s, 1.5 * self.radius)
                .or_else(|| self.mean_within(values, s, 2.0 * self.radius))
        })?;
        Ok(out)
    }

    /// The weighted plane fit at surfel `s` of the gathering texels within
    /// `radius`, or their mean where they do not span the plane.
    fn fit_within(&self, values: &[[f32; 3]], s: usize, radius: f32) -> Option<[f32; 3]> {
        let (u, v) = self.layout.surfels.normal[s].any_orthonormal_pair();
        // The moments of the normal equations of f ≈ c₀ + c₁a + c₂b, (a, b)
        // in units of the radius so the matrix stays well scaled.
        let mut moments = DMat3::ZERO;
        let mut rhs = [DVec3::ZERO; 3];
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        self.for_each_near(s, radius, |g, offset, w| {
            let w = f64::from(w);
            let x = DVec3::new(
                1.0,
                f64::from(offset.dot(u) / radius),
                f64::from(offset.dot(v) / radius),
            );
            moments += DMat3::from_cols(x * (w * x.x), x * (w * x.y), x * (w * x.z));
            for c in 0..3 {
                rhs[c] += x * (w * f64::from(values[g][c]));
                lo[c] = lo[c].min(values[g][c]);
                hi[c] = hi[c].max(values[g][c]);
            }
        });
        let weight = moments.x_axis.x;
        if !(weight > 0.0 && (0..3).all(|c| lo[c] <= hi[c])) {
            return None;
        }
        let mean = [0, 1, 2].map(|c| (rhs[c].x / weight) as f32);
        if least_spread(&moments) < SPANNED {
            return Some(mean);
        }
        // The plane may reach past the last row of gathering texels toward
        // a chart's edge, by half the values' range, but a fit never
        // invents a swing, nor takes a positive field to zero.
        let inverse = moments.inverse();
        Some([0, 1, 2].map(|c| {
            let margin = 0.5 * (hi[c] - lo[c]);
            let mut low = lo[c] - margin;
            if lo[c] >= 0.0 {
                low = low.max(0.5 * lo[c]);
            }
            let fitted = (inverse * rhs[c]).x as f32;
            if fitted.is_finite() {
                fitted.clamp(low, hi[c] + margin)
            } else {
                mean[c]
            }
        }))
    }

    fn mean_within(&self, values: &[[f32; 3]], s: usize, radius: f32) -> Option<[f32; 3]> {
        let (mut sum, mut weight) = ([0.0f32; 3], 0.0f32);
        self.for_each_near(s, radius, |g, _, w| {
            for c in 0..3 {
                sum[c] += w * values[g][c];
            }
            weight += w;
        });
        (weight > 0.0).then(|| sum.map(|v| v / weight))
    }

    /// Each gathering texel within `radius` of surfel `s`, facing its way
    /// and in its medium: its index, its offset from the surfel
    /// (mm) and its weight, falling smoothly to 0 at the radius and with
    /// the cosine between their normals.
    fn for_each_near(&self, s: usize, radius: f32, mut visit: impl FnMut(usize, Vec3, f32)) {
        let surfels = &self.layout.surfels;
        let (p, n) = (surfels.position[s], surfels.normal[s]);
        let piece = surfels.piece.get(s).copied();
        let r2 = radius * radius;
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
                visit(g, offset, (1.0 - d2 / r2).powi(2) * facing * facing);
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
        let fitted: Vec<[f32; 3]> = spread
            .fitted_to_surfels(&values, &control)
            .unwrap()
            .into_iter()
            .map(|v| v.expect("every texel of the square has gathering texels near"))
            .collect();
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
                .flatten()
                .all(|v| (0.0..=1.5).contains(v) && v.is_finite())
        );
        // A positive field falling toward an edge is never fitted to zero.
        let falling: Vec<[f32; 3]> = gathering
            .iter()
            .map(|&s| [(1.0 - layout.surfels.position[s as usize].x / 38.0).max(0.01); 3])
            .collect();
        let fitted = spread
            .fitted_to_surfels(&falling, &Control::default())
            .unwrap();
        assert!(
            fitted.iter().flatten().flatten().all(|&v| v >= 0.005),
            "a texel fitted to zero"
        );
    }

    #[test]
    fn a_row_is_meaned() {
        let layout = square_layout(64);
        let n = layout.surfels.resolution;
        // One row of gathering texels: a plane through it is undetermined
        // across the row, so each texel takes the mean.
        let row: Vec<u32> = (0..layout.surfels.len() as u32)
            .filter(|&s| {
                let t = layout.surfels.texel[s as usize];
                t / n == 32 && (t % n).is_multiple_of(4)
            })
            .collect();
        let values: Vec<[f32; 3]> = row
            .iter()
            .map(|&s| linear(layout.surfels.position[s as usize]))
            .collect();
        let spread = Spread::new(&layout, &row);
        let fitted = spread
            .fitted_to_surfels(&values, &Control::default())
            .unwrap();
        let (lo, hi) = values.iter().fold((f32::MAX, f32::MIN), |(lo, hi), v| {
            (lo.min(v[0]), hi.max(v[0]))
        });
        assert!(
            fitted
                .iter()
                .flatten()
                .all(|v| v[0] >= lo && v[0] <= hi && v.iter().all(|x| x.is_finite()))
        );
        assert!(fitted.iter().all(Option::is_some));
    }

    #[test]
    fn a_piece_without_gathering_texels_is_left_to_the_caller() {
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
        let values = vec![[1.0f32; 3]; gathering.len()];
        let spread = Spread::new(&layout, &gathering);
        let fitted = spread
            .fitted_to_surfels(&values, &Control::default())
            .unwrap();
        for (v, &piece) in fitted.iter().zip(&layout.surfels.piece) {
            match piece {
                1 => assert_eq!(*v, None),
                _ => assert_eq!(*v, Some([1.0; 3])),
            }
        }
    }
}
