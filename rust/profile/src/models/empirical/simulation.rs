//! Photon tracing for the empirical BSSRDF (Donner et al. 2009 §2.1):
//! a collimated beam at normal incidence into a semi-infinite medium of
//! albedo α, Henyey–Greenstein g and relative index η, with the exiting
//! light tallied by radius r from the entry point and by exit direction
//! (θ_o, φ_o), φ_o measured from the radial direction.
//!
//! Lengths are in mean free paths ℓ = 1/σt (the response of one albedo is
//! the same at every ℓ up to scale, §2). Steps are exponential (eq. 3);
//! every interaction multiplies the weight by α and scatters by
//! Henyey–Greenstein; the boundary reflects or transmits by its Fresnel
//! reflectance, chosen at random; Russian roulette ends light photons
//! without bias. The photon starts just inside with weight 1, so the
//! tallies are per unit flux entering, as every profile here is. Exiting
//! photons are tallied where they leave (no path reuse, eq. 4): the
//! estimate is the same, with more noise per photon.

use crate::boundary::fresnel::dielectric_reflectance;
use crate::models::monte_carlo::scatter;
use crate::numerics::rng::Rng;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Photons per reproducible stream.
pub(crate) const CHUNK: u64 = 4096;
/// Below this weight a photon plays Russian roulette...
const ROULETTE_THRESHOLD: f64 = 1e-4;
/// ...and survives with this probability, its weight divided by it.
const ROULETTE_SURVIVAL: f64 = 0.1;
/// Interactions after which a photon is dropped (nearly lossless media).
const MAX_INTERACTIONS: u64 = 200_000;

/// The tally grid: radial bin edges and the direction bins.
///
/// θ_o bins are even in sin²θ_o (equal projected solid angle, so every
/// bin of a diffuse exitance gathers as many photons); φ_o bins are centred on
/// 0, Δ, 2Δ, …, π (Δ = π/(phi_bins − 1)) and fold φ_o and −φ_o together,
/// which normal incidence makes equal. The bins at φ_o = 0 and π sit on
/// the plane of symmetry, where the fit reads its samples (eq. 9).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Grid {
    /// Radial bin edges in mean free paths, increasing from 0.
    pub edges_mfp: Vec<f64>,
    /// Number of θ_o bins.
    pub theta_bins: usize,
    /// Number of φ_o bins (at least 2).
    pub phi_bins: usize,
}

impl Grid {
    /// Radial bins.
    pub fn radial_bins(&self) -> usize {
        self.edges_mfp.len().saturating_sub(1)
    }

    /// Radius splitting bin `b` into halves of equal area, mean free paths.
    pub fn radius(&self, b: usize) -> f64 {
        let (r0, r1) = (self.edges_mfp[b], self.edges_mfp[b + 1]);
        ((r0 * r0 + r1 * r1) / 2.0).sqrt()
    }

    /// Width of the φ_o bins, rad.
    pub fn phi_step(&self) -> f64 {
        PI / (self.phi_bins - 1) as f64
    }

    /// θ_o at the edge below bin `i` (`i` = `theta_bins`: π/2), rad.
    pub fn theta_edge(&self, i: usize) -> f64 {
        (i as f64 / self.theta_bins as f64).sqrt().min(1.0).asin()
    }

    /// θ_o at the centre of bin `i` (halving its projected solid angle), rad.
    pub fn theta_centre(&self, i: usize) -> f64 {
        ((i as f64 + 0.5) / self.theta_bins as f64).sqrt().asin()
    }

    /// The θ_o bin of `theta_o` (rad).
    pub fn theta_bin(&self, theta_o: f64) -> usize {
        ((theta_o.sin().powi(2) * self.theta_bins as f64) as usize).min(self.theta_bins - 1)
    }

    /// φ_o at the centre of bin `k`, rad.
    pub fn phi_centre(&self, k: usize) -> f64 {
        k as f64 * self.phi_step()
    }

    /// Projected solid angle ∫ cos θ dω of direction bin (i, k), both
    /// mirrored halves counted, sr.
    pub fn projected_solid_angle(&self, i: usize, k: usize) -> f64 {
        let (t0, t1) = (self.theta_edge(i), self.theta_edge(i + 1));
        0.5 * (t1.sin().powi(2) - t0.sin().powi(2)) * self.phi_width(k)
    }

