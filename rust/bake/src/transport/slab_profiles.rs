//! Thin parts by the profile of their own slab: in each channel where a
//! part is thinner than about a diffusion length, a texel gathers with
//! R_t(r) and T_t(r), the light a slab of its thickness returns and sends
//! through at distance r, simulated by the Monte Carlo, instead of a
//! half-space's profile re-shared by the slab's totals
//! ([`super::local_slab`]).
//!
//! A slab spreads light less than a half-space: what goes sideways leaks
//! out through both faces as it goes. The totals alone keep a
//! half-space's spread, which on a thin part under a small light puts too
//! little light near it and too much far away (docs/accuracy.md, "Thin
//! parts spread red wider than light").
//!
//! Each rung of a thickness ladder ([`super::slab_ladder`]) is one
//! simulated slab, its tallies of R and T by radius
//! ([`sssbake_profile::models::monte_carlo`], kept in the cache folder)
//! tabulated as a [`Kernel`] and read as the exact sum reads a kernel: disk
//! means, a texel's own light over its parallelogram, and sub-samples of
//! the texels near the target. A texel takes the two rungs about its
//! thickness, linearly in ln t. A part's two faces are told apart by which
//! way they face, not blended by the pair's normals: a source on the face
//! behind (facing away, deeper than half the part's thickness below the
//! target) is weighed by T_t at its offset along the face, any other by R_t
//! at its distance, and a surface deeper than one and a half thicknesses,
//! beyond the face behind, sends nothing through the part. The light that
//! leaves without scattering (straight through, or back after internal
//! reflections) is a point at the texel behind or at the texel itself, and
//! is added there rather than spread by a profile. A thin texel's light is
//! raised where its slab's light would pass the part's rim by the share of
//! it the rim's boundary reflects back ([`SlabProfiles::gains`]), and the
//! rest comes in as the light entering through the rim
//! ([`crate::transport::rim_light`]).
//!
//! Every profile method bakes thin parts this way, through the octree
//! (at the method's own solid angle ε; the exact sum's is 0, every pair
//! apart): a kernel per target does not fit a texture-space blur or a
//! shared tree's summaries of one kernel. Above ε 0 the thin texels' map
//! is carried from a lattice of them as the whole map is
//! ([`crate::fitted_map`]), a lattice texel carrying only to texels about
//! as thick: where the ray behind finds another surface the thickness,
//! and the slab's sums, jump. The estimate checks it by the exact sum at
//! its texels.

use crate::control::{Cancelled, Control};
use crate::error::Error;
use crate::fitted_map::{Carrier, MapFit, NearSum, fitted_at};
use crate::prepared::Prepared;
use crate::surface::opposite::Opposite;
use crate::transport::brute::Reach;
use crate::transport::integrator::Summer;
use crate::transport::kernel::{Kernel, Separation};
use crate::transport::local_slab::MAX_GAIN;
use crate::transport::octree::{Gathering, TreeShape};
use crate::transport::rim_light::{LEAST_SHARE, RimSights, RimTexel, rim_sights};
use crate::transport::slab_ladder::{SlabProfiles, mix};
use crate::transport::sources::Sources;
use crate::transport::through_medium::longer_path;
use glam::Vec3;
use std::sync::{Arc, Mutex};

/// A texel on a part thin in some channel.
#[derive(Clone, Copy, Debug)]
pub struct ThinTexel {
    /// The texel.
    pub texel: usize,
    /// The part's thickness there, mm.
    pub thickness: f64,
    /// The texel across the part.
    pub behind: usize,
}

/// The exitance (W/m²) at each texel on a thin part, in the channels
/// where its part is thin (`None` in the others).
pub type ThinExitance = Vec<[Option<f32>; 3]>;

/// The most the thin parts hold per texel on them while an object bakes,
/// bytes: the texel, its sums under a unit light as shares, the same as its
/// rim sees it, and its exitance.
const BYTES_PER_THIN_TEXEL: usize = std::mem::size_of::<ThinTexel>()
    + std::mem::size_of::<[f32; 3]>()
    + std::mem::size_of::<crate::transport::rim_light::RimTexel>()
    + std::mem::size_of::<[Option<f32>; 3]>();

