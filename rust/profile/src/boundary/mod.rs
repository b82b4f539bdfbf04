//! Where light crosses a material's surface: Fresnel, rough boundaries, and the
//! share entering and leaving per angle.

pub mod fresnel;
pub mod rough;
pub mod surface;
