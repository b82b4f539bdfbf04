//! The corrected model: the profile's level set by light, and thin parts
//! by the slab of the local thickness.
//!
//! **The level.** Diffusion misstates how much light a medium returns
//! where the albedo is low (skin1's blue: the dipole's 0.131 against the
//! Monte Carlo's 0.115). Every profile's sums are scaled per channel by
//! R_∞/R, the Monte Carlo's total of the half-space over the profile's
//! own ([`crate::transport::slab_totals`]), so the bake returns what light
//! returns. The Monte Carlo's faces are smooth: a rough material keeps the
//! profile's level, as do the profiles made from Monte Carlo tallies
//! (`monte_carlo`, `empirical`), whose level is light's already.
//!
//! **Thin parts.** A profile of a semi-infinite medium keeps on the lit
//! face all the light a thin part sends through to its far face, and hands
//! the far face only what the profile's tail reaches across the thickness
//! t in 3-D: tail(t) = 2π ∫_t^d_max P(r) r dr of the light behind it, the
//! share an infinite sheet's far face gets from a uniformly lit near face.
//! A slab of thickness t (Donner & Jensen 2005's problem, its totals by
//! the Monte Carlo) says instead that the near face returns R_t and the
//! far face receives T_t.
//!
//! Each texel x with a face behind it t away ([`crate::surface::opposite`])
//! is corrected with the integrator's own sums at x and at the texel y
//! behind it, M_x and M_y. Those sums hold each face's own light blurred by
//! the profile, A_x and A_y, plus, for a 3-D integrator, the share
//! q = tail(t)/R of the other's: M_x = A_x + q·A_y, M_y = A_y + q·A_x.
//! Solving the pair gives A_x, A_y, and the slab's totals over the
//! profile's total rescale them:
//!
//! M'_x = (R_t/R)·A_x + (T_t/R)·A_y.
//!
//! The far face's light keeps the profile's blur of the lit face, so a
//! shadow edge on one side shows softened on the other. A texture-space
//! integrator carries nothing across (q = 0). Where the object is thicker
//! than the profile reaches, R_t = R_∞ and T_t = 0: only the level changes.
//!
//! **Where the surface ends within reach.** A profile hands the light
//! entering at a texel to the surface around it, and where that surface
//! ends within the reach (the rim of an ear, the tip of a nose, a part
//! smaller than the reach) the share that would have gone beyond is lost,
//! though in the body it comes out somewhere, mostly nearby. The same
//! integrator run under a unit light everywhere gives each texel its sum
//! of the kernel's weights over the real surface, U (corrected as above;
//! summed at a regular subset of the texels and fitted between where the
//! integrator can sum at some texels alone, [`crate::pipeline`]);
//! a plane's or, behind a thin part, a slab's is known: (R_t + T_t)/R
//! times the profile's total within its reach. Where U falls short, their
//! ratio g (at most [`MAX_GAIN`]) raises the texel's light, by √g where it
//! enters and √g where it leaves: the pair weight stays symmetric, as
//! light's is, and under uniform light a texel returns about what the
//! plane or the slab of its thickness returns (raised only where it
//! leaves, a small part lit from one side returned more power than
//! entered; only where it enters, the spread at a rim was wider). Where
//! the raised light would still leave more power than entered, the
//! object's map is scaled down to it ([`crate::pipeline`]). Only raised:
//! where surface faces surface across air within the reach (a fold, an eye
//! socket), U is more than a plane's, but that excess is light hopping
//! through air, and lowering a texel's own light by it darkened directly
//! lit skin (on the head at Blender's default reach, red's median against
//! the walk fell from 0.96 to 0.90).
//!
//! **Small convex parts.** Light that goes deep in a small convex body
//! meets its surface soon and comes out; the gain by the surface's
//! curvature, from walks in balls, raises it by the same square roots
//! ([`crate::transport::ball_gain`]).

use crate::scattering::Scattering;
use crate::surface::opposite::Opposite;
use crate::transport::ball_gain::BallGain;
use crate::transport::shares::{most_per_channel, share_of};
use crate::transport::slab_ladder::rungs_about;
use crate::transport::slab_totals::slab_totals;
use sssbake_profile::material::{Layer, Optics, TopLayer};
use sssbake_profile::model::Model;

