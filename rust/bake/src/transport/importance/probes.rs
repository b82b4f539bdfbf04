//! Monte Carlo per texel in the manner of Mertens et al. 2003: radii drawn
//! from the profile (exactly for the dipole, by the tabulated inverse CDF
//! otherwise, plus a uniform share for shadow borders), angles uniform,
//! and the surface found by probe rays through the disk point along the
//! normal or one of the two tangents.
//!
//! The probes are split between every pair of axis a and radius strategy k
//! in fixed counts n_ak (in proportion to the axis and strategy shares),
//! and each cell's probes are one randomly shifted lattice in (radius CDF,
//! angle): stratified, yet each probe on its own is distributed as its
//! strategy says. Every hit within d_max counts, divided by the density
//! with which the whole set finds that point of surface,
//! Σ_ak n_ak |n_f·a| p_k(r_a), where r_a is its distance from the target
//! across axis a and n_f the facet's normal: Veach's multi-sample balance
//! heuristic, an unbiased estimate of ∫ P(|x − x_o|) E(x) dA that stays
//! bounded where the surface turns away from any one axis. (Mertens et
//! al.'s eq. 9 draws axis and strategy at random from one number and
//! prefixes 1/(2π); fixed counts remove the noise of those draws, the
//! prefactor follows from the densities.) Under uniform light on flat
//! ground the error of a lattice falls nearly as 1/n instead of 1/√n.
//!
//! With an oblique kernel (the empirical model under scene lights) a hit
//! reads the light of the texel under it split by incidence and weighs it
//! by each light's kernel from there to the target
//! ([`crate::transport::oblique_sum::light_at`]); the probes are still drawn from the
//! radial profile, which is positive wherever the kernel is.

use crate::control::{Cancelled, Control, parallel_fill};
use crate::irradiance::incidence::{IncidentHarmonics, frame};
use crate::irradiance::sequence::basis;
use crate::mesh::Mesh;
use crate::rays::RayScene;
use crate::transport::kernel::{Kernel, Separation};
use crate::transport::oblique_sum::light_at;
use crate::transport::through_medium::pieces_joined;
use glam::{Vec2, Vec3};
use sssbake_profile::models::empirical::kernel::ObliqueKernel;
use sssbake_profile::models::empirical::oblique::HARMONICS_KEPT;
use sssbake_profile::numerics::rng::Rng;
use sssbake_profile::profile::Profile;
use std::f32::consts::{PI, TAU};

/// Share of probes along the normal, and along each tangent (on flat
/// ground tangent probes find nothing, so they are kept few).
const AXES: [f64; 3] = [0.75, 0.125, 0.125];
/// Share of each channel's radius distribution, and of the uniform disk
/// (which covers a dark channel and the far field).
const STRATEGIES: [f64; 4] = [0.3, 0.3, 0.3, 0.1];
/// The golden ratio's fractional part: a lattice i·φ mod 1 spreads any
/// number of angles evenly against the stratified radii.
const GOLDEN: f64 = 0.618_033_988_749_894_8;

/// Probes per (axis, strategy) out of `samples`, in proportion to their
/// shares, rounded so they sum to `samples` (largest remainders first).
fn allocation(samples: u32) -> [[u32; 4]; 3] {
    let ideal: [[f64; 4]; 3] = AXES.map(|a| STRATEGIES.map(|k| samples as f64 * a * k));
    let mut counts = ideal.map(|row| row.map(|x| x.floor() as u32));
    let placed: u32 = counts.iter().flatten().sum();
    let mut remainders: Vec<(f64, usize, usize)> = (0..3)
        .flat_map(|a| (0..4).map(move |k| (a, k)))
        .map(|(a, k)| (ideal[a][k].fract(), a, k))
        .collect();
    // Stable: equal remainders go to the earlier axis and strategy.
    remainders.sort_by(|x, y| y.0.total_cmp(&x.0));
    for &(_, a, k) in remainders.iter().take((samples - placed) as usize) {
        counts[a][k] += 1;
    }
    counts
}