/// The texels of one object on thin parts, with the rungs they read.
pub struct ThinParts {
    texels: Vec<ThinTexel>,
    /// The rungs simulated for them, `first..=last`.
    first: usize,
    last: usize,
}

impl ThinParts {
    /// The texels on thin parts.
    pub fn texels(&self) -> &[ThinTexel] {
        &self.texels
    }

    /// The texels' indices.
    fn texel_ids(&self) -> Vec<usize> {
        self.texels.iter().map(|t| t.texel).collect()
    }
}

impl SlabProfiles {
    /// The most the thin parts hold while an object of `texels` bakes,
    /// bytes, when at most the share `thin` of them lie on a part thinner
    /// than a slab reaches ([`crate::transport::thin::thin_share`]): each
    /// rung's kernel and its disk means for texels and for nodes, and each
    /// thin texel's own (its texel, sums, rim and exitance); nothing where
    /// no texel is thin. (The head at 512² held 40 MB of rungs' disk means
    /// at its peak.)
    pub fn planned_bytes(&self, texels: f64, thin: f64) -> f64 {
        if thin.is_nan() || thin <= 0.0 {
            return 0.0;
        }
        let rung = crate::transport::kernel::MOST_BYTES
            + 2 * crate::transport::disk_kernel::most_bytes(true);
        let texel = BYTES_PER_THIN_TEXEL + crate::transport::rim_light::BYTES_PER_TEXEL;
        (self.thickness.len() * rung) as f64 + texels * thin.min(1.0) * texel as f64
    }

    /// The face behind each of `prepared`'s texels within the reach of the
    /// half-space's profile, the thickest any slab here reads.
    pub(super) fn opposites(&self, prepared: &Prepared) -> Arc<Vec<Option<Opposite>>> {
        prepared.opposites(self.reach as f32)
    }

    /// The texels of `picked` (all of `prepared`'s where `None`) on a part
    /// thin in some channel and thinner than its radius of curvature, with
    /// the rungs from the thinnest to the thickest they read simulated;
    /// none when a rung cannot be simulated (the half-space's profile then
    /// serves).
    pub fn thin_texels(&self, prepared: &Prepared, picked: Option<&[usize]>) -> ThinParts {
        let opposites = self.opposites(prepared);
        let thin = |i: usize| {
            let o = opposites.get(i).copied().flatten()?;
            let thickness = f64::from(o.thickness);
            (0..3)
                .any(|c| self.is_thin(thickness, c))
                .then_some(ThinTexel {
                    texel: i,
                    thickness,
                    behind: o.surfel as usize,
                })
        };
        let mut texels: Vec<ThinTexel> = match picked {
            Some(picked) => picked.iter().filter_map(|&i| thin(i)).collect(),
            None => (0..opposites.len()).filter_map(thin).collect(),
        };
        // A slab is thinner than its faces' radius of curvature; a part as
        // thick as it is round (a ball, whose thickness is its diameter)
        // keeps the half-space's profile and a ball's gain. The curvature
        // is found only for an object with thin parts.
        if !texels.is_empty() {
            let curvature = prepared.mean_curvature(self.curvature_scale);
            texels.retain(|t| t.thickness * f64::from(curvature[t.texel]) < 1.0);
        }
        let (mut first, mut last) = (usize::MAX, 0);
        for t in &texels {
            let (a, b, _) = self.about(t.thickness);
            first = first.min(a);
            last = last.max(b);
        }
        let rungs: Vec<usize> = (first..=last).collect();
        if texels.is_empty() || !self.simulate(&rungs) {
            return ThinParts {
                texels: Vec::new(),
                first: 0,
                last: 0,
            };
        }
        ThinParts {
            texels,
            first,
            last,
        }
    }

