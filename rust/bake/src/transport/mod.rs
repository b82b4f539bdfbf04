//! Integrators: the radiant exitance M(x) = ∫ P(|x − x_i|) E_t(x_i) dA at
//! every texel, by several methods with the same inputs and output. Each
//! method is a folder (`brute`, `octree`, `texture_space`, `importance`,
//! `walk`) behind the one interface of [`integrator`]; the other modules
//! are what they share.

pub mod accuracy;
pub mod ball_gain;
pub mod ball_totals;
pub mod brute;
pub mod choice;
pub mod clusters;
pub mod disk_kernel;
#[cfg(test)]
mod exact_sum_tests;
pub mod importance;
pub mod integrator;
pub mod kernel;
pub mod light_check;
pub mod local_slab;
pub mod oblique_sum;
pub mod octree;
pub mod rim_light;
mod sample_sizes;
mod shares;
pub mod slab_ladder;
pub mod slab_profiles;
pub mod slab_totals;
mod source_table;
pub mod sources;
pub mod texture_space;
pub mod thin;
pub mod through_medium;
pub mod verify;
pub mod walk;
pub mod walk_budget;

/// An exitance (W/m²) as a map stores it: finite and non-negative (a sum
/// that is neither, from a truncated series or noise, stores 0 or its
/// positive part).
pub(crate) fn stored_exitance(value: f64) -> f32 {
    if value.is_finite() {
        value.max(0.0) as f32
    } else {
        0.0
    }
}

use integrator::Carries;
use serde::{Deserialize, Serialize};

/// How the exitance is integrated.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    Serialize,
    Deserialize,
    strum::Display,
    strum::EnumString,
    strum::IntoStaticStr,
    strum::VariantArray,
    strum::VariantNames,
    strum::EnumMessage,
)]
#[serde(rename_all = "lowercase")]
#[strum(serialize_all = "lowercase")]
pub enum Method {
    /// Let the plan choose (and say why).
    #[default]
    Auto,
    /// The exact discrete sum within d_max: the reference.
    Brute,
    /// The Jensen–Buhler hierarchy over Turk points.
    Octree,
    /// d'Eon–Luebke texture-space Gaussian blurs.
    Texture,
    /// Mertens-style Monte Carlo with probe rays.
    Importance,
    /// A volumetric random walk inside the object's mesh: the light
    /// transport the profile models, not the profile (never chosen by
    /// `auto`).
    Walk,
}

impl Method {
    /// Every concrete method that integrates the material's profile (the
    /// walk, which does not, is [`Method::Walk`] alone: comparing it with
    /// the exact sum measures the model, not an integrator).
    pub const ALL: [Method; 4] = [
        Method::Brute,
        Method::Octree,
        Method::Texture,
        Method::Importance,
    ];

    /// Every method, `auto` first, in the order they are declared (the C
    /// ABI numbers them so).
    pub const EVERY: &'static [Method] = <Method as strum::VariantArray>::VARIANTS;

    /// The name the command line, file names and summaries use.
    pub fn name(self) -> &'static str {
        self.into()
    }
}

/// Which kernel an object's exitance was integrated with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExitanceKernel {
    /// The model's radially symmetric profile (it has no other).
    #[default]
    Radial,
    /// The model's oblique kernel, each light at its own incidence and
    /// azimuth (the empirical model under scene lights, by a method that
    /// takes it).
    Oblique,
    /// The model has an oblique kernel, but the method (or an irradiance
    /// image without directions) used its radially symmetric profile at
    /// normal incidence: the azimuthal mean at θ_i = 0.
    AzimuthalMean,
    /// No kernel: a volumetric random walk in the object's mesh.
    Volumetric,
}

impl ExitanceKernel {
    /// The kernel an integrator that `carries` so much integrates with,
    /// for a model with an oblique kernel or not (`oblique`) under light
    /// with directions or not (`directions`).
    pub fn of(carries: Carries, oblique: bool, directions: bool) -> Self {
        if !carries.profile {
            return ExitanceKernel::Volumetric;
        }
        match (oblique, directions && carries.oblique) {
            (false, _) => ExitanceKernel::Radial,
            (true, true) => ExitanceKernel::Oblique,
            (true, false) => ExitanceKernel::AzimuthalMean,
        }
    }

    /// In words, for the summary.
    pub fn describe(self) -> &'static str {
        match self {
            ExitanceKernel::Radial => "the radial profile",
            ExitanceKernel::Oblique => "the oblique kernel, each light at its own incidence",
            ExitanceKernel::AzimuthalMean => {
                "the azimuthal mean at normal incidence (this method cannot take the oblique kernel)"
            }
            ExitanceKernel::Volumetric => {
                "a volumetric random walk inside the mesh (the material's medium, not its profile)"
            }
        }
    }
}
