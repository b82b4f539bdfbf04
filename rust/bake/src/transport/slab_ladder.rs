//! The ladder of slabs of one material by thickness, each simulated by the
//! Monte Carlo when a part of its thickness is first met and kept in the
//! cache folder: the kernels thin parts gather with
//! ([`super::slab_profiles`]).

use crate::monte_carlo_cache::{cache_dir, monte_carlo_tallies};
use crate::transport::kernel::Kernel;
use rayon::prelude::*;
use sssbake_profile::Rgb;
use sssbake_profile::boundary::fresnel::diffuse_reflectance_exact;
use sssbake_profile::material::{Layer, Material, Optics};
use sssbake_profile::models::monte_carlo::profile::ProfileSettings;
use sssbake_profile::models::tabulated::Tabulated;
use sssbake_profile::profile::Profile;
use std::sync::OnceLock;

/// Parts thinner than this many diffusion lengths 1/σtr of a channel take
/// their slab's profile in that channel; thicker parts keep the
/// half-space's, with the slab's totals ([`super::local_slab`]). Over a
/// diffusion length a slab's spread has become a half-space's but for the
/// light it still sends through, which the totals carry.
const THIN_DIFFUSION_LENGTHS: f64 = 1.2;
/// Rungs per factor e of thickness: neighbouring rungs 22% apart.
const RUNGS_PER_E: f64 = 5.0;
/// The thinnest rung, as a share of the finest mean free path; thinner
/// parts take it.
const THINNEST_MEAN_FREE_PATHS: f64 = 0.05;

/// One simulated slab.
pub(super) struct Rung {
    /// R_t(r) and T_t(r), tabulated.
    pub(super) kernel: Kernel,
    /// Light returned without scattering (internal reflections of the
    /// entering beam), per unit flux entering.
    pub(super) unscattered_back: Rgb,
    /// Light sent straight through without scattering.
    pub(super) unscattered_through: Rgb,
    /// The scattered light the slab returns and sends through (the
    /// kernel holds all but a share `d_max_epsilon` of it).
    pub(super) scattered_total: Rgb,
}

/// The slabs of one material, by thickness, each simulated when a part of
/// its thickness is first met.
pub struct SlabProfiles {
    material: Material,
    layer: Layer,
    /// The half-space profile's reach, mm: no slab's goes further.
    pub(super) reach: f64,
    /// The share of each slab's light its kernel may leave beyond its
    /// reach.
    d_max_epsilon: f64,
    /// The share of the light a slab would carry past a part's rim that
    /// returns into the part: the boundary's diffuse internal reflectance
    /// F_dr (0 where index-matched).
    pub(super) rim_return: f64,
    /// The ladder's thicknesses, mm, increasing: one per rung.
    pub(super) thickness: Vec<f64>,
    /// Each rung's slab once simulated (`None`: the simulation failed).
    rungs: Vec<OnceLock<Option<Rung>>>,
    /// Per channel, parts at least this thick (mm) keep the half-space's
    /// profile in that channel.
    pub thin_below: [f64; 3],
    /// The scale (mm) a part's curvature is read at to tell a slab from a
    /// ball: the longest half-light radius of the half-space's profile.
    pub curvature_scale: f32,
}

impl SlabProfiles {
    /// The ladder of slabs of `layer` (the one semi-infinite layer of
    /// `material`) up to the thickest part thin in some channel
    /// ([`THIN_DIFFUSION_LENGTHS`]), none reaching beyond `reach` mm (the
    /// half-space profile's), each tabulated to all but `d_max_epsilon` of
    /// its light, parts' curvature read at `curvature_scale` mm; `None`
    /// where no part can be thin. Nothing is simulated yet.
    pub fn new(
        material: &Material,
        layer: &Layer,
        reach: f64,
        d_max_epsilon: f64,
        curvature_scale: f32,
    ) -> Option<Self> {
        let d_max = reach;
        let thin_below =
            [0, 1, 2].map(|c| (THIN_DIFFUSION_LENGTHS / layer.medium(c).sigma_tr()).min(d_max));
        let thickest = thickest_of(thin_below);
        let finest = (0..3)
            .map(|c| 1.0 / (layer.sigma_a[c] + layer.sigma_s[c]))
            .fold(f64::INFINITY, f64::min);
        let thinnest = THINNEST_MEAN_FREE_PATHS * finest;
        if !(thickest.is_finite() && thinnest.is_finite() && thickest > thinnest) {
            return None;
        }
        let count = ((thickest / thinnest).ln() * RUNGS_PER_E).ceil() as usize + 1;
        let step = (thickest / thinnest).ln() / (count - 1) as f64;
        let thickness: Vec<f64> = (0..count)
            .map(|i| thinnest * (step * i as f64).exp())
            .collect();
        Some(Self {
            material: material.clone(),
            layer: layer.clone(),
            reach: d_max,
            d_max_epsilon,
            rim_return: diffuse_reflectance_exact(layer.ior),
            rungs: thickness.iter().map(|_| OnceLock::new()).collect(),
            thickness,
            thin_below,
            curvature_scale,
        })
    }

