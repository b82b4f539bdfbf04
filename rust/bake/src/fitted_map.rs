//! The map summed at a lattice of texels and carried to the texels
//! between, where the profile spreads light over many texels.
//!
//! The exitance M = N + F at each texel: N, the exact sum over the sources
//! within a few texels (the profile's sharp core, which carries a shadow's
//! edge), is found at every texel and is cheap; F, the rest, is a sum over
//! a disk no narrower than the lattice's cell and changes over that
//! spread, not from texel to texel. F is found at the lattice alone (the
//! integrator's sum there less N) and carried to each texel between by the
//! bilinear mean of the four lattice texels around it, where they lie on
//! its surface; a texel without four (a chart's edge, a crease, a part
//! smaller than the cell) is carried from a lattice half as wide, down to
//! its own sum. The work at every texel is then N's dozen pairs, not a
//! whole gather of hundreds of nodes and texels.
//!
//! The carried map is checked against the integrator's own sums at random
//! texels; where it misses by more than [`FIT_SHARE`] of the tolerance the
//! lattice's step halves (rounding up), down to every texel. The error
//! estimate measures the map that results against the exact sum, fit and
//! all.

use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::surface::lattice::Lattice;
use crate::transport::accuracy::relative_errors;
use crate::transport::brute::{Reach, sum_within};
use crate::transport::integrator::Summer;
use crate::transport::kernel::Kernel;
use crate::transport::sources::{OwnSource, Targets};
use crate::transport::verify::pick;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The share of the tolerance the fit may miss by (relative RMSE at the
/// probed texels): its error and the integrator's add about in quadrature,
/// and the pilot refines the integrator above 0.9 of the tolerance
/// (√(0.9² + 0.4²) < 1). The check overstates what the fit adds, since it
/// counts the integrator's own jitter between neighbouring texels, which
/// the fit smooths: on the head in skin1 at 1024² a fit missing by 0.36%
/// moved the estimate from 0.86% to 0.87%.
pub const FIT_SHARE: f64 = 0.4;

/// The widest lattice step, texels: the gathers at the lattice fall as its
/// square, and past 8 they are a small share beside N at every texel (on
/// the head in skin1 at 2048², 2.4 s at a step of 6 against N's 8.6 s).
pub const MOST_STEP: u32 = 8;

/// N's reach, in mean texels: the pairs it sums at every texel are
/// mostly a texel's own and its neighbours', weighed by sub-samples, and
/// cost more than the gathers at the lattice; on the head in skin1 at
/// 2048² the fit at a step of 6 misses by 0.25% at 2 texels, 0.24% at 3
/// and 0.21% at 6, for 9, 11 and 18 s.
const NEAR_TEXELS: f64 = 2.0;

/// One texel in this many is probed, and at most [`MOST_PROBED`].
const PROBED: usize = 64;
/// The fewest texels the fit is checked at (every texel of a smaller
/// object).
const FEWEST_PROBED: usize = 1024;
/// The most texels the fit is checked at.
const MOST_PROBED: usize = 16_384;

/// The cosine between two texels' normals above which one lies on the
/// other's surface and carries its share of the map.
const SAME_FACING: f32 = 0.9;

/// How the map was found: the lattice's step and how far the fit missed
/// the integrator's own sums at the probed texels.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapFit {
    /// Texels between lattice texels along u and along v (1: the map was
    /// summed at every texel).
    pub step: u32,
    /// The relative RMSE of the carried map against the integrator's sums
    /// at the probed texels (0 at step 1).
    pub missed: f64,
    /// The texels probed.
    pub probed: usize,
}

/// The lattice's first step for a profile whose narrowest channel holds
/// half its light within `half_light` texels: twice that, so a cell is no
/// wider than the spread it carries, from 1 (every texel) to
/// [`MOST_STEP`].
pub fn first_step(half_light: Option<f64>) -> u32 {
    match half_light {
        Some(h) if h.is_finite() && h > 0.0 => {
            (2.0 * h).floor().clamp(1.0, MOST_STEP as f64) as u32
        }
        _ => 1,
    }
}

/// The map of `lit` (the light as it enters, raised where the model raises
/// it) under `kernel` by `summer`: carried from a lattice of `step` texels
/// where the fit holds within [`FIT_SHARE`] of `tolerance`, else summed at
/// every texel. With how it was found.
pub fn fitted_map(
    lit: &Prepared,
    summer: &dyn Summer,
    kernel: &Kernel,
    step: u32,
    tolerance: f64,
    control: &Control,
) -> Result<(Vec<[f32; 3]>, MapFit), Error> {
    let texels = lit.surfels.len();
    let all: Vec<usize> = (0..texels).collect();
    if step <= 1 || texels == 0 {
        let fit = MapFit {
            step: 1,
            missed: 0.0,
            probed: 0,
        };
        return Ok((summer.at(&all, control)?, fit));
    }
    // N before the summer's first sums: the exact sum's table and the
    // integrator's (the octree's tree) are not held at once.
    let mut carrier = Carrier::split(lit, summer, kernel, control)?;
    let probed = (texels / PROBED).clamp(FEWEST_PROBED, MOST_PROBED);
    let probes = pick(texels, probed.min(texels), 0x6669_7474);
    let direct = summer.at(&probes, control)?;
    let mut step = step;
    while step > 1 {
        let fitted = carrier.at(&probes, step, control)?;
        let (missed, _) = relative_errors(&fitted, &direct);
        if missed <= FIT_SHARE * tolerance {
            let fit = MapFit {
                step,
                missed,
                probed: probes.len(),
            };
            return Ok((carrier.at(&all, step, control)?, fit));
        }
        step = step.div_ceil(2);
    }
    let fit = MapFit {
        step: 1,
        missed: 0.0,
        probed: probes.len(),
    };
    Ok((carrier.at(&all, 1, control)?, fit))
}

