//! `walk`: the exitance by a volumetric random walk inside the object's own
//! mesh ([`crate::walk`]), not by the material's profile. It is the truth
//! for the model (exits anywhere on the surface, through thin parts, never
//! across air), at the price of noise; `auto` never chooses it.
//!
//! | setting | default | meaning |
//! |---|---|---|
//! | `samples` | 256 | walks per texel and channel |
//! | `seed` | 1 | seed of the walks (stream = texel) |
//! | `max_events` | 1024 | bound on scatterings and boundary meetings per walk (Cycles stops at 256) |
//!
//! It follows light, not the profile: the corrected model is not applied
//! to it, and its distance from the exact sum measures the model. It needs
//! one homogeneous medium (a layered material is refused before any
//! work). Its cost is its expected walk events per texel.

mod surfels;

pub use surfels::walk_surfels;

use super::Method;
use super::integrator::{Carries, Integrated, Integrator, Work};
use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::scattering::Scattering;
use crate::walk::path::ROULETTE_WEIGHT;
use crate::walk::{StartDirection, WalkMedium, WalkSettings};
use serde::{Deserialize, Serialize};
use sssbake_profile::Material;

/// The most walks per texel a request may ask for.
pub const MOST_SAMPLES: u32 = 1 << 20;
/// The most events per walk a request may ask for.
pub const MOST_EVENTS: u32 = 1 << 24;

/// Walks per texel, their seed and their bound.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WalkIntegrator {
    /// Walks per texel and channel (at least 2, for a standard error).
    pub samples: u32,
    /// Seed of the walks (stream = texel, so any thread count agrees).
    pub seed: u64,
    /// Scatterings and boundary meetings per walk before it is dropped
    /// (the weight dropped is reported).
    pub max_events: u32,
}

impl Default for WalkIntegrator {
    fn default() -> Self {
        WalkIntegrator {
            samples: 256,
            seed: 1,
            max_events: 1024,
        }
    }
}

/// What the walk's noise and bound left in an object's exitance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WalkNoise {
    /// Walks per texel and channel.
    pub samples: u32,
    /// Per channel: the RMS over texels of the standard error over the
    /// mean exitance (of the walk's exitance before the colour after
    /// scattering).
    pub relative_standard_error: [f64; 3],
    /// Per channel: the share of a walk's unit start dropped at the event
    /// bound, averaged over walks (a bias towards dark, not noise).
    pub truncated: [f64; 3],
    /// Per channel: the share lost by flights that met no surface (a mesh
    /// not closed), as `truncated`.
    pub lost: [f64; 3],
    /// Events per walk, on average.
    pub events_per_walk: f64,
}

impl WalkIntegrator {
    /// Refuses settings it cannot run with.
    pub fn validate(&self) -> Result<(), Error> {
        if !(2..=MOST_SAMPLES).contains(&self.samples) {
            return Err(Error::field(
                "walk.samples",
                format!("must be 2 to {MOST_SAMPLES} (a standard error needs two walks)"),
            ));
        }
        if !(1..=MOST_EVENTS).contains(&self.max_events) {
            return Err(Error::field(
                "walk.max_events",
                format!("must be 1 to {MOST_EVENTS}"),
            ));
        }
        Ok(())
    }

    /// The events one texel's walks are expected to take in `medium`, all
    /// three channels: a coarse estimate for the plan's cost. With weights
    /// times the albedo α and roulette below [`ROULETTE_WEIGHT`], a walk
    /// that never left would live about ln(1/w_r)/(1 − α) + 1/(1 − α)
    /// events; leaving through the surface is a first passage, whose mean
    /// grows as the square root of that life. Never more than the bound.
    pub fn expected_events(&self, medium: &WalkMedium) -> f64 {
        let per_walk: f64 = medium
            .channels
            .iter()
            .map(|c| {
                let absorbed = (1.0 - c.albedo).max(1e-12);
                let life = (1.0 + (1.0 / ROULETTE_WEIGHT).ln()) / absorbed;
                (1.0 + 2.0 * life.sqrt()).min(f64::from(self.max_events))
            })
            .sum();
        per_walk * f64::from(self.samples)
    }
}

impl Integrator for WalkIntegrator {
    fn method(&self) -> Method {
        Method::Walk
    }

    fn carries(&self) -> Carries {
        Carries {
            profile: false,
            across: true,
            oblique: false,
        }
    }

    fn evaluations(&self, work: &Work) -> f64 {
        WalkMedium::of_material(work.material)
            .map_or(0.0, |medium| work.texels * self.expected_events(&medium))
    }

    fn accepts(&self, material: &Material) -> Result<(), String> {
        WalkMedium::of_material(material).map(|_| ())
    }

    fn integrate(
        &self,
        prepared: &Prepared,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Integrated, Error> {
        let medium = WalkMedium::of_material(&scattering.material).map_err(Error::input)?;
        let settings = WalkSettings {
            walks: self.samples,
            max_events: self.max_events,
            seed: self.seed,
            start: StartDirection::Pencil,
        };
        let estimate = walk_surfels(prepared, &medium, None, &settings, control)?;
        let noise = WalkNoise {
            samples: self.samples,
            relative_standard_error: estimate.relative_standard_error(),
            truncated: estimate.truncated,
            lost: estimate.lost,
            events_per_walk: estimate.events as f64 / estimate.walks.max(1) as f64,
        };
        Ok(Integrated {
            exitance: estimate
                .exitance
                .iter()
                .map(|m| m.map(|v| super::stored_exitance(v as f64)))
                .collect(),
            sources: 0,
            walk: Some(noise),
        })
    }
}
