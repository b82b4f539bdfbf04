//! The empirical model's oblique incidence (Donner et al. 2009 §2, the θ_i
//! and θ_s axes): a collimated beam refracted into the semi-infinite
//! medium at each of a few incidence angles, with the exiting light tallied
//! by radius r and by the surface azimuth θ_s (from the beam's travel
//! direction projected on the surface, so θ_s = 0 is forward).
//!
//! What a bake needs of the exitant hemispheres is their exitance
//! ∫ H cos θ_o dω, and each fitted lobe keeps its slice's simulated
//! exitance exactly ([`crate::models::empirical::fit`] rescales k_s to it), so the
//! exitance of the fitted lobes at (θ_i, r, θ_s) is the simulated one.
//! This module therefore tallies the exitance itself, not per exit
//! direction, and by its azimuthal Fourier harmonics rather than θ_s bins:
//! E(r, θ_s) = m₀(r) + Σ_k m_k(r) cos kθ_s (the beam's plane is a plane of
//! mirror symmetry, so there are no sine terms). Each photon adds its
//! weight × cos kθ_s to m_k directly, the least noisy estimate of a
//! harmonic there is, with no θ_s binning error.
//!
//! Incidence nodes are even in sin θ_i outside (0, 0.2, …, 1): the
//! refracted beam's horizontal part is sin θ_i/η, and it is what tilts
//! the exitance forward, so the kernel between nodes is close to linear in
//! sin θ_i; grazing light (sin θ_i = 1) still enters, refracted to the
//! critical angle.

use crate::models::empirical::SliceOptics;
use crate::models::empirical::simulation::{CHUNK, Exit, walk};
use crate::numerics::rng::Rng;
use rayon::prelude::*;
use std::f64::consts::PI;

/// sin θ_i (outside) of the incidence nodes.
pub const INCIDENCE_NODES: [f64; 6] = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0];
/// Azimuthal harmonics tallied, m₀ … m₈: the kernel keeps
/// [`HARMONICS_KEPT`]; the rest measure what dropping them costs.
pub const HARMONICS_TALLIED: usize = 9;
/// Harmonics the kernel keeps, m₀ … m₄. Near the entry point the exitance
/// of an oblique beam is a narrow forward lobe (m₁ above m₀ within a mean
/// free path), so the series converges slowly: at 60° the azimuthal mean
/// m₀ alone misplaces 31–68% of the light (L1: marble, skin1, ketchup),
/// m₀ and m₁ 12–34%, m₀ … m₄ 2–4% (6% for ketchup at 85°), about the
/// tallies' own noise at 2·10⁵ photons (docs/accuracy.md, "The empirical model at
/// oblique incidence").
pub const HARMONICS_KEPT: usize = 5;
/// Photons per channel and incidence node a bake simulates by default.
pub const DEFAULT_OBLIQUE_PHOTONS: u64 = 100_000;

/// One channel's exitance at one incidence, by radius and harmonic.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ObliqueTally {
    /// sin θ_i of the incident light outside.
    pub sin_outside: f64,
    /// Cosine of the refracted beam to the normal, inside.
    pub cos_inside: f64,
    /// `harmonics[b][k]`: m_k over annulus b (edges as the normal slice's),
    /// 1/ℓ² per unit flux entering.
    pub harmonics: Vec<[f64; HARMONICS_TALLIED]>,
    /// Their standard errors.
    pub harmonics_stderr: Vec<[f64; HARMONICS_TALLIED]>,
    /// Total diffuse reflectance (every radius).
    pub total: f64,
    /// Its standard error.
    pub total_stderr: f64,
    /// Mean position of the exitance along the forward direction, ℓ.
    pub centroid: f64,
    /// Its standard error (ratio estimate, first order).
    pub centroid_stderr: f64,
}

impl ObliqueTally {
    /// The share of the light a kernel keeping harmonics m₀ … m_{kept−1}
    /// puts in the wrong place: ∫ |Σ_{k ≥ kept} m_k cos kθ_s| dA over the
    /// total, on annuli `edges_mfp` (the tallies' own), θ_s on 360 points.
    /// Noise in the tallied harmonics adds to it; [`Self::noise_share`] is
    /// that floor.
    pub fn misplaced_share(&self, edges_mfp: &[f64], kept: usize) -> f64 {
        const POINTS: usize = 360;
        let mut dropped = 0.0;
        let mut total = 0.0;
        for (m, e) in self.harmonics.iter().zip(edges_mfp.windows(2)) {
            let area = PI * (e[1] * e[1] - e[0] * e[0]);
            total += area * m[0];
            let mean_abs = (0..POINTS)
                .map(|i| {
                    let theta = (i as f64 + 0.5) / POINTS as f64 * 2.0 * PI;
                    (kept..HARMONICS_TALLIED)
                        .map(|k| m[k] * (k as f64 * theta).cos())
                        .sum::<f64>()
                        .abs()
                })
                .sum::<f64>()
                / POINTS as f64;
            dropped += area * mean_abs;
        }
        if total > 0.0 { dropped / total } else { 0.0 }
    }

