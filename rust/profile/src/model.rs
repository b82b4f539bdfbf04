//! Choosing and building the profile a material needs.

use crate::material::{Layer, Material, Optics, TopLayer};
use crate::models::burley::Burley;
use crate::models::dipole::Dipole;
use crate::models::empirical::{EmpiricalProfile, EmpiricalSettings};
use crate::models::gaussians::fit_gaussians;
use crate::models::layered::Layered;
use crate::models::monte_carlo::profile::{MonteCarloProfile, ProfileSettings};
use crate::models::multipole::{DEFAULT_ACCURACY, Multipole};
use crate::models::stam::topped::StamTopped;
use crate::profile::Profile;

/// The profile models sssbake offers.
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    strum::Display,
    strum::EnumString,
    strum::IntoStaticStr,
    strum::VariantArray,
    strum::VariantNames,
    strum::EnumMessage,
)]
#[strum(serialize_all = "lowercase")]
pub enum Model {
    /// Semi-infinite dipole (the top layer, taken as semi-infinite).
    Dipole,
    /// One slab by the multipole.
    Multipole,
    /// Any stack, combined per frequency.
    Layered,
    /// A sum of Gaussians (fitted, or measured for d'Eon skin).
    Gaussians,
    /// Christensen–Burley normalized diffusion matched to the material.
    Burley,
    /// The Monte Carlo photon-transport reference, smoothed into a profile.
    MonteCarlo,
    /// Stam 2001's plane-parallel layer between smooth or rough faces, by
    /// discrete ordinates: R(θi), T(θi) and BRDFs ([`crate::models::stam`]); as a
    /// material's declared top layer, the surface of the stack below it
    /// ([`crate::models::stam::topped`]).
    Stam,
    /// Donner et al. 2009's empirical BSSRDF: elliptic lobes fitted to
    /// photon tracing of the top layer, whose exitance (the simulated one)
    /// the bake reads, at normal and at oblique incidence.
    Empirical,
}

impl Model {
    /// Every model, in the order the command line lists them.
    pub const ALL: [Model; 8] = [
        Model::Dipole,
        Model::Multipole,
        Model::Layered,
        Model::Gaussians,
        Model::Burley,
        Model::MonteCarlo,
        Model::Stam,
        Model::Empirical,
    ];

    /// The model's command-line name.
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// The model a material needs: stam for a top layer declared stam, the
    /// dipole for one semi-infinite layer, the layered solver for anything
    /// else, Gaussians for a measured sum.
    pub fn default_for(material: &Material) -> Model {
        match &material.optics {
            Optics::Gaussians(_) => Model::Gaussians,
            Optics::Layers(_) if material.top_layer == TopLayer::Stam => Model::Stam,
            Optics::Layers(layers) if layers.len() == 1 && layers[0].thickness_mm.is_none() => {
                Model::Dipole
            }
            Optics::Layers(_) => Model::Layered,
        }
    }
}

/// A model that cannot describe a material.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("material `{material}`: model {model}: {reason}")]
pub struct ModelError {
    /// The material's name.
    pub material: String,
    /// The model asked for.
    pub model: Model,
    /// Why it does not apply.
    pub reason: String,
}

/// Why `layers` are not one semi-infinite medium (the dipole's and the
/// empirical model's), naming the model that describes them; `None` when
/// they are.
fn not_a_half_space(layers: &[Layer]) -> Option<String> {
    match layers {
        [one] => one.thickness_mm.map(|t| {
            format!("it describes a semi-infinite medium; this material is one layer {t} mm thick (use multipole or layered)")
        }),
        _ => Some(format!(
            "it describes a semi-infinite medium; this material has {} layers (use layered)",
            layers.len()
        )),
    }
}

/// Builds `model` for `material`. Gaussians are fitted with `gaussians`
/// terms to the material's default profile. Monte Carlo simulates the
/// material with the default [`ProfileSettings`] (seconds; a bake caches
/// it) and smooths the tallies ([`MonteCarloProfile`]). Empirical
/// simulates and fits the top layer with the default
/// [`EmpiricalSettings`] (a bake caches it too).
pub fn build_profile(
    material: &Material,
    model: Model,
    gaussians: usize,
) -> Result<Box<dyn Profile>, ModelError> {
    let error = |reason: &str| ModelError {
        material: material.name.clone(),
        model,
        reason: reason.to_string(),
    };
    let layers: &[Layer] = match (&material.optics, model) {
        (Optics::Gaussians(g), Model::Gaussians) => return Ok(Box::new(g.clone())),
        (Optics::Gaussians(g), Model::Burley) => return Ok(Box::new(Burley::matching(g))),
        (Optics::Gaussians(_), _) => {
            return Err(error(
                "a measured sum of Gaussians has no optical coefficients; use gaussians or burley",
            ));
        }
        (Optics::Layers(layers), _) => layers,
    };
    let Some(top) = layers.first() else {
        return Err(error("the material has no layers"));
    };
    // Both model one semi-infinite medium: anything else would be taken
    // as its top layer alone, without a word.
    if matches!(model, Model::Dipole | Model::Empirical)
        && let Some(reason) = not_a_half_space(layers)
    {
        return Err(error(&reason));
    }
    Ok(match model {
        Model::Dipole => Box::new(Dipole::with_roughness(
            [0, 1, 2].map(|c| top.medium(c)),
            top.ior,
            material.roughness,
        )),
        Model::Multipole if layers.len() == 1 => Box::new(Multipole::with_roughness(
            top,
            material.roughness,
            DEFAULT_ACCURACY,
        )),
        Model::Multipole => {
            return Err(error(
                "the multipole describes one slab; this material has several layers (use layered)",
            ));
        }
        Model::Layered => Box::new(Layered::with_roughness(layers, material.roughness)),
        Model::Gaussians | Model::Burley => {
            let reference = build_profile(material, Model::default_for(material), gaussians)?;
            if model == Model::Burley {
                Box::new(Burley::matching(reference.as_ref()))
            } else {
                Box::new(fit_gaussians(reference.as_ref(), gaussians).gaussians)
            }
        }
        Model::Stam if material.top_layer == TopLayer::Stam => {
            Box::new(StamTopped::new(material).map_err(|reason| error(&reason))?)
        }
        Model::Stam => {
            return Err(error(
                "stam is a plane-parallel model of angles (R(θi), T(θi), BRDF and BTDF; see \
                 `sssbake profile --model stam`), not a radial profile R(r) a bake integrates; \
                 declare the top layer `model = \"stam\"` over others to bake it as their surface",
            ));
        }
        Model::MonteCarlo => Box::new(
            MonteCarloProfile::simulate(material, &ProfileSettings::default())
                .ok_or_else(|| error("the material has no layers to simulate"))?,
        ),
        Model::Empirical => Box::new(
            EmpiricalProfile::simulate(material, &EmpiricalSettings::default())
                .map_err(|reason| error(&reason))?,
        ),
    })
}
