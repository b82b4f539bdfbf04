//! How far a bake's exitance is from the exact sum, estimated where it is
//! cheap: the exact sum at one texel costs one gather, so a few thousand
//! random texels measure any method's error without running the reference
//! everywhere.

use super::brute;
use crate::control::Control;
use crate::error::Error;
use crate::prepared::{Prepared, Raised};
use crate::scattering::Scattering;
use crate::transport::accuracy::relative_errors;
use crate::transport::integrator::Integrator;
use crate::transport::local_slab::{LocalSlab, MAX_GAIN};
use sssbake_profile::numerics::rng::Rng;

/// Most texels checked.
const MOST_CHECKED: usize = 4096;
/// Fewest texels checked (fewer only when the object has fewer).
const FEWEST_CHECKED: usize = 64;
/// Source visits the check may spend (a few seconds at most): with long
/// reaches it checks fewer texels, never fewer than [`FEWEST_CHECKED`].
const VISIT_BUDGET: f64 = 1e8;

/// The solid angle (sr) at which the estimate sums thin parts by their own
/// slab's profile, at most a sixteenth of the bake's own for them: their
/// exact sums read every texel within a slab's reach, on the bundled ear
/// every texel of it (10 million at 4096², 38 s of a 142 s bake). On the
/// ear at 2048² these sums are 0.05% (the light's; the unit light's
/// 0.04%; relative RMSE over R, G, B) from the exact sums at the 63
/// checked thin texels, at a sixth of the cost; at 0.005 sr, 0.10% there
/// and 0.04% at 1024²; at 0.02 sr, 0.19% at 1024².
pub(crate) const THIN_REFERENCE_EPSILON: f32 = 0.002;

/// An estimate of a map's error against the exact sum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorEstimate {
    /// Relative RMSE over the checked texels and channels:
    /// RMS(M − M_exact)/RMS(M_exact).
    pub relative_rmse: f64,
    /// How many texels were checked.
    pub texels: usize,
}

/// Estimates the relative RMSE of `exitance` (after the colour split, as
/// `Prepared::integrate` returns it) against the exact sum at a seeded
/// random subset of texels, with `kept` of the light where the integration
/// kept less ([`crate::pipeline::Integration::kept`]); `neighbours` is the
/// mean count of texels within the profile's reach, which sets how many
/// are affordable. Where the bake `raised` the light entering, the
/// estimate counts the error of its gains too ([`half_space_exact`],
/// [`crate::transport::slab_profiles`]'s exitance at chosen texels).
/// Thin parts by their own slab's profile, which the bake summed at solid
/// angle `thin_epsilon`, are summed at [`THIN_REFERENCE_EPSILON`] or a
/// sixteenth of it, whichever is finer.
#[allow(clippy::too_many_arguments)]
pub fn estimate_error(
    prepared: &Prepared,
    scattering: &Scattering,
    exitance: &[[f32; 3]],
    raised: Option<&Raised>,
    kept: Option<[f32; 3]>,
    neighbours: f64,
    thin_epsilon: f32,
    seed: u64,
    control: &Control,
) -> Result<ErrorEstimate, Error> {
    let texels = prepared.surfels.position.len();
    let picked = pick(texels, checked(texels, neighbours), seed);
    // Thin parts by their slab's profile where the bake took it; the
    // half-space's exact sums only where some channel is not.
    let reference = THIN_REFERENCE_EPSILON.min(thin_epsilon / 16.0);
    let by_slab = match (raised, scattering.slab_profiles()) {
        (Some(r), Some(profiles)) => {
            profiles.exitance(prepared, &picked, &r.halves, &r.ball, reference, control)?
        }
        _ => vec![[None; 3]; picked.len()],
    };
    let by_half_space = |by: &[Option<f32>; 3]| by.iter().any(Option::is_none);
    let wanted: Vec<usize> = picked
        .iter()
        .zip(&by_slab)
        .filter(|(_, by)| by_half_space(by))
        .map(|(&i, _)| i)
        .collect();
    let mut half_space =
        half_space_exact(prepared, scattering, &wanted, raised, kept, control)?.into_iter();
    let kept = kept.unwrap_or([1.0; 3]);
    let exact: Vec<[f32; 3]> = picked
        .iter()
        .zip(&by_slab)
        .map(|(&i, by)| {
            let m = if by_half_space(by) {
                half_space.next().unwrap_or_default()
            } else {
                [0.0; 3]
            };
            let m = [0, 1, 2].map(|c| by[c].map_or(m[c], |v| v * kept[c]));
            prepared.after_scattering(i, m)
        })
        .collect();
    let got: Vec<[f32; 3]> = picked.iter().map(|&i| exitance[i]).collect();
    let (relative_rmse, _) = relative_errors(&got, &exact);
    Ok(ErrorEstimate {
        relative_rmse,
        texels: picked.len(),
    })
}

