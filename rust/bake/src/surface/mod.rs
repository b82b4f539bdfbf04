//! The surface side of a bake: where texels lie on the mesh and how they
//! connect. UV analysis and unwrapping (xatlas), rasterisation of triangles
//! into texel surfels, the mesh's topology (parts, open edges, seams),
//! dilation across seams and margins, and Turk's relaxed sample points.

pub mod curvature;
pub mod dilation;
pub mod frame;
pub mod gathering;
pub mod lattice;
pub mod medium;
pub mod opposite;
pub mod raster;
pub mod texels;
pub mod topology;
pub mod turk;
pub mod unwrap;
pub mod uv_analysis;
