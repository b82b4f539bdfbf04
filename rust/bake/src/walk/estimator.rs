//! The exitance at texels by walks started there: the adjoint estimator
//! Cycles' Random Walk uses.
//!
//! A walk starts at the texel's surface point heading into the medium and
//! ends where it leaves the mesh, x_exit. Its contribution is its weight
//! times the irradiance transmitted into the medium at x_exit (E_t, the
//! bake's own per-texel light, shadows included, read from the texel under
//! x_exit). The mean over walks estimates
//!
//!   M(x_o) = ∫ R(x_o ← x_i) E_t(x_i) dA(x_i),
//!
//! where R is the flux leaving into air at x_o per unit flux entering at
//! x_i, through the object itself: the `subsurface` map's quantity, in the
//! irradiance's units. "Leaving into air" is after the exit Fresnel test,
//! as the slab Monte Carlo's total R counts it and as the diffusion
//! profile's R_d (with its boundary term A) approximates it; the `diffuse`
//! step's exit factor applies to the walk's map as to the profile's.
//!
//! Two starts:
//! - [`StartDirection::Pencil`] (the default): straight along −n with
//!   weight 1, a unit flux entering at normal incidence, as MCML's pencil
//!   beam: under uniform E_t on a flat face it estimates E_t times the
//!   slab's total R (scattered or not) at normal incidence. It is Cycles'
//!   DIFFUSE bake of a Random Walk material: Cycles enters along the
//!   refracted view (`subsurface_entry_bounce`; a bake views along the
//!   normal) and lights the point its walk leaves through with a diffuse
//!   closure, that is by the irradiance there (within 0.4% of Cycles on a
//!   backlit slab, `tests/test_cycles_light.py`).
//! - [`StartDirection::Diffuse`]: light entering at x_i taken as diffuse,
//!   refracted through the boundary. By reciprocity the walk starts with
//!   that same distribution at x_o: a cosine-distributed direction about
//!   −n weighted by (1 − F(θ))/(1 − F_dr), which is 1 when index-matched
//!   (Cycles' Random Walk (Skin) starts so half the time). A start that
//!   points out of its own facet (a shading normal tilted against it) is
//!   mirrored into the medium.
//!
//! Each channel walks on its own (`walks` walks per channel per texel),
//! from the texel's own random stream, so any thread count gives the same
//! numbers. A texel costs at most 3 × walks × max_events events.

use super::enclosure::Enclosure;
use super::medium::WalkMedium;
use super::path::{Ending, WalkStart, walk};
use super::phase::cosine_hemisphere;
use crate::control::{Cancelled, Control, parallel_fill};
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};
use sssbake_profile::numerics::rng::Rng;

/// The direction walks start in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StartDirection {
    /// Cosine-distributed about −n, weighted by the boundary's
    /// transmittance: the exitance as a Lambertian view of it would have it.
    Diffuse,
    /// Straight along −n: by reciprocity, the light leaving along the
    /// normal for a pencil beam entering there, the convention of the
    /// profiles (R(r) for normal incidence) and of Cycles' DIFFUSE bake of
    /// a Random Walk material (its walk enters along the refracted view,
    /// and a bake views along the normal).
    #[default]
    Pencil,
}

/// How many walks, how long, from which seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkSettings {
    /// Walks per channel per texel (at least 1; the standard error needs 2).
    pub walks: u32,
    /// The bound on events (scatterings and boundary meetings) per walk.
    pub max_events: u32,
    /// Seed; texel i draws from stream i.
    pub seed: u64,
    /// The start direction.
    pub start: StartDirection,
}

/// The light walks leave into: the transmitted irradiance per texel of an
/// N × N layout.
pub struct ExitLight<'a> {
    /// E_t per texel, W/m² (any unit: the exitance comes out in it),
    /// row-major with y growing with v, dilated past chart borders.
    pub irradiance: &'a [[f32; 3]],
    /// N.
    pub resolution: u32,
}

impl ExitLight<'_> {
    /// The light of the texel under `uv` (nearest: a texel's light is its
    /// own surface's, and blending across a chart border would hand one
    /// piece of the mesh another's light).
    pub fn at(&self, uv: Vec2) -> [f32; 3] {
        let n = self.resolution.max(1);
        let cell = |x: f32| ((x * n as f32).floor() as i64).clamp(0, n as i64 - 1) as usize;
        let (x, y) = (cell(uv.x), cell(uv.y));
        self.irradiance
            .get(y * n as usize + x)
            .copied()
            .unwrap_or([0.0; 3])
    }
}

/// Where walks start: surface points with their normals and triangles.
pub struct WalkTargets<'a> {
    /// Points on the mesh, mm.
    pub position: &'a [Vec3],
    /// Unit outward shading normals there.
    pub normal: &'a [Vec3],
    /// The triangle each point lies on.
    pub triangle: &'a [u32],
}

/// The walks' estimate at each target.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WalkEstimate {
    /// Mean exitance per target and channel, in the irradiance's units.
    pub exitance: Vec<[f32; 3]>,
    /// Its standard error (the walks' standard deviation over √walks).
    pub standard_error: Vec<[f32; 3]>,
    /// Weight dropped at the event bound, per channel: the mean over every
    /// walk of the share of its unit start it still carried (0 to 1).
    pub truncated: [f64; 3],
    /// Weight lost by flights that met no surface (a mesh not closed), per
    /// channel, as `truncated`.
    pub lost: [f64; 3],
    /// Walks taken, all targets and channels.
    pub walks: u64,
    /// Events simulated, all walks.
    pub events: u64,
}

