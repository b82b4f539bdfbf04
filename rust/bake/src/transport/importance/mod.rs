//! `importance`: Monte Carlo per texel in the manner of Mertens et al.
//! 2003, probe rays along the normal and both tangents ([`probes`]).
//!
//! | setting | default | meaning |
//! |---|---|---|
//! | `samples` | 512 | probes per texel |
//! | `seed` | 1 | seed of the probes (stream = texel) |
//!
//! It carries thin parts (a probe finds the far face) and an oblique
//! kernel at each light's incidence. Its cost is `samples` probes per
//! texel. Above `auto`'s tolerance it hands over to the octree.

mod probes;

pub use probes::{Oblique, Pieces, Surface, integrate};

use super::Method;
use super::integrator::{Carries, Integrated, Integrator, Work};
use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::rays::RayScene;
use crate::scattering::Scattering;
use serde::{Deserialize, Serialize};

/// Mertens et al.'s Monte Carlo: radii drawn from the profile, probe rays
/// along the normal and both tangents, weighed by the balance heuristic.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ImportanceIntegrator {
    /// Probes per texel.
    pub samples: u32,
    /// Seed of the probes (stream = texel, so any thread count agrees).
    pub seed: u64,
}

impl Default for ImportanceIntegrator {
    fn default() -> Self {
        ImportanceIntegrator {
            samples: 512,
            seed: 1,
        }
    }
}

impl ImportanceIntegrator {
    /// Refuses settings it cannot run with.
    pub fn validate(&self) -> Result<(), Error> {
        if self.samples == 0 {
            return Err(Error::field("importance.samples", "must be at least 1"));
        }
        Ok(())
    }
}

impl Integrator for ImportanceIntegrator {
    fn method(&self) -> Method {
        Method::Importance
    }

    fn carries(&self) -> Carries {
        Carries {
            profile: true,
            across: true,
            oblique: true,
        }
    }

    fn evaluations(&self, work: &Work) -> f64 {
        work.texels * f64::from(self.samples)
    }

    /// A probe's hit reads the light split by incidence through each map
    /// texel's surfel: 4 bytes per map texel.
    fn extra_memory_bytes(&self, resolution: u32, split: bool) -> f64 {
        if split {
            4.0 * f64::from(resolution).powi(2)
        } else {
            0.0
        }
    }

    fn more_exact(&self) -> Option<Method> {
        Some(Method::Octree)
    }

    fn ladder(&self) -> Vec<(String, Box<dyn Integrator>)> {
        [16, 64, 256, 512]
            .into_iter()
            .map(|samples| {
                let rung: Box<dyn Integrator> = Box::new(ImportanceIntegrator {
                    samples,
                    ..self.clone()
                });
                (format!("{samples} spp"), rung)
            })
            .collect()
    }

    fn integrate(
        &self,
        prepared: &Prepared,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Integrated, Error> {
        let probes = RayScene::new(&[&prepared.mesh]);
        let texture = prepared.entering_texture();
        let incidence = match &scattering.oblique {
            Some(_) => prepared.incidence(control)?,
            None => None,
        };
        let texels = if incidence.is_some() {
            prepared.surfel_texture()
        } else {
            Vec::new()
        };
        let oblique = scattering
            .oblique
            .as_ref()
            .zip(incidence)
            .map(|(kernel, incidence)| Oblique {
                kernel,
                incidence,
                normal: &prepared.surfels.normal,
                texels: &texels,
            });
        let surface = Surface {
            mesh: &prepared.mesh,
            uvs: &prepared.uvs,
            probes: &probes,
            irradiance: &texture,
            resolution: prepared.surfels.resolution,
            oblique,
            pieces: Some(Pieces {
                triangle: &prepared.surfels.triangle_medium,
                target: &prepared.surfels.piece,
                triangle_part: &prepared.surfels.triangle_part,
                target_part: &prepared.surfels.part,
            }),
        };
        let exitance = integrate(
            &scattering.kernel,
            scattering.profile.as_ref(),
            &surface,
            &prepared.surfels.position,
            &prepared.surfels.normal,
            self.samples,
            self.seed,
            control,
        )?;
        Ok(Integrated {
            exitance,
            sources: 0,
            walk: None,
        })
    }
}
