//! The Monte Carlo reference: photons through a stack of layers, in the
//! manner of MCML, tallying diffuse reflectance and transmittance by radius.
//!
//! A pencil beam enters at the origin at normal incidence (or at any angle,
//! [`simulate_oblique`]). The specular reflection at the top is left out:
//! the photon starts inside the first layer with weight 1, so R(r) and T(r)
//! are per unit flux entering the medium, as the diffusion profiles are. Steps are exponential in σt;
//! every interaction multiplies the weight by the single-scattering albedo
//! and scatters by Henyey–Greenstein; every interface reflects or refracts
//! by its Fresnel reflectance, chosen at random; Russian roulette ends
//! light photons without bias. Light leaving without a single scattering
//! event is tallied apart (it is not diffuse).

pub(crate) mod faces;
pub mod profile;

use crate::Rgb;
use crate::boundary::fresnel::dielectric_reflectance;
use crate::material::Layer;
use crate::models::monte_carlo::faces::{Crossing, RoughFace};
use crate::numerics::rng::Rng;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Photons per reproducible stream.
const CHUNK: u64 = 4096;
/// Cosine of the half-angle of the cone around the normal in which light
/// leaving the top counts as seen at normal view (18.2°).
pub const NORMAL_VIEW_COS: f64 = 0.95;
/// Below this weight a photon plays Russian roulette...
const ROULETTE_THRESHOLD: f64 = 1e-4;
/// ...and survives with this probability, its weight divided by it.
const ROULETTE_SURVIVAL: f64 = 0.1;

/// What to simulate.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Photons per channel.
    pub photons: u64,
    /// Seed; the same seed gives the same result on any number of threads.
    pub seed: u64,
    /// Radial bin edges in mm, increasing, starting at 0 or above.
    pub edges_mm: Vec<f64>,
    /// A photon still alive after this many interactions is dropped and
    /// counted in [`MonteCarlo::truncated`] (walks in nearly lossless media
    /// can be arbitrarily long).
    pub max_interactions: u64,
    /// RMS facet slope m of the faces against air, top and bottom (0:
    /// smooth; rough faces as [`crate::models::monte_carlo::faces`] makes them).
    pub roughness: f64,
}

impl Settings {
    /// `photons` photons with `seed`, binned at `edges_mm`, at most a
    /// million interactions each.
    pub fn new(photons: u64, seed: u64, edges_mm: Vec<f64>) -> Self {
        Self {
            photons,
            seed,
            edges_mm,
            max_interactions: 1_000_000,
            roughness: 0.0,
        }
    }
}

/// Tallies with their standard errors, per channel.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MonteCarlo {
    /// Bin edges, mm.
    pub edges_mm: Vec<f64>,
    /// Radius splitting each annulus into halves of equal area, mm.
    pub radii_mm: Vec<f64>,
    /// Diffuse reflectance per bin, 1/mm².
    pub reflectance: Vec<Rgb>,
    /// Standard error of `reflectance`.
    pub reflectance_stderr: Vec<Rgb>,
    /// Diffuse transmittance per bin, 1/mm².
    pub transmittance: Vec<Rgb>,
    /// Standard error of `transmittance`.
    pub transmittance_stderr: Vec<Rgb>,
    /// Total diffuse reflectance (all radii).
    pub total_reflectance: Rgb,
    /// Its standard error.
    pub total_reflectance_stderr: Rgb,
    /// Total diffuse transmittance (all radii).
    pub total_transmittance: Rgb,
    /// Its standard error.
    pub total_transmittance_stderr: Rgb,
    /// Σ weight·x of the diffuse reflectance, mm per unit flux entering,
    /// x along the beam's horizontal travel direction: over
    /// `total_reflectance`, how far forward of the entry point the
    /// reflected light leaves on average (0 at normal incidence).
    #[serde(default)]
    pub reflectance_moment_x: Rgb,
    /// Its standard error.
    #[serde(default)]
    pub reflectance_moment_x_stderr: Rgb,
    /// π times the radiance leaving the top towards the normal, per unit
    /// flux entering (dimensionless): the scattered light leaving within
    /// [`NORMAL_VIEW_COS`] of the normal in air, over that cone's
    /// projected solid angle π(1 − cos²). Over `total_reflectance`, how
    /// much brighter than a Lambertian exitance the surface looks from
    /// above.
    #[serde(default)]
    pub reflectance_at_normal: Rgb,
    /// Its standard error.
    #[serde(default)]
    pub reflectance_at_normal_stderr: Rgb,
    /// Light leaving the top without scattering (internal reflections;
    /// entered from air, the face's own reflection too).
    pub unscattered_reflectance: Rgb,
    /// Light leaving the bottom without scattering (ballistic).
    pub unscattered_transmittance: Rgb,
    /// Fresnel reflectance of the top surface at normal incidence (excluded).
    pub specular_reflectance: f64,
    /// Photons per channel.
    pub photons: u64,
    /// Scattering and absorption events simulated, all channels.
    pub interactions: u64,
    /// Weight dropped with photons that reached the interaction limit, per channel.
    pub truncated: Rgb,
}

