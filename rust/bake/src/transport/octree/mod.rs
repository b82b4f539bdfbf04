//! `octree`: the hierarchy of Jensen & Buhler 2002 over the texels
//! ([`tree`]).
//!
//! | setting | default | meaning |
//! |---|---|---|
//! | `epsilon` | 0.5 sr | solid angle below which a node is taken whole; 0 is the exact sum |
//!
//! It carries thin parts (its 3-D sum reaches the far face) but takes an
//! oblique kernel's azimuthal mean. Its cost grows as n log n. Under
//! `auto` its pilot (its sums at a few texels against the exact sums
//! there) predicts its error before the whole map; above the tolerance it
//! refines once, to an ε scaled by the tolerance over the error, then
//! hands over to the exact sum.

pub(crate) mod shape;
mod tree;
mod weighed;

pub use shape::TreeShape;
pub use tree::{Gathering, Octree, integrate};

use super::Method;
use super::integrator::{Carries, Integrated, Integrator, Summer, Work};
use super::sources::{OwnSource, Targets};
use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::scattering::Scattering;
use serde::{Deserialize, Serialize};
use std::sync::Mutex;

/// The octree integrator over the texels.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OctreeIntegrator {
    /// Solid angle (sr) below which a node is taken whole; 0 is exact.
    pub epsilon: f32,
}

impl Default for OctreeIntegrator {
    fn default() -> Self {
        OctreeIntegrator { epsilon: 0.5 }
    }
}

impl OctreeIntegrator {
    /// Refuses settings it cannot run with.
    pub fn validate(&self) -> Result<(), Error> {
        if !(self.epsilon.is_finite() && self.epsilon >= 0.0) {
            return Err(Error::field(
                "octree.epsilon",
                format!("{} must be a non-negative solid angle", self.epsilon),
            ));
        }
        Ok(())
    }
}

/// The next solid-angle threshold after missing `tolerance` with relative
/// error `error` at `epsilon` (sr): the error falls at least in proportion
/// to ε (on the bundled ear at 512², 1.8% at 0.5, 0.26% at 0.2, 0.12% at
/// 0.1), so ε scaled by the tolerance over the error, with a margin, at
/// most 16 times finer. `None` when ε cannot usefully shrink.
pub fn finer_epsilon(epsilon: f32, error: f64, tolerance: f64) -> Option<f32> {
    const MARGIN: f64 = 0.7;
    if !(epsilon > 0.0 && error.is_finite() && error > tolerance) {
        return None;
    }
    let finer = (f64::from(epsilon) * MARGIN * tolerance / error) as f32;
    Some(finer.max(epsilon / 16.0))
}

impl Integrator for OctreeIntegrator {
    fn method(&self) -> Method {
        Method::Octree
    }

    fn carries(&self) -> Carries {
        Carries {
            profile: true,
            across: true,
            oblique: false,
        }
    }

    fn evaluations(&self, work: &Work) -> f64 {
        work.n_log_n()
    }

    fn thin_epsilon(&self) -> f32 {
        self.epsilon
    }

    fn refine(&mut self, error: f64, tolerance: f64) -> bool {
        match finer_epsilon(self.epsilon, error, tolerance) {
            Some(finer) => {
                self.epsilon = finer;
                true
            }
            None => false,
        }
    }

    fn more_exact(&self) -> Option<Method> {
        Some(Method::Brute)
    }

    fn summer<'a>(
        &'a self,
        prepared: &'a Prepared,
        scattering: &'a Scattering,
    ) -> Option<Box<dyn Summer + 'a>> {
        // At ε = 0 it is the exact sum, at every texel.
        if self.epsilon <= 0.0 {
            return None;
        }
        Some(Box::new(OctreeSummer {
            prepared,
            scattering,
            epsilon: self.epsilon,
            gathering: Mutex::new(None),
        }))
    }

    fn ladder(&self) -> Vec<(String, Box<dyn Integrator>)> {
        [2.0f32, 1.0, 0.5, 0.2, 0.05]
            .into_iter()
            .map(|epsilon| {
                let rung: Box<dyn Integrator> = Box::new(OctreeIntegrator { epsilon });
                (format!("ε {epsilon}"), rung)
            })
            .collect()
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
        let shape = prepared.texel_tree();
        let exitance = Gathering::over(shape, &[&scattering.kernel], &sources, self.epsilon)
            .at(targets, control)?;
        Ok(Integrated {
            exitance,
            sources: sources.len(),
            walk: None,
        })
    }
}

/// The octree's sums at chosen texels of one object, its tree built at
/// the first texels asked for and kept until released (so a caller may
/// free memory of its own before the tree takes its share, and the tree's
/// before it takes more).
struct OctreeSummer<'a> {
    prepared: &'a Prepared,
    scattering: &'a Scattering,
    epsilon: f32,
    gathering: Mutex<Option<Gathering<'a>>>,
}

impl Summer for OctreeSummer<'_> {
    fn at(&self, listed: &[usize], control: &Control) -> Result<Vec<[f32; 3]>, Error> {
        // Held while gathering, which is parallel itself: callers ask for
        // one list of texels at a time.
        let mut held = self.gathering.lock().unwrap_or_else(|e| e.into_inner());
        let gathering = held.get_or_insert_with(|| {
            let sources = self.prepared.texel_sources();
            let shape = self.prepared.texel_tree();
            Gathering::over(shape, &[&self.scattering.kernel], &sources, self.epsilon)
        });
        let targets = self.prepared.listed(listed);
        Ok(gathering.at(targets.targets(), control)?)
    }

    fn release(&self) {
        let mut held = self.gathering.lock().unwrap_or_else(|e| e.into_inner());
        *held = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_finer_epsilon_is_finer_and_bounded() {
        let finer = finer_epsilon(0.5, 0.0176, 0.01).unwrap();
        assert!(finer < 0.5 * 0.01 / 0.0176 && finer > 0.15, "{finer}");
        assert_eq!(finer_epsilon(0.5, 10.0, 0.01), Some(0.5 / 16.0));
        assert_eq!(finer_epsilon(0.5, 0.005, 0.01), None);
        assert_eq!(finer_epsilon(0.0, 0.5, 0.01), None);
        assert_eq!(finer_epsilon(0.5, f64::NAN, 0.01), None);
    }

    #[test]
    fn refining_changes_epsilon_once_it_can() {
        let mut octree = OctreeIntegrator::default();
        assert!(octree.refine(0.0176, 0.01));
        assert!(octree.epsilon < 0.5);
        let mut exact = OctreeIntegrator { epsilon: 0.0 };
        assert!(!exact.refine(0.5, 0.01));
        assert_eq!(exact.epsilon, 0.0);
    }
}