/// One object's map carried from lattices of texels: N at every texel
/// (none when carried whole), and the integrator's sums at the lattice
/// texels summed so far (NaN elsewhere).
pub struct Carrier<'a> {
    lit: &'a Prepared,
    summer: &'a dyn Summer,
    near: Vec<[f32; 3]>,
    summed: Vec<[f32; 3]>,
}

impl<'a> Carrier<'a> {
    /// The map of `lit` under `kernel` split as M = N + F, N (the sum
    /// within [`NEAR_TEXELS`] mean texels, tapered) found at every texel.
    pub fn split(
        lit: &'a Prepared,
        summer: &'a dyn Summer,
        kernel: &Kernel,
        control: &Control,
    ) -> Result<Self, Error> {
        let every = Targets {
            own: OwnSource::Same,
            ..lit.targets()
        };
        let reach = Reach {
            radius: (NEAR_TEXELS * lit.surfels.mean_side()) as f32,
            tapered: true,
        };
        let near = sum_within(kernel, &lit.texel_sources(), every, reach, control)?;
        Ok(Carrier {
            lit,
            summer,
            summed: vec![[f32::NAN; 3]; near.len()],
            near,
        })
    }

    /// `summer`'s sums over `lit` carried whole (N = 0): for a light with
    /// no edges, whose sums change only over the profile's spread.
    pub fn whole(lit: &'a Prepared, summer: &'a dyn Summer) -> Self {
        let texels = lit.surfels.len();
        Carrier {
            lit,
            summer,
            near: Vec::new(),
            summed: vec![[f32::NAN; 3]; texels],
        }
    }

    /// N at texel `i` (0 when carried whole).
    fn near(&self, i: usize) -> [f32; 3] {
        self.near.get(i).copied().unwrap_or([0.0; 3])
    }

    /// The map at `texels`: each carried from the lattice of `step` texels
    /// where it has four corners on its surface, else from the lattice of
    /// half the step (rounding up), down to its own sum. The lattice texels
    /// it needs are summed once and kept.
    pub fn at(
        &mut self,
        texels: &[usize],
        step: u32,
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Error> {
        let surfels = &self.lit.surfels;
        let mut out = vec![[0.0f32; 3]; texels.len()];
        let mut pending: Vec<usize> = (0..texels.len()).collect();
        let mut step = step.max(1);
        let mut needed = vec![false; surfels.len()];
        loop {
            let lattice = Lattice::new(surfels, step);
            let mut missing = Vec::new();
            for &k in &pending {
                let around = lattice.around(surfels, texels[k]).into_iter().flatten();
                for j in around.filter_map(|(j, _)| j) {
                    if self.summed[j][0].is_nan() && !needed[j] {
                        needed[j] = true;
                        missing.push(j);
                    }
                }
            }
            self.sum(&missing, control)?;
            let carried: Vec<Option<[f32; 3]>> = pending
                .par_iter()
                .map(|&k| self.carry(&lattice, texels[k]))
                .collect();
            let mut left = Vec::new();
            for (k, m) in pending.into_iter().zip(carried) {
                match m {
                    Some(m) => out[k] = m,
                    None => left.push(k),
                }
            }
            // At step 1 every texel is its own corner, so none is left.
            if left.is_empty() || step == 1 {
                return Ok(out);
            }
            pending = left;
            step = step.div_ceil(2);
        }
    }

    /// The integrator's sums at `listed` (none known yet), kept.
    fn sum(&mut self, listed: &[usize], control: &Control) -> Result<(), Error> {
        for (&s, m) in listed.iter().zip(self.summer.at(listed, control)?) {
            self.summed[s] = m;
        }
        Ok(())
    }

    /// Texel `i`'s exitance: its own sum on the lattice; else its own N
    /// and the bilinear mean of F at the four lattice texels around it,
    /// where they lie on its surface (same medium, facing its way, within
    /// a cell's reach on the surface: a texel beside it in the layout may
    /// lie on another chart).
    fn carry(&self, lattice: &Lattice, i: usize) -> Option<[f32; 3]> {
        let surfels = &self.lit.surfels;
        if lattice.holds(surfels.texel[i]) && !self.summed[i][0].is_nan() {
            return Some(self.summed[i]);
        }
        let medium = |s: usize| surfels.piece.get(s).copied();
        let (p, n) = (surfels.position[i], surfels.normal[i]);
        let within = 1.5 * lattice.step as f32 * surfels.stretch[i].length();
        let alike = |j: usize| {
            !self.summed[j][0].is_nan()
                && medium(j) == medium(i)
                && surfels.normal[j].dot(n) > SAME_FACING
                && surfels.position[j].distance_squared(p) <= within * within
        };
        let corners = lattice.corners(surfels, i, alike)?;
        let far = |c: usize| -> f32 {
            corners
                .iter()
                .map(|&(j, w)| w * (self.summed[j][c] - self.near(j)[c]))
                .sum()
        };
        let near = self.near(i);
        Some([0, 1, 2].map(|c| near[c] + far(c)))
    }
}
