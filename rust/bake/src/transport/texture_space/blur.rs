//! Texture-space diffusion (d'Eon & Luebke 2007; Mikkelsen §3.4): the
//! profile as a sum of Gaussians, each a separable blur of the irradiance
//! texture, each built from the previous one by the difference of their
//! variances. Each texel's taps are spaced by its own stretch (mm per
//! texel along u and v), so the blur is measured on the surface, not in
//! UV space. Texels outside the layout are dilated first (across seams
//! where the caller gives seam-aware offsets) so blurs near chart borders
//! read the surface that continues there instead of black; beyond an open
//! edge of the mesh there is no surface, so they read nothing there, as
//! the exact sum does (half the light at a straight border).
//!
//! The blur knows only the surface around each texel in the layout: light
//! cannot cross thin parts (ears, nostrils) to the far face; the 3-D
//! integrators do that.

use crate::control::{Cancelled, Control};
use crate::surface::dilation::{ImageSides, SeamAwareDilation};
use crate::surface::texels::{EMPTY, TexelSurfels};
use rayon::prelude::*;
use sssbake_profile::models::gaussians::SumOfGaussians;

/// Blurs whose σ is below this many texels are skipped (a Gaussian that
/// narrow leaves a texel grid unchanged to within its sampling).
const SHARP: f32 = 0.2;

pub use crate::surface::dilation::MAX_REACH;

/// Texels within this many steps (in any of the 8 directions) of a texel
/// the layout leaves empty take the exact sum.
pub(super) const EDGE_RING: usize = 2;

/// Source visits the exact sum at those texels may take (a few seconds on
/// two cores); beyond (a long reach at a fine resolution) the blurs stand
/// there too, and the error check says what that costs.
pub(super) const EDGE_VISITS: f64 = 3e8;

/// Radiant exitance (W/m²) at each surfel by texture-space blurs of its
/// irradiance. `dilation` lists (empty texel, covered texel it copies) and
/// which lie beyond open edges.
///
/// The image is padded beyond its edges by the widest blur's reach and
/// blurred as a normalised convolution: the light and a mask of where
/// surface is known (1 on the layout, its dilation and beyond open edges,
/// where the surface is known to be absent and its light is 0; 0 beyond the
/// image where the chart continues past the edge, as across a seam the
/// layout cut there) are blurred alike and divided at the end. Light that
/// spreads past an open edge is kept in the padding, so each Gaussian built
/// from the previous one stays the blur of the original.
pub fn integrate(
    gaussians: &SumOfGaussians,
    surfels: &TexelSurfels,
    irradiance: &[[f32; 3]],
    dilation: &SeamAwareDilation,
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let n = surfels.resolution as usize;
    // Stretch per texel (mm per texel step), dilated with the irradiance.
    let mut stretch = vec![glam::Vec2::ZERO; n * n];
    for (s, &t) in surfels.texel.iter().enumerate() {
        stretch[t as usize] = surfels.stretch[s];
    }
    for &(to, from) in &dilation.offsets {
        stretch[to as usize] = stretch[from as usize];
    }
    let widest = gaussians
        .terms
        .iter()
        .flatten()
        .map(|&(_, v)| v)
        .fold(0.0f64, f64::max)
        .sqrt() as f32;
    let pad = border(n, widest, &stretch, &dilation.open_beyond_image);
    let frame = Frame::new(n, pad, &stretch, &dilation.open_beyond_image);
    let blurs: usize = gaussians.terms.iter().map(Vec::len).sum();
    control.plan((2 * blurs * frame.texels()) as u64);
    let mut out = vec![[0.0f32; 3]; surfels.len()];
    for c in 0..3 {
        let mut image = vec![0.0f32; n * n];
        for (s, &t) in surfels.texel.iter().enumerate() {
            image[t as usize] = irradiance[s][c];
        }
        for (&(to, from), &open) in dilation.offsets.iter().zip(&dilation.open) {
            image[to as usize] = if open { 0.0 } else { image[from as usize] };
        }
        let mut light = frame.embed(&image);
        let mut known = frame.known.clone();
        let mut terms = gaussians.terms[c].clone();
        terms.sort_by(|a, b| a.1.total_cmp(&b.1));
        // The power entering (irradiance × area, W/m² · mm²): no Gaussian
        // spreads more than its weight of it.
        let entering: f64 = (0..surfels.len())
            .map(|s| f64::from(irradiance[s][c]) * f64::from(surfels.area[s]))
            .sum();
        let mut variance = 0.0f64;
        let mut term = vec![0.0f32; surfels.len()];
        for (weight, v) in terms {
            let step = ((v - variance).max(0.0)) as f32;
            variance = v.max(variance);
            for axis in [Axis::U, Axis::V] {
                (light, known) = blur(&light, &known, &frame, step, axis, control)?;
            }
            for (s, &t) in surfels.texel.iter().enumerate() {
                let at = frame.at(t as usize);
                term[s] = if known[at] > 0.0 {
                    weight as f32 * light[at] / known[at]
                } else {
                    0.0
                };
            }
            // Dividing by the blurred mask fills in what lies past the
            // frame as if the surface went on lit alike: right across a
            // seam, but a blur wider than the whole object would spread
            // the mean light over an endless surface and return more
            // light than entered. The term keeps at most its share.
            let leaving: f64 = (0..surfels.len())
                .map(|s| f64::from(term[s]) * f64::from(surfels.area[s]))
                .sum();
            let most = weight * entering;
            let scale = if leaving > most && leaving > 0.0 {
                (most / leaving) as f32
            } else {
                1.0
            };
            for (m, t) in out.iter_mut().zip(&term) {
                m[c] += scale * t;
            }
        }
    }
    Ok(out)
}