/// Sums of weights and squared weights, per bin and in total.
#[derive(Clone, Debug)]
struct Tally {
    reflect: Vec<[f64; 2]>,
    transmit: Vec<[f64; 2]>,
    reflect_total: [f64; 2],
    transmit_total: [f64; 2],
    reflect_moment: [f64; 2],
    reflect_at_normal: [f64; 2],
    unscattered: [f64; 2],
    truncated: f64,
    interactions: u64,
}

impl Tally {
    fn new(bins: usize) -> Self {
        Self {
            reflect: vec![[0.0; 2]; bins],
            transmit: vec![[0.0; 2]; bins],
            reflect_total: [0.0; 2],
            transmit_total: [0.0; 2],
            reflect_moment: [0.0; 2],
            reflect_at_normal: [0.0; 2],
            unscattered: [0.0; 2],
            truncated: 0.0,
            interactions: 0,
        }
    }

    fn merge(mut self, other: &Tally) -> Self {
        let add = |a: &mut [f64; 2], b: &[f64; 2]| {
            a[0] += b[0];
            a[1] += b[1];
        };
        self.reflect
            .iter_mut()
            .zip(&other.reflect)
            .for_each(|(a, b)| add(a, b));
        self.transmit
            .iter_mut()
            .zip(&other.transmit)
            .for_each(|(a, b)| add(a, b));
        add(&mut self.reflect_total, &other.reflect_total);
        add(&mut self.transmit_total, &other.transmit_total);
        add(&mut self.reflect_moment, &other.reflect_moment);
        add(&mut self.reflect_at_normal, &other.reflect_at_normal);
        add(&mut self.unscattered, &other.unscattered);
        self.truncated += other.truncated;
        self.interactions += other.interactions;
        self
    }
}

/// One layer's coefficients in one channel, with its depth range.
#[derive(Clone, Copy, Debug)]
struct Slab {
    sigma_t: f64,
    albedo: f64,
    g: f64,
    ior: f64,
    top: f64,
    bottom: f64,
}

/// Simulates `settings.photons` photons per channel through `layers`.
pub fn simulate(layers: &[Layer], settings: &Settings) -> MonteCarlo {
    simulate_oblique(layers, settings, 1.0)
}

/// Where the photons start.
#[derive(Clone, Copy)]
enum Start {
    /// Inside the top layer, travelling along the direction.
    Inside([f64; 3]),
    /// In air above the top face, travelling along the direction.
    Above([f64; 3]),
}

/// As [`simulate`], for a collimated beam arriving from air at cosine
/// `cos_outside` (in (0, 1]) to the normal, which meets the top face as
/// it is (smooth, or rough with `settings.roughness`): the tallies are per
/// unit flux arriving, and what the face reflects is in
/// [`MonteCarlo::unscattered_reflectance`].
pub fn simulate_from_air(layers: &[Layer], settings: &Settings, cos_outside: f64) -> MonteCarlo {
    let mu = if cos_outside.is_finite() {
        cos_outside.clamp(1e-6, 1.0)
    } else {
        1.0
    };
    run(
        layers,
        settings,
        Start::Above([(1.0 - mu * mu).sqrt(), 0.0, mu]),
    )
}

/// As [`simulate`], for a beam that enters the top layer travelling at
/// cosine `cos_inside` (in (0, 1]) to the normal: the refracted direction
/// of light arriving obliquely from outside. The tallies stay per unit
/// flux entering, and [`MonteCarlo::specular_reflectance`] stays the
/// normal-incidence one; the caller weighs by its own angle's Fresnel.
pub fn simulate_oblique(layers: &[Layer], settings: &Settings, cos_inside: f64) -> MonteCarlo {
    let cos_inside = if cos_inside.is_finite() {
        cos_inside.clamp(1e-6, 1.0)
    } else {
        1.0
    };
    let start = [(1.0 - cos_inside * cos_inside).sqrt(), 0.0, cos_inside];
    run(layers, settings, Start::Inside(start))
}

