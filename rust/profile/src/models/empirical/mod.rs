//! The empirical BSSRDF of Donner et al. 2009 at normal incidence, as a
//! radial profile a bake can use.
//!
//! The paper's fitted parameter table (about 250 MB) is not printed in the
//! paper, so this model does what the paper does: per material channel it
//! simulates the exitant hemispheres (§2.1, [`crate::models::empirical::simulation`])
//! and fits the elliptic lobe H (eq. 8, [`crate::models::empirical::lobe`]) to each
//! by the contour-wise fit of §4.1 ([`crate::models::empirical::fit`]), reporting the
//! fit's RMS error per slice (the paper's is 3.2·10⁻³ on average, §4.3).
//! A slice depends only on (α, g, η); σt scales it (eq. 12). R(r) is the
//! exitance ∫ H cos θ_o dω of the fitted lobes, constant over each tallied
//! annulus (even in ln r past 0.01 mean free paths), so the profile holds
//! exactly the light of its lobes.
//!
//! The fit rescales each lobe's k_s so that its exitance is the slice's
//! simulated one ([`crate::models::empirical::fit`]): what a bake reads, the
//! exitance, is therefore the simulation's, and the lobe's shape (its
//! spread over exit directions, which one radiance per texel cannot keep)
//! changes no map.
//!
//! Scope: the top layer taken as semi-infinite under a smooth boundary
//! (a layered material is refused). This profile is the normal-incidence,
//! radially symmetric one; oblique incidence (the paper's θ_i axis and its
//! θ_s dependence) is [`crate::models::empirical::oblique`], by the exitance's
//! azimuthal harmonics.

pub mod fit;
pub mod kernel;
pub mod lobe;
pub mod oblique;
pub mod simulation;

use crate::diffusion::medium::Medium;
use crate::material::{Layer, Material};
use crate::models::dipole::Dipole;
use crate::models::empirical::fit::{SliceFit, fit_slice};
use crate::models::empirical::simulation::{Grid, simulate};
use crate::profile::Profile;
use crate::{Rgb, rgb_map};
use rayon::prelude::*;
use std::f64::consts::PI;

/// Photons per channel a bake simulates by default.
pub const DEFAULT_PHOTONS: u64 = 500_000;
/// Seed of the default simulation.
pub const DEFAULT_SEED: u64 = 1;
/// Smallest radius tallied, mean free paths (the paper's first, §2.2).
pub const INNERMOST_RADIUS_MFP: f64 = 0.01;
/// Radial bins, even in ln r past the first.
pub const RADIAL_BINS: usize = 40;
/// θ_o bins, even in sin²θ_o.
pub const THETA_BINS: usize = 12;
/// φ_o bins, centred every 15° from 0 to 180°.
pub const PHI_BINS: usize = 13;

/// How a slice is simulated: photons, seed and the grid's resolution.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EmpiricalSettings {
    /// Photons per channel.
    pub photons: u64,
    /// The simulation's seed.
    pub seed: u64,
    /// Radial bins.
    pub radial_bins: usize,
    /// θ_o bins.
    pub theta_bins: usize,
    /// φ_o bins.
    pub phi_bins: usize,
}

impl Default for EmpiricalSettings {
    fn default() -> Self {
        Self {
            photons: DEFAULT_PHOTONS,
            seed: DEFAULT_SEED,
            radial_bins: RADIAL_BINS,
            theta_bins: THETA_BINS,
            phi_bins: PHI_BINS,
        }
    }
}

/// The optical parameters a slice depends on (§2).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SliceOptics {
    /// Single-scattering albedo α = σs/σt.
    pub albedo: f64,
    /// Henyey–Greenstein g.
    pub g: f64,
    /// Relative index η of the medium over the outside.
    pub eta: f64,
}

impl SliceOptics {
    /// The channel-`c` optics of `layer`.
    pub fn of(layer: &Layer, c: usize) -> Self {
        let sigma_t = layer.sigma_a[c] + layer.sigma_s[c];
        Self {
            albedo: if sigma_t > 0.0 {
                (layer.sigma_s[c] / sigma_t).clamp(0.0, 1.0)
            } else {
                0.0
            },
            g: layer.g,
            eta: layer.ior,
        }
    }

    /// Radial bin edges (mean free paths): 0, then from
    /// [`INNERMOST_RADIUS_MFP`] out to twice the radius holding all but 10⁻⁴
    /// of the dipole's reflectance (at least 10 mfp, the paper's last).
    pub fn edges_mfp(&self, bins: usize) -> Vec<f64> {
        let medium = Medium {
            sigma_a: 1.0 - self.albedo,
            sigma_s_reduced: self.albedo * (1.0 - self.g),
        };
        let reach = Dipole::new([medium; 3], self.eta).d_max(1e-4)[0];
        let outer = if reach.is_finite() && reach > 0.0 {
            (2.0 * reach).clamp(10.0, 1e4)
        } else {
            1e4
        };
        let inner = INNERMOST_RADIUS_MFP;
        let mut edges = vec![0.0];
        let steps = bins.max(2) - 1;
        edges.extend((0..=steps).map(|i| inner * (outer / inner).powf(i as f64 / steps as f64)));
        edges
    }
}