/// What the estimator reads the surface from.
pub struct Surface<'a> {
    /// The object's mesh (mesh 0 of `probes`).
    pub mesh: &'a Mesh,
    /// Its texture coordinates.
    pub uvs: &'a [Vec2],
    /// Rays against this object alone.
    pub probes: &'a RayScene,
    /// Transmitted irradiance per texel, dilated, row-major N × N.
    pub irradiance: &'a [[f32; 3]],
    /// N.
    pub resolution: u32,
    /// The oblique kernel and the light split by incidence, when used.
    pub oblique: Option<Oblique<'a>>,
    /// The pieces of the mesh, when hits on another piece than the
    /// target's are to be left out (light does not cross air).
    pub pieces: Option<Pieces<'a>>,
}

/// Which medium each triangle and each target lies in, and which piece
/// of it where media join several.
pub struct Pieces<'a> {
    /// Per triangle of the mesh.
    pub triangle: &'a [u32],
    /// Per target.
    pub target: &'a [u32],
    /// The piece of its medium per triangle
    /// ([`crate::surface::medium::Media::piece`]; empty: one piece each).
    pub triangle_part: &'a [u32],
    /// The piece of its medium per target (empty: one piece each).
    pub target_part: &'a [u32],
}

/// What a hit reads for an oblique kernel.
pub struct Oblique<'a> {
    /// The kernel.
    pub kernel: &'a ObliqueKernel,
    /// Each surfel's light split by incidence.
    pub incidence: &'a [IncidentHarmonics],
    /// Each surfel's unit normal (its light's frame).
    pub normal: &'a [Vec3],
    /// The surfel each texel of the N × N layout holds or copies
    /// (`u32::MAX`: none).
    pub texels: &'a [u32],
}

/// Radiant exitance (W/m²) at each target by `samples` probes per target,
/// from generator `seed` (stream = target index, so any thread count gives
/// the same numbers).
#[allow(clippy::too_many_arguments)]
pub fn integrate(
    kernel: &Kernel,
    profile: &dyn Profile,
    surface: &Surface,
    position: &[Vec3],
    normal: &[Vec3],
    samples: u32,
    seed: u64,
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let totals = kernel.enclosed(kernel.d_max);
    let exact = (0..3).all(|c| profile.sample_radius(c, 0.5, kernel.d_max as f64).is_some());
    let count = samples.max(1);
    let cells = allocation(count);
    let share = cells.map(|row| row.map(|n| n as f32 / count as f32));
    let mut out = vec![[0.0f32; 3]; position.len()];
    parallel_fill(&mut out, 64, control, |i| {
        let mut rng = Rng::new(seed, i as u64);
        let estimate = Estimate {
            kernel,
            profile,
            surface,
            totals,
            exact,
            share,
            origin: position[i],
            normal: normal[i],
            piece: surface
                .pieces
                .as_ref()
                .and_then(|pieces| Some((pieces.triangle, *pieces.target.get(i)?))),
            part: surface
                .pieces
                .as_ref()
                .and_then(|pieces| Some((pieces.triangle_part, *pieces.target_part.get(i)?))),
        };
        let mut sum = [0.0f64; 3];
        for (axis, row) in cells.iter().enumerate() {
            for (strategy, &n) in row.iter().enumerate() {
                // Each probe's two numbers are uniform on their own (one
                // random shift of the lattice), so every probe is drawn
                // from its strategy while the cell covers [0, 1)² evenly.
                let shift = [rng.uniform(), rng.uniform()];
                for j in 0..n {
                    let u = [
                        (j as f64 + shift[0]) / n as f64,
                        (j as f64 * GOLDEN + shift[1]).fract(),
                    ];
                    let v = estimate.sample(axis, strategy, u);
                    for c in 0..3 {
                        sum[c] += v[c] as f64;
                    }
                }
            }
        }
        // A truncated oblique kernel may dip below zero behind an entry
        // point, and the probes' noise with it; exitance does not.
        sum.map(|s| crate::transport::stored_exitance(s / count as f64))
    })?;
    Ok(out)
}

