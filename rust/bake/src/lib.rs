//! sssbake: bakes subsurface scattering into textures.
//!
//! Lengths are millimetres throughout; scene units are converted once, when
//! a scene is read. UV space is [0, 1]² with v running up the image, as
//! USD's t does (readers of glTF, whose v runs down, flip it); texel (x, y)
//! covers [x/N, (x+1)/N] × [y/N, (y+1)/N], with y growing with v.
//!
//! A bake is two calls. [`plan()`] turns a [`Scene`] and a [`BakeRequest`]
//! into a [`Plan`]: each object's material and profile, its layout (kept or
//! unwrapped UVs, texels), the stages its outputs need and the integrator,
//! each with the reason. [`bake()`] (or [`bake_each`], which hands over one
//! object at a time) runs that plan and returns [`BakedObject`]s, which
//! render any requested [`Output`] as an [`image::Image`], and a
//! [`Summary`]. Writing files is `sssbake_io::bake_to_folder`'s job; this
//! crate does no I/O beyond reading material files.
//!
//! # Example
//!
//! A 20 mm square of skin lit by a sun straight above, baked at 32²:
//!
//! ```
//! use glam::{Vec2, Vec3};
//! use sssbake::control::Control;
//! use sssbake::materials::{MaterialAssignment, preset};
//! use sssbake::{BakeRequest, Light, LightKind, Mesh, Output, Scene, SceneObject};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // Two triangles in the xy plane, facing +Z, with UVs covering [0, 1]².
//! let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
//! let positions = corners.iter().map(|&[x, y]| Vec3::new(20.0 * x, 20.0 * y, 0.0)).collect();
//! let uvs = corners.iter().map(|&[u, v]| Vec2::new(u, v)).collect();
//! let (mesh, _warnings) =
//!     Mesh::new("square", positions, None, Some(uvs), vec![[0, 1, 2], [0, 2, 3]])?;
//!
//! let sun = Light {
//!     name: "sun".into(),
//!     kind: LightKind::Directional { angle: 0.0 },
//!     color: [1.0; 3],
//!     intensity: 1.0, // W/m² on a surface facing it
//!     position: Vec3::ZERO,
//!     direction: Vec3::NEG_Z, // pointing down onto the square
//!     tangent: Vec3::X,
//!     casts_shadow: true,
//! };
//! let scene = Scene {
//!     source: "built in code".into(),
//!     millimetres_per_unit: 1.0,
//!     objects: vec![SceneObject { mesh, ..SceneObject::default() }],
//!     lights: vec![sun],
//!     notes: Vec::new(),
//! };
//!
//! let request = BakeRequest {
//!     materials: MaterialAssignment::everywhere(preset("skin1")?, "example"),
//!     resolution: 32,
//!     margin: 2,
//!     outputs: vec![Output::Subsurface],
//!     ..BakeRequest::default()
//! };
//! let plan = sssbake::plan(&scene, &request)?;
//! let object = &plan.objects[0];
//! let integrator = object.integrator.as_ref().expect("a subsurface map scatters");
//! println!("{}: {} because {}", object.name, integrator.method, integrator.reason);
//!
//! let (baked, summary) = sssbake::bake(&scene, &plan, &Control::new())?;
//! println!("{summary}");
//! let map = baked[0].render(Output::Subsurface)?;
//! assert_eq!((map.width, map.height), (32, 32));
//! assert!(map.texels.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
//! assert!(map.texels.iter().flatten().any(|v| *v > 0.0));
//! # Ok(())
//! # }
//! ```

pub mod bake;
pub mod blackbody;
pub mod colour;
pub mod control;
pub mod empirical_cache;
pub mod error;
pub mod fast_hash;
pub mod fitted_map;
pub mod image;
pub mod irradiance;
pub mod layout;
pub mod limits;
pub mod maps;
pub mod materials;
pub mod mesh;
pub mod monte_carlo_cache;
pub mod pipeline;
pub mod plan;
pub mod prepared;
pub mod rays;
pub mod request;
pub mod scattering;
pub mod scene;
pub mod surface;
pub mod transport;
pub mod walk;

pub use bake::{BakedObject, Corrected, Summary, bake, bake_each};
pub use error::{Error, InputError};
pub use maps::Output;
pub use mesh::{Mesh, MeshError, MeshWarnings};
pub use plan::{Plan, plan};
pub use request::{BakeRequest, Lighting, UvPolicy};
pub use scene::{ConeFalloff, Light, LightKind, LightRow, MaterialHint, Scene, SceneObject};
pub use surface::texels::{TexelSurfels, rasterize};
pub use surface::uv_analysis::{UvReport, analyse_uvs};
pub use transport::Method;