/// Rungs of the thickness ladder, geometric from [`THINNEST`]·d_max to d_max.
const RUNGS: usize = 32;
/// The thinnest rung as a share of the reach; thinner parts take it.
const THINNEST: f64 = 1e-3;
/// The most of a face's light the 3-D sum may be taken to carry across:
/// the pair of sums is solved only while the two faces stay told apart.
const MOST_CROSSED: f64 = 0.9;
/// The most a texel's sum is raised to the plane's or the slab's: a body
/// far smaller than the reach is not a slab, and the gain stays bounded
/// where the surface within reach is a speck.
pub const MAX_GAIN: f64 = 4.0;
/// A gain above which a texel counts as raised in the summary.
pub const RAISED: f64 = 1.01;

/// How a slab of one thickness shares out the light, per channel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SlabShares {
    /// R_t/R: the light the near face keeps, over the profile's total.
    pub kept: [f64; 3],
    /// T_t/R: the light the far face receives, over the profile's total.
    pub sent: [f64; 3],
    /// tail(t)/R: the share of a face's light the profile's 3-D sum hands
    /// the other face.
    pub summed_across: [f64; 3],
}

/// A material's slab shares on a ladder of thicknesses up to its reach.
#[derive(Clone, Debug)]
pub struct LocalSlab {
    /// R_∞/R per channel: the shares of a part thicker than the reach.
    level: [f64; 3],
    /// Per channel, the most the Monte Carlo's totals may be low by, as a
    /// share of R_∞ ([`SlabTotals::unfinished`]), or the balls' gains off
    /// by ([`BallGain::unfinished`]), whichever is more.
    unfinished: [f64; 3],
    /// The profile's total within its reach per channel: a plane's sum of
    /// the kernel's weights.
    within_reach: [f64; 3],
    thickness: Vec<f64>,
    shares: Vec<SlabShares>,
    /// The gain of small convex parts, by curvature.
    ball: BallGain,
}

impl LocalSlab {
    /// The ladder for `scattering`'s material, when it is one semi-infinite
    /// layer with optical coefficients (a slab of it is then defined) and
    /// the model is not Stam's top layer; `None` otherwise, and the bake
    /// keeps the profile's half-space.
    pub fn of(scattering: &Scattering) -> Option<Self> {
        let layer = Self::layer_of(scattering)?;
        let d_max = f64::from(scattering.kernel.d_max);
        let thickness: Vec<f64> = (0..RUNGS)
            .map(|i| d_max * THINNEST.powf(1.0 - i as f64 / (RUNGS - 1) as f64))
            .collect();
        let totals = slab_totals(layer, &thickness);
        let total = scattering.profile.total_reflectance();
        let within_reach = scattering.profile.enclosed_reflectance(d_max);
        let r_infinite = totals.semi_infinite;
        // The slab's totals are over the Monte Carlo's half-space, then
        // scaled to its level: R_∞/R for a diffusion profile with smooth
        // faces; 1 for rough faces (the simulation's are smooth) and for
        // the profiles made from Monte Carlo tallies already.
        let levelled = scattering.material.roughness == 0.0
            && !matches!(scattering.model, Model::MonteCarlo | Model::Empirical);
        let level = [0, 1, 2].map(|c| {
            let level = r_infinite[c] / total[c];
            if levelled && level.is_finite() && level > 0.0 {
                level
            } else {
                1.0
            }
        });
        let shares = thickness
            .iter()
            .enumerate()
            .map(|(i, &t)| {
                let enclosed = scattering.profile.enclosed_reflectance(t);
                let mut shares = SlabShares::default();
                for c in 0..3 {
                    let ratio = |x: f64| {
                        if r_infinite[c] > 0.0 && x.is_finite() {
                            (x / r_infinite[c]).max(0.0)
                        } else {
                            0.0
                        }
                    };
                    shares.kept[c] = level[c] * ratio(totals.reflectance[i][c]).min(1.0);
                    shares.sent[c] = level[c] * ratio(totals.transmittance[i][c]);
                    shares.summed_across[c] = if total[c] > 0.0 {
                        ((within_reach[c] - enclosed[c]) / total[c]).clamp(0.0, MOST_CROSSED)
                    } else {
                        0.0
                    };
                }
                shares
            })
            .collect();
        let unfinished = share_of(totals.unfinished, r_infinite);
        // The balls' walks are bounded as the slabs' are: either may be short.
        let ball = BallGain::of(&scattering.kernel, layer);
        let unfinished = most_per_channel(unfinished, std::iter::once(ball.unfinished()));
        Some(LocalSlab {
            level,
            unfinished,
            within_reach,
            thickness,
            shares,
            ball,
        })
    }

    /// The scales (mm) per channel at which the gain of small convex parts
    /// reads the surface's mean curvature; `None` where no ball raises its
    /// light, and no curvature is needed.
    pub fn ball_scales(&self) -> Option<[f32; 3]> {
        self.ball.raises().then(|| self.ball.curvature_scales())
    }

