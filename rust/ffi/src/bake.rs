//! One object's bake: settings, the call with its progress callback and
//! cancel flag, and the result whose maps the host copies out. The library
//! plans and bakes; this file only converts.

use crate::errors::{Failure, SssbakeStatus, guarded, slice, text};
use crate::handles::{self, Handles};
use crate::material::{SssbakeMaterial, host_material};
use crate::scene::{SCENES, SssbakeScene, reading};
use sssbake::control::{Control, watch_while};
use sssbake::limits::size_text;
use sssbake::{BakeRequest, Method, Output};
use sssbake_host::{Composite, HostScene, PartRunner, bake_materials, object_request};
use sssbake_io::BakeOptions;
use sssbake_io::atomic_write::write_atomically;
use sssbake_io::image_writer::{Precision, exr_bytes};
use std::ffi::{CString, c_char, c_void};
use std::sync::Arc;
use std::sync::atomic::{AtomicI32, Ordering};
use std::time::Duration;

/// How a bake runs. [`sssbake_settings_default`] fills the library's
/// defaults.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct SssbakeSettings {
    /// Texels per side, 1 to 16384.
    pub resolution: u32,
    /// 0 auto, 1 brute, 2 octree, 3 texture, 4 importance, 5 walk.
    pub method: u32,
    /// Texels filled beyond each chart's edge.
    pub margin: u32,
    /// Samples per soft light and for the world, per texel.
    pub light_samples: u32,
    /// Seed of the importance integrator's Monte Carlo.
    pub seed: u64,
    /// Octree: the solid angle below which a node is taken whole.
    pub octree_epsilon: f32,
    /// Texture: Gaussians in the fit.
    pub gaussians: u32,
    /// Importance: probes per texel.
    pub samples: u32,
    /// The maps to make: bit i for output i (0 subsurface, 1 irradiance,
    /// 2 diffuse, 3 thickness, 4 stretch, 5 area). The bake runs only the
    /// stages they need.
    pub outputs: u32,
    /// Relative RMSE against the exact sum that method 0 (auto) holds each
    /// object to, moving to a more exact method above it (0.01 is 1%).
    pub tolerance: f32,
    /// Peak memory the bake may hold, bytes; the plan refuses a bake
    /// estimated to need more, before any work. 0: the library's default.
    pub max_memory_bytes: u64,
    /// Shadow rays, kernel evaluations and probes the bake may take; the
    /// plan refuses more, before any work. 0: the library's default;
    /// infinity lifts the limit.
    pub max_evaluations: f64,
    /// Walk: walks per texel and channel (method 5).
    pub walk_samples: u32,
}

/// The method of number `code` (the numbers of
/// [`SssbakeSettings::method`]): the order the library declares them in.
pub(crate) const METHODS: &[Method] = Method::EVERY;

/// The library's defaults for a host bake.
///
/// # Safety
/// `out` points to writable storage for settings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_settings_default(out: *mut SssbakeSettings) -> SssbakeStatus {
    guarded(|| {
        let request = BakeRequest::default();
        let integrators = &request.integrators;
        let settings = SssbakeSettings {
            resolution: request.resolution,
            method: METHODS
                .iter()
                .position(|&m| m == request.method)
                .unwrap_or(0) as u32,
            margin: request.margin,
            light_samples: request.light_samples,
            seed: integrators.importance.seed,
            octree_epsilon: integrators.octree.epsilon,
            gaussians: integrators.texture.gaussians as u32,
            samples: integrators.importance.samples,
            outputs: output_mask(&request.outputs),
            tolerance: request.tolerance as f32,
            max_memory_bytes: request.limits.max_memory_bytes,
            max_evaluations: request.limits.max_evaluations,
            walk_samples: integrators.walk.samples,
        };
        // SAFETY: the caller gives writable storage or null.
        let out = unsafe { out.as_mut() }.ok_or_else(|| Failure::argument("out is null"))?;
        *out = settings;
        Ok(())
    })
}

fn output_mask(outputs: &[Output]) -> u32 {
    Output::ALL
        .iter()
        .enumerate()
        .filter(|(_, o)| outputs.contains(o))
        .map(|(i, _)| 1u32 << i)
        .sum()
}

/// Called with the fraction done, in [0, 1], from a thread of the library
/// about five times a second; `user` is the pointer given to the bake.
pub type SssbakeProgress = Option<unsafe extern "C" fn(user: *mut c_void, fraction: f32)>;

/// A finished bake (opaque): its maps, rendered on request.
pub struct SssbakeResult {
    composite: Composite,
    summary: CString,
}

/// The live results.
static RESULTS: Handles<SssbakeResult> = Handles::new(handles::RESULT);

