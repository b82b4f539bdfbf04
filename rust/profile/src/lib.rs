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
pub mod burley;
pub mod cycles;
pub mod dipole;
pub mod empirical;
pub mod empirical_fit;
pub mod empirical_kernel;
pub mod empirical_lobe;
pub mod empirical_oblique;
pub mod empirical_simulation;
pub mod fresnel;
pub mod gaussians;
pub mod hankel;
pub mod images;
pub mod inversion;
pub mod layered;
pub mod material;
pub mod medium;
pub mod model;
pub mod monte_carlo;
mod monte_carlo_faces;
pub mod monte_carlo_profile;
pub mod multipole;
pub mod presets;
pub mod profile;
pub mod quadrature;
pub mod rng;
pub mod roots;
pub mod rough;
pub mod slab;
pub mod split;
pub mod stam;
pub mod stam_topped;
pub mod surface;
pub mod tabulated;

pub use appearance::Appearance;
pub use burley::Burley;
pub use dipole::Dipole;
pub use empirical::EmpiricalProfile;
pub use gaussians::{GaussianFit, SumOfGaussians};
pub use layered::Layered;
pub use material::{Layer, Material, MaterialError, Optics};
pub use model::{Model, ModelError, build_profile};
pub use monte_carlo_profile::MonteCarloProfile;
pub use multipole::Multipole;
pub use profile::Profile;
pub use tabulated::Tabulated;

/// One value per colour channel, in the order red, green, blue.
pub type Rgb = [f64; 3];

/// Applies `f` to each channel.
pub fn rgb_map(f: impl Fn(usize) -> f64) -> Rgb {
    [f(0), f(1), f(2)]
}