    /// Per surfel, the gain of small convex parts ([`BallGain::gains`]),
    /// from `curvature`, each surfel's at [`Self::ball_scales`], with
    /// `opposites` the face behind each.
    pub fn ball_gains(
        &self,
        curvature: &[[f32; 3]],
        opposites: &[Option<Opposite>],
    ) -> Vec<[f32; 3]> {
        self.ball.gains(curvature, opposites, self)
    }

    /// Whether [`Self::of`] gives a ladder for `scattering`, without
    /// simulating it.
    pub fn applies(scattering: &Scattering) -> bool {
        Self::layer_of(scattering).is_some()
    }

    /// The one semi-infinite layer a slab of `scattering`'s material is
    /// made of, where it is defined (see [`Self::of`]).
    pub(crate) fn layer_of(scattering: &Scattering) -> Option<&Layer> {
        let material = &scattering.material;
        let Optics::Layers(layers) = &material.optics else {
            return None;
        };
        let [layer] = layers.as_slice() else {
            return None;
        };
        let d_max = f64::from(scattering.kernel.d_max);
        let defined = layer.thickness_mm.is_none()
            && material.top_layer != TopLayer::Stam
            && scattering.model != Model::Stam
            && d_max.is_finite()
            && d_max > 0.0;
        defined.then_some(layer)
    }

    /// R_∞/R per channel: how much the profile's level is changed.
    pub fn level(&self) -> [f64; 3] {
        self.level
    }

    /// Per channel, the most the level, the slabs' totals and the balls'
    /// gains may be off by, as a share: the light of the Monte Carlo's
    /// photons and the balls' walks stopped unfinished, where the bound on
    /// their work binds ([`crate::transport::walk_budget`]); 0 where every
    /// one finished.
    pub fn unfinished(&self) -> [f64; 3] {
        self.unfinished
    }

    /// The shares of a part thicker than the reach: its level, nothing
    /// across.
    pub fn thick(&self) -> SlabShares {
        SlabShares {
            kept: self.level,
            ..SlabShares::default()
        }
    }

    /// The thickest rung, mm: the profile's reach, beyond which a part is
    /// a half-space ([`Self::at`] is `None`).
    pub fn reach(&self) -> f32 {
        self.thickness.last().map_or(0.0, |&t| t as f32)
    }

    /// The shares at thickness `t` mm (linear in ln t between rungs; the
    /// thinnest rung below it), or `None` where the part is thicker than
    /// the reach ([`Self::thick`]).
    pub fn at(&self, t: f32) -> Option<SlabShares> {
        let t = f64::from(t);
        let last = *self.thickness.last()?;
        // A NaN thickness is no thin part either.
        if t.is_nan() || t > last {
            return None;
        }
        let (below, above, w) = rungs_about(&self.thickness, t);
        let (a, b) = (self.shares[below], self.shares[above]);
        let mix = |x: [f64; 3], y: [f64; 3]| [0, 1, 2].map(|c| x[c] + w * (y[c] - x[c]));
        Some(SlabShares {
            kept: mix(a.kept, b.kept),
            sent: mix(a.sent, b.sent),
            summed_across: mix(a.summed_across, b.summed_across),
        })
    }

    /// The exitance at a texel from its own sum `here`, the sum `behind` at
    /// the texel behind it, and the slab between them; `summed_across`
    /// false for an integrator that carries nothing between faces.
    pub fn corrected(
        shares: &SlabShares,
        here: [f32; 3],
        behind: [f32; 3],
        summed_across: bool,
    ) -> [f32; 3] {
        [0, 1, 2].map(|c| {
            let q = if summed_across {
                shares.summed_across[c]
            } else {
                0.0
            };
            let (x, y) = (f64::from(here[c]), f64::from(behind[c]));
            let own_here = ((x - q * y) / (1.0 - q * q)).max(0.0);
            let own_behind = ((y - q * x) / (1.0 - q * q)).max(0.0);
            let m = shares.kept[c] * own_here + shares.sent[c] * own_behind;
            if m.is_finite() { m as f32 } else { here[c] }
        })
    }

    /// The factor, in [1, [`MAX_GAIN`]] per channel, that brings a texel's
    /// corrected sum of weights (`uniform`, here and behind) up to the
    /// plane's or the slab's of `shares`: how much the light entering
    /// there is raised.
    pub fn gain(
        &self,
        shares: &SlabShares,
        uniform: ([f32; 3], [f32; 3]),
        summed_across: bool,
    ) -> [f64; 3] {
        let u = Self::corrected(shares, uniform.0, uniform.1, summed_across);
        [0, 1, 2].map(|c| {
            let expected = (shares.kept[c] + shares.sent[c]) * self.within_reach[c];
            let gain = expected / f64::from(u[c]);
            if gain.is_finite() && gain > 0.0 {
                gain.clamp(1.0, MAX_GAIN)
            } else {
                1.0
            }
        })
    }