    /// The same sum over the standard errors in place of the harmonics
    /// (each error with a random sign): what noise alone misplaces.
    pub fn noise_share(&self, edges_mfp: &[f64], kept: usize) -> f64 {
        // E|Σ e_k cos kθ ε_k| ≈ √(2/π) · RMS, the RMS being √(Σ e_k²/2).
        let mut dropped = 0.0;
        let mut total = 0.0;
        let errors = self.harmonics_stderr.iter().zip(edges_mfp.windows(2));
        for (m, (e, edge)) in self.harmonics.iter().zip(errors) {
            let area = PI * (edge[1] * edge[1] - edge[0] * edge[0]);
            total += area * m[0];
            let rms = (kept..HARMONICS_TALLIED)
                .map(|k| e[k] * e[k] / 2.0)
                .sum::<f64>()
                .sqrt();
            dropped += area * (2.0 / PI).sqrt() * rms;
        }
        if total > 0.0 { dropped / total } else { 0.0 }
    }
}

/// A channel's tallies at every incidence node.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ObliqueSlice {
    /// What was simulated.
    pub optics: SliceOptics,
    /// Annulus edges, mean free paths, from 0.
    pub edges_mfp: Vec<f64>,
    /// One tally per oblique node, [`INCIDENCE_NODES`] from the second
    /// (normal incidence is the normal slice's).
    pub nodes: Vec<ObliqueTally>,
}

impl ObliqueSlice {
    /// Simulates `photons` photons per node for `optics` on annuli
    /// `edges_mfp` (those of the normal slice), seeded by `seed`, `stream`
    /// separating a material's channels.
    pub fn simulate(
        optics: SliceOptics,
        edges_mfp: Vec<f64>,
        photons: u64,
        seed: u64,
        stream: u64,
    ) -> Self {
        let nodes = INCIDENCE_NODES
            .iter()
            .enumerate()
            .skip(1)
            .map(|(j, &s)| {
                // Streams apart from the normal slice's (stream << 40).
                let stream = (1 << 36) | (stream << 8) | j as u64;
                simulate_incidence(optics, &edges_mfp, s, photons, seed, stream)
            })
            .collect();
        Self {
            optics,
            edges_mfp,
            nodes,
        }
    }

    /// Relative L2 error, over the plane and every node, of keeping harmonics m₀ … m_{kept−1}: the energy of the
    /// dropped harmonics (their noise variance removed) over the whole.
    pub fn truncation_error(&self, kept: usize) -> f64 {
        let (mut dropped, mut whole) = (0.0, 0.0);
        for node in &self.nodes {
            for (b, (m, e)) in node
                .harmonics
                .iter()
                .zip(&node.harmonics_stderr)
                .enumerate()
            {
                let (r0, r1) = (self.edges_mfp[b], self.edges_mfp[b + 1]);
                let area = PI * (r1 * r1 - r0 * r0);
                // ∫ cos² kθ dθ / 2π is 1 for k = 0 and 1/2 above.
                let energy = |k: usize| {
                    let w = if k == 0 { 1.0 } else { 0.5 };
                    w * (m[k] * m[k] - e[k] * e[k]).max(0.0)
                };
                whole += area * (0..HARMONICS_TALLIED).map(energy).sum::<f64>();
                dropped += area * (kept..HARMONICS_TALLIED).map(energy).sum::<f64>();
            }
        }
        if whole > 0.0 { dropped / whole } else { 0.0 }.sqrt()
    }
}

/// Sums per annulus of w cos kθ_s and its square, and of w and w·x.
struct Tally {
    bins: Vec<[[f64; 2]; HARMONICS_TALLIED]>,
    total: [f64; 2],
    moment: [f64; 2],
    cross: f64,
}

impl Tally {
    fn new(n: usize) -> Self {
        Self {
            bins: vec![[[0.0; 2]; HARMONICS_TALLIED]; n],
            total: [0.0; 2],
            moment: [0.0; 2],
            cross: 0.0,
        }
    }

    fn merge(mut self, other: &Tally) -> Self {
        for (a, b) in self.bins.iter_mut().zip(&other.bins) {
            for (a, b) in a.iter_mut().zip(b) {
                a[0] += b[0];
                a[1] += b[1];
            }
        }
        for (a, b) in [
            (&mut self.total, &other.total),
            (&mut self.moment, &other.moment),
        ] {
            a[0] += b[0];
            a[1] += b[1];
        }
        self.cross += other.cross;
        self
    }
}