fn run(layers: &[Layer], settings: &Settings, start: Start) -> MonteCarlo {
    let edges = settings.edges_mm.clone();
    let bins = edges.len().saturating_sub(1);
    let mut result = MonteCarlo {
        radii_mm: edges
            .windows(2)
            .map(|e| ((e[0] * e[0] + e[1] * e[1]) / 2.0).sqrt())
            .collect(),
        edges_mm: edges.clone(),
        reflectance: vec![[0.0; 3]; bins],
        reflectance_stderr: vec![[0.0; 3]; bins],
        transmittance: vec![[0.0; 3]; bins],
        transmittance_stderr: vec![[0.0; 3]; bins],
        specular_reflectance: layers
            .first()
            .map_or(0.0, |l| dielectric_reflectance(1.0, 1.0, l.ior)),
        photons: settings.photons,
        ..Default::default()
    };
    if layers.is_empty() || settings.photons == 0 {
        return result;
    }
    let n = settings.photons as f64;
    let mean_and_error = |s: [f64; 2]| {
        let mean = s[0] / n;
        let variance = (s[1] / n - mean * mean).max(0.0);
        (mean, (variance / n).sqrt())
    };
    let faces = Faces::new(layers, settings.roughness);
    for c in 0..3 {
        let slabs = channel_slabs(layers, c);
        let chunks = settings.photons.div_ceil(CHUNK);
        let tallies: Vec<Tally> = (0..chunks)
            .into_par_iter()
            .map(|chunk| {
                let count = CHUNK.min(settings.photons - chunk * CHUNK);
                let mut rng = Rng::new(settings.seed, ((c as u64) << 40) | chunk);
                let mut tally = Tally::new(bins);
                for _ in 0..count {
                    let Some((direction, weight)) = enter(&faces, start, &mut rng, &mut tally)
                    else {
                        continue;
                    };
                    let photon = Photon { direction, weight };
                    trace_photon(
                        &slabs,
                        &faces,
                        photon,
                        &edges,
                        settings.max_interactions,
                        &mut rng,
                        &mut tally,
                    );
                }
                tally
            })
            .collect();
        let total = tallies.iter().fold(Tally::new(bins), |acc, t| acc.merge(t));
        for b in 0..bins {
            let area = PI * (edges[b + 1] * edges[b + 1] - edges[b] * edges[b]);
            let (r, r_err) = mean_and_error(total.reflect[b]);
            let (t, t_err) = mean_and_error(total.transmit[b]);
            result.reflectance[b][c] = r / area;
            result.reflectance_stderr[b][c] = r_err / area;
            result.transmittance[b][c] = t / area;
            result.transmittance_stderr[b][c] = t_err / area;
        }
        (
            result.total_reflectance[c],
            result.total_reflectance_stderr[c],
        ) = mean_and_error(total.reflect_total);
        (
            result.total_transmittance[c],
            result.total_transmittance_stderr[c],
        ) = mean_and_error(total.transmit_total);
        (
            result.reflectance_moment_x[c],
            result.reflectance_moment_x_stderr[c],
        ) = mean_and_error(total.reflect_moment);
        let cone = 1.0 - NORMAL_VIEW_COS * NORMAL_VIEW_COS;
        let (at_normal, at_normal_err) = mean_and_error(total.reflect_at_normal);
        result.reflectance_at_normal[c] = at_normal / cone;
        result.reflectance_at_normal_stderr[c] = at_normal_err / cone;
        result.unscattered_reflectance[c] = total.unscattered[0] / n;
        result.unscattered_transmittance[c] = total.unscattered[1] / n;
        result.truncated[c] = total.truncated / n;
        result.interactions += total.interactions;
    }
    result
}

fn channel_slabs(layers: &[Layer], c: usize) -> Vec<Slab> {
    let mut depth = 0.0;
    layers
        .iter()
        .map(|l| {
            let sigma_t = l.sigma_a[c] + l.sigma_s[c];
            let top = depth;
            depth += l.thickness_mm.unwrap_or(f64::INFINITY);
            Slab {
                sigma_t,
                albedo: if sigma_t > 0.0 {
                    l.sigma_s[c] / sigma_t
                } else {
                    0.0
                },
                g: l.g,
                ior: l.ior,
                top,
                bottom: depth,
            }
        })
        .collect()
}

