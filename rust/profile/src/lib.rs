//! Optics of subsurface scattering, per RGB channel.
//!
//! Every length is in millimetres, every coefficient in 1/mm, and every
//! reflectance or transmittance profile `R(r)`, `T(r)` in 1/mm² (flux leaving
//! per unit area, per unit flux entering at the origin). The crate knows
//! nothing of meshes or files other than material descriptions.
//!
//! Models:
//! - [`Dipole`]: a semi-infinite medium (Mikkelsen eq. 30).
//! - [`Multipole`]: one slab with its own boundaries above and below.
//! - [`Layered`]: any stack of slabs over an optional semi-infinite base,
//!   combined per spatial frequency and tabulated.
//! - [`SumOfGaussians`]: a fit of any profile, or d'Eon's measured skin.
//! - [`Burley`]: Christensen–Burley normalized diffusion, as Blender's Cycles uses it.
//! - [`monte_carlo`]: photon transport through the stack, the ground truth.
//! - [`EmpiricalProfile`]: Donner et al. 2009's elliptic lobes fitted to
//!   photon tracing of the top layer, at normal incidence.
//!
//! # Example
//!
//! A preset's profile, built by the model the material calls for:
//!
//! ```
//! use sssbake_profile::{Model, Profile, build_profile, presets};
//!
//! let skin = presets::named("skin1").expect("skin1 is a preset");
//! let model = Model::default_for(&skin); // one semi-infinite layer: the dipole
//! let profile = build_profile(&skin, model, 6).expect("the dipole describes skin1");
//! let total = profile.total_reflectance(); // ∫ 2πr R(r) dr per channel
//! println!("{model}: total diffuse reflectance {total:?}, R(1 mm) = {:?} /mm²",
//!     profile.reflectance(1.0));
//! assert!(total.iter().all(|&t| t > 0.0 && t < 1.0));
//! ```

pub mod appearance;
pub mod boundary;
pub mod diffusion;
pub mod material;
pub mod model;
pub mod models;
pub mod numerics;
pub mod presets;
pub mod profile;

pub use appearance::Appearance;
pub use material::{Layer, Material, MaterialError, Optics};
pub use model::{Model, ModelError, build_profile};
pub use models::burley::Burley;
pub use models::dipole::Dipole;
pub use models::empirical::EmpiricalProfile;
pub use models::gaussians::{GaussianFit, SumOfGaussians};
pub use models::layered::Layered;
pub use models::monte_carlo::profile::MonteCarloProfile;
pub use models::multipole::Multipole;
pub use models::tabulated::Tabulated;
pub use profile::Profile;

/// One value per colour channel, in the order red, green, blue.
pub type Rgb = [f64; 3];

/// Applies `f` to each channel.
pub fn rgb_map(f: impl Fn(usize) -> f64) -> Rgb {
    [f(0), f(1), f(2)]
}