/// The host's user pointer, handed back to its callback on another thread.
pub(crate) struct UserData(pub(crate) *mut c_void);
// SAFETY: the library only passes the pointer back to the host's callback,
// which the host wrote to be called from another thread.
unsafe impl Send for UserData {}
unsafe impl Sync for UserData {}

/// The options a host's `settings` give, each under its name in the
/// library's schema (`sssbake_io::settings`): the struct is one more way to
/// write [`BakeOptions`], which check and make the request as for every
/// door. A zero limit is the library's default.
pub(crate) fn host_options(settings: &SssbakeSettings) -> Result<BakeOptions, Failure> {
    let method = METHODS.get(settings.method as usize).ok_or_else(|| {
        Failure::argument(format!(
            "method {} is not 0 to {}",
            settings.method,
            METHODS.len() - 1
        ))
    })?;
    if settings.outputs >> Output::ALL.len() != 0 {
        return Err(Failure::argument(format!(
            "outputs {:#x} names outputs beyond the {} there are",
            settings.outputs,
            Output::ALL.len()
        )));
    }
    let outputs = Output::ALL
        .iter()
        .enumerate()
        .filter(|(i, _)| settings.outputs & (1 << i) != 0)
        .map(|(_, o)| o.name().to_string())
        .collect();
    Ok(BakeOptions {
        resolution: Some(settings.resolution),
        method: Some(method.name().to_string()),
        margin: Some(settings.margin),
        light_samples: Some(settings.light_samples),
        seed: Some(settings.seed),
        octree_epsilon: Some(settings.octree_epsilon),
        gaussians: Some(settings.gaussians as usize),
        samples: Some(settings.samples),
        walk_samples: Some(settings.walk_samples),
        outputs: Some(outputs),
        tolerance: Some(f64::from(settings.tolerance)),
        max_memory: (settings.max_memory_bytes != 0).then(|| size_text(settings.max_memory_bytes)),
        max_evaluations: (settings.max_evaluations != 0.0).then_some(settings.max_evaluations),
        ..BakeOptions::default()
    })
}

/// Bakes `object` of `scene` with `material` and `settings`, into the
/// object's own UVs as they are (a host shows the maps through them). Every
/// face bakes with `material`, whatever material indices the mesh gives.
///
/// `progress` (may be null) is called with the fraction done; the bake
/// stops with [`SssbakeStatus::Cancelled`] soon after `*cancel` (may be
/// null) becomes nonzero. On success `*out` holds the result.
///
/// # Safety
/// `object` is NUL-terminated; `material` and `settings` point to valid
/// values; `cancel` is null or stays readable (and is only written
/// atomically) until the call returns; `out` is writable. A `scene` that
/// is not a live scene is refused.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_bake(
    scene: *const SssbakeScene,
    object: *const c_char,
    material: *const SssbakeMaterial,
    settings: *const SssbakeSettings,
    progress: SssbakeProgress,
    user: *mut c_void,
    cancel: *const i32,
    out: *mut *mut SssbakeResult,
) -> SssbakeStatus {
    // SAFETY: forwarded from the caller; one material is a slice of one.
    unsafe {
        sssbake_bake_materials(
            scene,
            object,
            material,
            usize::from(!material.is_null()),
            settings,
            progress,
            user,
            cancel,
            out,
        )
    }
}

