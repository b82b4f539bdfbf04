//! The corrected model on small convex parts: each texel's light raised by
//! what a ball as curved as the surface there returns beyond what the
//! model gives it.
//!
//! Light gives a uniformly lit ball of radius r the walk's return over
//! the half-space's ([`crate::transport::ball_totals`]), B(r) ≥ 1, falling
//! to 1 as r grows past the reach. The
//! model gives a texel the slab of its thickness t where a face lies
//! behind it within the reach ([`crate::transport::local_slab`]): S(t) =
//! (R_t + T_t)/R_∞, 1 for a thick part. A texel reads the ball of radius
//! 1/H, H the surface's mean curvature around it
//! ([`crate::surface::curvature`]) at the channel's half-light radius, and
//! is raised by B(1/H)/S(min(t, 2/H)): on a ball the slab of its diameter;
//! on a thin part the slab of its thickness, which already returns what
//! crosses it and the gain by the surface ending within reach brings to
//! it. On a plane, in a fold or a saddle H is at most 0 and nothing is
//! raised. B is tabulated on a ladder of radii and interpolated linearly
//! in H, with B = 1 at H = 0 (past the largest ball B − 1 falls as 1/r,
//! as the first term of a curvature expansion does).

use crate::surface::curvature::planned_steps;
use crate::surface::opposite::Opposite;
use crate::transport::ball_totals::ball_totals;
use crate::transport::kernel::Kernel;
use crate::transport::local_slab::{LocalSlab, MAX_GAIN};
use sssbake_profile::material::Layer;

/// Rungs of the radius ladder.
const RUNGS: usize = 12;
/// The smallest ball, as a share of the shortest half-light radius.
const SMALLEST: f64 = 0.25;
/// The largest ball, as a multiple of the longest half-light radius.
const LARGEST: f64 = 40.0;

/// A material's balls by mean curvature, per channel.
#[derive(Clone, Debug, PartialEq)]
pub struct BallGain {
    /// The scale each channel's curvature is read at: its half-light
    /// radius, mm.
    scale: [f32; 3],
    /// Mean curvatures, 1/mm, rising from 0.
    curvature: Vec<f64>,
    /// At each curvature, B: the ball's return over the half-space's, per
    /// channel (1 at 0).
    light: Vec<[f64; 3]>,
    /// Per channel, the most B may be off by where the bound on the walks'
    /// events binds, as a share
    /// ([`crate::transport::ball_totals::BallTotals::unfinished_share`]).
    unfinished: [f64; 3],
}