    /// `halves` (√gain per texel, as [`crate::prepared::Raised`] has it)
    /// with each of `parts`' texels' gains in each channel where its part
    /// is thin: of its slab's scattered total, the share its sum under a
    /// unit light misses is light the slab would carry past the part's
    /// rim, where it meets the rim's own surface and leaves through it but
    /// for the share F_dr the boundary reflects back (`rim_return`);
    /// (the rest is light entering through the rim, [`Self::lit`]);
    /// so the gain is 1 + F_dr·(total / sum − 1), within [1,
    /// [`MAX_GAIN`]], times `ball`'s gain of convex parts. (In the middle
    /// of a 12 mm square of skin1 3 mm thick the slab's profile alone is
    /// the walk's; raised by the whole shortfall, as a half-space's is
    /// where the surface ends, it was 4% over, and 9% near the rim.) The
    /// sums are the octree's at solid angle `epsilon` (0: exact), as shares
    /// of the slab's total, on a lattice `stride` texels apart and carried
    /// between ([`Carrier::whole`]; 1: at every texel): like the
    /// half-space's, they change over the profile's spread. With, for
    /// each of `parts`' texels, where the rest of that light comes in
    /// through the rim ([`crate::transport::rim_light`]).
    #[allow(clippy::too_many_arguments)]
    pub fn gains(
        &self,
        prepared: &Prepared,
        parts: &ThinParts,
        halves: &mut [[f32; 3]],
        ball: &[[f32; 3]],
        epsilon: f32,
        stride: u32,
        control: &Control,
    ) -> Result<RimSights, Error> {
        if parts.texels.is_empty() {
            return Ok(RimSights::default());
        }
        let held = SlabSums::new(self, prepared, parts, epsilon, true);
        let even = evenly_thick(&held.opposites);
        let shares = Carrier::whole(prepared, &held).joining(&even).at(
            &parts.texel_ids(),
            stride.max(1),
            control,
        )?;
        for (t, share) in parts.texels.iter().zip(&shares) {
            let convex = ball.get(t.texel).copied().unwrap_or([1.0; 3]);
            let half = &mut halves[t.texel];
            for c in 0..3 {
                if self.is_thin(t.thickness, c) {
                    half[c] = self.gain(share[c], convex[c]).sqrt() as f32;
                }
            }
        }
        Ok(self.rim_sights(prepared, parts, &shares))
    }

    /// Where the light `parts`' texels' sums miss (`shares`: each texel's
    /// sum under a unit light as a share of its slab's scattered total)
    /// comes in through the rim, but for the share F_dr the rim reflects
    /// back, which the gain holds ([`crate::transport::rim_light`]).
    fn rim_sights(&self, prepared: &Prepared, parts: &ThinParts, shares: &[[f32; 3]]) -> RimSights {
        // The rim's boundary returns F_dr of what reaches it from inside
        // (the gain) and passes the rest, which light from outside crosses
        // the other way: under a unit light on the faces and the rim, the
        // texel returns its slab's total, as a half-space's texel returns
        // the plane's.
        let passing = 1.0 - self.rim_return;
        let texels: Vec<RimTexel> = parts
            .texels
            .iter()
            .zip(shares)
            .map(|(t, share)| {
                let (a, b, w) = self.rungs_at(t.thickness);
                let total = mix(a.scattered_total, b.scattered_total, w);
                RimTexel {
                    texel: t.texel,
                    thickness: t.thickness as f32,
                    reach: a.kernel.d_max.max(b.kernel.d_max),
                    through_rim: [0, 1, 2].map(|c| {
                        let missing = (1.0 - f64::from(share[c])).max(0.0);
                        let missing = missing * total[c];
                        // A texel far from its rim misses almost nothing:
                        // below LEAST_SHARE its rays are not worth casting.
                        let sought = missing >= LEAST_SHARE * total[c];
                        if self.is_thin(t.thickness, c) && missing.is_finite() && sought {
                            (passing * missing) as f32
                        } else {
                            0.0
                        }
                    }),
                }
            })
            .collect();
        rim_sights(prepared, &texels, &|t, d| self.beyond(t, d))
    }

