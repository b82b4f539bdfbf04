//! Scenes read from glTF or USD files and baked whole into a folder, the
//! way `sssbake bake` bakes them; strings the library hands out; and the
//! library's name tables, so a host does not restate them.

use crate::bake::{
    METHODS, SssbakeProgress, SssbakeSettings, UserData, clear, host_arguments, host_options,
    watched,
};
use crate::errors::{Failure, SssbakeStatus, guarded, text};
use crate::handles::{free_string, issue_string};
use crate::material::{SssbakeMaterial, host_material};
use crate::scene::{SCENES, SssbakeScene, reading};
use sssbake::Output;
use sssbake::control::Control;
use sssbake_host::{HostScene, scene_request};
use sssbake_io::image_writer::Precision;
use sssbake_io::{FolderOptions, ReadOptions, bake_to_folder, read_scene, scene_lighting};
use std::ffi::{c_char, c_void};
use std::path::Path;

/// [`sssbake_bake_to_folder`] flag: replace files already in the folder.
pub const SSSBAKE_FOLDER_FORCE: u32 = 1;
/// [`sssbake_bake_to_folder`] flag: write EXRs as 16-bit half floats
/// instead of 32-bit.
pub const SSSBAKE_FOLDER_HALF: u32 = 2;

/// [`sssbake_names`] kind: the outputs, in the order of their numbers
/// (bit i of [`SssbakeSettings::outputs`] is output i).
pub const SSSBAKE_NAMES_OUTPUTS: u32 = 0;
/// [`sssbake_names`] kind: the methods, in the order of
/// [`SssbakeSettings::method`].
pub const SSSBAKE_NAMES_METHODS: u32 = 1;
/// [`sssbake_names`] kind: the presets a bake can use, each `{"name", "description"}`.
pub const SSSBAKE_NAMES_PRESETS: u32 = 2;

/// Reads the scene in the glTF or USD file at `path` (UTF-8), taking its
/// UVs from texture-coordinate set `uv_set` and its units from
/// `unit_scale_mm` millimetres per unit (0: the file's own units). The
/// scene keeps the path: [`sssbake_bake_to_folder`] writes the file's
/// glTF copy or USD layer. On success `*out` holds the scene, freed by
/// [`sssbake_scene_free`](crate::sssbake_scene_free); errors name the file.
///
/// # Safety
/// `path` is NUL-terminated; `out` points to writable storage for a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_scene_read(
    path: *const c_char,
    uv_set: u32,
    unit_scale_mm: f64,
    out: *mut *mut SssbakeScene,
) -> SssbakeStatus {
    guarded(|| {
        if out.is_null() {
            return Err(Failure::argument("out is null"));
        }
        // SAFETY: checked non-null; the caller gives writable storage.
        unsafe { *out = std::ptr::null_mut() };
        // SAFETY: forwarded from the caller.
        let path = Path::new(unsafe { text(path, "path") }?);
        let unit_scale = match unit_scale_mm {
            0.0 => None,
            s if s.is_finite() && s > 0.0 => Some(s),
            s => {
                return Err(Failure::argument(format!(
                    "{}: unit scale {s} mm must be positive, or 0 for the file's own units",
                    path.display()
                )));
            }
        };
        let options = ReadOptions {
            uv_set: uv_set as usize,
            unit_scale,
        };
        let scene = read_scene(path, &options).map_err(sssbake::Error::from)?;
        let scene = SssbakeScene {
            host: HostScene::from_file(scene, path.to_path_buf(), options.uv_set),
        };
        let handle = SCENES.issue(std::sync::RwLock::new(scene))?;
        // SAFETY: checked non-null; the caller gives writable storage.
        unsafe { *out = handle };
        Ok(())
    })
}