/// Bakes `object` of `scene` as [`sssbake_bake`] does, each triangle with
/// the material of `materials` (`material_count` of them) that its mesh's
/// `material_indices` names (material 0 when the mesh gives none). A texel
/// takes the bake of its own face's material: the object is baked once per
/// material its faces use, each time as if the whole object were of that
/// material (light entering another material's faces included). Faces of an
/// [`SSSBAKE_MATERIAL_NONE`](crate::SSSBAKE_MATERIAL_NONE) material are left
/// out (their texels empty); the summary's object lists each material in
/// `materials` with the texels it owns.
///
/// # Safety
/// As [`sssbake_bake`]; `materials` points to `material_count` valid
/// materials whose images hold the floats they state.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_bake_materials(
    scene: *const SssbakeScene,
    object: *const c_char,
    materials: *const SssbakeMaterial,
    material_count: usize,
    settings: *const SssbakeSettings,
    progress: SssbakeProgress,
    user: *mut c_void,
    cancel: *const i32,
    out: *mut *mut SssbakeResult,
) -> SssbakeStatus {
    guarded(|| {
        // SAFETY: forwarded from the caller.
        let (settings, cancel) = unsafe { host_arguments(settings, cancel) }?;
        let options = host_options(settings)?;
        let request = |host: &HostScene| Ok(object_request(options, host)?);
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

/// What a bake reports to and hears from the host while it runs: its
/// progress callback with its user pointer, and its cancel flag.
pub(crate) type Watch<'a> = (SssbakeProgress, UserData, Option<&'a AtomicI32>);

/// Bakes `object` of `scene` with `materials` and the request `request`
/// makes for the scene, watched by `watch`, into `*out`.
///
/// # Safety
/// As [`sssbake_bake_materials`].
pub(crate) unsafe fn bake_host(
    scene: *const SssbakeScene,
    object: *const c_char,
    materials: *const SssbakeMaterial,
    material_count: usize,
    request: impl FnOnce(&HostScene) -> Result<BakeRequest, Failure>,
    (progress, user, cancel): Watch<'_>,
    out: *mut *mut SssbakeResult,
) -> Result<(), Failure> {
    // SAFETY: forwarded from the caller.
    unsafe { clear(out, "out") }?;
    let scene = SCENES.get(scene, "scene")?;
    // SAFETY: forwarded from the caller.
    let materials = unsafe { slice(materials, material_count, "materials") }?;
    // SAFETY: forwarded from the caller.
    let object = unsafe { text(object, "object name") }?;
    let materials = materials
        .iter()
        // SAFETY: forwarded from the caller.
        .map(|m| unsafe { host_material(m) })
        .collect::<Result<Vec<_>, _>>()?;
    let host = reading(&scene);
    let request = request(&host)?;
    let mut runner = HostRunner {
        progress,
        user: &user,
        cancel,
    };
    let (composite, summary) = bake_materials(&host, object, &materials, &request, &mut runner)?;
    let summary = serde_json::to_string(&summary).unwrap_or_default();
    let result = SssbakeResult {
        composite,
        summary: CString::new(summary).unwrap_or_default(),
    };
    let handle = RESULTS.issue(result)?;
    // SAFETY: checked non-null; the caller gives writable storage.
    unsafe { *out = handle };
    Ok(())
}

/// Runs each part of a bake watched: the host's progress callback and
/// cancel flag.
struct HostRunner<'a> {
    progress: SssbakeProgress,
    user: &'a UserData,
    cancel: Option<&'a AtomicI32>,
}

impl PartRunner for HostRunner<'_> {
    type Error = Failure;

    fn run<T: Send>(
        &mut self,
        part: (usize, usize),
        work: impl FnOnce(&Control) -> Result<T, sssbake::Error> + Send,
    ) -> Result<T, Failure> {
        let control = Control::new();
        let value = watched(
            &control,
            self.progress,
            self.user,
            self.cancel,
            part,
            || work(&control),
        )?;
        control.check().map_err(sssbake::Error::from)?;
        Ok(value)
    }
}

/// The settings and cancel flag a host's bake takes, the settings checked
/// for null.
///
/// # Safety
/// Each pointer is null or points to a valid value that outlives the call;
/// an i32 the host writes atomically reads as an AtomicI32 (same size and
/// alignment).
pub(crate) unsafe fn host_arguments<'a>(
    settings: *const SssbakeSettings,
    cancel: *const i32,
) -> Result<(&'a SssbakeSettings, Option<&'a AtomicI32>), Failure> {
    // SAFETY: as the caller promises.
    let (settings, cancel) = unsafe { (settings.as_ref(), cancel.cast::<AtomicI32>().as_ref()) };
    let settings = settings.ok_or_else(|| Failure::argument("settings is null"))?;
    Ok((settings, cancel))
}

/// Clears the caller's result slot `out` (named `what` in errors), so a
/// failure leaves it null.
///
/// # Safety
/// `out` is null or writable.
pub(crate) unsafe fn clear<T>(out: *mut *mut T, what: &str) -> Result<(), Failure> {
    if out.is_null() {
        return Err(Failure::argument(format!("{what} is null")));
    }
    // SAFETY: checked non-null; the caller gives writable storage.
    unsafe { *out = std::ptr::null_mut() };
    Ok(())
}

/// Runs `work` while a thread reports progress and passes the host's
/// cancel flag on to `control`, and once more after it; `(part, parts)`: the work is part `part` of
/// `parts` equal parts of the call, so the fraction reported runs from
/// part / parts to (part + 1) / parts. Work that fails is not reported
/// done.
pub(crate) fn watched<T, E>(
    control: &Control,
    progress: SssbakeProgress,
    user: &UserData,
    cancel: Option<&AtomicI32>,
    (part, parts): (usize, usize),
    work: impl FnOnce() -> Result<T, E>,
) -> Result<T, E> {
    let tick = || {
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed) != 0) {
            control.cancel();
        }
        if let Some(callback) = progress {
            let fraction = (part as f64 + control.fraction()) / parts.max(1) as f64;
            // SAFETY: the host's callback, called as documented.
            unsafe { callback(user.0, fraction as f32) };
        }
    };
    let result = watch_while(Duration::from_millis(200), tick, work);
    let raised = || cancel.is_some_and(|c| c.load(Ordering::Relaxed) != 0);
    if let (Some(callback), true, false) = (progress, result.is_ok(), raised()) {
        // The last tick may have come before the end: the part is done.
        // SAFETY: the host's callback, called as documented.
        unsafe { callback(user.0, ((part + 1) as f64 / parts.max(1) as f64) as f32) };
    }
    // A flag raised since the last tick, the host's answer to that last
    // report included, still counts: the caller sees it in `control` and
    // discards what the work made.
    if raised() {
        control.cancel();
    }
    result
}