/// One channel's fitted slice: a lobe per radius, in mean free paths.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Slice {
    /// What was simulated.
    pub optics: SliceOptics,
    /// Edges of the tallied annuli, mean free paths, from 0.
    pub edges_mfp: Vec<f64>,
    /// Radii of the fitted hemispheres (each annulus halved in area), mfp.
    pub radii_mfp: Vec<f64>,
    /// The fit per radius.
    pub fits: Vec<SliceFit>,
    /// The simulated exitance per radius, 1/ℓ² per unit flux entering.
    pub simulated_exitance: Vec<f64>,
    /// The simulated total diffuse reflectance.
    pub simulated_total: f64,
    /// Its standard error.
    pub simulated_total_stderr: f64,
}

impl Slice {
    /// Simulates and fits the slice of `optics`; `stream` separates the
    /// random streams of a material's channels.
    pub fn simulate(optics: SliceOptics, settings: &EmpiricalSettings, stream: u64) -> Self {
        let grid = Grid {
            edges_mfp: optics.edges_mfp(settings.radial_bins),
            theta_bins: settings.theta_bins.max(2),
            phi_bins: settings.phi_bins.max(3),
        };
        let data = simulate(
            optics.albedo,
            optics.g,
            optics.eta,
            &grid,
            settings.photons,
            settings.seed,
            stream,
        );
        let exitance = |values: &[f64]| -> f64 {
            (0..grid.theta_bins)
                .flat_map(|i| (0..grid.phi_bins).map(move |k| (i, k)))
                .map(|(i, k)| values[grid.index(i, k)] * grid.projected_solid_angle(i, k))
                .sum()
        };
        let simulated_exitance: Vec<f64> = data.radiance.iter().map(|v| exitance(v)).collect();
        Self {
            optics,
            radii_mfp: (0..grid.radial_bins()).map(|b| grid.radius(b)).collect(),
            edges_mfp: grid.edges_mfp.clone(),
            fits: (0..grid.radial_bins())
                .into_par_iter()
                .map(|b| {
                    let (v, e) = (&data.radiance[b], &data.radiance_stderr[b]);
                    fit_slice(&grid, v, e, optics.eta, simulated_exitance[b])
                })
                .collect(),
            simulated_exitance,
            simulated_total: data.total_reflectance,
            simulated_total_stderr: data.total_reflectance_stderr,
        }
    }

    /// The model's exitance per radius, 1/ℓ² per unit flux entering.
    pub fn exitance(&self) -> Vec<f64> {
        self.fits
            .iter()
            .map(|f| f.lobe.exitance(self.optics.eta))
            .collect()
    }
}

/// How well the lobes follow the simulation, for one channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitError {
    /// Mean over the slices within 10 mean free paths (the paper's radii)
    /// of the RMS fit error, 1/(ℓ² sr) with ℓ the mean free path: the
    /// quantity the paper reports as 3.2·10⁻³ (§4.3).
    pub mean_rms: f64,
    /// Mean over the same slices of the RMS relative to the slice's peak.
    pub mean_relative_rms: f64,
    /// Mean over the same slices of the simulation's own noise RMS.
    pub mean_noise_rms: f64,
    /// Total reflectance of the fitted model over the simulation's, minus 1.
    pub total_error: f64,
}

/// The empirical model's profile of a material.
#[derive(Clone, Debug)]
pub struct EmpiricalProfile {
    slices: [Slice; 3],
    tables: [Annuli; 3],
}

impl EmpiricalProfile {
    /// Simulates and fits each channel of `material`'s top layer. `Err`
    /// says why the model does not apply.
    pub fn simulate(material: &Material, settings: &EmpiricalSettings) -> Result<Self, String> {
        let top = check(material)?;
        let slices =
            [0, 1, 2].map(|c| Slice::simulate(SliceOptics::of(top, c), settings, c as u64));
        Self::from_slices(material, slices)
    }

    /// The profile of `material` from slices fitted before (a cache);
    /// `Err` when they do not belong to the material.
    pub fn from_slices(material: &Material, slices: [Slice; 3]) -> Result<Self, String> {
        let top = check(material)?;
        for (c, slice) in slices.iter().enumerate() {
            if slice.optics != SliceOptics::of(top, c) {
                return Err(format!(
                    "the fitted slice of channel {c} is for other optics"
                ));
            }
        }
        let tables = [0, 1, 2].map(|c| {
            let sigma_t = top.sigma_a[c] + top.sigma_s[c];
            Annuli::new(&slices[c], sigma_t)
        });
        Ok(Self { slices, tables })
    }

    /// The fitted slices, red, green, blue.
    pub fn slices(&self) -> &[Slice; 3] {
        &self.slices
    }

