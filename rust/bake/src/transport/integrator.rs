//! The one interface every integrator implements, and the registry of
//! them. Each integrator is a folder of `transport/` whose `mod.rs` is its
//! face: its settings with their defaults and checks (a table at the top),
//! what it carries of the model, its cost model and how it refines; the
//! plan, `auto`, the limits and the corrected model read those here
//! instead of knowing every method. A new integrator is its folder, a
//! variant of [`Method`] and a field of [`IntegratorSettings`].

use super::Method;
use super::brute::BruteIntegrator;
use super::importance::ImportanceIntegrator;
use super::octree::OctreeIntegrator;
use super::texture_space::TextureIntegrator;
use super::walk::{WalkIntegrator, WalkNoise};
use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::scattering::Scattering;
use serde::{Deserialize, Serialize};
use sssbake_profile::Material;

/// An integrator's result before the colour after scattering.
#[derive(Clone, Debug)]
pub struct Integrated {
    /// Radiant exitance per surfel, W/m².
    pub exitance: Vec<[f32; 3]>,
    /// Sources the 3-D methods gathered from (texels or Turk points).
    pub sources: usize,
    /// The walk's noise and dropped weight (the walk alone).
    pub walk: Option<WalkNoise>,
}

/// What an integrator carries of the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Carries {
    /// It integrates the material's profile, so it bakes the corrected
    /// model (light shared through thin parts by the local slab, sums
    /// raised where the surface ends) and its error against the exact sum
    /// is an integrator's error. `false` for the walk, which follows light
    /// itself.
    pub profile: bool,
    /// Its sums reach across thin parts to the far face in 3-D (texture
    /// space blurs within the charts and carries none across).
    pub across: bool,
    /// It integrates an oblique kernel at each light's own incidence (the
    /// others take the kernel's azimuthal mean at normal incidence).
    pub oblique: bool,
}

/// The size of one object's scattering, for an integrator's cost model.
#[derive(Clone, Copy, Debug)]
pub struct Work<'a> {
    /// Texels (surfels) of the object.
    pub texels: f64,
    /// Texels within the profile's reach of a texel, on average.
    pub neighbours: f64,
    /// The object's material.
    pub material: &'a Material,
}

impl Work<'_> {
    /// The order of a hierarchical or separable method, n log₂ n, never
    /// more than the exact sum's pairs.
    pub fn n_log_n(&self) -> f64 {
        let n = self.texels;
        (n * n.max(2.0).log2()).min(n * self.neighbours)
    }
}

/// An integrator's sums at chosen texels of one prepared object
/// ([`Integrator::summer`]).
pub trait Summer: Sync {
    /// Radiant exitance (W/m²) at the texels `listed`, in order, before
    /// any correction.
    fn at(&self, listed: &[usize], control: &Control) -> Result<Vec<[f32; 3]>, Error>;

    /// Sums at `listed` nearer the exact sum than [`Summer::at`]'s (an
    /// octree at a smaller ε), against which a map carried from a lattice
    /// is checked where the summer's own sums jitter from texel to texel;
    /// `None` where `at`'s serve.
    fn finer(&self, _listed: &[usize], _control: &Control) -> Option<Result<Vec<[f32; 3]>, Error>> {
        None
    }

    /// Lets go of what it holds between sums (an integrator's tree), for a
    /// caller done summing; a later sum builds it again.
    fn release(&self) {}
}

/// M(x) = ∫ P(|x − x_i|) E_t(x_i) dA at every texel of a prepared object.
/// Its `Debug` form names it with its settings (what a result found by it
/// is kept under).
pub trait Integrator: Send + Sync + std::fmt::Debug {
    /// Which method this is.
    fn method(&self) -> Method;

    /// What it carries of the model.
    fn carries(&self) -> Carries;

    /// Kernel evaluations, probes or ray casts it takes for `work`: the
    /// plan's bound on a bake, checked before any work.
    fn evaluations(&self, work: &Work) -> f64;

    /// Bytes it holds beyond the bake's own per texel, for maps of
    /// `resolution`² texels when the light is split by incidence (`split`).
    fn extra_memory_bytes(&self, _resolution: u32, _split: bool) -> f64 {
        0.0
    }

    /// Why it cannot bake `material`, before any work (the walk needs one
    /// homogeneous medium).
    fn accepts(&self, _material: &Material) -> Result<(), String> {
        Ok(())
    }

