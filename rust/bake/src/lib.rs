//! sssbake: bakes subsurface scattering into textures.
//!
//! Lengths are millimetres throughout; scene units are converted once, when
//! a scene is read. UV space is [0, 1]² with v running up the image, as
//! USD's t does (readers of glTF, whose v runs down, flip it); texel (x, y)
//! covers [x/N, (x+1)/N] × [y/N, (y+1)/N], with y growing with v.

pub mod bake;
pub mod control;
pub mod error;
pub mod fast_hash;
pub mod image;
pub mod irradiance;
pub mod maps;
pub mod materials;
pub mod mesh;
pub mod pipeline;
pub mod plan;
pub mod rays;
pub mod request;
pub mod scattering;
pub mod scene;
pub mod surface;
pub mod transport;

pub use bake::{BakedObject, Summary, bake, bake_each};
pub use error::{Error, InputError};
pub use maps::Output;
pub use mesh::{Mesh, MeshError, MeshWarnings};
pub use pipeline::Lighting;
pub use plan::{Plan, plan};
pub use request::{BakeRequest, UvPolicy};
pub use scene::{Light, LightKind, MaterialHint, Scene, SceneObject};
pub use surface::texels::{TexelSurfels, rasterize};
pub use surface::uv_analysis::{UvReport, analyse_uvs};
pub use transport::Method;