    /// The share per channel of the light of a slab `thickness` mm thick
    /// that leaves it farther than `distance` mm from where it entered.
    fn beyond(&self, thickness: f32, distance: f32) -> [f32; 3] {
        let (a, b, w) = self.rungs_at(f64::from(thickness));
        let outside = |kernel: &Kernel| {
            let (within, all) = (kernel.enclosed(distance), kernel.enclosed(kernel.d_max));
            [0, 1, 2].map(|c| f64::from((1.0 - within[c] / all[c]).clamp(0.0, 1.0)))
        };
        mix(outside(&a.kernel), outside(&b.kernel), w)
            .map(|share| if share.is_finite() { share as f32 } else { 0.0 })
    }

    /// A thin texel's gain in one channel, as [`Self::gains`] finds it:
    /// from `share`, its sum under a unit light as a share of its slab's
    /// scattered total, and `convex`, the ball's gain of convex parts.
    fn gain(&self, share: f32, convex: f32) -> f64 {
        let missing = 1.0 / f64::from(share) - 1.0;
        let gain = if missing.is_finite() {
            (1.0 + self.rim_return * missing.max(0.0)).min(MAX_GAIN)
        } else {
            1.0
        };
        (gain * f64::from(convex)).min(MAX_GAIN)
    }

    /// The exitance (W/m², before the colour after scattering) at each of
    /// `parts`' texels by the profiles of their slabs, under `raised` (the
    /// light entering raised by `halves`, √gain per texel) and raised
    /// again where it leaves, through the octree at solid angle `epsilon`
    /// (0: exact), with the light `rim` brings in (found with the gains,
    /// one entry per texel of `parts`); `None` in the channels where a
    /// texel's part is not thin. With a `lattice` (step and tolerance) and
    /// ε above 0, the
    /// scattered part is carried from the lattice's texels as a map is
    /// ([`fitted_at`]: N, the pairs within two texels, summed exactly
    /// where the light is not smooth; the step halved until the fit holds
    /// at random thin texels), else summed at every thin texel. With how
    /// the scattered part was carried, where it was.
    #[allow(clippy::too_many_arguments)]
    pub fn lit(
        &self,
        raised: &Prepared,
        halves: &[[f32; 3]],
        rim: &RimSights,
        parts: &ThinParts,
        epsilon: f32,
        lattice: Option<(u32, f64)>,
        control: &Control,
    ) -> Result<(ThinExitance, Option<MapFit>), Error> {
        if parts.texels.is_empty() {
            return Ok((Vec::new(), None));
        }
        let sums = SlabSums::new(self, raised, parts, epsilon, false);
        let texels = parts.texel_ids();
        let even = evenly_thick(&sums.opposites);
        let (scattered, fit) = match lattice {
            Some((step, tolerance)) if epsilon > 0.0 && step > 1 => {
                let carrier = Carrier::split_by(raised, &sums, Box::new(&sums), tolerance);
                let carrier = carrier.joining(&even);
                let (map, fit) = fitted_at(carrier, &sums, &texels, step, tolerance, control)?;
                (map, Some(fit))
            }
            _ => (sums.at(&texels, control)?, None),
        };
        Ok((self.leaving(raised, halves, rim, parts, scattered), fit))
    }

    /// The exitance at `parts`' texels from their `scattered` sums of
    /// `raised`'s light: with the light that leaves unscattered, at the
    /// texel and from the texel behind, raised where it leaves by
    /// `halves`, and the light `rim` brings in through the rim, as it
    /// entered there.
    fn leaving(
        &self,
        raised: &Prepared,
        halves: &[[f32; 3]],
        rim: &RimSights,
        parts: &ThinParts,
        scattered: Vec<[f32; 3]>,
    ) -> ThinExitance {
        // Read texel by texel: the error estimate asks for a few hundred.
        let entering = |s: usize| raised.entering_at(s);
        // The rim's light as it entered, before the raise.
        let unraised = |s: usize| {
            let e = entering(s);
            [0, 1, 2].map(|c| e[c] / halves[s][c].max(1.0))
        };
        parts
            .texels
            .iter()
            .zip(scattered)
            .enumerate()
            .map(|(k, (t, sum))| {
                let rim = rim.light(k, &raised.surfels, unraised);
                let (a, b, w) = self.rungs_at(t.thickness);
                let back = mix(a.unscattered_back, b.unscattered_back, w);
                let through = mix(a.unscattered_through, b.unscattered_through, w);
                [0, 1, 2].map(|c| {
                    if !self.is_thin(t.thickness, c) {
                        return None;
                    }
                    let raised = |j: usize| f64::from(entering(j)[c]);
                    let m = f64::from(sum[c])
                        + back[c] * raised(t.texel)
                        + through[c] * raised(t.behind);
                    Some((m * f64::from(halves[t.texel][c]) + rim[c]) as f32)
                })
            })
            .collect()
    }

