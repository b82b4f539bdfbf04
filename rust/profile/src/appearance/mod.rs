//! What asset shaders say about subsurface scattering — a colour, a
//! scattering distance per channel, an index of refraction and an
//! anisotropy — turned into a material.
//!
//! OpenPBR's `subsurface_color` / `subsurface_radius`, Blender's Principled
//! BSDF (base colour, Subsurface Radius × Scale) and glTF's volume
//! extensions all describe the same two things: the colour the surface
//! shows under uniform light (its total diffuse reflectance) and the mean
//! free path 1/σt of each channel. The albedo inversion finds the σa and σs
//! whose dipole gives exactly that colour.

pub mod cycles;
pub mod inversion;

use crate::Rgb;
use crate::appearance::inversion::{InversionError, InversionModel, invert_albedo};
use crate::material::{Material, Optics};

/// Shortest mean free path kept, mm: a zero radius (a channel that does
/// not scatter, in Blender's words) becomes one micron, far below a texel.
pub const MIN_MEAN_FREE_PATH_MM: f64 = 1e-3;

/// Largest |g| kept: at |g| → 1 σs = σs'/(1 − g) has no finite value.
pub const MAX_ANISOTROPY: f64 = 0.95;

/// A subsurface material as a shader describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct Appearance {
    /// Material name for reports.
    pub name: String,
    /// Total diffuse reflectance per channel, linear, in [0, 1] (clamped).
    pub colour: Rgb,
    /// Mean free path 1/σt per channel, mm.
    pub mean_free_path_mm: Rgb,
    /// Index of refraction of the surface.
    pub ior: f64,
    /// Henyey–Greenstein mean cosine g (0: isotropic).
    pub anisotropy: f64,
}

impl Appearance {
    /// The semi-infinite layer whose dipole total reflectance is the colour,
    /// with 1/σt' equal to the mean free path and σs = σs'/(1 − g).
    ///
    /// Colours are clamped to [0, 1], mean free paths to at least
    /// [`MIN_MEAN_FREE_PATH_MM`], g to ±[`MAX_ANISOTROPY`]; non-finite values
    /// and a non-positive index are errors.
    pub fn to_material(&self) -> Result<Material, InversionError> {
        let mut colour = [0.0; 3];
        let mut mfp = [0.0; 3];
        for c in 0..3 {
            let value = self.colour[c];
            if !value.is_finite() {
                return Err(InversionError::Colour { channel: c, value });
            }
            colour[c] = value.clamp(0.0, 1.0);
            let length = self.mean_free_path_mm[c];
            if !length.is_finite() || length < 0.0 {
                return Err(InversionError::MeanFreePath {
                    channel: c,
                    value: length,
                });
            }
            mfp[c] = length.max(MIN_MEAN_FREE_PATH_MM);
        }
        let ior = if self.ior.is_finite() && self.ior > 0.0 {
            self.ior
        } else {
            return Err(InversionError::Index { value: self.ior });
        };
        let g = if self.anisotropy.is_finite() {
            self.anisotropy.clamp(-MAX_ANISOTROPY, MAX_ANISOTROPY)
        } else {
            0.0
        };
        let mut layer = invert_albedo(colour, mfp, ior, InversionModel::Dipole)?;
        // The inversion fixes σs' = σs(1 − g); keep it and carry g.
        layer.sigma_s = layer.sigma_s.map(|s| s / (1.0 - g));
        layer.g = g;
        Ok(Material {
            name: self.name.clone(),
            optics: Optics::Layers(vec![layer]),
            coat_ior: None,
            top_layer: crate::material::TopLayer::Diffusion,
            roughness: crate::material::DEFAULT_ROUGHNESS,
        })
    }
}

/// The transport mean free path 1/σt' of each channel of a material's top
/// layer, mm; for a measured Gaussian profile, the square root of each
/// channel's weighted variance. Gives a scattering distance to a shader that states only a
/// colour.
pub fn channel_mean_free_paths(material: &Material) -> Rgb {
    match &material.optics {
        Optics::Layers(layers) => [0, 1, 2].map(|c| {
            layers[0]
                .medium(c)
                .mean_free_path()
                .max(MIN_MEAN_FREE_PATH_MM)
        }),
        Optics::Gaussians(g) => [0, 1, 2].map(|c| {
            let (weight, moment) = g.terms[c]
                .iter()
                .fold((0.0, 0.0), |(w, m), &(wi, vi)| (w + wi, m + wi * vi));
            if weight > 0.0 {
                (moment / weight).sqrt().max(MIN_MEAN_FREE_PATH_MM)
            } else {
                1.0
            }
        }),
    }
}
