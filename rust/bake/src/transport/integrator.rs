//! The one interface every integrator implements, and the settings of all
//! of them. Each integrator is a struct holding its own settings, with
//! their defaults and their checks (`validate`), so every front door gets
//! the same meaning for the same knob.
//!
//! | method | settings (default) |
//! |---|---|
//! | `brute` | none |
//! | `octree` | `epsilon` (0.5 sr) |
//! | `texture` | `gaussians` (6) |
//! | `importance` | `samples` (64), `seed` (1) |
//! | `walk` | `samples` (256), `seed` (1), `max_events` (1024) |

use super::Method;
use super::brute::BruteIntegrator;
use super::importance::ImportanceIntegrator;
use super::octree::OctreeIntegrator;
use super::texture_space::TextureIntegrator;
use super::walk::{WalkIntegrator, WalkNoise};
use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::scattering::Scattering;
use serde::{Deserialize, Serialize};

/// An integrator's result before the colour after scattering.
#[derive(Clone, Debug)]
pub struct Integrated {
    /// Radiant exitance per surfel, W/m².
    pub exitance: Vec<[f32; 3]>,
    /// Sources the 3-D methods gathered from (texels or Turk points).
    pub sources: usize,
    /// The walk's noise and dropped weight (the walk alone).
    pub walk: Option<WalkNoise>,
}

/// M(x) = ∫ P(|x − x_i|) E_t(x_i) dA at every texel of a prepared object.
/// Its `Debug` form names it with its settings (what a result found by it
/// is kept under).
pub trait Integrator: Send + Sync + std::fmt::Debug {
    /// Which method this is.
    fn method(&self) -> Method;

    /// The exitance of `prepared` under `scattering`'s profile (the
    /// irradiance entering after the colour split's first part).
    fn integrate(
        &self,
        prepared: &Prepared,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Integrated, Error>;
}

/// The settings of every integrator; a bake uses the one it runs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct IntegratorSettings {
    /// The Jensen–Buhler hierarchy.
    pub octree: OctreeIntegrator,
    /// Texture-space Gaussian blurs.
    pub texture: TextureIntegrator,
    /// Monte Carlo with probe rays.
    pub importance: ImportanceIntegrator,
    /// The volumetric random walk.
    pub walk: WalkIntegrator,
}

impl IntegratorSettings {
    /// The integrator of `method` (`auto` must be chosen first).
    pub fn get(&self, method: Method) -> &dyn Integrator {
        match method {
            Method::Auto | Method::Brute => &BruteIntegrator,
            Method::Octree => &self.octree,
            Method::Texture => &self.texture,
            Method::Importance => &self.importance,
            Method::Walk => &self.walk,
        }
    }

    /// Sets the seed of every integrator that draws random numbers.
    pub fn seed(&mut self, seed: u64) {
        self.importance.seed = seed;
        self.walk.seed = seed;
    }

    /// Refuses settings no integrator can run with, naming the field.
    pub fn validate(&self) -> Result<(), Error> {
        self.octree.validate()?;
        self.texture.validate()?;
        self.importance.validate()?;
        self.walk.validate()
    }
}