    /// The shares at a texel with `opposite` behind it, with the texel
    /// behind where it lies within the reach.
    pub fn shares_at(&self, opposite: Option<Opposite>) -> (SlabShares, Option<usize>) {
        opposite
            .and_then(|o| Some((self.at(o.thickness)?, Some(o.surfel as usize))))
            .unwrap_or((self.thick(), None))
    }

    /// The texels the corrected model reads to correct `picked`: for each
    /// the texel behind it where a face lies within the reach (`None`
    /// elsewhere), and the list of `picked` followed by those behind, in
    /// the same order.
    pub fn behind(
        &self,
        opposites: &[Option<Opposite>],
        picked: &[usize],
    ) -> (Vec<Option<usize>>, Vec<usize>) {
        let behind: Vec<Option<usize>> = picked
            .iter()
            .map(|&i| {
                self.shares_at(opposites[i])
                    .1
                    .filter(|&j| j < opposites.len())
            })
            .collect();
        let read = picked
            .iter()
            .copied()
            .chain(behind.iter().flatten().copied())
            .collect();
        (behind, read)
    }

    /// Per surfel, the gain of the light entering there ([`Self::gain`]),
    /// from `uniform`, the integrator's sums under a unit light
    /// everywhere; and how many texels are raised by more than [`RAISED`]
    /// in some channel.
    pub fn gains(
        &self,
        opposites: &[Option<Opposite>],
        uniform: &[[f32; 3]],
        summed_across: bool,
    ) -> (Vec<[f32; 3]>, usize) {
        let gains: Vec<[f32; 3]> = (0..uniform.len())
            .map(|i| {
                let (shares, behind) = self.shares_at(opposites.get(i).copied().flatten());
                let j = behind.filter(|&j| j < uniform.len()).unwrap_or(i);
                let gain = self.gain(&shares, (uniform[i], uniform[j]), summed_across);
                gain.map(|g| g as f32)
            })
            .collect();
        let raised = gains
            .iter()
            .filter(|g| g.iter().any(|&g| f64::from(g) > RAISED))
            .count();
        (gains, raised)
    }

    /// `exitance` (the integrator's sums, one per surfel) corrected at
    /// every surfel: brought to the level, and re-shared with the texel
    /// behind where a face lies within the reach.
    pub fn correct_all(
        &self,
        opposites: &[Option<Opposite>],
        exitance: &[[f32; 3]],
        summed_across: bool,
    ) -> Vec<[f32; 3]> {
        (0..exitance.len())
            .map(|i| {
                let (shares, behind) = self.shares_at(opposites.get(i).copied().flatten());
                let j = behind.filter(|&j| j < exitance.len()).unwrap_or(i);
                Self::corrected(&shares, exitance[i], exitance[j], summed_across)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slab() -> LocalSlab {
        LocalSlab {
            level: [0.9, 1.0, 1.1],
            unfinished: [0.0; 3],
            within_reach: [0.5, 0.4, 0.3],
            thickness: vec![1.0, 2.0],
            shares: vec![SlabShares::default(); 2],
            ball: BallGain::none(),
        }
    }

    #[test]
    fn a_sum_short_of_the_planes_is_raised_and_no_other_is_lowered() {
        let slab = slab();
        let thick = slab.thick();
        let gain = |u: [f32; 3]| slab.gain(&thick, (u, [0.0; 3]), true);
        // A plane's sums: no gain (the level scales both).
        let plane = [0.5, 0.4, 0.3];
        for g in gain(plane) {
            assert!((g - 1.0).abs() < 1e-6, "{g}");
        }
        // Half a plane's surface within reach: twice the light.
        for g in gain(plane.map(|u| u / 2.0)) {
            assert!((g - 2.0).abs() < 1e-5, "{g}");
        }
        // A speck: the cap.
        assert_eq!(gain([1e-9; 3]), [MAX_GAIN; 3]);
        // More surface than a plane's (across air): left as it is.
        assert_eq!(gain(plane.map(|u| u * 2.0)), [1.0; 3]);
        // No sum at all, or a broken one: no gain.
        assert_eq!(gain([0.0; 3]), [1.0; 3]);
        assert_eq!(gain([f32::NAN; 3]), [1.0; 3]);
    }
}
