//! Diffusion theory's parts: one medium's coefficients, a slab's response per
//! spatial frequency, the image series in real space, and responses kept as
//! unscattered and diffuse parts.

pub mod images;
pub mod medium;
pub mod slab;
pub mod split;