    /// The exitance (W/m², before the colour after scattering) at the
    /// texels `picked` of `prepared`, by the profiles of their slabs in each
    /// channel where the part is thin (`None` elsewhere), for a bake that
    /// raised the light entering by `halves` (√gain per texel, times
    /// `ball`'s gain of convex parts where thin), through the octree at
    /// solid angle `epsilon` (0: exact): the sums of that light and of a
    /// unit light, in one walk over the pairs, give the bake's light summed
    /// there and the gain g at each picked texel, which raises the light
    /// where it leaves by √g instead of the bake's h. The light entering
    /// stays as the bake raised it, the picked texels' own too: among the
    /// millions of texels within a slab's reach, exact gains at a few dozen
    /// of them would move the sums by about a millionth, and what a texel
    /// sends back unscattered is a small share of its light.
    pub fn exitance(
        &self,
        prepared: &Prepared,
        picked: &[usize],
        halves: &[[f32; 3]],
        ball: &[[f32; 3]],
        epsilon: f32,
        control: &Control,
    ) -> Result<ThinExitance, Error> {
        let parts = self.thin_texels(prepared, Some(picked));
        if parts.texels.is_empty() {
            return Ok(vec![[None; 3]; picked.len()]);
        }
        let raised = prepared.raised_by(halves);
        let sums = SlabSums::new(self, &raised, &parts, epsilon.max(0.0), false);
        let [scattered, shares] = sums.with_shares(&parts.texel_ids(), control)?;
        // The rim's light by the exact shares, beside the light raised by
        // the exact gains.
        let rim = self.rim_sights(prepared, &parts, &shares);
        let rim = (0..parts.texels.len())
            .map(|k| rim.light(k, &prepared.surfels, |s| prepared.entering_at(s)));
        let lit = self.leaving(&raised, halves, &RimSights::default(), &parts, scattered);
        let mut at = parts.texels.iter().zip(lit).zip(shares).zip(rim).peekable();
        Ok(picked
            .iter()
            .map(|&i| {
                // The thin texels follow the picked ones, in order.
                let Some((((_, m), share), rim)) = at.next_if(|(((t, _), _), _)| t.texel == i)
                else {
                    return [None; 3];
                };
                let convex = ball.get(i).copied().unwrap_or([1.0; 3]);
                [0, 1, 2].map(|c| {
                    let bake = f64::from(halves[i][c]).max(f64::from(f32::MIN_POSITIVE));
                    let exact = self.gain(share[c], convex[c]).sqrt();
                    m[c].map(|m| (f64::from(m) * exact / bake + rim[c]) as f32)
                })
            })
            .collect())
    }

    /// The share of `exitance`'s Σ M² (every texel and channel) at
    /// `parts`' texels, in the channels where their part is thin: at most
    /// 1.
    pub fn share_of_map(&self, parts: &ThinParts, exitance: &[[f32; 3]]) -> f64 {
        let square = |m: f32| f64::from(m) * f64::from(m);
        let whole: f64 = exitance.iter().flatten().map(|&m| square(m)).sum();
        let thin: f64 = parts
            .texels
            .iter()
            .map(|t| {
                (0..3)
                    .filter(|&c| self.is_thin(t.thickness, c))
                    .map(|c| square(exitance[t.texel][c]))
                    .sum::<f64>()
            })
            .sum();
        if whole > 0.0 {
            (thin / whole).min(1.0)
        } else {
            1.0
        }
    }