/// Frees a result (null is allowed and frees nothing). A result freed
/// already, never handed out, or a handle of another kind is refused with
/// [`SssbakeStatus::InvalidArgument`] and frees nothing.
#[unsafe(no_mangle)]
pub extern "C" fn sssbake_result_free(result: *mut SssbakeResult) -> SssbakeStatus {
    guarded(|| RESULTS.free(result, "result"))
}

/// The maps' side in texels; 0 for a handle that is not a live result,
/// with [`sssbake_last_error`](crate::sssbake_last_error) saying why.
#[unsafe(no_mangle)]
pub extern "C" fn sssbake_result_resolution(result: *const SssbakeResult) -> u32 {
    let mut resolution = 0;
    guarded(|| {
        resolution = RESULTS.get(result, "result")?.composite.resolution();
        Ok(())
    });
    resolution
}

/// What the bake did, as JSON: the summary `sssbake bake --json` prints
/// (docs/outputs.md, "The summary"), for this one object. Owned by the result
/// (valid until it is freed; do not free it); null for a handle that is
/// not a live result, with [`sssbake_last_error`](crate::sssbake_last_error)
/// saying why.
#[unsafe(no_mangle)]
pub extern "C" fn sssbake_result_summary(result: *const SssbakeResult) -> *const c_char {
    let mut summary = std::ptr::null();
    guarded(|| {
        // The text stays where it is while the registry holds the result.
        summary = RESULTS.get(result, "result")?.summary.as_ptr();
        Ok(())
    });
    summary
}

/// Copies map `output` (0 subsurface, 1 irradiance, 2 diffuse, 3 thickness,
/// 4 stretch, 5 area; units as docs/outputs.md gives them) into
/// `rgba`, `len` = 4 × resolution² floats, rows from v = 0 up (Blender's
/// and OpenGL's order), alpha 1 on covered and filled texels, 0 elsewhere.
///
/// # Safety
/// `rgba` points to `len` writable floats (a `result` that is not a live
/// result is refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_result_image(
    result: *const SssbakeResult,
    output: u32,
    rgba: *mut f32,
    len: usize,
) -> SssbakeStatus {
    guarded(|| {
        let (result, output) = result_output(result, output)?;
        let n = result.composite.resolution() as usize;
        if len != 4 * n * n || rgba.is_null() {
            return Err(Failure::argument(format!(
                "the buffer holds {len} floats; a {n}² RGBA map needs {}",
                4 * n * n
            )));
        }
        // SAFETY: checked non-null; the caller gives `len` writable floats.
        let pixels = unsafe { std::slice::from_raw_parts_mut(rgba, len) };
        result.composite.write_rgba(output, pixels)?;
        Ok(())
    })
}

/// Writes map `output` (as for [`sssbake_result_image`]) to `path` as a
/// linear OpenEXR file, 32-bit float (or 16-bit when `half` is nonzero),
/// the same bytes `sssbake bake` writes. The file appears whole or not at
/// all: it is written beside its place and renamed.
///
/// # Safety
/// `path` is NUL-terminated UTF-8 (a `result` that is not a live result is
/// refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_result_write_exr(
    result: *const SssbakeResult,
    output: u32,
    path: *const c_char,
    half: u32,
) -> SssbakeStatus {
    guarded(|| {
        let (result, output) = result_output(result, output)?;
        let image = result.composite.render(output)?;
        // SAFETY: forwarded from the caller.
        let path = std::path::Path::new(unsafe { text(path, "path") }?);
        let precision = if half != 0 {
            Precision::Half
        } else {
            Precision::Float
        };
        let bytes = exr_bytes(&image, precision).map_err(Failure::input)?;
        write_atomically(path, &bytes).map_err(|e| {
            Failure(
                SssbakeStatus::CannotWrite,
                format!("{}: cannot write: {e}", path.display()),
            )
        })
    })
}

/// The live result of `result` and the output numbered `output`.
fn result_output(
    result: *const SssbakeResult,
    output: u32,
) -> Result<(Arc<SssbakeResult>, Output), Failure> {
    let result = RESULTS.get(result, "result")?;
    let output = *Output::ALL
        .get(output as usize)
        .ok_or_else(|| Failure::argument(format!("output {output} is not 0 to 5")))?;
    Ok((result, output))
}