/// The surfels within `ring` texel steps of an empty texel or of the
/// image's edge, in surfel order.
pub(super) fn near_chart_edges(surfels: &TexelSurfels, ring: usize) -> Vec<usize> {
    let n = surfels.resolution as usize;
    let empty = |x: isize, y: isize| {
        x < 0
            || y < 0
            || x >= n as isize
            || y >= n as isize
            || surfels.index[y as usize * n + x as usize] == EMPTY
    };
    let r = ring as isize;
    (0..surfels.len())
        .into_par_iter()
        .filter(|&s| {
            let t = surfels.texel[s] as usize;
            let (x, y) = ((t % n) as isize, (t / n) as isize);
            (-r..=r).any(|dy| (-r..=r).any(|dx| empty(x + dx, y + dy)))
        })
        .collect()
}

/// Texels of border the widest blur (σ `widest`, mm) needs beyond the
/// image: its reach from the texels at open edges (none where no chart
/// ends at the image's edge, since then the border is never read), at
/// most half the image: a blur wider than the object is nearly flat over
/// it, and light spread past that border is left out of the light and
/// the mask alike.
fn border(n: usize, widest: f32, stretch: &[glam::Vec2], open: &ImageSides) -> usize {
    let most = (n / 2).min(MAX_REACH as usize);
    let reach = |step: f32| {
        if step > 0.0 {
            ((3.0 * widest / step).ceil() as usize).min(most)
        } else {
            0
        }
    };
    let mut pad = 0;
    for i in 0..n {
        for (flag, texel, vertical) in [
            (open.left[i], i * n, false),
            (open.right[i], i * n + n - 1, false),
            (open.bottom[i], i, true),
            (open.top[i], (n - 1) * n + i, true),
        ] {
            if flag {
                let s = stretch[texel];
                pad = pad.max(reach(if vertical { s.y } else { s.x }));
            }
        }
    }
    pad
}

/// The image inside a border of `pad` texels on every side.
struct Frame {
    n: usize,
    pad: usize,
    side: usize,
    /// mm per texel step along u and v at each framed texel, the
    /// border's copied from the nearest edge.
    step: [Vec<f32>; 2],
    /// 1 where the surface is known (the image, and the border beyond open
    /// edges), 0 beyond the image where the chart continues.
    known: Vec<f32>,
}