    /// The fit's error per channel (see [`FitError`]).
    pub fn fit_error(&self) -> [FitError; 3] {
        let totals = self.total_reflectance();
        [0, 1, 2].map(|c| {
            let slice = &self.slices[c];
            let within: Vec<&SliceFit> = slice
                .radii_mfp
                .iter()
                .zip(&slice.fits)
                .filter(|(r, _)| **r <= 10.0)
                .map(|(_, f)| f)
                .collect();
            let n = within.len().max(1) as f64;
            let mean = |f: &dyn Fn(&SliceFit) -> f64| within.iter().map(|s| f(s)).sum::<f64>() / n;
            FitError {
                mean_rms: mean(&|f| f.rms),
                mean_relative_rms: mean(&|f| if f.peak > 0.0 { f.rms / f.peak } else { 0.0 }),
                mean_noise_rms: mean(&|f| f.noise_rms),
                total_error: if slice.simulated_total > 0.0 {
                    totals[c] / slice.simulated_total - 1.0
                } else {
                    0.0
                },
            }
        })
    }
}

/// The top layer, if the model applies to `material`.
fn check(material: &Material) -> Result<&Layer, String> {
    let top = material
        .layers()
        .and_then(|l| l.first())
        .ok_or("a measured sum of Gaussians has no optical coefficients to simulate")?;
    if material.roughness > 0.0 {
        return Err(
            "the empirical model is fitted under a smooth boundary; this material is rough".into(),
        );
    }
    Ok(top)
}

/// One channel's R(r) in mm: the lobes' exitance, constant over each
/// annulus the simulation tallied, scaled by σt (eq. 12), so every
/// annulus holds exactly the light its lobe sends out.
#[derive(Clone, Debug)]
struct Annuli {
    /// Annulus edges, mm, increasing from 0.
    edges_mm: Vec<f64>,
    /// R per annulus, 1/mm².
    values: Vec<f64>,
    /// Reflectance inside each outer edge.
    enclosed: Vec<f64>,
}

impl Annuli {
    fn new(slice: &Slice, sigma_t: f64) -> Self {
        let usable = sigma_t.is_finite() && sigma_t > 0.0 && slice.edges_mfp.len() >= 2;
        if !usable {
            return Self {
                edges_mm: vec![0.0],
                values: Vec::new(),
                enclosed: Vec::new(),
            };
        }
        let edges_mm: Vec<f64> = slice.edges_mfp.iter().map(|e| e / sigma_t).collect();
        let values: Vec<f64> = slice
            .exitance()
            .iter()
            .map(|m| (m * sigma_t * sigma_t).max(0.0))
            .collect();
        let mut sum = 0.0;
        let enclosed = values
            .iter()
            .zip(edges_mm.windows(2))
            .map(|(v, e)| {
                sum += v * PI * (e[1] * e[1] - e[0] * e[0]);
                sum
            })
            .collect();
        Self {
            edges_mm,
            values,
            enclosed,
        }
    }

    /// The annulus holding `r`, if any.
    fn annulus(&self, r: f64) -> Option<usize> {
        let i = self.edges_mm.partition_point(|&e| e <= r);
        (i >= 1 && i <= self.values.len()).then(|| i - 1)
    }

    fn reflectance(&self, r: f64) -> f64 {
        self.annulus(r.max(0.0)).map_or(0.0, |i| self.values[i])
    }

    fn enclosed(&self, r: f64) -> f64 {
        let total = self.enclosed.last().copied().unwrap_or(0.0);
        if r.is_nan() || r <= 0.0 {
            return 0.0;
        }
        match self.annulus(r) {
            None => total,
            Some(i) => {
                let inner = if i == 0 { 0.0 } else { self.enclosed[i - 1] };
                let e0 = self.edges_mm[i];
                inner + self.values[i] * PI * (r * r - e0 * e0)
            }
        }
    }

    /// The radius where r²R(r), the reflectance per unit ln r, peaks.
    fn length_scale(&self) -> f64 {
        let mut best = (0.0, self.edges_mm.get(1).copied().unwrap_or(1.0));
        for (v, e) in self.values.iter().zip(self.edges_mm.windows(2)) {
            let r = ((e[0] * e[0] + e[1] * e[1]) / 2.0).sqrt();
            if r * r * v > best.0 {
                best = (r * r * v, r);
            }
        }
        if best.1 > 0.0 && best.1.is_finite() {
            best.1
        } else {
            1.0
        }
    }
}

impl Profile for EmpiricalProfile {
    fn model(&self) -> &'static str {
        "empirical"
    }

    fn reflectance(&self, r: f64) -> Rgb {
        rgb_map(|c| self.tables[c].reflectance(r))
    }

    fn total_reflectance(&self) -> Rgb {
        rgb_map(|c| self.tables[c].enclosed(f64::INFINITY))
    }

    fn enclosed_reflectance(&self, r: f64) -> Rgb {
        rgb_map(|c| self.tables[c].enclosed(r))
    }

    fn length_scale(&self) -> Rgb {
        rgb_map(|c| self.tables[c].length_scale())
    }
}