    /// The octree's solid angle (sr) at which it gathers thin parts by
    /// their own slab's profile ([`super::slab_profiles`]), a kernel per
    /// target that only the octree's walk carries: the octree's default,
    /// its own ε for the octree, 0 (every pair apart) for the exact sum.
    fn thin_epsilon(&self) -> f32 {
        OctreeIntegrator::default().epsilon
    }

    /// Its settings made more exact, after it missed `tolerance` with
    /// relative error `error`: `true` when they changed (the octree's ε),
    /// so `auto` runs it once more before a more exact method.
    fn refine(&mut self, _error: f64, _tolerance: f64) -> bool {
        false
    }

    /// The method `auto` moves to when this one misses its tolerance and
    /// cannot refine; `None` at the top of the ladder.
    fn more_exact(&self) -> Option<Method> {
        None
    }

    /// What finds its sums at chosen texels alone, built once over
    /// `prepared`'s light (the octree's tree, at the first texels asked
    /// for, so making a summer costs nothing), where it can find them
    /// without the whole map: exactly the sums [`Integrator::integrate`]
    /// gives those texels with the same settings, not a cheaper stand-in.
    /// `auto` predicts its error from them before running it (a pilot),
    /// the corrected model finds the sums under a unit light from them at a
    /// subset of the texels, and the map is fitted between a lattice of
    /// them ([`crate::pipeline`]). `None` for a method that integrates the
    /// whole map at once (texture-space blurs), and for the exact sum,
    /// which has no error to predict and stays the exact sum at every
    /// texel.
    fn summer<'a>(
        &'a self,
        _prepared: &'a Prepared,
        _scattering: &'a Scattering,
    ) -> Option<Box<dyn Summer + 'a>> {
        None
    }

    /// Itself across its settings from cheap to exact, each named as the
    /// error-against-time report shows it; empty where there is no setting
    /// that trades time for error (the exact sum).
    fn ladder(&self) -> Vec<(String, Box<dyn Integrator>)> {
        Vec::new()
    }

    /// The exitance of `prepared` under `scattering`'s profile (the
    /// irradiance entering after the colour split's first part).
    fn integrate(
        &self,
        prepared: &Prepared,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Integrated, Error>;
}

/// The settings of every integrator; a bake uses the one it runs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct IntegratorSettings {
    /// The exact sum (no settings).
    #[serde(skip)]
    pub brute: BruteIntegrator,
    /// The Jensen–Buhler hierarchy.
    pub octree: OctreeIntegrator,
    /// Texture-space Gaussian blurs.
    pub texture: TextureIntegrator,
    /// Monte Carlo with probe rays.
    pub importance: ImportanceIntegrator,
    /// The volumetric random walk.
    pub walk: WalkIntegrator,
}

impl IntegratorSettings {
    /// The integrator of `method` (`auto` is the exact sum until chosen).
    pub fn get(&self, method: Method) -> &dyn Integrator {
        match method {
            Method::Auto | Method::Brute => &self.brute,
            Method::Octree => &self.octree,
            Method::Texture => &self.texture,
            Method::Importance => &self.importance,
            Method::Walk => &self.walk,
        }
    }

    /// The integrator of `method`, to refine.
    pub fn get_mut(&mut self, method: Method) -> &mut dyn Integrator {
        match method {
            Method::Auto | Method::Brute => &mut self.brute,
            Method::Octree => &mut self.octree,
            Method::Texture => &mut self.texture,
            Method::Importance => &mut self.importance,
            Method::Walk => &mut self.walk,
        }
    }

    /// The octree's solid-angle threshold (sr) when `method` is the
    /// octree, as summaries report it.
    pub fn octree_epsilon(&self, method: Method) -> Option<f32> {
        (method == Method::Octree).then_some(self.octree.epsilon)
    }

    /// Sets the seed of every integrator that draws random numbers.
    pub fn seed(&mut self, seed: u64) {
        self.importance.seed = seed;
        self.walk.seed = seed;
    }

    /// Refuses settings no integrator can run with, naming the field.
    pub fn validate(&self) -> Result<(), Error> {
        self.octree.validate()?;
        self.texture.validate()?;
        self.importance.validate()?;
        self.walk.validate()
    }
}

impl Method {
    /// What this method's integrator carries of the model (`auto`: the
    /// exact sum's, until it is chosen).
    pub fn carries(self) -> Carries {
        IntegratorSettings::default().get(self).carries()
    }
}