/// The tally at one incidence, sin θ_i = `sin_outside` outside.
pub fn simulate_incidence(
    optics: SliceOptics,
    edges_mfp: &[f64],
    sin_outside: f64,
    photons: u64,
    seed: u64,
    stream: u64,
) -> ObliqueTally {
    let sin_outside = if sin_outside.is_finite() {
        sin_outside.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let eta = if optics.eta.is_finite() && optics.eta > 0.0 {
        optics.eta
    } else {
        1.0
    };
    let sin_inside = (sin_outside / eta).min(1.0);
    let cos_inside = (1.0 - sin_inside * sin_inside).sqrt();
    let start = [sin_inside, 0.0, cos_inside];
    let bins = edges_mfp.len().saturating_sub(1);
    let chunks = photons.div_ceil(CHUNK);
    let tallies: Vec<Tally> = (0..chunks)
        .into_par_iter()
        .map(|chunk| {
            let count = CHUNK.min(photons - chunk * CHUNK);
            let mut rng = Rng::new(seed, (stream << 24) | chunk);
            let mut tally = Tally::new(bins);
            for _ in 0..count {
                let exit = walk(optics.albedo, optics.g, eta, start, &mut rng);
                if let Exit::Left {
                    position, weight, ..
                } = exit
                {
                    record(position, weight, edges_mfp, &mut tally);
                }
            }
            tally
        })
        .collect();
    // Merged in chunk order, so any thread count gives the same sums.
    let sum = tallies.iter().fold(Tally::new(bins), |a, b| a.merge(b));
    let n = photons.max(1) as f64;
    let mean_and_error = |s: [f64; 2]| {
        let mean = s[0] / n;
        let variance = (s[1] / n - mean * mean).max(0.0);
        (mean, (variance / n).sqrt())
    };
    let mut harmonics = vec![[0.0; HARMONICS_TALLIED]; bins];
    let mut harmonics_stderr = harmonics.clone();
    for b in 0..bins {
        let (r0, r1) = (edges_mfp[b], edges_mfp[b + 1]);
        let area = PI * (r1 * r1 - r0 * r0);
        for k in 0..HARMONICS_TALLIED {
            // m_k = (2 − δ_k0) ⟨w cos kθ_s⟩ per unit area.
            let scale = if k == 0 { 1.0 } else { 2.0 } / area;
            let (mean, error) = mean_and_error(sum.bins[b][k]);
            harmonics[b][k] = mean * scale;
            harmonics_stderr[b][k] = error * scale;
        }
    }
    let (total, total_stderr) = mean_and_error(sum.total);
    let (moment, moment_stderr) = mean_and_error(sum.moment);
    let centroid = if total > 0.0 { moment / total } else { 0.0 };
    // Var(X/Y) ≈ (Var X − 2c Cov + c² Var Y)/Y², per photon, over n.
    let cov = sum.cross / n - moment * total;
    let var_x = moment_stderr * moment_stderr * n;
    let var_y = total_stderr * total_stderr * n;
    let centroid_var = (var_x - 2.0 * centroid * cov + centroid * centroid * var_y).max(0.0);
    let centroid_stderr = if total > 0.0 {
        (centroid_var / n).sqrt() / total
    } else {
        0.0
    };
    ObliqueTally {
        sin_outside,
        cos_inside,
        harmonics,
        harmonics_stderr,
        total,
        total_stderr,
        centroid,
        centroid_stderr,
    }
}

/// Tallies a photon leaving at `position` with weight `w`.
fn record(position: [f64; 3], w: f64, edges_mfp: &[f64], tally: &mut Tally) {
    let (x, y) = (position[0], position[1]);
    tally.total[0] += w;
    tally.total[1] += w * w;
    tally.moment[0] += w * x;
    tally.moment[1] += w * x * w * x;
    tally.cross += w * x * w;
    let radius = x.hypot(y);
    let bin = edges_mfp.partition_point(|&e| e <= radius);
    if bin == 0 || bin >= edges_mfp.len() {
        return;
    }
    let cos_s = if radius > 0.0 { x / radius } else { 1.0 };
    // cos kθ by the Chebyshev recurrence.
    let (mut previous, mut current) = (1.0, cos_s);
    for (k, slot) in tally.bins[bin - 1].iter_mut().enumerate() {
        let c = if k == 0 { 1.0 } else { current };
        if k >= 1 {
            let next = 2.0 * cos_s * current - previous;
            previous = current;
            current = next;
        }
        slot[0] += w * c;
        slot[1] += w * c * w * c;
    }
}
