//! The C ABI of sssbake: the library behind a handful of C functions, for
//! hosts such as the Blender add-on (`include/sssbake.h` is generated from
//! this crate by cbindgen; a test keeps it current).
//!
//! Conventions: every function returns an [`SssbakeStatus`]; on failure
//! [`sssbake_last_error`] says why. Handles are opaque and freed by the
//! `_free` function of their kind; every call checks the handles it takes
//! against the live ones, so a handle freed already, never handed out, of
//! another kind, null or misaligned is refused, never read or freed twice.
//! Buffers the caller passes stay the caller's. No panic crosses the boundary. Lengths count elements, not
//! bytes. Positions and sizes are in scene units, converted with the
//! scene's millimetres per unit.

mod bake;
mod errors;
mod folder;
mod handles;
mod lights;
mod material;
mod options;
mod scene;
mod unwrap;

pub use bake::*;
pub use errors::*;
pub use folder::*;
pub use lights::*;
pub use material::*;
pub use options::*;
pub use scene::*;
pub use unwrap::*;

/// The version of this ABI: hosts refuse a library of another version.
pub const SSSBAKE_ABI_VERSION: u32 = 9;

/// The version of this ABI ([`SSSBAKE_ABI_VERSION`]).
#[unsafe(no_mangle)]
pub extern "C" fn sssbake_abi_version() -> u32 {
    SSSBAKE_ABI_VERSION
}
