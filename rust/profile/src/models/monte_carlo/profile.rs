//! The Monte Carlo reference as a profile a bake can use: R(r) and T(r)
//! tallied per radial bin with standard errors ([`crate::models::monte_carlo`]),
//! then smoothed by a sum of Gaussians per channel fitted to the tallies
//! (non-negative weights, the simulation's total kept), with the fit's
//! error reported. The fit only smooths: its weights sum to the simulated
//! total, so the profile neither gains nor loses light, and what it cannot
//! follow shows in [`MonteCarloProfile::fit_error`].
//!
//! Where diffusion fails (low albedo, thin layers, just under the entry
//! point) this is the better profile; it costs a simulation per material,
//! which a bake keeps on disk (`sssbake::scattering`).

use crate::material::Layer;
use crate::model::{Model, build_profile};
use crate::models::gaussians::{SumOfGaussians, fit_gaussians};
use crate::models::monte_carlo::{MonteCarlo, Settings, simulate};
use crate::models::tabulated::Tabulated;
use crate::profile::Profile;
use crate::{Material, Rgb, rgb_map};

/// Photons per channel the bakeable profile simulates by default.
pub const DEFAULT_PHOTONS: u64 = 200_000;
/// Seed of the bakeable profile's simulation.
pub const DEFAULT_SEED: u64 = 1;
/// Gaussians per channel in the smoothing fit.
pub const SMOOTHING_GAUSSIANS: usize = 8;
/// Radial bins, evenly spaced in ln r.
const BINS: usize = 64;

/// What the bakeable profile simulates: photons, seed and bin edges, all
/// derived from the material, so they (with the code's version) key a
/// cache of the tallies.
#[derive(Clone, Debug)]
pub struct ProfileSettings {
    /// Photons per channel.
    pub photons: u64,
    /// The simulation's seed.
    pub seed: u64,
}

impl Default for ProfileSettings {
    fn default() -> Self {
        Self {
            photons: DEFAULT_PHOTONS,
            seed: DEFAULT_SEED,
        }
    }
}

impl ProfileSettings {
    /// The simulation's settings for `material`: bins from a fiftieth of
    /// the finest mean free path out to twice the reach (all but 10⁻⁴ of
    /// the reflectance) of the material's diffusion profile, evenly spaced
    /// in ln r, the first reaching down to 0.
    pub fn simulation(&self, material: &Material) -> Settings {
        let finest = material.finest_mean_free_path_mm();
        let reach = build_profile(material, Model::default_for(material), 6)
            .map(|p| p.d_max(1e-4).into_iter().fold(0.0, f64::max))
            .unwrap_or(0.0);
        let lo = (finest / 50.0).max(1e-6);
        let hi = (2.0 * reach).max(100.0 * lo);
        let mut edges = vec![0.0];
        edges.extend((0..BINS).map(|i| lo * (hi / lo).powf(i as f64 / (BINS - 1) as f64)));
        Settings::new(self.photons, self.seed, edges)
    }
}

/// The simulation's tallies as a smooth profile.
#[derive(Clone, Debug)]
pub struct MonteCarloProfile {
    tallies: MonteCarlo,
    reflectance: SumOfGaussians,
    transmittance: SumOfGaussians,
    fit_error: [Rgb; 2],
}

impl MonteCarloProfile {
    /// Simulates `material` (which must have layers) with `settings`.
    pub fn simulate(material: &Material, settings: &ProfileSettings) -> Option<Self> {
        let layers: &[Layer] = material.layers()?;
        Some(Self::from_tallies(simulate(
            layers,
            &settings.simulation(material),
        )))
    }

    /// Smooths tallies made elsewhere (read back from a cache).
    pub fn from_tallies(tallies: MonteCarlo) -> Self {
        let positive: Vec<usize> = (0..tallies.radii_mm.len())
            .filter(|&i| tallies.radii_mm[i] > 0.0)
            .collect();
        let radii: Vec<f64> = positive.iter().map(|&i| tallies.radii_mm[i]).collect();
        let table = |values: &[Rgb], total: Rgb| {
            Tabulated::new(
                "montecarlo",
                radii.clone(),
                positive.iter().map(|&i| values[i]).collect(),
                vec![[0.0; 3]; radii.len()],
                total,
                [0.0; 3],
            )
        };
        let r = fit_gaussians(
            &table(&tallies.reflectance, tallies.total_reflectance),
            SMOOTHING_GAUSSIANS,
        );
        let t = fit_gaussians(
            &table(&tallies.transmittance, tallies.total_transmittance),
            SMOOTHING_GAUSSIANS,
        );
        Self {
            tallies,
            reflectance: r.gaussians,
            transmittance: t.gaussians,
            fit_error: [r.error, t.error],
        }
    }

    /// The simulation behind the profile, with its standard errors.
    pub fn tallies(&self) -> &MonteCarlo {
        &self.tallies
    }

    /// The smoothing fit's relative r-weighted RMS error per channel, of
    /// R(r) (`[0]`) and T(r) (`[1]`) against the tallies.
    pub fn fit_error(&self) -> [Rgb; 2] {
        self.fit_error
    }
}

impl Profile for MonteCarloProfile {
    fn model(&self) -> &'static str {
        "montecarlo"
    }

    fn reflectance(&self, r: f64) -> Rgb {
        self.reflectance.reflectance(r)
    }

    fn transmittance(&self, r: f64) -> Rgb {
        self.transmittance.reflectance(r)
    }

    fn total_reflectance(&self) -> Rgb {
        self.reflectance.total_reflectance()
    }

    fn total_transmittance(&self) -> Rgb {
        self.transmittance.total_reflectance()
    }

    fn ballistic_reflectance(&self) -> Rgb {
        self.tallies.unscattered_reflectance
    }

    fn ballistic_transmittance(&self) -> Rgb {
        self.tallies.unscattered_transmittance
    }

    fn enclosed_reflectance(&self, r: f64) -> Rgb {
        self.reflectance.enclosed_reflectance(r)
    }

    fn length_scale(&self) -> Rgb {
        self.reflectance.length_scale()
    }

    fn reflectance_spectrum(&self, k: f64) -> Option<Rgb> {
        self.reflectance.reflectance_spectrum(k)
    }

    fn d_max(&self, epsilon: f64) -> Rgb {
        self.reflectance.d_max(epsilon)
    }
}

/// A quick check that tallies are usable: finite and non-negative.
pub fn tallies_are_physical(tallies: &MonteCarlo) -> bool {
    let ok = |v: &Rgb| v.iter().all(|x| x.is_finite() && *x >= 0.0);
    tallies.reflectance.iter().all(ok)
        && tallies.transmittance.iter().all(ok)
        && ok(&tallies.total_reflectance)
        && ok(&tallies.total_transmittance)
        && ok(&rgb_map(|c| tallies.truncated[c]))
}