    /// Simulates the rungs `needed` not yet simulated, in parallel; `false`
    /// when one of them cannot be.
    pub(super) fn simulate(&self, needed: &[usize]) -> bool {
        needed.par_iter().all(|&r| self.rung(r).is_some())
    }

    /// Rung `r`, simulated on first use.
    fn rung(&self, r: usize) -> Option<&Rung> {
        self.rungs[r]
            .get_or_init(|| {
                Self::simulated(
                    &self.material,
                    &self.layer,
                    self.thickness[r],
                    self.reach,
                    self.d_max_epsilon,
                )
            })
            .as_ref()
    }

    fn simulated(
        material: &Material,
        layer: &Layer,
        thickness: f64,
        reach: f64,
        d_max_epsilon: f64,
    ) -> Option<Rung> {
        let slab = Material {
            optics: Optics::Layers(vec![Layer {
                thickness_mm: Some(thickness),
                ..layer.clone()
            }]),
            ..material.clone()
        };
        // The tallies as they are: the smoothing fit of the Monte Carlo
        // profile loses a slab's far tail (red 10% short 11–15 mm from a
        // light on 2 mm of skin1), and a kernel reads the near field
        // through its disk means, which average the tallies' noise there.
        let tallies =
            &monte_carlo_tallies(&slab, &ProfileSettings::default(), cache_dir().as_deref())?;
        let binned: Vec<usize> = (0..tallies.radii_mm.len())
            .filter(|&i| tallies.radii_mm[i] > 0.0)
            .collect();
        let profile = Tabulated::new(
            "slab",
            binned.iter().map(|&i| tallies.radii_mm[i]).collect(),
            binned.iter().map(|&i| tallies.reflectance[i]).collect(),
            binned.iter().map(|&i| tallies.transmittance[i]).collect(),
            tallies.total_reflectance,
            tallies.total_transmittance,
        );
        // A slab spreads light less than the half-space beneath it.
        let kernel = Kernel::within(&profile, d_max_epsilon, reach);
        let (reflected, sent) = (profile.total_reflectance(), profile.total_transmittance());
        Some(Rung {
            kernel,
            unscattered_back: tallies.unscattered_reflectance,
            unscattered_through: tallies.unscattered_transmittance,
            scattered_total: [0, 1, 2].map(|c| reflected[c] + sent[c]),
        })
    }

    /// The thicknesses of the rungs, mm.
    pub fn thicknesses(&self) -> &[f64] {
        &self.thickness
    }

    /// The two rungs about `t` mm and the weight of the second
    /// ([`rungs_about`]).
    pub(super) fn about(&self, t: f64) -> (usize, usize, f64) {
        rungs_about(&self.thickness, t)
    }

    /// Whether a part `t` mm thick takes its slab's profile in channel `c`.
    pub fn is_thin(&self, t: f64, c: usize) -> bool {
        t < self.thin_below[c]
    }

    /// The thickest part (mm) thin in some channel: thicker ones keep the
    /// half-space's profile.
    pub fn thickest_thin(&self) -> f64 {
        thickest_of(self.thin_below)
    }

    /// The rungs about `t` mm, simulated by [`Self::thin_texels`], and the
    /// weight of the second.
    pub(super) fn rungs_at(&self, t: f64) -> (&Rung, &Rung, f64) {
        let (a, b, w) = self.about(t);
        (self.rung_simulated(a), self.rung_simulated(b), w)
    }

    /// Rung `r`, which [`Self::thin_texels`] simulated.
    pub(super) fn rung_simulated(&self, r: usize) -> &Rung {
        self.rungs[r]
            .get()
            .and_then(Option::as_ref)
            .expect("thin_texels simulates every rung its texels read")
    }
}

pub(super) fn mix(a: Rgb, b: Rgb, w: f64) -> Rgb {
    [0, 1, 2].map(|c| a[c] + w * (b[c] - a[c]))
}

/// The two rungs of the ladder `thickness` (mm, increasing) about `t` mm
/// and the weight of the second, linear in ln t: the thinnest rung alone
/// (weight 0) below it and the thickest alone (weight 1) above it. The
/// ladder has at least one rung.
pub(crate) fn rungs_about(thickness: &[f64], t: f64) -> (usize, usize, f64) {
    let last = thickness.len() - 1;
    if last == 0 {
        return (0, 0, 0.0);
    }
    let above = thickness.partition_point(|&rung| rung < t).clamp(1, last);
    let (t0, t1) = (thickness[above - 1], thickness[above]);
    let w = ((t.max(t0) / t0).ln() / (t1 / t0).ln()).clamp(0.0, 1.0);
    (above - 1, above, w)
}

/// The largest of the channels' `thin_below`, mm.
fn thickest_of(thin_below: [f64; 3]) -> f64 {
    thin_below.iter().copied().fold(0.0, f64::max)
}