/// The exact model's exitance (before the colour after scattering) at
/// `picked` by the half-space's profile, corrected by the slab of each
/// texel's thickness and raised as the bake raised it, with `kept` of the
/// light where the integration kept less.
///
/// Where the integration `raised` the light entering, its gains came from
/// its own sums under a unit light, with its own error. The exact sum
/// raises the light by the same gains, and the exact gains at the checked
/// texels (from the exact sums under a unit light there and behind) scale
/// it: to first order in an error of the gains that varies slowly within
/// the reach, the exact model's exitance. So the estimate counts the
/// gains' error too.
fn half_space_exact(
    prepared: &Prepared,
    scattering: &Scattering,
    picked: &[usize],
    raised: Option<&Raised>,
    kept: Option<[f32; 3]>,
    control: &Control,
) -> Result<Vec<[f32; 3]>, Error> {
    if picked.is_empty() {
        return Ok(Vec::new());
    }
    let slab = scattering.local_slab();
    let opposites = slab.map_or_else(Default::default, |s| prepared.opposites(s.reach()));
    let (behind, gathered) = match slab {
        Some(slab) => slab.behind(&opposites, picked),
        None => (vec![None; picked.len()], picked.to_vec()),
    };
    let listed = prepared.listed(&gathered);
    let targets = listed.targets();
    let mut sources = prepared.texel_sources();
    // The light entering as the bake raised it where the surface ends.
    if let Some(raised) = raised {
        for (e, g) in sources.irradiance.iter_mut().zip(&raised.halves) {
            *e = [0, 1, 2].map(|c| e[c] * g[c]);
        }
    }
    // The oblique exact sum where the material has one: the estimate then
    // counts what an azimuthal-mean method misses of each light's direction.
    // Where the bake raised its light, the exact sums under a unit light
    // (the integration's gains were found under it too) give the exact
    // gains at the checked texels; both sums walk the pairs once.
    let (sums, exact_gains) = match (raised, slab) {
        (Some(_), Some(slab)) => {
            let [sums, uniform] =
                brute::exact_sum_and_unit(prepared, scattering, &sources, targets, control)?;
            let mut behind_uniform = uniform[picked.len()..].iter();
            let gains: Vec<[f64; 3]> = picked
                .iter()
                .zip(&behind)
                .zip(&uniform)
                .map(|((&i, behind), here)| {
                    let (shares, _) = slab.shares_at(opposites[i]);
                    let there = match behind {
                        Some(_) => behind_uniform.next().copied().unwrap_or(*here),
                        None => *here,
                    };
                    slab.gain(&shares, (*here, there), true)
                })
                .collect();
            (sums, Some(gains))
        }
        _ => (
            brute::exact_sum(prepared, scattering, &sources, targets, control)?.0,
            None,
        ),
    };
    let mut others = sums[picked.len()..].iter();
    Ok(picked
        .iter()
        .zip(&sums)
        .zip(&behind)
        .enumerate()
        .map(|(k, ((&i, &here), behind))| {
            // The sums behind follow the picked ones, in the same order.
            let corrected = match (slab, behind) {
                (Some(slab), Some(_)) => {
                    let (shares, _) = slab.shares_at(opposites[i]);
                    let there = others.next().copied().unwrap_or(here);
                    LocalSlab::corrected(&shares, here, there, true)
                }
                (Some(slab), None) => LocalSlab::corrected(&slab.thick(), here, here, true),
                (None, _) => here,
            };
            let kept = kept.unwrap_or([1.0; 3]);
            raised.map_or(corrected, |r| {
                let h = r.halves[i];
                // The bake's gain h², the exact one g: the light entering
                // and leaving both scale by g/h² to first order.
                // The ball's part of the gain is found without an
                // integrator and is exact as it is.
                let ball = r.ball.get(i).copied().unwrap_or([1.0; 3]);
                let g = exact_gains.as_ref().map_or([1.0; 3], |g| {
                    [0, 1, 2].map(|c| {
                        let exact = (g[k][c] * f64::from(ball[c])).min(MAX_GAIN);
                        (exact / f64::from(h[c] * h[c])) as f32
                    })
                });
                [0, 1, 2].map(|c| corrected[c] * h[c] * kept[c] * g[c])
            })
        })
        .collect())
}

