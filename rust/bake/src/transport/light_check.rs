//! How far a bake's exitance is from light itself: the volumetric random
//! walk through the object's own mesh ([`crate::walk`]) at a few hundred
//! random texels, beside the estimate against the exact sum.
//!
//! The exact sum shares the profile's assumptions (a semi-infinite planar
//! medium, distances in 3-D, diffusion's level); the walk shares none of
//! them, so this is the only figure that sees a model's error. The walk is
//! noisy: with per-texel standard errors σ_i and relative RMSE ρ measured
//! against it, the bake's own distance from light is estimated as
//! √max(0, ρ² − ν²), ν = RMS(σ)/RMS(M_walk) being what the walk's noise
//! alone would give. Both ρ and ν are reported.

use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::scattering::Scattering;
use crate::transport::accuracy::relative_errors;
use crate::transport::verify::pick;
use crate::transport::walk::WalkIntegrator;
use crate::transport::walk::walk_surfels;
use crate::walk::{StartDirection, WalkMedium, WalkSettings};
use serde::{Deserialize, Serialize};

/// Texels walked by default (0 turns the check off).
pub const DEFAULT_TEXELS: u32 = 256;
/// Most walks per texel and channel: enough that the walk's own noise
/// (about 10% a texel at skin's reach) leaves a bake's error of a few
/// percent measurable over a few hundred texels.
pub const MOST_WALKS: u32 = 1024;
/// Fewest walks per texel and channel, however long the walks are.
pub const FEWEST_WALKS: u32 = 64;
/// Walk events the check may spend on an object of many texels (about
/// 1.5 s on two cores): where the medium's walks are long (a high albedo),
/// fewer walks per texel, and more noise, which the check states.
pub const EVENT_BUDGET: f64 = 1.5e7;
/// Walk events per texel of the object the check may spend, so that it
/// stays a small share of a small bake (within [`SMALLEST_BUDGET`] and
/// [`EVENT_BUDGET`]).
pub const EVENTS_PER_TEXEL: f64 = 16.0;
/// The fewest walk events the check may spend.
pub const SMALLEST_BUDGET: f64 = 1e6;
/// The bound on events per walk, as the walk integrator's default.
pub const MAX_EVENTS: u32 = 1024;
/// Most texels a request may ask for.
pub const MOST_TEXELS: u32 = 65_536;

/// A bake's distance from light, measured by the walk.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LightCheck {
    /// Texels walked.
    pub texels: usize,
    /// Walks per texel and channel.
    pub walks: u32,
    /// RMS(M − M_walk)/RMS(M_walk) over the texels and channels.
    pub relative_rmse: f64,
    /// What the walk's noise alone gives: RMS(σ_walk)/RMS(M_walk).
    pub walk_noise: f64,
    /// The bake's distance from light with the walk's noise taken out,
    /// √max(0, relative_rmse² − walk_noise²).
    pub estimated_error: f64,
    /// Events per walk, on average.
    pub events_per_walk: f64,
    /// Seconds the check took.
    pub seconds: f64,
}

/// The walk events a bake's check may spend on an object of
/// `object_texels` texels.
pub fn event_budget(object_texels: usize) -> f64 {
    (object_texels as f64 * EVENTS_PER_TEXEL).clamp(SMALLEST_BUDGET, EVENT_BUDGET)
}

/// Walks per texel and channel for `texels` texels in `medium`: as many
/// as `budget` events afford, within [`FEWEST_WALKS`] and [`MOST_WALKS`].
pub fn walks_per_texel(medium: &WalkMedium, texels: usize, budget: f64) -> u32 {
    let per_walk = one_walk().expected_events(medium).max(1.0);
    let affordable = budget / (per_walk * texels.max(1) as f64);
    (affordable as u32).clamp(FEWEST_WALKS, MOST_WALKS)
}

/// The events of a check of `texels` texels in `medium` within `budget`,
/// all channels.
pub fn planned_events(medium: &WalkMedium, texels: usize, budget: f64) -> f64 {
    let walks = f64::from(walks_per_texel(medium, texels, budget));
    texels as f64 * walks * one_walk().expected_events(medium)
}

/// One walk per texel with the check's bound on events.
fn one_walk() -> WalkIntegrator {
    WalkIntegrator {
        samples: 1,
        max_events: MAX_EVENTS,
        ..WalkIntegrator::default()
    }
}

/// Why a bake has no check against light.
#[derive(Clone, Debug, PartialEq)]
pub enum NoCheck {
    /// The request turned it off.
    Off,
    /// The walk cannot follow the material (the reason).
    Material(String),
}

/// Walks `texels` seeded random texels of `prepared` under `scattering`'s
/// medium, within about `budget` walk events ([`event_budget`] in a
/// bake), and compares the bake's `exitance` (after the colour split, as
/// `Prepared::integrate` returns it) with them.
pub fn check_against_light(
    prepared: &Prepared,
    scattering: &Scattering,
    exitance: &[[f32; 3]],
    texels: u32,
    budget: f64,
    seed: u64,
    control: &Control,
) -> Result<Result<LightCheck, NoCheck>, Error> {
    if texels == 0 || prepared.surfels.is_empty() {
        return Ok(Err(NoCheck::Off));
    }
    let medium = match WalkMedium::of_material(&scattering.material) {
        Ok(medium) => medium,
        Err(reason) => return Ok(Err(NoCheck::Material(reason))),
    };
    let start = std::time::Instant::now();
    let picked = pick(prepared.surfels.len(), texels as usize, seed);
    let walks = walks_per_texel(&medium, picked.len(), budget);
    let settings = WalkSettings {
        walks,
        max_events: MAX_EVENTS,
        seed,
        start: StartDirection::Pencil,
    };
    let estimate = walk_surfels(prepared, &medium, Some(&picked), &settings, control)?;
    let walked: Vec<[f32; 3]> = picked
        .iter()
        .zip(&estimate.exitance)
        .map(|(&i, &m)| prepared.after_scattering(i, m))
        .collect();
    let noise: Vec<[f32; 3]> = picked
        .iter()
        .zip(&estimate.standard_error)
        .map(|(&i, &s)| prepared.after_scattering(i, s))
        .collect();
    let baked: Vec<[f32; 3]> = picked.iter().map(|&i| exitance[i]).collect();
    let (relative_rmse, _) = relative_errors(&baked, &walked);
    let walk_noise = rms(&noise) / rms(&walked).max(1e-30);
    Ok(Ok(LightCheck {
        texels: picked.len(),
        walks,
        relative_rmse,
        walk_noise,
        estimated_error: (relative_rmse.powi(2) - walk_noise.powi(2)).max(0.0).sqrt(),
        events_per_walk: estimate.events as f64 / estimate.walks.max(1) as f64,
        seconds: start.elapsed().as_secs_f64(),
    }))
}

/// RMS of `values` over every texel and channel.
fn rms(values: &[[f32; 3]]) -> f64 {
    let squares: f64 = values.iter().flatten().map(|&v| f64::from(v).powi(2)).sum();
    (squares / (3 * values.len()).max(1) as f64).sqrt()
}
