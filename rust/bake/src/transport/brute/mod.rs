//! `brute`: the exact discrete sum over every texel within d_max
//! ([`sum`]), the reference every other method is measured against.
//!
//! It has no settings. It carries everything the model has: thin parts
//! (its 3-D sum reaches the far face) and an oblique kernel at each
//! light's incidence. Its cost is every pair within reach, n × the texels
//! within d_max; it is the top of `auto`'s ladder.

mod near_targets;
mod sum;

pub use sum::{Reach, exact_sum, exact_sum_and_unit, integrate, integrate_with_unit, sum_within};

use super::Method;
use super::integrator::{Carries, Integrated, Integrator, Work};
use super::sources::{OwnSource, Targets};
use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::scattering::Scattering;

/// The exact discrete sum over every texel within d_max: the reference
/// every other method is measured against. It has no settings.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BruteIntegrator;

impl Integrator for BruteIntegrator {
    fn method(&self) -> Method {
        Method::Brute
    }

    fn carries(&self) -> Carries {
        Carries {
            profile: true,
            across: true,
            oblique: true,
        }
    }

    fn evaluations(&self, work: &Work) -> f64 {
        work.texels * work.neighbours
    }

    fn thin_epsilon(&self) -> f32 {
        0.0
    }

    fn integrate(
        &self,
        prepared: &Prepared,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Integrated, Error> {
        let sources = prepared.texel_sources();
        // The targets are the texels the sources were made from, in order.
        let targets = Targets {
            own: OwnSource::Same,
            ..prepared.targets()
        };
        let (exitance, _) = exact_sum(prepared, scattering, &sources, targets, control)?;
        Ok(Integrated {
            exitance,
            sources: sources.len(),
            walk: None,
        })
    }
}