/// The faces against air: smooth, or rough on the top layer's top and the
/// bottom layer's bottom.
struct Faces {
    top: Option<RoughFace>,
    bottom: Option<RoughFace>,
    /// The top layer's index, for a smooth entry.
    top_ior: f64,
}

impl Faces {
    fn new(layers: &[Layer], roughness: f64) -> Self {
        let rough = |layer: Option<&Layer>| {
            layer
                .filter(|_| roughness > 0.0)
                .map(|l| RoughFace::new(roughness, l.ior))
        };
        Faces {
            top: rough(layers.first()),
            bottom: rough(layers.last()),
            top_ior: layers.first().map_or(1.0, |l| l.ior),
        }
    }
}

/// A photon as it starts inside: its direction and weight.
struct Photon {
    direction: [f64; 3],
    weight: f64,
}

/// The photon inside the top layer, or `None` where the top face sent it
/// back into air (counted as unscattered reflectance).
fn enter(faces: &Faces, start: Start, rng: &mut Rng, tally: &mut Tally) -> Option<([f64; 3], f64)> {
    let d = match start {
        Start::Inside(d) => return Some((d, 1.0)),
        Start::Above(d) => d,
    };
    if let Some(face) = &faces.top {
        return match face.cross(d, true, rng) {
            Crossing::Through(d, w) => Some((d, w)),
            Crossing::Back(_, w) => {
                tally.unscattered[0] += w;
                None
            }
        };
    }
    if rng.uniform() < dielectric_reflectance(d[2], 1.0, faces.top_ior) {
        tally.unscattered[0] += 1.0;
        return None;
    }
    let ratio = 1.0 / faces.top_ior;
    let cos_t = (1.0 - ratio * ratio * (1.0 - d[2] * d[2])).max(0.0).sqrt();
    Some(([d[0] * ratio, d[1] * ratio, cos_t], 1.0))
}

fn trace_photon(
    slabs: &[Slab],
    faces: &Faces,
    photon: Photon,
    edges: &[f64],
    max_interactions: u64,
    rng: &mut Rng,
    tally: &mut Tally,
) {
    let mut position = [0.0f64; 3];
    let mut direction = photon.direction;
    let mut layer = 0usize;
    let mut weight = photon.weight;
    let mut scattered = false;
    let mut interactions = 0u64;
    loop {
        let slab = &slabs[layer];
        let step = if slab.sigma_t > 0.0 {
            -rng.uniform_open().ln() / slab.sigma_t
        } else {
            f64::INFINITY
        };
        let to_boundary = if direction[2] > 0.0 {
            (slab.bottom - position[2]) / direction[2]
        } else if direction[2] < 0.0 {
            (slab.top - position[2]) / direction[2]
        } else {
            f64::INFINITY
        };
        if step >= to_boundary {
            if !to_boundary.is_finite() {
                return; // lost into a non-interacting semi-infinite layer
            }
            let downward = direction[2] > 0.0;
            position[0] += to_boundary * direction[0];
            position[1] += to_boundary * direction[1];
            position[2] = if downward { slab.bottom } else { slab.top };
            let neighbour = if downward {
                Some(layer + 1).filter(|&i| i < slabs.len())
            } else {
                layer.checked_sub(1)
            };
            let rough = match (neighbour, downward) {
                (Some(_), _) => None,
                (None, true) => faces.bottom.as_ref(),
                (None, false) => faces.top.as_ref(),
            };
            if let Some(face) = rough {
                match face.cross(direction, false, rng) {
                    Crossing::Back(d, w) => {
                        direction = d;
                        weight *= w;
                        if weight <= 0.0 {
                            return;
                        }
                    }
                    Crossing::Through(d, w) => {
                        let exit = Exit {
                            downward,
                            position,
                            cos_out: d[2].abs(),
                        };
                        record(tally, edges, exit, weight * w, scattered);
                        return;
                    }
                }
                continue;
            }
            let n_t = neighbour.map_or(1.0, |i| slabs[i].ior);
            let cos_i = direction[2].abs();
            if rng.uniform() < dielectric_reflectance(cos_i, slab.ior, n_t) {
                direction[2] = -direction[2];
                continue;
            }
            let ratio = slab.ior / n_t;
            let cos_t = (1.0 - ratio * ratio * (1.0 - cos_i * cos_i))
                .max(0.0)
                .sqrt();
            let Some(next) = neighbour else {
                let exit = Exit {
                    downward,
                    position,
                    cos_out: cos_t,
                };
                record(tally, edges, exit, weight, scattered);
                return;
            };
            direction = [
                direction[0] * ratio,
                direction[1] * ratio,
                cos_t.copysign(direction[2]),
            ];
            layer = next;
            continue;
        }
        for (p, d) in position.iter_mut().zip(direction) {
            *p += step * d;
        }
        tally.interactions += 1;
        interactions += 1;
        if interactions > max_interactions {
            tally.truncated += weight;
            return;
        }
        scattered = true;
        weight *= slab.albedo;
        direction = scatter(direction, slab.g, rng);
        if weight < ROULETTE_THRESHOLD {
            if rng.uniform() < ROULETTE_SURVIVAL {
                weight /= ROULETTE_SURVIVAL;
            } else {
                return;
            }
        }
    }
}