/// How many of `texels` texels the estimate checks when `neighbours` lie
/// within the profile's reach of each.
fn checked(texels: usize, neighbours: f64) -> usize {
    let affordable = (VISIT_BUDGET / neighbours.max(1.0)) as usize;
    affordable.clamp(FEWEST_CHECKED, MOST_CHECKED).min(texels)
}

/// The relative RMSE `integrator` would make against the exact sum,
/// predicted before it runs: its pilot sums ([`Integrator::summer`]) at a
/// quarter of the texels the estimate checks (at least
/// [`FEWEST_CHECKED`]), against the exact sums there. Both are the sums
/// before the corrections, which would change both alike. `None` when the
/// integrator has no pilot.
pub fn predict_error(
    prepared: &Prepared,
    scattering: &Scattering,
    integrator: &dyn Integrator,
    neighbours: f64,
    seed: u64,
    control: &Control,
) -> Result<Option<ErrorEstimate>, Error> {
    let texels = prepared.surfels.position.len();
    let count = (checked(texels, neighbours) / 4)
        .max(FEWEST_CHECKED)
        .min(texels);
    let picked = pick(texels, count, seed);
    let Some(summer) = integrator.summer(prepared, scattering) else {
        return Ok(None);
    };
    let got = summer.at(&picked, control)?;
    // The integrator's tree goes before the exact sum's table comes.
    drop(summer);
    let sources = prepared.texel_sources();
    let listed = prepared.listed(&picked);
    let (exact, _) = brute::exact_sum(prepared, scattering, &sources, listed.targets(), control)?;
    let (relative_rmse, _) = relative_errors(&got, &exact);
    Ok(Some(ErrorEstimate {
        relative_rmse,
        texels: picked.len(),
    }))
}

/// `count` distinct indices below `n`, drawn by a seeded Fisher–Yates
/// prefix (all of them, in order, when `count ≥ n`).
pub(crate) fn pick(n: usize, count: usize, seed: u64) -> Vec<usize> {
    if count >= n {
        return (0..n).collect();
    }
    let mut index: Vec<usize> = (0..n).collect();
    let mut rng = Rng::new(seed, 0x7665_7269_6679);
    for i in 0..count {
        let j = i + (rng.next_u64() % (n - i) as u64) as usize;
        index.swap(i, j);
    }
    index.truncate(count);
    index
}

#[cfg(test)]
mod tests {
    use super::pick;

    #[test]
    fn picks_are_distinct_and_in_range() {
        let p = pick(1000, 300, 7);
        let mut sorted = p.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), 300);
        assert!(p.iter().all(|&i| i < 1000));
        assert_eq!(pick(5, 10, 1), vec![0, 1, 2, 3, 4]);
        assert_ne!(pick(1000, 10, 1), pick(1000, 10, 2));
    }
}
