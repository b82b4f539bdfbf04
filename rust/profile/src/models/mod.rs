//! The reflectance models: each a way to the light a material returns at a
//! distance from where it entered, and Monte Carlo transport as the truth.

pub mod burley;
pub mod dipole;
pub mod empirical;
pub mod gaussians;
pub mod layered;
pub mod monte_carlo;
pub mod multipole;
pub mod stam;
pub mod tabulated;
