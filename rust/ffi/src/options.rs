//! Bake options by name: every setting of the library
//! (`sssbake_io::settings`, the table docs/pipelines.md shows), set as the
//! text the command line takes. A setting the library adds later is set the
//! same way, so no struct a host compiled against changes, as with Embree's
//! device properties. [`sssbake_bake_options`] bakes with them.

use crate::bake::{SssbakeProgress, SssbakeResult, UserData, bake_host};
use crate::errors::{Failure, SssbakeStatus, guarded, text};
use crate::handles::{self, Handles};
use crate::material::SssbakeMaterial;
use crate::scene::SssbakeScene;
use serde_json::Value;
use sssbake_host::object_request;
use sssbake_io::BakeOptions;
use sssbake_io::settings::setting;
use std::ffi::{c_char, c_void};
use std::sync::atomic::AtomicI32;
use std::sync::{Mutex, PoisonError};

/// Bake options (opaque): every setting left out is the library's default.
pub struct SssbakeOptions {
    options: Mutex<BakeOptions>,
}

/// The live options.
static OPTIONS: Handles<SssbakeOptions> = Handles::new(handles::OPTIONS);

/// New options, every setting the library's default. On success `*out`
/// holds them; free them with [`sssbake_options_free`].
///
/// # Safety
/// `out` is writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_options_new(out: *mut *mut SssbakeOptions) -> SssbakeStatus {
    guarded(|| {
        if out.is_null() {
            return Err(Failure::argument("out is null"));
        }
        let handle = OPTIONS.issue(SssbakeOptions {
            options: Mutex::new(BakeOptions::default()),
        })?;
        // SAFETY: checked non-null; the caller gives writable storage.
        unsafe { *out = handle };
        Ok(())
    })
}

/// Sets the setting named `key` (as in a batch manifest: `resolution`,
/// `method`, `octree_epsilon`, …) to `value`, written as on the command
/// line (`1024`, `octree`, `0.35`, `subsurface,diffuse`, `16G`, `true`). An
/// unknown key, or a value the setting does not take, is refused naming
/// the key and its range, and the options stay as they were. A host's own
/// scene decides its units, UV set, materials and objects: those keys are
/// refused when the options bake.
///
/// # Safety
/// `key` and `value` are NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_options_set(
    options: *mut SssbakeOptions,
    key: *const c_char,
    value: *const c_char,
) -> SssbakeStatus {
    guarded(|| {
        let options = OPTIONS.get(options, "options")?;
        // SAFETY: forwarded from the caller.
        let key = unsafe { text(key, "key") }?;
        // SAFETY: forwarded from the caller.
        let value = unsafe { text(value, "value") }?;
        let setting = setting(key)
            .ok_or_else(|| Failure::argument(format!("no setting is called `{key}`")))?;
        let parsed = setting
            .parse(value)
            .map_err(|message| sssbake::Error::field(key, message))?;
        let mut current = options
            .options
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        let Value::Object(mut table) = serde_json::to_value(&*current).unwrap_or_default() else {
            unreachable!("options serialize as a table")
        };
        table.insert(key.to_string(), parsed);
        *current = serde_json::from_value(Value::Object(table))
            .map_err(|e| sssbake::Error::field(key, e.to_string()))?;
        Ok(())
    })
}

/// Frees options (null is allowed and frees nothing); a bake running with
/// them keeps them until it returns.
#[unsafe(no_mangle)]
pub extern "C" fn sssbake_options_free(options: *mut SssbakeOptions) -> SssbakeStatus {
    guarded(|| OPTIONS.free(options, "options"))
}

/// Bakes `object` of `scene` as [`sssbake_bake_materials`](crate::sssbake_bake_materials)
/// does, with `options` in place of settings: the object's own UVs kept as
/// they are unless `uvs` says otherwise.
///
/// # Safety
/// As [`sssbake_bake_materials`](crate::sssbake_bake_materials).
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn sssbake_bake_options(
    scene: *const SssbakeScene,
    object: *const c_char,
    materials: *const SssbakeMaterial,
    material_count: usize,
    options: *const SssbakeOptions,
    progress: SssbakeProgress,
    user: *mut c_void,
    cancel: *const i32,
    out: *mut *mut SssbakeResult,
) -> SssbakeStatus {
    guarded(|| {
        let options = OPTIONS.get(options, "options")?;
        let options = options
            .options
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone();
        // SAFETY: the caller promises an i32 it writes atomically.
        let cancel = unsafe { cancel.cast::<AtomicI32>().as_ref() };
        let request = |host: &_| Ok(object_request(options, host)?);
        let watch = (progress, UserData(user), cancel);
        // SAFETY: forwarded from the caller.
        unsafe {
            bake_host(
                scene,
                object,
                materials,
                material_count,
                request,
                watch,
                out,
            )
        }
    })
}
