//! The truth for the model: light transport inside an object's closed
//! mesh by a volumetric random walk, as Cycles' Random Walk computes it.
//!
//! The profile bake assumes a semi-infinite planar medium and measures the
//! distance between surface points in 3-D; the walk assumes neither. Light
//! enters where the bake's irradiance says, travels through one homogeneous
//! medium (σa, σs, g per channel, 1/mm, from the material's layer) bounded
//! by the object's own triangles, and leaves wherever it meets the surface:
//! through thin parts to the far side, never across air to another piece.
//!
//! - [`medium`]: the coefficients and the boundary (index-matched or a
//!   smooth dielectric), from a material.
//! - [`enclosure`]: the mesh and its BVH, closest hits against it alone.
//! - [`phase`]: Henyey–Greenstein turns and cosine-distributed directions.
//! - [`path`]: one walk, inside whatever [`path::Confinement`] bounds it.
//! - [`shapes`]: a ball and a half-space, exactly.
//! - [`estimator`]: the exitance at texels by walks started there.

pub mod enclosure;
pub mod estimator;
pub mod medium;
pub mod path;
pub mod phase;
pub mod shapes;

pub use enclosure::Enclosure;
pub use estimator::{
    ExitLight, StartDirection, WalkEstimate, WalkSettings, WalkTargets, walk_exitance,
};
pub use medium::{Boundary, ChannelMedium, WalkMedium};