impl WalkEstimate {
    /// The noise relative to the signal, per channel: the root mean square
    /// of the per-target standard errors over the mean exitance (0 for a
    /// dark channel).
    pub fn relative_standard_error(&self) -> [f64; 3] {
        let count = self.exitance.len().max(1) as f64;
        [0, 1, 2].map(|c| {
            let mean = self.exitance.iter().map(|m| m[c] as f64).sum::<f64>() / count;
            let noise = (self
                .standard_error
                .iter()
                .map(|e| (e[c] as f64).powi(2))
                .sum::<f64>()
                / count)
                .sqrt();
            if mean > 0.0 { noise / mean } else { 0.0 }
        })
    }
}

/// What one target's walks gathered.
#[derive(Clone, Copy, Default)]
struct TargetTally {
    sum: [f64; 3],
    sum_squares: [f64; 3],
    truncated: [f64; 3],
    lost: [f64; 3],
    events: u64,
}

/// The exitance at every target of `targets` by `settings.walks` walks
/// per channel through `medium` inside `enclosure`, each scoring the
/// `light` where it leaves.
pub fn walk_exitance(
    enclosure: &Enclosure,
    light: &ExitLight,
    medium: &WalkMedium,
    targets: &WalkTargets,
    settings: &WalkSettings,
    control: &Control,
) -> Result<WalkEstimate, Cancelled> {
    let count = targets.position.len();
    let walks = settings.walks.max(1);
    // The diffuse start's weight (1 − F(θ))/(1 − F_dr); F_dr < 1 for any
    // finite index, the floor only guards a division.
    let transmitted_share = (1.0 - medium.boundary.diffuse_reflectance()).max(1e-12);
    let mut tallies = vec![TargetTally::default(); count];
    parallel_fill(&mut tallies, 16, control, |i| {
        let mut rng = Rng::new(settings.seed, i as u64);
        let mut tally = TargetTally::default();
        let normal = targets.normal[i].normalize_or(Vec3::Z);
        let triangle = targets.triangle[i];
        // The facet faced like the shading normal, to keep starts inside.
        let facet = enclosure.facet_normal(triangle);
        let facet = if facet.dot(normal) < 0.0 {
            -facet
        } else {
            facet
        };
        for (c, channel) in medium.channels.iter().enumerate() {
            for _ in 0..walks {
                let (direction, start_weight) = match settings.start {
                    StartDirection::Pencil => (-normal, 1.0),
                    StartDirection::Diffuse => {
                        let (mut d, cos) = cosine_hemisphere(-normal, &mut rng);
                        if d.dot(facet) > 0.0 {
                            d -= 2.0 * d.dot(facet) * facet;
                        }
                        let share = 1.0 - medium.boundary.reflectance(cos);
                        (d, share / transmitted_share)
                    }
                };
                let start = WalkStart {
                    position: targets.position[i],
                    direction,
                    triangle,
                };
                let walked = walk(
                    enclosure,
                    channel,
                    medium.boundary,
                    start,
                    settings.max_events,
                    &mut rng,
                );
                tally.events += walked.events as u64;
                let score = match walked.ending {
                    Ending::Left {
                        triangle,
                        barycentric,
                        weight,
                    } => {
                        let e = light.at(enclosure.uv_at(triangle, barycentric))[c] as f64;
                        start_weight * weight * e
                    }
                    Ending::Absorbed => 0.0,
                    Ending::Truncated { weight } => {
                        tally.truncated[c] += start_weight * weight;
                        0.0
                    }
                    Ending::Lost { weight } => {
                        tally.lost[c] += start_weight * weight;
                        0.0
                    }
                };
                let score = if score.is_finite() {
                    score.max(0.0)
                } else {
                    0.0
                };
                tally.sum[c] += score;
                tally.sum_squares[c] += score * score;
            }
        }
        tally
    })?;
    let n = walks as f64;
    let mut estimate = WalkEstimate {
        exitance: Vec::with_capacity(count),
        standard_error: Vec::with_capacity(count),
        walks: count as u64 * 3 * walks as u64,
        ..WalkEstimate::default()
    };
    for tally in &tallies {
        let mean = tally.sum.map(|s| s / n);
        let error = [0, 1, 2].map(|c| {
            if walks < 2 {
                return 0.0;
            }
            let variance = (tally.sum_squares[c] - n * mean[c] * mean[c]).max(0.0) / (n - 1.0);
            (variance / n).sqrt()
        });
        estimate.exitance.push(mean.map(|m| m as f32));
        estimate.standard_error.push(error.map(|e| e as f32));
        for c in 0..3 {
            estimate.truncated[c] += tally.truncated[c];
            estimate.lost[c] += tally.lost[c];
        }
        estimate.events += tally.events;
    }
    let per_channel = (count as f64 * n).max(1.0);
    estimate.truncated = estimate.truncated.map(|t| t / per_channel);
    estimate.lost = estimate.lost.map(|t| t / per_channel);
    Ok(estimate)
}
