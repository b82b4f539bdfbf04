//! `texture`: d'Eon & Luebke's texture-space diffusion ([`blur`]).
//!
//! | setting | default | meaning |
//! |---|---|---|
//! | `gaussians` | 6 | Gaussians in the fit, 1 to [`MAX_GAUSSIANS`] |
//!
//! It carries no light across thin parts (a blur knows only the surface
//! around each texel in the layout) and takes an oblique kernel's
//! azimuthal mean. Its cost grows as n log n; the few texels near chart
//! edges take the exact sum. Above `auto`'s tolerance it hands over to the
//! octree.

mod blur;

pub use blur::{MAX_REACH, integrate};

use super::integrator::{Carries, Integrated, Integrator, Work};
use super::{Method, brute, choice};
use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::scattering::Scattering;
use blur::{EDGE_RING, EDGE_VISITS, near_chart_edges};
use serde::{Deserialize, Serialize};
use sssbake_profile::models::gaussians::fit_gaussians;

/// d'Eon & Luebke's texture-space diffusion: the profile fitted by a sum
/// of Gaussians, each a separable blur of the irradiance texture.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TextureIntegrator {
    /// Gaussians in the fit, 1 to [`MAX_GAUSSIANS`].
    pub gaussians: usize,
}

/// The most Gaussians a fit takes.
pub const MAX_GAUSSIANS: usize = 16;

impl Default for TextureIntegrator {
    fn default() -> Self {
        TextureIntegrator { gaussians: 6 }
    }
}

impl TextureIntegrator {
    /// Refuses settings it cannot run with.
    pub fn validate(&self) -> Result<(), Error> {
        if !(1..=MAX_GAUSSIANS).contains(&self.gaussians) {
            return Err(Error::field(
                "texture.gaussians",
                format!("{} must be between 1 and {MAX_GAUSSIANS}", self.gaussians),
            ));
        }
        Ok(())
    }
}

impl Integrator for TextureIntegrator {
    fn method(&self) -> Method {
        Method::Texture
    }

    fn carries(&self) -> Carries {
        Carries {
            profile: true,
            across: false,
            oblique: false,
        }
    }

    fn evaluations(&self, work: &Work) -> f64 {
        work.n_log_n()
    }

    fn more_exact(&self) -> Option<Method> {
        Some(Method::Octree)
    }

    fn ladder(&self) -> Vec<(String, Box<dyn Integrator>)> {
        [1, 2, 3, 4, 6, 8]
            .into_iter()
            .map(|gaussians| {
                let rung: Box<dyn Integrator> = Box::new(TextureIntegrator { gaussians });
                (format!("{gaussians} G"), rung)
            })
            .collect()
    }

    fn integrate(
        &self,
        prepared: &Prepared,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Integrated, Error> {
        let fit = fit_gaussians(scattering.profile.as_ref(), self.gaussians);
        let mut exitance = integrate(
            &fit.gaussians,
            &prepared.surfels,
            &prepared.entering(),
            prepared.dilation(),
            control,
        )?;
        // Where a chart's edge is near, a texel's blur reads copies across
        // the seam or nothing past an open border, and its own texel is only
        // partly surface: most of the blurs' error lives in those few
        // texels, so they take the exact sum instead.
        let edge = near_chart_edges(&prepared.surfels, EDGE_RING);
        let texels = prepared.surfels.len().max(1);
        let neighbours = choice::neighbours(
            prepared.surfels.total_area() / texels as f64,
            f64::from(scattering.kernel.d_max),
        );
        let affordable = edge.len() as f64 * neighbours <= EDGE_VISITS;
        let mut sources = 0;
        if !edge.is_empty() && affordable {
            let texels = prepared.texel_sources();
            let listed = prepared.listed(&edge);
            let exact = brute::integrate(&scattering.kernel, &texels, listed.targets(), control)?;
            for (&s, m) in edge.iter().zip(exact) {
                exitance[s] = m;
            }
            sources = texels.len();
        }
        Ok(Integrated {
            exitance,
            sources,
            walk: None,
        })
    }
}