    /// The octree of `shape` over `sources` under `parts`' rungs, at solid
    /// angle `epsilon`.
    fn gathering<'a>(
        &'a self,
        parts: &ThinParts,
        shape: &TreeShape,
        sources: &Sources<'a>,
        epsilon: f32,
    ) -> Gathering<'a> {
        let kernels: Vec<&Kernel> = (parts.first..=parts.last)
            .map(|r| &self.rung_simulated(r).kernel)
            .collect();
        Gathering::over(shape, &kernels, sources, epsilon)
    }
}

/// The sums of the slabs' profiles over `lit`'s texels at chosen texels
/// (the thin texels, or a lattice's for [`Carrier`]), each texel's
/// thickness held within the rungs simulated (the thickest where it has
/// none): of `lit`'s light, or, with `shares`, of a unit light as shares
/// of its slab's scattered total (R and T). The octree is built at the
/// first texels asked for and held until released.
struct SlabSums<'a> {
    profiles: &'a SlabProfiles,
    lit: &'a Prepared,
    parts: &'a ThinParts,
    epsilon: f32,
    shares: bool,
    gathering: Mutex<Option<Gathering<'a>>>,
    /// The face behind each of `lit`'s texels.
    opposites: Arc<Vec<Option<Opposite>>>,
}

impl<'a> SlabSums<'a> {
    fn new(
        profiles: &'a SlabProfiles,
        lit: &'a Prepared,
        parts: &'a ThinParts,
        epsilon: f32,
        shares: bool,
    ) -> Self {
        SlabSums {
            profiles,
            lit,
            parts,
            epsilon,
            shares,
            gathering: Mutex::new(None),
            opposites: profiles.opposites(lit),
        }
    }

    /// The sums of `gathering` (over the rungs from the first simulated)
    /// at texels `at` of `lit`, each under the two rungs about its
    /// thickness (mm), mixed in ln t, its pairs placed by [`separation`],
    /// at solid angle `epsilon`; only those `within` a reach, every one
    /// apart, where given.
    fn placed(
        &self,
        gathering: &Gathering,
        at: &[(usize, f64)],
        epsilon: f32,
        within: Option<&[Reach]>,
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        let reading: Vec<usize> = at.iter().map(|&(i, _)| i).collect();
        let listed = self.lit.listed(&reading);
        let placing = |k: usize| self.placing(at[k]);
        gathering.at_placed(listed.targets(), placing, epsilon, within, control)
    }

    /// For texel `i` of thickness `t` (mm), the shares of the rungs it
    /// mixes and how a source sits from it.
    fn placing(
        &self,
        (i, t): (usize, f64),
    ) -> (RungMix, impl Fn(Vec3, Vec3) -> Option<Separation>) {
        let (profiles, first) = (self.profiles, self.parts.first);
        let (a, b, w) = profiles.about(t);
        let mix = [(a - first, 1.0 - w as f32), (b - first, w as f32)];
        let (p, n) = (self.lit.surfels.position[i], self.lit.surfels.normal[i]);
        let half = 0.5 * self.opposites[i].map_or(0.0, |o| o.thickness);
        let reach = profiles.rung_simulated(a).kernel.d_max;
        let reach = reach.max(profiles.rung_simulated(b).kernel.d_max);
        (mix, move |q: Vec3, m: Vec3| {
            separation(p, n, half, q, m, reach)
        })
    }

    /// `listed` with each texel's thickness (mm), held within the rungs
    /// simulated (the thickest where it has none).
    fn thicknesses(&self, listed: &[usize]) -> Vec<(usize, f64)> {
        let profiles = self.profiles;
        let (first, last) = (self.parts.first, self.parts.last);
        let (thinnest, thickest) = (profiles.thickness[first], profiles.thickness[last]);
        let opposites = &self.opposites;
        listed
            .iter()
            .map(|&i| {
                let t = opposites[i].map_or(thickest, |o| f64::from(o.thickness));
                (i, t.clamp(thinnest, thickest))
            })
            .collect()
    }