struct Estimate<'a> {
    kernel: &'a Kernel,
    profile: &'a dyn Profile,
    surface: &'a Surface<'a>,
    totals: [f32; 3],
    exact: bool,
    /// Share of the probes in each (axis, strategy) cell.
    share: [[f32; 4]; 3],
    origin: Vec3,
    normal: Vec3,
    /// The media of the triangles, and the target's medium.
    piece: Option<(&'a [u32], u32)>,
    /// The pieces of their media of the triangles, and the target's.
    part: Option<(&'a [u32], u32)>,
}

impl Estimate<'_> {
    fn axes(&self) -> [Vec3; 3] {
        let (t, b) = basis(self.normal);
        [self.normal, t, b]
    }

    /// Each strategy's density per unit disk area at radius `r`.
    fn disk_densities(&self, r: f32) -> [f32; 4] {
        let d_max = self.kernel.d_max;
        if r > d_max {
            return [0.0; 4];
        }
        let uniform = 1.0 / (PI * d_max * d_max);
        let reflectance = self.kernel.reflectance(r);
        // A dark channel's draws fall back to the uniform disk.
        let channel = |c: usize| {
            if self.totals[c] > 0.0 {
                reflectance[c] / self.totals[c]
            } else {
                uniform
            }
        };
        [channel(0), channel(1), channel(2), uniform]
    }

    /// A radius from strategy `strategy` (a channel, or 3: the uniform
    /// disk), drawn from `xi`.
    fn radius(&self, strategy: usize, xi: f64) -> f32 {
        let d_max = self.kernel.d_max;
        let channel = strategy;
        if channel >= 3 || self.totals[channel].is_nan() || self.totals[channel] <= 0.0 {
            return d_max * (xi as f32).sqrt();
        }
        if self.exact
            && let Some(r) = self.profile.sample_radius(channel, xi, d_max as f64)
        {
            return (r as f32).min(d_max);
        }
        self.kernel.sample_radius(channel, xi as f32)
    }

    /// One probe along axis `a` with a radius from `strategy`, from the
    /// two uniform numbers `u` (radius, angle).
    fn sample(&self, a: usize, strategy: usize, u: [f64; 2]) -> [f32; 3] {
        let d_max = self.kernel.d_max;
        if d_max.is_nan() || d_max <= 0.0 {
            return [0.0; 3];
        }
        let axes = self.axes();
        let axis = axes[a];
        let (e1, e2) = (axes[(a + 1) % 3], axes[(a + 2) % 3]);
        let r = self.radius(strategy, u[0]);
        let phi = TAU * u[1] as f32;
        let q = self.origin + r * (phi.cos() * e1 + phi.sin() * e2);
        let half = (d_max * d_max - r * r).max(0.0).sqrt();
        let mut total = [0.0f32; 3];
        let surface = self.surface;
        surface
            .probes
            .for_each_hit(q - axis * half, axis, 0.0, 2.0 * half, |hit| {
                if let Some((pieces, own)) = self.piece
                    && pieces.get(hit.triangle as usize).is_some_and(|&p| p != own)
                {
                    return;
                }
                let tri = surface.mesh.triangles[hit.triangle as usize];
                let w = [1.0 - hit.uv.x - hit.uv.y, hit.uv.x, hit.uv.y];
                let point = q - axis * half + axis * hit.t;
                let offset = point - self.origin;
                let d = offset.length();
                if d > d_max {
                    return;
                }
                let n_hit = (0..3)
                    .map(|k| surface.mesh.normals[tri[k] as usize] * w[k])
                    .sum::<Vec3>()
                    .normalize_or_zero();
                if let Some((parts, own)) = self.part
                    && let Some(&part) = parts.get(hit.triangle as usize)
                    && !pieces_joined(part, point, n_hit, own, self.origin, self.normal)
                {
                    return;
                }
                // Lines cross the facet itself, so the density of hits per
                // unit area takes the facet's normal, not the shading one.
                let [p0, p1, p2] = tri.map(|v| surface.mesh.positions[v as usize]);
                let facet = (p1 - p0).cross(p2 - p0).normalize_or_zero();
                let mut density = 0.0;
                for (share, &ax) in self.share.iter().zip(&axes) {
                    let across = (offset - ax * offset.dot(ax)).length();
                    let densities = self.disk_densities(across);
                    let mixture: f32 = share.iter().zip(&densities).map(|(s, p)| s * p).sum();
                    density += facet.dot(ax).abs() * mixture;
                }
                if density.is_nan() || density <= 0.0 {
                    return;
                }
                let uv: Vec2 = (0..3).map(|k| surface.uvs[tri[k] as usize] * w[k]).sum();
                if let Some(oblique) = &surface.oblique {
                    let v = oblique_hit(oblique, surface.resolution, uv, self.origin - point);
                    for c in 0..3 {
                        total[c] += v[c] as f32 / density;
                    }
                    return;
                }
                let e = bilinear(surface.irradiance, surface.resolution, uv);
                let separation = Separation::new(
                    point,
                    n_hit,
                    self.origin,
                    self.normal,
                    d * d,
                    self.kernel.transmits(),
                );
                let p = self.kernel.point(separation);
                for c in 0..3 {
                    total[c] += p[c] * e[c] / density;
                }
            });
        total.map(|v| if v.is_finite() { v } else { 0.0 })
    }
}

