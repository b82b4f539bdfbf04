//! A material's profile and the kernel the integrators read it through,
//! built once and together, so every stage sees the same reach.

use crate::empirical_cache::{empirical_oblique_kernel, empirical_profile};
use crate::error::Error;
use crate::monte_carlo_cache::{cache_dir, monte_carlo_profile};
use crate::transport::kernel::Kernel;
use crate::transport::local_slab::LocalSlab;
use crate::transport::slab_ladder::SlabProfiles;
use sssbake_profile::Material;
use sssbake_profile::boundary::surface::Surface;
use sssbake_profile::model::{Model, ModelError, build_profile};
use sssbake_profile::models::empirical::EmpiricalSettings;
use sssbake_profile::models::empirical::kernel::ObliqueKernel;
use sssbake_profile::models::monte_carlo::profile::ProfileSettings;
use sssbake_profile::profile::Profile;
use std::sync::OnceLock;

/// Share of the reflectance left outside d_max when none is asked for.
pub const D_MAX_EPSILON: f64 = 1e-3;

/// A material's diffusion profile, ready to integrate.
pub struct Scattering {
    /// The material.
    pub material: Material,
    /// The model that describes it.
    pub model: Model,
    /// Its profile.
    pub profile: Box<dyn Profile>,
    /// The profile tabulated for the integrators, cut at d_max.
    pub kernel: Kernel,
    /// Where light crosses the surface, in and out: the boundary of the
    /// material's index and roughness, or its Stam top layer under the
    /// `stam` model.
    pub surface: Surface,
    /// The exitance kernel at oblique incidence, for models that have one
    /// (`empirical`): the exact sum and importance integrate each light's
    /// incidence with it; the other integrators, and every model without
    /// one, use the radially symmetric `profile`.
    pub oblique: Option<ObliqueKernel>,
    /// How a slab of each thickness shares out the light, simulated on
    /// first use (only a bake with thin parts needs it).
    local_slab: OnceLock<Option<LocalSlab>>,
    /// The profiles of thin slabs of the material, each simulated when a
    /// part of its thickness is first met.
    slab_profiles: OnceLock<Option<SlabProfiles>>,
}

impl std::fmt::Debug for Scattering {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Scattering")
            .field("material", &self.material.name)
            .field("model", &self.model)
            .field("d_max", &self.kernel.d_max)
            .finish()
    }
}

impl Scattering {
    /// Builds `model` (the material's own when `None`) for `material`,
    /// fitting `gaussians` terms where the model is a sum of Gaussians, and
    /// its kernel keeping all but `d_max_epsilon` of the reflectance.
    pub fn new(
        material: Material,
        model: Option<Model>,
        gaussians: usize,
        d_max_epsilon: f64,
    ) -> Result<Self, Error> {
        let model = model.unwrap_or_else(|| Model::default_for(&material));
        let mut oblique = None;
        let profile = if model == Model::MonteCarlo {
            // Simulated once per material and kept on disk.
            let cached = monte_carlo_profile(
                &material,
                &ProfileSettings::default(),
                cache_dir().as_deref(),
            );
            match cached {
                Some(profile) => Box::new(profile) as Box<dyn Profile>,
                // A material without layers: the library says why.
                None => build_profile(&material, model, gaussians)?,
            }
        } else if model == Model::Empirical {
            // Fitted once per channel's optics and kept on disk.
            let fitted = empirical_profile(
                &material,
                &EmpiricalSettings::default(),
                cache_dir().as_deref(),
            );
            match fitted {
                Ok(profile) => {
                    // A profile without its oblique kernel would bake every
                    // light as if at normal incidence: say why instead.
                    let kernel = empirical_oblique_kernel(
                        &material,
                        &profile,
                        &EmpiricalSettings::default(),
                        cache_dir().as_deref(),
                    )
                    .map_err(|reason| ModelError {
                        material: material.name.clone(),
                        model,
                        reason: format!("its kernel at oblique incidence: {reason}"),
                    })?;
                    oblique = Some(kernel);
                    Box::new(profile) as Box<dyn Profile>
                }
                // The model does not apply: the library says why.
                Err(_) => build_profile(&material, model, gaussians)?,
            }
        } else {
            build_profile(&material, model, gaussians)?
        };
        let surface = Surface::of(&material, model).map_err(|reason| ModelError {
            material: material.name.clone(),
            model,
            reason,
        })?;
        Ok(Scattering {
            surface,
            oblique,
            ..Scattering::from_profile(material, model, profile, d_max_epsilon)
        })
    }

    /// A profile built elsewhere (a measured or test profile), with its
    /// kernel, under the material's face ([`Surface::face`]: such a profile
    /// carries no Stam top layer).
    pub fn from_profile(
        material: Material,
        model: Model,
        profile: Box<dyn Profile>,
        d_max_epsilon: f64,
    ) -> Self {
        let kernel = Kernel::new(profile.as_ref(), d_max_epsilon);
        let surface = Surface::face(&material);
        Scattering {
            material,
            model,
            profile,
            kernel,
            surface,
            oblique: None,
            local_slab: OnceLock::new(),
            slab_profiles: OnceLock::new(),
        }
    }

    /// The slab shares of the material by thickness, for the bake's thin
    /// parts; `None` where a slab of it is not defined (see
    /// [`LocalSlab::of`]). Simulated once, on first use.
    pub fn local_slab(&self) -> Option<&LocalSlab> {
        self.local_slab.get_or_init(|| LocalSlab::of(self)).as_ref()
    }

    /// The profiles of slabs of the material by thickness, for the bake's
    /// thin parts; `None` where a slab of it is not defined (see
    /// [`SlabProfiles::new`]).
    pub fn slab_profiles(&self) -> Option<&SlabProfiles> {
        self.slab_profiles
            .get_or_init(|| {
                let layer = LocalSlab::layer_of(self)?;
                let reach = f64::from(self.kernel.d_max);
                let scale = [0, 1, 2]
                    .map(|c| self.kernel.sample_radius(c, 0.5))
                    .into_iter()
                    .fold(0.0, f32::max);
                SlabProfiles::new(&self.material, layer, reach, D_MAX_EPSILON, scale)
            })
            .as_ref()
    }

    /// Per channel, the share of the light entering a plane of the
    /// material that leaves it as diffuse light through the exit at the
    /// normal: the profile's total at light's level (levelled as the bake
    /// levels it) times [`Surface::exit_at_normal`], in [0, 1].
    pub fn diffuse_albedo(&self) -> [f64; 3] {
        let total = self.profile.total_reflectance();
        let level = self.local_slab().map(|s| s.level()).unwrap_or([1.0; 3]);
        let exit = self.surface.exit_at_normal();
        std::array::from_fn(|c| (total[c] * level[c] * exit[c]).clamp(0.0, 1.0))
    }

    /// The material's index of refraction where light enters (inside over
    /// outside).
    pub fn entry_index(&self) -> f64 {
        self.material.entry_index()
    }
}