impl Frame {
    fn new(n: usize, pad: usize, stretch: &[glam::Vec2], open: &ImageSides) -> Self {
        let side = n + 2 * pad;
        let mut framed = vec![glam::Vec2::ZERO; side * side];
        let mut known = vec![0.0f32; side * side];
        for fy in 0..side {
            for fx in 0..side {
                let (x, y) = (fx as i64 - pad as i64, fy as i64 - pad as i64);
                let (cx, cy) = (x.clamp(0, n as i64 - 1), y.clamp(0, n as i64 - 1));
                let (cx, cy) = (cx as usize, cy as usize);
                framed[fy * side + fx] = stretch[cy * n + cx];
                let beyond_x = match x {
                    _ if x < 0 => Some(open.left[cy]),
                    _ if x >= n as i64 => Some(open.right[cy]),
                    _ => None,
                };
                let beyond_y = match y {
                    _ if y < 0 => Some(open.bottom[cx]),
                    _ if y >= n as i64 => Some(open.top[cx]),
                    _ => None,
                };
                let inside = match (beyond_x, beyond_y) {
                    (None, None) => true,
                    (Some(a), None) | (None, Some(a)) => a,
                    (Some(a), Some(b)) => a && b,
                };
                known[fy * side + fx] = if inside { 1.0 } else { 0.0 };
            }
        }
        Frame {
            n,
            pad,
            side,
            step: [
                framed.iter().map(|s| s.x).collect(),
                framed.iter().map(|s| s.y).collect(),
            ],
            known,
        }
    }

    fn texels(&self) -> usize {
        self.side * self.side
    }

    /// The framed index of image texel `t`.
    fn at(&self, t: usize) -> usize {
        (t / self.n + self.pad) * self.side + t % self.n + self.pad
    }

    /// `image` (N × N) in the frame, 0 in the border.
    fn embed(&self, image: &[f32]) -> Vec<f32> {
        let mut framed = vec![0.0f32; self.texels()];
        for (t, &v) in image.iter().enumerate() {
            framed[self.at(t)] = v;
        }
        framed
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Axis {
    U,
    V,
}

/// Texels of a row blurred together: their taps are stepped in lock-step,
/// so each step is a vector instruction over the block.
const BLOCK: usize = 32;

/// One 1-D Gaussian pass of `variance` (mm²) along `axis` over the framed
/// light and the mask of known surface alike (the same taps for both),
/// gathering: each texel's σ in texels is √variance over its own step (mm
/// per texel along the axis), its taps reach ⌈3σ⌉ and are normalised by
/// their sum. Taps beyond the frame read nothing.
///
/// The taps at ±k are walked for a block of texels of a row at once: along
/// v they read rows y ± k, along u the row shifted by ±k, both contiguous.
/// Each texel's weights exp(−k²/2σ²) follow the recurrence
/// w(k+1) = w(k)·q^(2k+1), q = exp(−1/2σ²): two products a tap instead of
/// an exponential, with a relative drift of a few ulps per tap.
fn blur(
    light: &[f32],
    known: &[f32],
    frame: &Frame,
    variance: f32,
    axis: Axis,
    control: &Control,
) -> Result<(Vec<f32>, Vec<f32>), Cancelled> {
    let side = frame.side;
    if variance <= 0.0 {
        control.advance(light.len() as u64)?;
        return Ok((light.to_vec(), known.to_vec()));
    }
    let sigma_mm = variance.sqrt();
    let step = &frame.step[axis as usize];
    let mut out = vec![0.0f32; light.len()];
    let mut out_known = vec![0.0f32; known.len()];
    out.par_chunks_mut(side)
        .zip(out_known.par_chunks_mut(side))
        .enumerate()
        .try_for_each(|(y, (row, row_known))| {
            control.check()?;
            let line = y * side;
            for x0 in (0..side).step_by(BLOCK) {
                let width = BLOCK.min(side - x0);
                let taps = Taps::new(&step[line + x0..][..width], sigma_mm);
                let source = Source { light, known, side };
                let (y, x0) = (y as isize, x0 as isize);
                let (sum, sum_known) = match axis {
                    Axis::U => taps.gather(width, |k| {
                        let k = k as isize;
                        (source.run(y, x0 + k, width), source.run(y, x0 - k, width))
                    }),
                    Axis::V => taps.gather(width, |k| {
                        let k = k as isize;
                        (source.run(y + k, x0, width), source.run(y - k, x0, width))
                    }),
                };
                let x0 = x0 as usize;
                row[x0..x0 + width].copy_from_slice(&sum[..width]);
                row_known[x0..x0 + width].copy_from_slice(&sum_known[..width]);
            }
            control.advance(side as u64)
        })?;
    Ok((out, out_known))
}

/// A run of source values: (texels of the block before it starts, light,
/// known); values past its end read nothing.
type Run<'a> = (usize, &'a [f32], &'a [f32]);

/// The framed light and mask a pass reads.
struct Source<'a> {
    light: &'a [f32],
    known: &'a [f32],
    side: usize,
}

impl<'a> Source<'a> {
    /// The `width` texels of row `y` from column `x`, clipped to the frame.
    fn run(&self, y: isize, x: isize, width: usize) -> Run<'a> {
        let side = self.side as isize;
        if !(0..side).contains(&y) {
            return (0, &self.light[..0], &self.known[..0]);
        }
        let (from, to) = (x.clamp(0, side), (x + width as isize).clamp(0, side));
        let line = y as usize * self.side;
        let range = line + from as usize..line + to.max(from) as usize;
        (
            (from - x).max(0) as usize,
            &self.light[range.clone()],
            &self.known[range],
        )
    }
}