/// The oblique kernel of the light entering the texel under `uv` (nearest:
/// each texel's light is in its own frame), read at offset `d` from there.
fn oblique_hit(oblique: &Oblique, n: u32, uv: Vec2, d: Vec3) -> [f64; 3] {
    let n_f = n as f32;
    let x = ((uv.x * n_f).floor() as i64).clamp(0, n as i64 - 1) as usize;
    let y = ((uv.y * n_f).floor() as i64).clamp(0, n as i64 - 1) as usize;
    let Some(&s) = oblique.texels.get(y * n as usize + x) else {
        return [0.0; 3];
    };
    let (Some(light), Some(&normal)) = (
        oblique.incidence.get(s as usize),
        oblique.normal.get(s as usize),
    ) else {
        return [0.0; 3];
    };
    let nodes = light
        .iter()
        .enumerate()
        .filter(|(_, l)| l.iter().flatten().any(|&v| v != 0.0));
    // Not clamped per hit: a truncated series can dip below zero behind an
    // entry point, and the exact sum clamps only the sum.
    light_at(
        oblique.kernel,
        nodes,
        normal,
        frame(normal),
        d,
        HARMONICS_KEPT,
    )
}

/// Bilinear lookup of an N × N texture at `uv` (texel centres at
/// (x + ½)/N, clamped at the borders).
fn bilinear(image: &[[f32; 3]], n: u32, uv: Vec2) -> [f32; 3] {
    let n_f = n as f32;
    let x = (uv.x * n_f - 0.5).clamp(0.0, n_f - 1.0);
    let y = (uv.y * n_f - 0.5).clamp(0.0, n_f - 1.0);
    let (x0, y0) = (x.floor() as usize, y.floor() as usize);
    let (x1, y1) = ((x0 + 1).min(n as usize - 1), (y0 + 1).min(n as usize - 1));
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let at = |x: usize, y: usize| image[y * n as usize + x];
    let (a, b, c, d) = (at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1));
    [0, 1, 2].map(|k| {
        (a[k] * (1.0 - fx) + b[k] * fx) * (1.0 - fy) + (c[k] * (1.0 - fx) + d[k] * fx) * fy
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_probe_is_allotted_in_proportion_to_the_shares() {
        for samples in [1, 4, 7, 64, 512, 1000] {
            let cells = allocation(samples);
            assert_eq!(cells.iter().flatten().sum::<u32>(), samples);
            for (a, row) in cells.iter().enumerate() {
                for (k, &n) in row.iter().enumerate() {
                    let ideal = samples as f64 * AXES[a] * STRATEGIES[k];
                    assert!((n as f64 - ideal).abs() < 1.0, "{samples}: {a} {k} {n}");
                }
            }
        }
    }
}