    /// `sum` of the octree over the sources, built at the first call and
    /// held (locked while summing, which is parallel itself).
    fn with_gathering<R>(&self, sum: impl FnOnce(&Gathering) -> R) -> R {
        let mut held = self.gathering.lock().unwrap_or_else(|e| e.into_inner());
        let gathering = held.get_or_insert_with(|| {
            let mut sources = self.lit.texel_sources();
            if self.shares {
                sources.irradiance.iter_mut().for_each(|e| *e = [1.0; 3]);
            }
            self.profiles
                .gathering(self.parts, self.lit.texel_tree(), &sources, self.epsilon)
        });
        sum(gathering)
    }

    /// `sums` at `at` under a unit light as shares of each texel's slab's
    /// scattered total.
    fn as_shares(&self, at: &[(usize, f64)], sums: Vec<[f32; 3]>) -> Vec<[f32; 3]> {
        at.iter()
            .zip(sums)
            .map(|(&(_, t), sum)| {
                let (a, b, w) = self.profiles.rungs_at(t);
                let expected = mix(a.scattered_total, b.scattered_total, w);
                [0, 1, 2].map(|c| (f64::from(sum[c]) / expected[c]) as f32)
            })
            .collect()
    }

    /// The sums at `listed` of the light and, as shares of each texel's
    /// slab's scattered total, of a unit light, at the gathering's solid
    /// angle, in one walk over the pairs.
    fn with_shares(
        &self,
        listed: &[usize],
        control: &Control,
    ) -> Result<[Vec<[f32; 3]>; 2], Cancelled> {
        let at = self.thicknesses(listed);
        let listed = self.lit.listed(listed);
        let placing = |k: usize| self.placing(at[k]);
        let both = self.with_gathering(|gathering| {
            gathering.placed_with_unit(listed.targets(), placing, self.epsilon, control)
        })?;
        let (lit, unit): (Vec<_>, Vec<_>) = both.into_iter().map(|[l, u]| (l, u)).unzip();
        Ok([lit, self.as_shares(&at, unit)])
    }

    /// The sums at `listed` at solid angle `epsilon` (at most the
    /// gathering's), from the sources `within` each texel's reach (one per
    /// texel) where given.
    fn sums(
        &self,
        listed: &[usize],
        epsilon: f32,
        within: Option<&[Reach]>,
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        let at = self.thicknesses(listed);
        let sums =
            self.with_gathering(|gathering| self.placed(gathering, &at, epsilon, within, control))?;
        if !self.shares {
            return Ok(sums);
        }
        Ok(self.as_shares(&at, sums))
    }
}

impl Summer for SlabSums<'_> {
    fn at(&self, listed: &[usize], control: &Control) -> Result<Vec<[f32; 3]>, Error> {
        Ok(self.sums(listed, self.epsilon, None, control)?)
    }

    /// At a quarter of the solid angle: a slab's sums through the octree
    /// jitter from texel to texel (where its placing jumps, at the depth
    /// where a part's slab ends, a node beyond ε/32 is still read all as
    /// its centre's side), which a carried map smooths.
    fn finer(&self, listed: &[usize], control: &Control) -> Option<Result<Vec<[f32; 3]>, Error>> {
        let finer = FINER * self.epsilon;
        Some(self.sums(listed, finer, None, control).map_err(Error::from))
    }

    fn release(&self) {
        *self.gathering.lock().unwrap_or_else(|e| e.into_inner()) = None;
    }
}

impl NearSum for SlabSums<'_> {
    fn within(
        &self,
        listed: &[usize],
        reaches: &[Reach],
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        self.sums(listed, 0.0, Some(reaches), control)
    }
}

/// The least share of the map's Σ M² the thin parts' fit is allowed for:
/// however little of the map they hold, their own fit misses their own
/// sums by at most four times the map's tolerance. A part a sixteenth of
/// the map's light, or far less (a lit ear's rim on a dim head), is still
/// a part an artist looks at.
const LEAST_THIN_SHARE: f64 = 1.0 / 16.0;