impl BallGain {
    /// The balls of `layer` (the slab's semi-infinite layer), on a
    /// ladder of radii set by `kernel` (the layer's profile, tabulated).
    pub fn of(kernel: &Kernel, layer: &Layer) -> Self {
        let scale = Self::scales(kernel).map(f64::from);
        let (shortest, longest) = scale.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &s| {
            (lo.min(s), hi.max(s))
        });
        let radius: Vec<f64> = if shortest > 0.0 && longest.is_finite() {
            let (lo, hi) = (SMALLEST * shortest, LARGEST * longest);
            (0..RUNGS)
                .map(|i| lo * (hi / lo).powf(i as f64 / (RUNGS - 1) as f64))
                .collect()
        } else {
            Vec::new()
        };
        let totals = ball_totals(layer, &radius);
        let balls = totals.over_half_space();
        // From the largest ball (least curved) to the smallest.
        let mut curvature = vec![0.0];
        let mut light = vec![[1.0; 3]];
        for (r, ball) in radius.iter().zip(balls).rev() {
            curvature.push(1.0 / r);
            light.push(ball.map(|b| if b.is_finite() { b.max(1.0) } else { 1.0 }));
        }
        BallGain {
            scale: scale.map(|s| s as f32),
            curvature,
            light,
            unfinished: totals.unfinished_share(),
        }
    }

    /// The scale each channel's curvature is read at: its half-light
    /// radius within the reach of `kernel`, mm.
    fn scales(kernel: &Kernel) -> [f32; 3] {
        [0, 1, 2].map(|c| kernel.sample_radius(c, 0.5))
    }

    /// About how many steps finding the curvature in every channel takes
    /// for `texels` texels covering `area_mm2` under `kernel`
    /// ([`crate::surface::curvature::planned_steps`]).
    pub fn planned_steps(kernel: &Kernel, texels: f64, area_mm2: f64) -> f64 {
        Self::scales(kernel)
            .iter()
            .map(|&s| planned_steps(texels, area_mm2, s))
            .sum()
    }

    /// No gain anywhere.
    pub fn none() -> Self {
        BallGain {
            scale: [0.0; 3],
            curvature: vec![0.0],
            light: vec![[1.0; 3]],
            unfinished: [0.0; 3],
        }
    }

    /// Per channel, the most the gain may be off by where the bound on the
    /// walks' events binds, as a share (0 where every walk ended).
    pub fn unfinished(&self) -> [f64; 3] {
        self.unfinished
    }

    /// B in channel `c` where the mean curvature is `h` (1/mm): 1 at or
    /// below 0, the smallest ball's past it.
    pub fn at(&self, h: f64, c: usize) -> f64 {
        if h.is_nan() || h <= 0.0 {
            return 1.0;
        }
        let above = self.curvature.partition_point(|&k| k < h);
        let Some(&k1) = self.curvature.get(above) else {
            return self.light.last().map_or(1.0, |g| g[c]);
        };
        let (k0, g0, g1) = (
            self.curvature[above - 1],
            self.light[above - 1][c],
            self.light[above][c],
        );
        g0 + (g1 - g0) * ((h - k0) / (k1 - k0)).clamp(0.0, 1.0)
    }

    /// Whether any ball of the ladder returns more than the half-space in
    /// some channel.
    pub fn raises(&self) -> bool {
        self.light.iter().flatten().any(|&g| g > 1.0)
    }

    /// The scale each channel's curvature is read at, mm
    /// ([`Self::gains`]).
    pub fn curvature_scales(&self) -> [f32; 3] {
        self.scale
    }

    /// The gain at every surfel, per channel, in [1, [`MAX_GAIN`]]:
    /// B(1/H)/S(min(t, 2/H)), with `curvature` each surfel's mean
    /// curvature H at each channel's [`Self::curvature_scales`], `opposites` the
    /// face behind each and `slab` the model's slabs.
    pub fn gains(
        &self,
        curvature: &[[f32; 3]],
        opposites: &[Option<Opposite>],
        slab: &LocalSlab,
    ) -> Vec<[f32; 3]> {
        let mut gains = vec![[1.0f32; 3]; curvature.len()];
        if !self.raises() {
            return gains;
        }
        let level = slab.level();
        for c in 0..3 {
            for (i, (g, h)) in gains.iter_mut().zip(curvature).enumerate() {
                let h = h[c];
                let ball = self.at(f64::from(h), c);
                if ball <= 1.0 {
                    continue;
                }
                let behind = opposites.get(i).copied().flatten().map(|o| o.thickness);
                let thickness = behind.map_or(2.0 / h, |t| t.min(2.0 / h));
                let model = slab
                    .at(thickness)
                    .map_or(1.0, |s| (s.kept[c] + s.sent[c]) / level[c]);
                let gain = ball / model;
                g[c] = if gain.is_finite() {
                    gain.clamp(1.0, MAX_GAIN) as f32
                } else {
                    1.0
                };
            }
        }
        gains
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ladder() -> BallGain {
        BallGain {
            scale: [1.0; 3],
            curvature: vec![0.0, 0.1, 0.5],
            light: vec![[1.0; 3], [1.2, 1.1, 1.0], [2.0, 1.5, 1.0]],
            unfinished: [0.0; 3],
        }
    }

    #[test]
    fn the_gain_is_linear_in_curvature_and_one_where_nothing_bulges() {
        let g = ladder();
        assert_eq!(g.at(0.0, 0), 1.0);
        assert_eq!(g.at(-0.3, 0), 1.0);
        assert_eq!(g.at(f64::NAN, 0), 1.0);
        assert!((g.at(0.05, 0) - 1.1).abs() < 1e-12);
        assert!((g.at(0.3, 1) - 1.3).abs() < 1e-12);
        // Past the smallest ball: its gain, not an extrapolation.
        assert_eq!(g.at(10.0, 0), 2.0);
        assert_eq!(g.at(f64::INFINITY, 0), 2.0);
        assert!(g.raises());
        assert!(!BallGain::none().raises());
    }
}