    /// Solid angle of direction bin (i, k), both halves counted, sr.
    pub fn solid_angle(&self, i: usize, k: usize) -> f64 {
        let (t0, t1) = (self.theta_edge(i), self.theta_edge(i + 1));
        (t0.cos() - t1.cos()) * self.phi_width(k)
    }

    /// The φ extent of bin `k` over the whole circle (both halves).
    fn phi_width(&self, k: usize) -> f64 {
        if k == 0 || k + 1 == self.phi_bins {
            self.phi_step()
        } else {
            2.0 * self.phi_step()
        }
    }

    /// Index into a slice's values of direction bin (i, k).
    pub fn index(&self, i: usize, k: usize) -> usize {
        i * self.phi_bins + k
    }

    /// Direction bins per slice.
    pub fn directions(&self) -> usize {
        self.theta_bins * self.phi_bins
    }
}

/// What the simulation found: radiance per radius and direction bin.
#[derive(Clone, Debug)]
pub struct Hemispheres {
    /// The grid.
    pub grid: Grid,
    /// Radiance per unit flux entering, 1/(ℓ² sr), indexed
    /// `[radial bin][grid.index(i, k)]`.
    pub radiance: Vec<Vec<f64>>,
    /// Its standard error.
    pub radiance_stderr: Vec<Vec<f64>>,
    /// Total diffuse reflectance (every radius and direction).
    pub total_reflectance: f64,
    /// Its standard error.
    pub total_reflectance_stderr: f64,
    /// Weight dropped with photons past the interaction limit.
    pub truncated: f64,
}

/// Sums of weights and squared weights.
struct Tally {
    bins: Vec<[f64; 2]>,
    total: [f64; 2],
    truncated: f64,
}

impl Tally {
    fn new(n: usize) -> Self {
        Self {
            bins: vec![[0.0; 2]; n],
            total: [0.0; 2],
            truncated: 0.0,
        }
    }

    fn merge(mut self, other: &Tally) -> Self {
        for (a, b) in self.bins.iter_mut().zip(&other.bins) {
            a[0] += b[0];
            a[1] += b[1];
        }
        self.total[0] += other.total[0];
        self.total[1] += other.total[1];
        self.truncated += other.truncated;
        self
    }
}

/// Traces `photons` photons (seeded by `seed` and `stream`, reproducible on
/// any number of threads) into the medium (`albedo`, `g`, `eta`) and
/// tallies them on `grid`.
pub fn simulate(
    albedo: f64,
    g: f64,
    eta: f64,
    grid: &Grid,
    photons: u64,
    seed: u64,
    stream: u64,
) -> Hemispheres {
    let per_slice = grid.directions();
    let bins = grid.radial_bins() * per_slice;
    let chunks = photons.div_ceil(CHUNK);
    let tallies: Vec<Tally> = (0..chunks)
        .into_par_iter()
        .map(|chunk| {
            let count = CHUNK.min(photons - chunk * CHUNK);
            let mut rng = Rng::new(seed, (stream << 40) | chunk);
            let mut tally = Tally::new(bins);
            for _ in 0..count {
                trace(albedo, g, eta, grid, &mut rng, &mut tally);
            }
            tally
        })
        .collect();
    // Merged in chunk order, so any thread count gives the same sums.
    let total = tallies.iter().fold(Tally::new(bins), |a, b| a.merge(b));
    let n = photons.max(1) as f64;
    let mean_and_error = |s: [f64; 2]| {
        let mean = s[0] / n;
        let variance = (s[1] / n - mean * mean).max(0.0);
        (mean, (variance / n).sqrt())
    };
    let mut radiance = vec![vec![0.0; per_slice]; grid.radial_bins()];
    let mut radiance_stderr = radiance.clone();
    for (b, (values, errors)) in radiance.iter_mut().zip(&mut radiance_stderr).enumerate() {
        let (r0, r1) = (grid.edges_mfp[b], grid.edges_mfp[b + 1]);
        let area = PI * (r1 * r1 - r0 * r0);
        for i in 0..grid.theta_bins {
            for k in 0..grid.phi_bins {
                let j = grid.index(i, k);
                let scale = area * grid.projected_solid_angle(i, k);
                let (mean, error) = mean_and_error(total.bins[b * per_slice + j]);
                values[j] = mean / scale;
                errors[j] = error / scale;
            }
        }
    }
    let (total_reflectance, total_reflectance_stderr) = mean_and_error(total.total);
    Hemispheres {
        grid: grid.clone(),
        radiance,
        radiance_stderr,
        total_reflectance,
        total_reflectance_stderr,
        truncated: total.truncated / n,
    }
}

