//! The medium a walk travels through and the boundary it leaves by, taken
//! from a material the way the bake's profile takes them.
//!
//! The profile crate builds every model from the material's layers
//! (`Layer::sigma_a`, `sigma_s`, `g`, `ior`, all per mm); Blender's
//! Principled inputs become such a layer in `sssbake_profile::appearance::cycles`
//! (index-matched, `ior` 1, under a coat that only shapes the entry). The
//! walk reads the same first layer, so a bake and its walk see one medium.
//!
//! A material of several layers is refused: the walk fills the whole
//! object with one homogeneous medium, and filling it with a thin top
//! layer (an epidermis of 0.03 mm) would be a different material, not the
//! truth for this one. A measured sum of Gaussians carries no coefficients
//! and is refused too.

use sssbake_profile::boundary::fresnel::{dielectric_reflectance, diffuse_reflectance_exact};
use sssbake_profile::material::{Material, Optics};

/// Below this distance from 1 a boundary index counts as index-matched.
const INDEX_MATCHED_TOLERANCE: f64 = 1e-9;

/// How a walk meets the surface from inside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Boundary {
    /// The medium's index equals the outside's: a walk leaves at the first
    /// crossing, as Cycles' Random Walk does.
    IndexMatched,
    /// A smooth dielectric of relative index `eta` (inside over outside,
    /// positive): each crossing reflects with the Fresnel reflectance,
    /// chosen at random, and otherwise leaves.
    Dielectric {
        /// Relative index, inside over outside.
        eta: f64,
    },
}

impl Boundary {
    /// The boundary of relative index `eta`: index-matched at 1 (or for a
    /// non-finite or non-positive index, as `Surface::boundary` reads one).
    pub fn of_index(eta: f64) -> Self {
        if !(eta.is_finite() && eta > 0.0) || (eta - 1.0).abs() < INDEX_MATCHED_TOLERANCE {
            Boundary::IndexMatched
        } else {
            Boundary::Dielectric { eta }
        }
    }

    /// The probability (in [0, 1]) that light inside meeting the surface
    /// at incidence cosine `cos_inside` is reflected back in.
    pub fn reflectance(self, cos_inside: f64) -> f64 {
        match self {
            Boundary::IndexMatched => 0.0,
            Boundary::Dielectric { eta } => dielectric_reflectance(cos_inside, eta, 1.0),
        }
    }

    /// F_dr: the reflectance averaged over a cosine-weighted hemisphere
    /// inside (dimensionless, in [0, 1]); 0 when index-matched.
    pub fn diffuse_reflectance(self) -> f64 {
        match self {
            Boundary::IndexMatched => 0.0,
            Boundary::Dielectric { eta } => diffuse_reflectance_exact(eta),
        }
    }
}

/// One channel of a homogeneous medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChannelMedium {
    /// Extinction σt = σa + σs, 1/mm (≥ 0).
    pub sigma_t: f64,
    /// Single-scattering albedo σs/σt, in [0, 1].
    pub albedo: f64,
    /// Henyey–Greenstein mean cosine, in (−1, 1).
    pub g: f64,
}

impl ChannelMedium {
    /// From absorption and scattering (1/mm) and the mean cosine; negative
    /// or non-finite coefficients count as 0 and g is kept inside
    /// (−0.999, 0.999), where the phase function's sampling is stable.
    pub fn new(sigma_a: f64, sigma_s: f64, g: f64) -> Self {
        let clean = |v: f64| if v.is_finite() { v.max(0.0) } else { 0.0 };
        let (sigma_a, sigma_s) = (clean(sigma_a), clean(sigma_s));
        let sigma_t = sigma_a + sigma_s;
        let albedo = if sigma_t > 0.0 {
            (sigma_s / sigma_t).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let g = if g.is_finite() {
            g.clamp(-0.999, 0.999)
        } else {
            0.0
        };
        ChannelMedium { sigma_t, albedo, g }
    }
}

/// A homogeneous medium per RGB channel and its boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkMedium {
    /// Red, green and blue.
    pub channels: [ChannelMedium; 3],
    /// The surface from inside.
    pub boundary: Boundary,
}

impl WalkMedium {
    /// The medium of `material`'s only layer, with the boundary of that
    /// layer's index against air (a coat's index shapes only the entry,
    /// which the bake's irradiance has already taken). Refuses a material
    /// of several layers or of measured Gaussians, saying why.
    pub fn of_material(material: &Material) -> Result<Self, String> {
        let layers = match &material.optics {
            Optics::Layers(layers) => layers,
            Optics::Gaussians(_) => {
                return Err(format!(
                    "material `{}` is a measured profile with no optical coefficients to walk through",
                    material.name
                ));
            }
        };
        let [layer] = layers.as_slice() else {
            return Err(format!(
                "material `{}` has {} layers; the random walk fills the object with one \
                 homogeneous medium and would misstate a layered one",
                material.name,
                layers.len()
            ));
        };
        Ok(WalkMedium {
            channels: [0, 1, 2]
                .map(|c| ChannelMedium::new(layer.sigma_a[c], layer.sigma_s[c], layer.g)),
            boundary: Boundary::of_index(layer.ior),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sssbake_profile::material::Layer;

    #[test]
    fn principled_materials_walk_index_matched() {
        let layer = Layer::semi_infinite([0.1; 3], [1.0; 3], 1.0);
        let material = Material {
            name: "rw".into(),
            optics: Optics::Layers(vec![layer]),
            coat_ior: Some(1.5),
            roughness: 0.0,
            top_layer: Default::default(),
        };
        let medium = WalkMedium::of_material(&material).unwrap();
        assert_eq!(medium.boundary, Boundary::IndexMatched);
        assert!((medium.channels[0].sigma_t - 1.1).abs() < 1e-12);
        assert!((medium.channels[0].albedo - 1.0 / 1.1).abs() < 1e-12);
    }

    #[test]
    fn layered_and_measured_materials_are_refused() {
        let layer = Layer::semi_infinite([0.1; 3], [1.0; 3], 1.4);
        let material = Material {
            name: "two".into(),
            optics: Optics::Layers(vec![
                Layer {
                    thickness_mm: Some(0.1),
                    ..layer.clone()
                },
                layer,
            ]),
            coat_ior: None,
            roughness: 0.0,
            top_layer: Default::default(),
        };
        assert!(
            WalkMedium::of_material(&material)
                .unwrap_err()
                .contains("2 layers")
        );
    }

    #[test]
    fn a_dielectric_reflects_more_than_nothing_and_at_most_everything() {
        let boundary = Boundary::of_index(1.4);
        assert!(matches!(boundary, Boundary::Dielectric { .. }));
        let fdr = boundary.diffuse_reflectance();
        assert!(fdr > 0.4 && fdr < 0.7, "F_dr(1.4) = {fdr}");
        assert_eq!(boundary.reflectance(0.1), 1.0, "beyond the critical angle");
        assert_eq!(Boundary::of_index(f64::NAN), Boundary::IndexMatched);
    }
}