/// Where and how a photon leaves the layers.
struct Exit {
    /// Through the bottom.
    downward: bool,
    position: [f64; 3],
    /// Cosine to the normal of its direction outside.
    cos_out: f64,
}

fn record(tally: &mut Tally, edges: &[f64], exit: Exit, weight: f64, scattered: bool) {
    let Exit {
        downward,
        position,
        cos_out,
    } = exit;
    let radius = position[0].hypot(position[1]);
    if !scattered {
        tally.unscattered[usize::from(downward)] += weight;
        return;
    }
    let (total, bins) = if downward {
        (&mut tally.transmit_total, &mut tally.transmit)
    } else {
        (&mut tally.reflect_total, &mut tally.reflect)
    };
    total[0] += weight;
    total[1] += weight * weight;
    if !downward {
        let moment = weight * position[0];
        tally.reflect_moment[0] += moment;
        tally.reflect_moment[1] += moment * moment;
        if cos_out >= NORMAL_VIEW_COS {
            tally.reflect_at_normal[0] += weight;
            tally.reflect_at_normal[1] += weight * weight;
        }
    }
    let bin = edges.partition_point(|&e| e <= radius);
    if bin >= 1 && bin < edges.len() {
        bins[bin - 1][0] += weight;
        bins[bin - 1][1] += weight * weight;
    }
}

/// A new direction at Henyey–Greenstein angle to `d`.
pub(crate) fn scatter(d: [f64; 3], g: f64, rng: &mut Rng) -> [f64; 3] {
    let u = rng.uniform();
    let cos_theta = if g.abs() < 1e-3 {
        2.0 * u - 1.0
    } else {
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
        ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
    };
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let (sin_phi, cos_phi) = (2.0 * PI * rng.uniform()).sin_cos();
    // An orthonormal basis around d without branches on near-axis cases.
    let sign = 1.0f64.copysign(d[2]);
    let a = -1.0 / (sign + d[2]);
    let b = d[0] * d[1] * a;
    let t = [1.0 + sign * d[0] * d[0] * a, sign * b, -sign * d[0]];
    let s = [b, sign + d[1] * d[1] * a, -d[1]];
    let (x, y) = (sin_theta * cos_phi, sin_theta * sin_phi);
    let out: [f64; 3] = std::array::from_fn(|i| x * t[i] + y * s[i] + cos_theta * d[i]);
    let norm = (out[0] * out[0] + out[1] * out[1] + out[2] * out[2]).sqrt();
    out.map(|v| v / norm)
}

/// Bin edges (mm) around increasing sample radii: geometric midpoints
/// between positive neighbours (arithmetic next to 0), the first bin
/// reaching down to 0 and the last as far past its radius as it reaches before.
pub fn edges_around(radii: &[f64]) -> Vec<f64> {
    let mut edges = vec![0.0];
    for w in radii.windows(2) {
        edges.push(if w[0] > 0.0 {
            (w[0] * w[1]).sqrt()
        } else {
            0.5 * (w[0] + w[1])
        });
    }
    if let Some(&last) = radii.last() {
        let previous = edges[edges.len() - 1];
        edges.push(last + (last - previous).max(1e-9));
    }
    edges
}
