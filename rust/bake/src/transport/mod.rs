//! Integrators: the radiant exitance M(x) = ∫ P(|x − x_i|) E_t(x_i) dA at
//! every texel, by four methods with the same inputs and output.

pub mod accuracy;
pub mod brute;
pub mod choice;
pub mod clusters;
pub mod disk_kernel;
#[cfg(test)]
mod exact_sum_tests;
pub mod importance;
pub mod integrator;
pub mod kernel;
pub mod oblique_sum;
pub mod octree;
mod source_table;
pub mod sources;
pub mod texture_space;
pub mod thin;
pub mod verify;

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
}

impl Method {
    /// Every concrete method.
    pub const ALL: [Method; 4] = [
        Method::Brute,
        Method::Octree,
        Method::Texture,
        Method::Importance,
    ];

    /// The name the command line, file names and summaries use.
    pub fn name(self) -> &'static str {
        self.into()
    }
}