/// One photon from entry to absorption or exit, tallied on `grid`.
fn trace(albedo: f64, g: f64, eta: f64, grid: &Grid, rng: &mut Rng, tally: &mut Tally) {
    match walk(albedo, g, eta, [0.0, 0.0, 1.0], rng) {
        Exit::Left {
            position,
            direction,
            weight,
        } => record(direction, position, eta, grid, weight, tally),
        Exit::Absorbed => {}
        Exit::Truncated(weight) => tally.truncated += weight,
    }
}

/// How a photon's walk ended.
pub(crate) enum Exit {
    /// It left through the surface at `position` (z = 0, mean free paths
    /// from the entry point) travelling `direction` inside, with `weight`.
    Left {
        position: [f64; 3],
        direction: [f64; 3],
        weight: f64,
    },
    /// Russian roulette ended it.
    Absorbed,
    /// It was still alive after the interaction limit, with this weight.
    Truncated(f64),
}

/// One photon entering at the origin travelling `start` (unit, z > 0 is
/// down into the medium), walked to absorption or exit. Depth z grows
/// downwards.
pub(crate) fn walk(albedo: f64, g: f64, eta: f64, start: [f64; 3], rng: &mut Rng) -> Exit {
    let mut position = [0.0f64; 3];
    let mut direction = start;
    let mut weight = 1.0;
    for _ in 0..MAX_INTERACTIONS {
        let step = -rng.uniform_open().ln();
        if direction[2] < 0.0 && step >= position[2] / -direction[2] {
            let to_surface = position[2] / -direction[2];
            position[0] += to_surface * direction[0];
            position[1] += to_surface * direction[1];
            position[2] = 0.0;
            let cos_i = -direction[2];
            if rng.uniform() < dielectric_reflectance(cos_i, eta, 1.0) {
                direction[2] = cos_i;
                continue;
            }
            return Exit::Left {
                position,
                direction,
                weight,
            };
        }
        for (p, d) in position.iter_mut().zip(direction) {
            *p += step * d;
        }
        weight *= albedo;
        direction = scatter(direction, g, rng);
        if weight < ROULETTE_THRESHOLD {
            if rng.uniform() < ROULETTE_SURVIVAL {
                weight /= ROULETTE_SURVIVAL;
            } else {
                return Exit::Absorbed;
            }
        }
    }
    Exit::Truncated(weight)
}

/// Tallies a photon leaving at `position` (on the surface) travelling
/// `direction` inside, refracted out through the boundary.
fn record(
    direction: [f64; 3],
    position: [f64; 3],
    eta: f64,
    grid: &Grid,
    w: f64,
    tally: &mut Tally,
) {
    tally.total[0] += w;
    tally.total[1] += w * w;
    let radius = position[0].hypot(position[1]);
    let bin = grid.edges_mfp.partition_point(|&e| e <= radius);
    if bin == 0 || bin >= grid.edges_mfp.len() {
        return;
    }
    // Outside, the horizontal part scales by η (Snell) and keeps its azimuth.
    let sin_inside = direction[0].hypot(direction[1]);
    let theta_o = (eta * sin_inside).clamp(0.0, 1.0).asin();
    let radial = if radius > 0.0 {
        [position[0] / radius, position[1] / radius]
    } else {
        [1.0, 0.0]
    };
    let along = direction[0] * radial[0] + direction[1] * radial[1];
    let across = direction[1] * radial[0] - direction[0] * radial[1];
    let phi_o = across.abs().atan2(along);
    let i = grid.theta_bin(theta_o);
    let k = ((phi_o / grid.phi_step()).round() as usize).min(grid.phi_bins - 1);
    let slot = &mut tally.bins[(bin - 1) * grid.directions() + grid.index(i, k)];
    slot[0] += w;
    slot[1] += w * w;
}
