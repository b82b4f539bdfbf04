//! From what an artist knows, a diffuse colour and a mean free path per
//! channel, to the σa and σs' that give exactly that colour as the chosen
//! model's total diffuse reflectance.

use crate::boundary::fresnel::boundary_a;
use crate::diffusion::medium::Medium;
use crate::diffusion::slab::{Incidence, SlabChannel};
use crate::material::Layer;
use crate::models::dipole::dipole_total_reflectance;
use crate::{Rgb, rgb_map};

/// The model whose total diffuse reflectance the colour must equal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InversionModel {
    /// A semi-infinite medium by the dipole (closed-form total).
    Dipole,
    /// A slab of the given thickness (mm) over air, by the multipole.
    Slab {
        /// Thickness in mm.
        thickness_mm: f64,
    },
}

/// Why a colour could not be inverted.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InversionError {
    /// A colour component outside [0, 1] or not finite.
    #[error("colour channel {channel} is {value}; a diffuse colour lies in [0, 1]")]
    Colour {
        /// Channel index.
        channel: usize,
        /// The value given.
        value: f64,
    },
    /// A mean free path that is not positive and finite.
    #[error("mean free path of channel {channel} is {value} mm; it must be positive and finite")]
    MeanFreePath {
        /// Channel index.
        channel: usize,
        /// The value given.
        value: f64,
    },
    /// An index of refraction that is not positive and finite.
    #[error("index of refraction {value}; it must be positive and finite")]
    Index {
        /// The value given.
        value: f64,
    },
    /// The model cannot reflect this much.
    #[error("channel {channel}: colour {value} exceeds the most this model reflects ({limit:.4})")]
    Unreachable {
        /// Channel index.
        channel: usize,
        /// The colour asked for.
        value: f64,
        /// The largest reachable total reflectance.
        limit: f64,
    },
}

/// A layer (g = 0, σs = σs') whose `model` total reflectance is `colour`,
/// with transport mean free path 1/σt' = `mfp_mm`, under air at index `ior`.
pub fn invert_albedo(
    colour: Rgb,
    mfp_mm: Rgb,
    ior: f64,
    model: InversionModel,
) -> Result<Layer, InversionError> {
    let a = boundary_a(ior);
    let total = |albedo: f64, c: usize| -> f64 {
        match model {
            InversionModel::Dipole => dipole_total_reflectance(albedo, a),
            InversionModel::Slab { thickness_mm } => {
                let medium = Medium {
                    sigma_a: (1.0 - albedo) / mfp_mm[c],
                    sigma_s_reduced: albedo / mfp_mm[c],
                };
                SlabChannel::new(medium, thickness_mm, ior, ior, Incidence::Collimated)
                    .image_totals()
                    .reflectance
            }
        }
    };
    let mut albedo = [0.0; 3];
    for c in 0..3 {
        let (value, mfp) = (colour[c], mfp_mm[c]);
        if !(value.is_finite() && (0.0..=1.0).contains(&value)) {
            return Err(InversionError::Colour { channel: c, value });
        }
        if !(mfp.is_finite() && mfp > 0.0) {
            return Err(InversionError::MeanFreePath {
                channel: c,
                value: mfp,
            });
        }
        let limit = total(1.0, c);
        if value > limit + 1e-12 {
            return Err(InversionError::Unreachable {
                channel: c,
                value,
                limit,
            });
        }
        albedo[c] = albedo_for(value, |albedo| total(albedo, c));
    }
    Ok(Layer {
        sigma_a: rgb_map(|c| (1.0 - albedo[c]) / mfp_mm[c]),
        sigma_s: rgb_map(|c| albedo[c] / mfp_mm[c]),
        g: 0.0,
        ior,
        thickness_mm: match model {
            InversionModel::Dipole => None,
            InversionModel::Slab { thickness_mm } => Some(thickness_mm),
        },
    })
}

/// The reduced albedo α′ in [0, 1] at which `total(α′)`, rising
/// monotonically, reaches `target`: bisected to machine precision.
pub fn albedo_for(target: f64, total: impl Fn(f64) -> f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if total(mid) < target {
            lo = mid
        } else {
            hi = mid
        }
    }
    0.5 * (lo + hi)
}