/// The Gaussian taps of a block of texels.
struct Taps {
    /// Reach per texel in taps either side (0: the texel is left as it is).
    reach: [u32; BLOCK],
    /// q = exp(−1/2σ²) per texel.
    q: [f32; BLOCK],
    /// The widest reach in the block.
    widest: u32,
}

impl Taps {
    fn new(step: &[f32], sigma_mm: f32) -> Self {
        let (mut reach, mut q) = ([0u32; BLOCK], [0.0f32; BLOCK]);
        for (i, &s) in step.iter().enumerate() {
            let sigma = if s > 0.0 { sigma_mm / s } else { 0.0 };
            if sigma >= SHARP {
                reach[i] = ((3.0 * sigma).ceil() as u32).min(MAX_REACH);
                q[i] = (-0.5 / (sigma * sigma)).exp();
            }
        }
        let widest = reach.iter().copied().max().unwrap_or(0);
        Taps { reach, q, widest }
    }

    /// The normalised sums of light and known over each texel's taps;
    /// `runs(k)` gives the sources k taps ahead and behind.
    #[inline]
    fn gather<'a>(
        &self,
        width: usize,
        runs: impl Fn(u32) -> (Run<'a>, Run<'a>),
    ) -> ([f32; BLOCK], [f32; BLOCK]) {
        let ((_, centre, centre_known), _) = runs(0);
        let (mut sum, mut sum_known) = ([0.0f32; BLOCK], [0.0f32; BLOCK]);
        sum[..width].copy_from_slice(&centre[..width]);
        sum_known[..width].copy_from_slice(&centre_known[..width]);
        let (mut weight, mut ratio, mut norm) = ([1.0f32; BLOCK], self.q, [1.0f32; BLOCK]);
        let mut tap = [0.0f32; BLOCK];
        for k in 1..=self.widest {
            for i in 0..BLOCK {
                weight[i] *= ratio[i];
                ratio[i] *= self.q[i] * self.q[i];
                tap[i] = if k <= self.reach[i] { weight[i] } else { 0.0 };
                norm[i] += 2.0 * tap[i];
            }
            let (ahead, behind) = runs(k);
            for (skip, values, known) in [ahead, behind] {
                let end = (skip + values.len()).min(width);
                for i in skip..end {
                    sum[i] += tap[i] * values[i - skip];
                    sum_known[i] += tap[i] * known[i - skip];
                }
            }
        }
        for i in 0..BLOCK {
            sum[i] /= norm[i];
            sum_known[i] /= norm[i];
        }
        (sum, sum_known)
    }
}
