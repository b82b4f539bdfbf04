//! Scenes a host application builds from its own arrays — meshes as flat
//! arrays, lights in Blender's terms, Principled BSDF materials with their
//! images, faces in material slots — and the bake of one object of such a
//! scene with a material per face. The C ABI (`sssbake-ffi`) and the Python
//! package (`sssbake-python`) are thin doors over this crate: they turn
//! pointers or numpy arrays into the slices here, and its errors into their
//! statuses or exceptions.
//!
//! Lengths are in scene units, converted once, with the scene's millimetres
//! per unit, as a host's arrays enter.

pub mod lights;
pub mod material;
pub mod mesh;
pub mod options;
pub mod scene;
pub mod slots;
pub mod unwrap;

pub use lights::{HostLight, LightShape};
pub use material::{HostImage, HostMaterial, HostMaterialKind, HostPrincipled};
pub use mesh::HostMesh;
pub use options::{HOST_SCENE, host_options, object_request, scene_request};
pub use scene::{HostScene, SceneFile};
pub use slots::{Composite, PartRunner, bake_materials};
pub use unwrap::unwrap_corners;
