//! Where light crosses a material's surface, in and out: the share of
//! light from each incidence angle that reaches the layers beneath, and
//! the radiance leaving towards the normal per unit of exitance.
//!
//! Three kinds: a dielectric boundary (smooth Fresnel ρt = 1 − F(θ), or the
//! rough boundary's ρdt(θ) of Donner & Jensen 2005 eq. 25–26), crossed by
//! light both ways; Blender's Principled specular layer, which Cycles lets
//! take its share only where the surface is viewed (so light enters whole
//! and leaves towards the normal through ρdt(0)); and a Stam top layer
//! ([`crate::models::stam::epidermis`]), whose angular transmittance T(θi) replaces
//! the boundary's when the material declares one and the `stam` model
//! describes it.

use crate::Rgb;
use crate::boundary::rough::{diffuse_transmittance, hemispherical_transmittance};
use crate::material::{Material, TopLayer};
use crate::model::Model;
use crate::models::stam::epidermis::Epidermis;

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
    /// Blender's Principled specular layer over an index-matched medium, as
    /// Cycles weighs it ([`TopLayer::PrincipledSpecular`]): nothing taken
    /// from the light entering, ρdt(0) of a boundary of `eta` and
    /// `roughness` from the light leaving towards the normal.
    ViewedBoundary {
        /// Relative index of the specular layer, > 0.
        eta: f64,
        /// RMS facet slope m in [0, 1].
        roughness: f64,
    },
    /// A Stam top layer, solved.
    Stam(Box<Epidermis>),
}

impl Surface {
    /// The surface of `material` as `model` describes it: its Stam top
    /// layer under the `stam` model when it declares one, else
    /// [`Self::face`].
    pub fn of(material: &Material, model: Model) -> Result<Self, String> {
        if model == Model::Stam && material.top_layer == TopLayer::Stam {
            return Ok(Surface::Stam(Box::new(Epidermis::solve(material)?)));
        }
        Ok(Self::face(material))
    }

    /// The face of `material` without a Stam top layer: the boundary of its
    /// entry index (a coat's, or the top layer's) and roughness, weighed
    /// only where viewed under a Principled specular layer.
    pub fn face(material: &Material) -> Self {
        match Self::boundary(material.entry_index(), material.roughness) {
            Surface::Boundary { eta, roughness }
                if material.top_layer == TopLayer::PrincipledSpecular =>
            {
                Surface::ViewedBoundary { eta, roughness }
            }
            boundary => boundary,
        }
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
    /// surface: ρt or ρdt(θ) of a boundary, 1 under a Principled specular
    /// layer, T(θi) of a Stam layer.
    pub fn entry(&self, cos: f64) -> Rgb {
        match self {
            Surface::Boundary { eta, roughness } => {
                [diffuse_transmittance(cos.clamp(0.0, 1.0), *eta, *roughness); 3]
            }
            Surface::ViewedBoundary { .. } => [1.0; 3],
            Surface::Stam(epidermis) => epidermis.transmittance(cos),
        }
    }

    /// π L(0)/M: π times the radiance leaving towards the normal per unit
    /// of the exitance M that leaves into air (dimensionless, per
    /// channel), the factor the `diffuse` map applies. Every profile's
    /// exitance is the light that has left (the diffusion profiles' net
    /// flux through the boundary, the Monte Carlo's tallies in air).
    ///
    /// - A boundary: the light meeting it from inside is nearly isotropic
    ///   (diffusion), radiance L_i. Leaving towards ω it is L_i ρdt(ω)/η²
    ///   (reciprocity: the share crossing out towards ω is the share
    ///   crossing in from ω, and radiance divides by η² going out), so
    ///   M = π L_i ρ̄dt/η² and π L(0)/M = ρdt(0)/ρ̄dt, with ρ̄dt the
    ///   hemispherical transmittance from outside. Smooth, that is
    ///   (1 − F(0))/(η²(1 − F_dr(η))); index-matched, 1 (Lambertian).
    /// - A Principled specular layer over an index-matched medium: the
    ///   medium's exitance leaves Lambertian and Cycles gives the layer
    ///   its share where viewed, so ρdt(0).
    /// - A Stam top layer: its solved share of Lambertian light from below
    ///   leaving at the normal ([`Epidermis::exit_at_normal`]), the same
    ///   quantity.
    pub fn exit_at_normal(&self) -> Rgb {
        match self {
            Surface::Boundary { eta, roughness } => {
                let through = hemispherical_transmittance(*eta, *roughness);
                let at_normal = diffuse_transmittance(1.0, *eta, *roughness);
                [if through > 0.0 {
                    at_normal / through
                } else {
                    1.0
                }; 3]
            }
            Surface::ViewedBoundary { eta, roughness } => {
                [diffuse_transmittance(1.0, *eta, *roughness); 3]
            }
            Surface::Stam(epidermis) => epidermis.exit_at_normal(),
        }
    }
}
