//! Integrators: the radiant exitance M(x) = ∫ P(|x − x_i|) E_t(x_i) dA at
//! every texel, by four methods with the same inputs and output.

pub mod accuracy;
pub mod brute;
pub mod choice;
pub mod clusters;
pub mod disk_kernel;
pub mod importance;
pub mod kernel;
pub mod octree;
pub mod sources;
pub mod texture_space;

use std::fmt;
use std::str::FromStr;

/// How the exitance is integrated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Let the plan choose (and say why).
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

    /// The name the command line uses.
    pub fn name(self) -> &'static str {
        match self {
            Method::Auto => "auto",
            Method::Brute => "brute",
            Method::Octree => "octree",
            Method::Texture => "texture",
            Method::Importance => "importance",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        [Method::Auto]
            .into_iter()
            .chain(Method::ALL)
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                format!("unknown method `{s}` (auto, brute, octree, texture or importance)")
            })
    }
}

/// The knobs of every method; each uses its own.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodSettings {
    /// Share of the reflectance left outside d_max.
    pub d_max_epsilon: f64,
    /// Octree: the solid angle (sr) below which a node is taken whole.
    pub octree_epsilon: f32,
    /// Octree: Turk points per disk of one mean free path.
    pub point_multiplier: f64,
    /// Texture: Gaussians in the fit.
    pub gaussians: usize,
    /// Importance: probes per texel.
    pub samples: u32,
    /// Importance and Turk placement: the random seed.
    pub seed: u64,
}

impl Default for MethodSettings {
    fn default() -> Self {
        MethodSettings {
            d_max_epsilon: 1e-3,
            octree_epsilon: 0.05,
            point_multiplier: 4.0,
            gaussians: 6,
            samples: 64,
            seed: 1,
        }
    }
}
