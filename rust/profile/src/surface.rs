//! Where light crosses a material's surface, in and out: the share of
//! light from each incidence angle that reaches the layers beneath, and
//! the radiance leaving towards the normal per unit of exitance.
//!
//! Two kinds: a dielectric boundary (smooth Fresnel ρt = 1 − F(θ), or the
//! rough boundary's ρdt(θ) of Donner & Jensen 2005 eq. 25–26), and a Stam
//! top layer ([`crate::stam::epidermis`]), whose angular transmittance
//! T(θi) replaces the boundary's when the material declares one and the
//! `stam` model describes it.

use crate::Rgb;
use crate::material::{Material, TopLayer};
use crate::model::Model;
use crate::rough::diffuse_transmittance;
use crate::stam::epidermis::Epidermis;

/// A material's surface as the light crossing it sees it.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// A dielectric boundary of relative index `eta` (inside over outside)
    /// and RMS facet slope `roughness` (0: smooth).
    Boundary {
        /// Relative index, > 0.
        eta: f64,
        /// RMS facet slope m in [0, 1].
        roughness: f64,
    },
    /// A Stam top layer, solved.
    Stam(Box<Epidermis>),
}

impl Surface {
    /// The surface of `material` as `model` describes it: its Stam top
    /// layer under the `stam` model when it declares one, else the
    /// boundary of its entry index (a coat's, or the top layer's) and
    /// roughness.
    pub fn of(material: &Material, model: Model) -> Result<Self, String> {
        if model == Model::Stam && material.top_layer == TopLayer::Stam {
            return Ok(Surface::Stam(Box::new(Epidermis::solve(material)?)));
        }
        Ok(Self::boundary(material.entry_index(), material.roughness))
    }

    /// A dielectric boundary; a non-finite or non-positive index is taken
    /// as index-matched.
    pub fn boundary(eta: f64, roughness: f64) -> Self {
        let eta = if eta.is_finite() && eta > 0.0 {
            eta
        } else {
            1.0
        };
        Surface::Boundary { eta, roughness }
    }

    /// The share (dimensionless, in [0, 1], per channel) of the irradiance
    /// from incidence cosine `cos` that reaches the layers beneath the
    /// surface: ρt or ρdt(θ) of a boundary, T(θi) of a Stam layer.
    pub fn entry(&self, cos: f64) -> Rgb {
        match self {
            Surface::Boundary { eta, roughness } => {
                [diffuse_transmittance(cos.clamp(0.0, 1.0), *eta, *roughness); 3]
            }
            Surface::Stam(epidermis) => epidermis.transmittance(cos),
        }
    }

    /// π times the radiance leaving towards the normal per unit exitance
    /// (dimensionless, per channel), the factor the `diffuse` map applies:
    /// ρdt(0°) of a boundary (Donner & Jensen 2005 eq. 25, the
    /// diffusion profile's exitance taken before the exit term), or for a
    /// Stam top layer, whose profile's exitance is what already left into
    /// air, the share of it leaving at the normal
    /// ([`Epidermis::exit_at_normal`]).
    pub fn exit_at_normal(&self) -> Rgb {
        match self {
            Surface::Boundary { .. } => self.entry(1.0),
            Surface::Stam(epidermis) => epidermis.exit_at_normal(),
        }
    }
}
