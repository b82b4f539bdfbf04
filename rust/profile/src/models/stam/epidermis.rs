//! A material's Stam top layer (an epidermis) seen as the surface the
//! light crosses to reach the layers beneath: its total reflectance and
//! transmittance per incidence angle from air, and its response to the
//! diffuse light coming back up from below, per channel.
//!
//! The layer is solved with its top face against air (smooth, or rough of
//! the material's roughness) and its bottom face in optical contact with
//! the layer beneath ([`super::contact`]); a difference of index between
//! the two is the next layer's own diffusion boundary, as between any two
//! layers of a stack.

use super::StamError;
use super::contact::ContactTotals;
use super::material::layers_for;
use crate::diffusion::split::{Split, SplitSide, SplitSlab};
use crate::material::Material;
use crate::{Rgb, rgb_map};

/// Ordinates per half range the epidermis is solved on (as
/// [`super::DEFAULT_ORDINATES`]).
const ORDINATES: usize = super::DEFAULT_ORDINATES;

/// The epidermis's totals, per channel.
#[derive(Clone, Debug, PartialEq)]
pub struct Epidermis {
    channels: [ContactTotals; 3],
}

impl Epidermis {
    /// Solves `material`'s top layer ([`layers_for`]) in each channel.
    pub fn solve(material: &Material) -> Result<Self, String> {
        let layers = layers_for(material)?;
        let mut channels = Vec::with_capacity(3);
        for layer in layers {
            channels.push(
                layer
                    .solve_in_contact(ORDINATES)
                    .map_err(|StamError(e)| e)?,
            );
        }
        let channels: [ContactTotals; 3] = channels
            .try_into()
            .map_err(|_| "three channels".to_string())?;
        Ok(Self { channels })
    }

    /// The totals of channel `c` on the ordinates.
    pub fn channel(&self, c: usize) -> &ContactTotals {
        &self.channels[c]
    }

    /// T(θi) (dimensionless, per channel): the share of collimated light
    /// arriving from air at incidence cosine `cos` that reaches the layer
    /// beneath, quadratic in the cosine between ordinates, held at the last
    /// beyond it (θ ≈ 1.5°) and falling linearly to 0 at grazing below the
    /// first: the rule has no ordinate at 0 and 1, a smooth face lets no
    /// grazing light in, and the irradiance from there is cos θ·T, small
    /// whatever T is.
    pub fn transmittance(&self, cos: f64) -> Rgb {
        rgb_map(|c| {
            let t = &self.channels[c];
            let first = t.cosines.first().copied().unwrap_or(0.0);
            let value = interpolate(&t.cosines, &t.transmittance, cos);
            if cos < first && first > 0.0 {
                value * (cos / first).max(0.0)
            } else {
                value
            }
        })
    }

    /// R(θi) (dimensionless, per channel), interpolated likewise.
    pub fn reflectance(&self, cos: f64) -> Rgb {
        rgb_map(|c| {
            let t = &self.channels[c];
            interpolate(&t.cosines, &t.reflectance, cos)
        })
    }

    /// The share of Lambertian light from below returned below.
    pub fn reflectance_from_below(&self) -> Rgb {
        rgb_map(|c| self.channels[c].reflectance_from_below)
    }

    /// The share of Lambertian light from below that leaves into air.
    pub fn transmittance_from_below(&self) -> Rgb {
        rgb_map(|c| self.channels[c].transmittance_from_below)
    }

    /// π times the radiance leaving towards the normal per unit exitance
    /// into air, for the Lambertian light from below (dimensionless; 1 for
    /// a Lambertian exitance, below 1 when the faces tilt it to grazing).
    pub fn exit_at_normal(&self) -> Rgb {
        rgb_map(|c| {
            let t = &self.channels[c];
            interpolate(&t.cosines, &t.exit_distribution, 1.0)
        })
    }

    /// The layer in channel `c` as the stack algebra's slab with no
    /// lateral spread (all of it in the r = 0 "ballistic" part, the same
    /// at every frequency): an epidermis is a few hundredths of a
    /// millimetre thick against the dermis's millimetres of spread.
    ///
    /// From above its transmittance is 1 and its reflectance 0, because
    /// the light from above is counted after it crossed: the bake's entry
    /// term is T(θi) per light. From below it returns and passes its
    /// shares of Lambertian light (the diffusion layers below send their
    /// light up as such). A stack's reflectance under it is then the light
    /// that leaves into air, T⁻·R_b/(1 − R⁻·R_b) at k = 0.
    pub fn split_slab(&self, c: usize) -> SplitSlab {
        let delta = |x: f64| Split {
            ballistic: x,
            diffuse: 0.0,
        };
        let t = &self.channels[c];
        SplitSlab {
            down: SplitSide {
                reflectance: delta(0.0),
                transmittance: delta(1.0),
            },
            up: SplitSide {
                reflectance: delta(t.reflectance_from_below),
                transmittance: delta(t.transmittance_from_below),
            },
        }
    }
}

/// `values` on increasing `cosines`, by the parabola through the three
/// nearest (a smooth function's error falls as the spacing cubed, where a
/// straight line's falls as its square), held beyond the ends, never
/// below 0; 0 for an empty table or a NaN cosine.
fn interpolate(cosines: &[f64], values: &[f64], cos: f64) -> f64 {
    let n = cosines.len();
    let (Some(&first), Some(&last)) = (cosines.first(), cosines.last()) else {
        return 0.0;
    };
    if cos.is_nan() {
        return 0.0;
    }
    let value = if cos <= first {
        values[0]
    } else if cos >= last {
        values[n - 1]
    } else if n < 3 {
        let f = (cos - first) / (last - first);
        values[0] * (1.0 - f) + values[n - 1] * f
    } else {
        // The three ordinates around `cos`: the interval's two and the
        // nearer of their neighbours.
        let i = cosines.partition_point(|&m| m <= cos).clamp(1, n - 1);
        let start = if i == 1 {
            0
        } else if i == n - 1 || cos - cosines[i - 1] < cosines[i] - cos {
            i - 2
        } else {
            i - 1
        };
        let x = &cosines[start..start + 3];
        let y = &values[start..start + 3];
        (0..3)
            .map(|a| {
                let weight: f64 = (0..3)
                    .filter(|&b| b != a)
                    .map(|b| (cos - x[b]) / (x[a] - x[b]))
                    .product();
                weight * y[a]
            })
            .sum()
    };
    value.max(0.0)
}