/// The relative RMSE the thin parts' own map may miss by when the whole
/// map's is `tolerance` and theirs is `share` of its Σ M²: as much over
/// the square root of their share ([`SlabProfiles::share_of_map`]), which
/// adds at most `tolerance` to the whole map's, but at least
/// [`LEAST_THIN_SHARE`] of it.
pub fn thin_tolerance(tolerance: f64, share: f64) -> f64 {
    let share = if share.is_finite() { share } else { 1.0 };
    tolerance / share.clamp(LEAST_THIN_SHARE, 1.0).sqrt()
}

/// The shares of the two rungs about a texel's thickness, by their places
/// among the gathering's kernels.
type RungMix = [(usize, f32); 2];

/// The share of the solid angle at which a carried map of thin parts is
/// checked against finer sums.
const FINER: f32 = 0.25;

/// The most two texels' thicknesses may differ by, as a ratio, for one to
/// carry its slab's sums to the other. Across a lattice's cell a part's
/// thickness changes gradually, but where the ray behind a texel finds
/// another surface it jumps (from 10 to 107 mm between texels two apart on
/// the head's ear), and so do its slab's sums.
const CARRIED_THICKNESS_RATIO: f32 = 1.25;

/// Whether texel `j` is as thick as texel `i` by their faces behind
/// (`opposites`), within [`CARRIED_THICKNESS_RATIO`], both having one.
fn evenly_thick(opposites: &[Option<Opposite>]) -> impl Fn(usize, usize) -> bool + Sync + '_ {
    move |i, j| match (opposites[i], opposites[j]) {
        (Some(a), Some(b)) => {
            let (thin, thick) = (a.thickness.min(b.thickness), a.thickness.max(b.thickness));
            thick <= CARRIED_THICKNESS_RATIO * thin
        }
        _ => false,
    }
}

/// How a source at `q` (normal `m`) sits from a target at `p` (normal
/// `n`) on a part `2·half` mm thick, for the slab's kernel: across the
/// face behind (read as T at the offset along the face), along the same
/// face or round a crease (read as R), or `None` beyond `reach` mm or
/// deeper than the face behind.
fn separation(p: Vec3, n: Vec3, half: f32, q: Vec3, m: Vec3, reach: f32) -> Option<Separation> {
    let d = q - p;
    let d2 = d.length_squared();
    if d2 > reach * reach {
        return None;
    }
    if let Some(length) = longer_path(q, m, p, n, d2) {
        return Some(Separation {
            distance: length,
            across: length,
            t: 0.0,
        });
    }
    let along = d.dot(n);
    let distance = d2.sqrt();
    if m.dot(n) < 0.0 && along < -half {
        // Deeper than the face behind: another surface beyond the part,
        // which its slab does not join to this face.
        if along < -3.0 * half {
            return None;
        }
        return Some(Separation {
            distance,
            across: (d2 - along * along).max(0.0).sqrt(),
            t: 1.0,
        });
    }
    Some(Separation {
        distance,
        across: distance,
        t: 0.0,
    })
}

#[cfg(test)]
mod tests {
    use super::thin_tolerance;

    /// The thin parts' allowance grows as their share of the map shrinks,
    /// up to four times the tolerance, and stays finite on any share.
    #[test]
    fn thin_parts_may_miss_by_at_most_four_times_the_tolerance() {
        assert_eq!(thin_tolerance(0.01, 1.0), 0.01);
        assert!((thin_tolerance(0.01, 0.25) - 0.02).abs() < 1e-12);
        for share in [1.0 / 16.0, 1e-3, 1e-300, 0.0, -1.0] {
            let allowed = thin_tolerance(0.01, share);
            assert!((allowed - 0.04).abs() < 1e-12, "share {share}: {allowed}");
        }
        // A share that is no number holds them to the tolerance itself.
        for share in [4.0, f64::INFINITY, f64::NAN] {
            assert_eq!(thin_tolerance(0.01, share), 0.01, "share {share}");
        }
    }
}