/// Bakes every object of `scene` (read by [`sssbake_scene_read`]; a host's
/// scene is refused) into the folder `out_dir` (UTF-8; made if missing,
/// never the file's own), as `sssbake bake` does: each planned map as a
/// linear OpenEXR file (and an sRGB PNG preview of each colour map), and
/// the file's glTF copy or USD layer, all renamed into place together or
/// none. Objects whose UVs are missing or unusable are unwrapped.
///
/// `flags` is a sum of `SSSBAKE_FOLDER_*`. `material`, `settings`,
/// `progress`, `user` and `cancel` are as for
/// [`sssbake_bake`](crate::sssbake_bake). On success `*summary_out` holds
/// the summary as JSON (docs/outputs.md, "The summary"), freed by
/// [`sssbake_string_free`].
///
/// # Safety
/// `material` and `settings` point to valid values; `out_dir` is
/// NUL-terminated; `cancel` is null or stays readable (and is only written
/// atomically) until the call returns; `summary_out` is writable. A
/// `scene` that is not a live scene is refused.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)] // one per part of the request, as C passes them
pub unsafe extern "C" fn sssbake_bake_to_folder(
    scene: *const SssbakeScene,
    material: *const SssbakeMaterial,
    settings: *const SssbakeSettings,
    out_dir: *const c_char,
    flags: u32,
    progress: SssbakeProgress,
    user: *mut c_void,
    cancel: *const i32,
    summary_out: *mut *mut c_char,
) -> SssbakeStatus {
    guarded(|| {
        // SAFETY: forwarded from the caller.
        unsafe { clear(summary_out, "summary_out") }?;
        let scene = SCENES.get(scene, "scene")?;
        let scene = reading(&scene);
        // SAFETY: forwarded from the caller.
        let (settings, cancel) = unsafe { host_arguments(settings, cancel) }?;
        // SAFETY: the caller passes a valid material or null.
        let material =
            unsafe { material.as_ref() }.ok_or_else(|| Failure::argument("material is null"))?;
        let Some(file) = &scene.file else {
            return Err(Failure::argument(
                "a host's scene has no file to bake beside: bake it with sssbake_bake, \
                 or read the scene with sssbake_scene_read",
            ));
        };
        if flags & !(SSSBAKE_FOLDER_FORCE | SSSBAKE_FOLDER_HALF) != 0 {
            return Err(Failure::argument(format!(
                "flags {flags:#x} has bits that are not SSSBAKE_FOLDER_*"
            )));
        }
        // SAFETY: forwarded from the caller.
        let out_dir = unsafe { text(out_dir, "out_dir") }?;
        let mut request = scene_request(&host_options(settings)?, &scene)?;
        let scene_file = &file.path;
        let scene = &scene.scene;
        request.lighting = scene_lighting(scene, scene_file, None, None)?;
        // SAFETY: forwarded from the caller.
        request.materials =
            unsafe { host_material(material) }?.assignment(scene.millimetres_per_unit)?;
        let options = FolderOptions {
            out: out_dir.into(),
            force: flags & SSSBAKE_FOLDER_FORCE != 0,
            precision: if flags & SSSBAKE_FOLDER_HALF != 0 {
                Precision::Half
            } else {
                Precision::Float
            },
            uv_set: file.uv_set,
            layer_writer: None,
            ..FolderOptions::default()
        };
        let control = Control::new();
        let user = UserData(user);
        let summary = watched(&control, progress, &user, cancel, (0, 1), || {
            let plan = sssbake::plan(scene, &request)?;
            bake_to_folder(scene_file, scene, &plan, &options, &control)
        })?;
        let json = serde_json::to_string(&summary).unwrap_or_default();
        // SAFETY: checked non-null; the caller gives writable storage.
        unsafe { *summary_out = issue_string(json) };
        Ok(())
    })
}

/// Frees a string [`sssbake_bake_to_folder`] or [`sssbake_names`] handed
/// out (null is allowed and frees nothing). A string freed already, or one
/// the library did not hand out to be freed (such as a result's summary),
/// is refused with [`SssbakeStatus::InvalidArgument`] and frees nothing.
#[unsafe(no_mangle)]
pub extern "C" fn sssbake_string_free(string: *mut c_char) -> SssbakeStatus {
    guarded(|| free_string(string))
}

/// The library's names of one `kind` (`SSSBAKE_NAMES_*`) as a JSON array:
/// the outputs' and methods' names in the order of their numbers, or the
/// presets as `{"name", "description"}` objects. On success `*out` holds
/// the text, freed by [`sssbake_string_free`].
///
/// # Safety
/// `out` points to writable storage for a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_names(kind: u32, out: *mut *mut c_char) -> SssbakeStatus {
    guarded(|| {
        if out.is_null() {
            return Err(Failure::argument("out is null"));
        }
        let names = match kind {
            SSSBAKE_NAMES_OUTPUTS => serde_json::json!(Output::ALL.map(Output::name)),
            SSSBAKE_NAMES_METHODS => serde_json::json!(METHODS.iter().map(|m| m.name()).collect::<Vec<_>>()),
            SSSBAKE_NAMES_PRESETS => sssbake_profile::presets::list()
                .into_iter()
                .filter(|(name, _)| !sssbake_profile::presets::ANGULAR_ONLY.contains(name))
                .map(|(name, description)| {
                    serde_json::json!({ "name": name, "description": description })
                })
                .collect(),
            other => {
                // SAFETY: checked non-null; the caller gives writable storage.
                unsafe { *out = std::ptr::null_mut() };
                return Err(Failure::argument(format!(
                    "names kind {other} is not one of SSSBAKE_NAMES_*"
                )));
            }
        };
        // SAFETY: checked non-null; the caller gives writable storage.
        unsafe { *out = issue_string(names.to_string()) };
        Ok(())
    })
}
