//! The map summed at a lattice of texels and carried to the texels
//! between, where the profile spreads light over many texels.
//!
//! The exitance M = N + F at each texel: N, the exact sum over the sources
//! within a few texels (the profile's sharp core, which carries a shadow's
//! edge), and F, the rest, a sum over a disk no narrower than the
//! lattice's cell, which changes over that spread, not from texel to
//! texel. F is found at the lattice alone (the integrator's sum there less
//! N) and carried to each texel between by the bilinear mean of the four
//! lattice texels around it, where they lie on its surface; a texel
//! without four (a chart's edge, a crease, a part smaller than the cell)
//! is carried from a lattice half as wide, down to its own sum. Where the
//! light entering is itself bilinear over the cells about a texel
//! ([`smooth`]), so is N, and the whole map is carried, N and all: N is
//! summed only near a shadow's edge, a terminator, a chart's edge and
//! small texels, and at the lattice texels around them.
//!
//! The carried map is checked against the integrator's own sums at random
//! texels; where it misses by more than [`FIT_SHARE`] of the tolerance the
//! lattice's step halves (rounding up), down to every texel. The error
//! estimate measures the map that results against the exact sum, fit and
//! all.

use crate::control::Cancelled;
use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::transport::accuracy::relative_errors;
use crate::transport::brute::{Reach, sum_within};
use crate::transport::integrator::Summer;
use crate::transport::kernel::Kernel;
use crate::transport::verify::pick;
use serde::{Deserialize, Serialize};

mod carrier;
mod near_reach;
mod smooth;

pub use carrier::Carrier;

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

/// N's reach, in the texels about each target ([`near_reach`]): the
/// pairs it sums at every texel are mostly a texel's own and its
/// neighbours', weighed by sub-samples, and cost more than the gathers at
/// the lattice; on the head in skin1 at 2048² the fit at a step of 6
/// missed by 0.25% at 2 texels, 0.24% at 3 and 0.21% at 6, for 9, 11 and
/// 18 s (texels then counted in the map's mean texel).
const NEAR_TEXELS: f64 = 2.0;

/// The share of the tolerance by which the light entering may miss its
/// bilinear mean over a lattice's cells around a texel and the map there
/// still be carried whole, N and all (N, a part of the map, then misses
/// by less, and the fit's check counts it). On the head in skin1 at 2048²
/// a share of 1 carries 66% of the texels whole and moves the map by
/// 0.01–0.07% (relative RMSE per channel) from N at every texel.
const SMOOTH_SHARE: f64 = 0.5;

/// One texel in this many is probed, and at most [`MOST_PROBED`].
const PROBED: usize = 64;
/// The fewest texels the fit is checked at (every texel of a smaller
/// object).
const FEWEST_PROBED: usize = 1024;
/// The most texels the fit is checked at.
const MOST_PROBED: usize = 16_384;

/// How many of `texels` a fit is checked at: one in [`PROBED`], at least
/// [`FEWEST_PROBED`] (every texel of a smaller object) and at most
/// [`MOST_PROBED`], whose relative RMSE is then known within about 1%
/// of itself.
pub fn probe_count(texels: usize) -> usize {
    (texels / PROBED)
        .clamp(FEWEST_PROBED, MOST_PROBED)
        .min(texels)
}

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

/// N of M = N + F: the exact sum within a short reach of chosen texels.
pub trait NearSum: Sync {
    /// The exitance (W/m²) at the texels `listed`, in order, from the
    /// sources within each one's reach (`reaches`, one per texel).
    fn within(
        &self,
        listed: &[usize],
        reaches: &[Reach],
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled>;
}

impl<T: NearSum + ?Sized> NearSum for &T {
    fn within(
        &self,
        listed: &[usize],
        reaches: &[Reach],
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        (**self).within(listed, reaches, control)
    }
}

/// N under one kernel, by the exact sum over `lit`'s texels.
struct KernelNear<'a> {
    lit: &'a Prepared,
    kernel: &'a Kernel,
}

impl NearSum for KernelNear<'_> {
    fn within(
        &self,
        listed: &[usize],
        reaches: &[Reach],
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        let targets = self.lit.listed(listed);
        let sources = self.lit.texel_sources();
        sum_within(self.kernel, &sources, targets.targets(), reaches, control)
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
    let all: Vec<usize> = (0..lit.surfels.len()).collect();
    let carrier = Carrier::split(lit, summer, kernel, tolerance);
    fitted_at(carrier, summer, &all, step, tolerance, control)
}

/// The map at `texels` by `carrier` (which splits M = N + F) and its
/// summer: carried from a lattice of `step` texels where the fit at
/// [`probe_count`] of them holds, the step halved (rounding up) where not,
/// else summed at each (and summed at each where every one is probed).
/// The fit holds where it misses the summer's own sums by at most
/// [`FIT_SHARE`] of `tolerance`; where the summer has finer sums
/// ([`Summer::finer`]), where it is no farther from them than the
/// summer's own sums are, with that share added in quadrature. With how
/// it was found.
pub fn fitted_at(
    mut carrier: Carrier,
    summer: &dyn Summer,
    texels: &[usize],
    step: u32,
    tolerance: f64,
    control: &Control,
) -> Result<(Vec<[f32; 3]>, MapFit), Error> {
    let every = |probed| MapFit {
        step: 1,
        missed: 0.0,
        probed,
    };
    if step <= 1 || texels.is_empty() {
        return Ok((summer.at(texels, control)?, every(0)));
    }
    let probes: Vec<usize> = pick(texels.len(), probe_count(texels.len()), 0x6669_7474)
        .into_iter()
        .map(|k| texels[k])
        .collect();
    // So few texels that every one is probed: their sums are the map.
    if probes.len() == texels.len() {
        return Ok((summer.at(texels, control)?, every(0)));
    }
    // N before the summer's first sums: the exact sum's table and the
    // integrator's (the octree's tree) are not held at once.
    carrier.near_for(texels, step, control)?;
    let direct = summer.at(&probes, control)?;
    // Against finer sums where the summer has them, the fit may add its
    // share of the tolerance, in quadrature, to the summer's own error.
    let finer = summer.finer(&probes, control).transpose()?;
    let own = finer.as_ref().map(|fine| relative_errors(&direct, fine).0);
    let mut step = step;
    while step > 1 {
        let fitted = carrier.at(&probes, step, control)?;
        let (missed, _) = relative_errors(&fitted, &direct);
        let holds = match (&finer, own) {
            (Some(fine), Some(own)) => {
                let (off, _) = relative_errors(&fitted, fine);
                off <= own.hypot(FIT_SHARE * tolerance)
            }
            _ => missed <= FIT_SHARE * tolerance,
        };
        if holds {
            let fit = MapFit {
                step,
                missed,
                probed: probes.len(),
            };
            return Ok((carrier.last_map(texels, step, control)?, fit));
        }
        step = step.div_ceil(2);
    }
    Ok((carrier.last_map(texels, 1, control)?, every(probes.len())))
}
