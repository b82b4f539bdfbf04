//! The C ABI called as a host calls it: a scene from flat arrays, a bake
//! with progress and cancellation, maps copied out; and every misuse
//! answered with a status and a message, never a crash.

mod plain_light;

use plain_light::light;
use sssbake_ffi::*;
use std::ffi::{CStr, CString, c_void};
use std::path::Path;
use std::ptr::{null, null_mut};

fn last_error() -> String {
    unsafe { CStr::from_ptr(sssbake_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// A latitude–longitude sphere of radius 20 mm with its lat-long UVs.
fn sphere() -> (Vec<f32>, Vec<f32>, Vec<f32>, Vec<u32>) {
    let (nu, nv) = (48u32, 24u32);
    let (mut p, mut n, mut uv, mut idx) = (vec![], vec![], vec![], vec![]);
    for j in 0..=nv {
        for i in 0..=nu {
            let (u, v) = (i as f32 / nu as f32, j as f32 / nv as f32);
            let (theta, phi) = (std::f32::consts::PI * v, 2.0 * std::f32::consts::PI * u);
            let d = [
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                -theta.cos(),
            ];
            p.extend(d.map(|x| 20.0 * x));
            n.extend(d);
            uv.extend([0.02 + 0.96 * u, 0.02 + 0.96 * v]);
        }
    }
    for j in 0..nv {
        for i in 0..nu {
            let a = j * (nu + 1) + i;
            let (b, c, d) = (a + 1, a + nu + 1, a + nu + 2);
            idx.extend([a, b, d, a, d, c]);
        }
    }
    (p, n, uv, idx)
}

struct Scene(*mut SssbakeScene);

impl Drop for Scene {
    fn drop(&mut self) {
        sssbake_scene_free(self.0);
    }
}

fn lit_sphere() -> Scene {
    let mut scene = null_mut();
    assert_eq!(
        unsafe { sssbake_scene_new(1.0, &mut scene) },
        SssbakeStatus::Ok
    );
    let (p, n, uv, idx) = sphere();
    let name = CString::new("Ball").unwrap();
    let mesh = SssbakeMesh {
        name: name.as_ptr(),
        positions: p.as_ptr(),
        normals: n.as_ptr(),
        uvs: uv.as_ptr(),
        vertex_count: p.len() / 3,
        indices: idx.as_ptr(),
        index_count: idx.len(),
        ..SssbakeMesh::default()
    };
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene, &mesh) },
        SssbakeStatus::Ok,
        "{}",
        last_error()
    );
    let sun = SssbakeLight {
        colour: [1.0, 0.9, 0.8],
        direction: [0.0, -0.6, -0.8],
        ..light(SSSBAKE_LIGHT_SUN, 3.0)
    };
    assert_eq!(
        unsafe { sssbake_scene_add_light(scene, &sun) },
        SssbakeStatus::Ok
    );
    assert_eq!(
        unsafe { sssbake_scene_set_world(scene, [0.1f32, 0.1, 0.2].as_ptr(), 0.5) },
        SssbakeStatus::Ok
    );
    Scene(scene)
}

fn preset(name: &CString) -> SssbakeMaterial {
    SssbakeMaterial {
        kind: SSSBAKE_MATERIAL_PRESET,
        name: name.as_ptr(),
        toml: null(),
        base_colour: [0.0; 3],
        subsurface_weight: 0.0,
        radius: [0.0; 3],
        scale: 0.0,
        ior: 0.0,
        anisotropy: 0.0,
        subsurface_method: SSSBAKE_SUBSURFACE_RANDOM_WALK,
        subsurface_ior: 1.4,
        specular_ior_level: 0.5,
        albedo_mapping: SSSBAKE_ALBEDO_CYCLES,
        ..SssbakeMaterial::default()
    }
}

fn settings(resolution: u32, method: u32) -> SssbakeSettings {
    let mut s = std::mem::MaybeUninit::uninit();
    assert_eq!(
        unsafe { sssbake_settings_default(s.as_mut_ptr()) },
        SssbakeStatus::Ok
    );
    SssbakeSettings {
        resolution,
        method,
        light_samples: 4,
        outputs: 0b11_1111,
        ..unsafe { s.assume_init() }
    }
}

unsafe extern "C" fn record(user: *mut c_void, fraction: f32) {
    let seen = unsafe { &*(user as *const std::sync::Mutex<Vec<f32>>) };
    seen.lock().unwrap().push(fraction);
}

#[test]
fn the_version_is_the_constant() {
    assert_eq!(sssbake_abi_version(), SSSBAKE_ABI_VERSION);
}

#[test]
fn a_bake_gives_physical_maps_and_reports_progress() {
    let scene = lit_sphere();
    let skin = CString::new("skin1").unwrap();
    let object = CString::new("Ball").unwrap();
    let seen = std::sync::Mutex::new(Vec::<f32>::new());
    let mut result = null_mut();
    let status = unsafe {
        sssbake_bake(
            scene.0,
            object.as_ptr(),
            &preset(&skin),
            &SssbakeSettings {
                margin: 0,
                ..settings(64, 1)
            },
            Some(record),
            &seen as *const _ as *mut c_void,
            null(),
            &mut result,
        )
    };
    assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
    assert_eq!(sssbake_result_resolution(result), 64);
    let summary = unsafe { CStr::from_ptr(sssbake_result_summary(result)) }
        .to_str()
        .unwrap();
    let summary: serde_json::Value = serde_json::from_str(summary).unwrap();
    assert_eq!(summary["objects"][0]["integrator"]["method"], "brute");
    assert_eq!(summary["objects"][0]["material"]["name"], "skin1");
    let map = |output: u32| {
        let mut pixels = vec![f32::NAN; 4 * 64 * 64];
        let status =
            unsafe { sssbake_result_image(result, output, pixels.as_mut_ptr(), pixels.len()) };
        assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
        pixels
    };
    let (subsurface, irradiance, area) = (map(0), map(1), map(5));
    assert!(subsurface.iter().all(|v| v.is_finite() && *v >= 0.0));
    // Flux out over flux in stays below one and well above nothing.
    let flux = |m: &[f32]| -> f64 {
        m.chunks(4)
            .zip(area.chunks(4))
            .filter(|(_, a)| a[3] > 0.0)
            .map(|(t, a)| (t[0] + t[1] + t[2]) as f64 * a[0] as f64)
            .sum()
    };
    let ratio = flux(&subsurface) / flux(&irradiance);
    assert!(0.2 < ratio && ratio < 1.0, "{ratio}");
    // Rows run up with v: the sun shines down on the pole at v = 1.
    let band = |rows: std::ops::Range<usize>| -> f32 {
        rows.map(|y| irradiance[4 * 64 * y..4 * 64 * (y + 1)].iter().sum::<f32>())
            .sum()
    };
    assert!(
        band(48..64) > 3.0 * band(0..16),
        "{} {}",
        band(48..64),
        band(0..16)
    );
    // Covered texels have alpha 1, the UV border outside the charts 0.
    assert!(area.chunks(4).any(|t| t[3] == 1.0) && area.chunks(4).any(|t| t[3] == 0.0));
    // Progress rises through [0, 1] and ends at 1.
    let seen = seen.lock().unwrap();
    assert!(seen.iter().all(|f| (0.0..=1.0).contains(f)), "{seen:?}");
    assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
    assert_eq!(seen.last(), Some(&1.0), "{seen:?}");
    // Written whole, with nothing left beside it; a folder that is not there
    // is named in the error.
    let dir = std::env::temp_dir().join(format!("sssbake-abi-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = CString::new(dir.join("Ball_subsurface.exr").to_str().unwrap()).unwrap();
    let status = unsafe { sssbake_result_write_exr(result, 0, path.as_ptr(), 0) };
    assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("Ball_subsurface.exr")]);
    let nowhere = CString::new(dir.join("no/such/folder/x.exr").to_str().unwrap()).unwrap();
    let status = unsafe { sssbake_result_write_exr(result, 0, nowhere.as_ptr(), 0) };
    assert_eq!(status, SssbakeStatus::CannotWrite);
    assert!(last_error().contains("no/such/folder"), "{}", last_error());
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
}

#[test]
fn a_raised_cancel_flag_stops_the_bake() {
    let scene = lit_sphere();
    let skin = CString::new("skin1").unwrap();
    let object = CString::new("Ball").unwrap();
    let cancel: i32 = 1;
    let mut result = null_mut();
    let status = unsafe {
        sssbake_bake(
            scene.0,
            object.as_ptr(),
            &preset(&skin),
            &settings(256, 1),
            None,
            null_mut(),
            &cancel,
            &mut result,
        )
    };
    assert_eq!(status, SssbakeStatus::Cancelled);
    assert!(result.is_null());
}

/// A progress callback that raises the cancel flag once the bake is past
/// `at` (a fraction of the work), as a host's Esc would.
struct CancelAt {
    at: f32,
    flag: std::sync::atomic::AtomicI32,
    last: std::sync::Mutex<f32>,
}

unsafe extern "C" fn cancel_at(user: *mut c_void, fraction: f32) {
    let state = unsafe { &*(user as *const CancelAt) };
    *state.last.lock().unwrap() = fraction;
    if fraction >= state.at {
        state.flag.store(1, std::sync::atomic::Ordering::Relaxed);
    }
}

#[test]
fn a_cancel_flag_raised_at_any_stage_stops_the_bake_cleanly() {
    let scene = lit_sphere();
    let skin = CString::new("skin1").unwrap();
    let object = CString::new("Ball").unwrap();
    let mut mid_bake = [false; 5];
    for at in [0.0, 0.5] {
        // auto, brute, octree, texture, importance (SssbakeSettings::method;
        // 5, the walk, is tested by the library: its walks are slow to cancel into).
        for method in 0..5 {
            let state = CancelAt {
                at,
                flag: std::sync::atomic::AtomicI32::new(0),
                last: std::sync::Mutex::new(0.0),
            };
            let mut result = null_mut();
            let status = unsafe {
                sssbake_bake(
                    scene.0,
                    object.as_ptr(),
                    &preset(&skin),
                    &settings(128, method),
                    Some(cancel_at),
                    &state as *const _ as *mut c_void,
                    state.flag.as_ptr(),
                    &mut result,
                )
            };
            let raised = state.flag.load(std::sync::atomic::Ordering::Relaxed) != 0;
            if raised {
                // Raised at any point before the call returned: cancelled,
                // nothing handed back.
                assert_eq!(status, SssbakeStatus::Cancelled, "at {at}, method {method}");
                assert!(result.is_null());
                assert!(last_error().contains("cancel"), "{}", last_error());
                mid_bake[method as usize] |= *state.last.lock().unwrap() > 0.0;
            } else {
                assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
                assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
            }
        }
    }
    // Some were stopped once part of their work was done, not only before
    // it began (the flag is polled every 200 ms, so a quick bake may end
    // first; then the flag raised after still cancels it, above).
    assert!(mid_bake.iter().any(|m| *m), "{mid_bake:?}");
}

#[test]
fn principled_inputs_bake_their_colour() {
    let scene = lit_sphere();
    let name = CString::new("Wax").unwrap();
    let object = CString::new("Ball").unwrap();
    let wax = SssbakeMaterial {
        kind: SSSBAKE_MATERIAL_PRINCIPLED,
        name: name.as_ptr(),
        toml: null(),
        base_colour: [0.9, 0.6, 0.3],
        subsurface_weight: 1.0,
        radius: [1.0, 0.5, 0.25],
        scale: 0.5,
        ior: 1.4,
        anisotropy: 0.0,
        subsurface_method: SSSBAKE_SUBSURFACE_RANDOM_WALK,
        subsurface_ior: 1.4,
        specular_ior_level: 0.5,
        albedo_mapping: SSSBAKE_ALBEDO_CYCLES,
        ..SssbakeMaterial::default()
    };
    let mut result = null_mut();
    let status = unsafe {
        sssbake_bake(
            scene.0,
            object.as_ptr(),
            &wax,
            &settings(32, 1),
            None,
            null_mut(),
            null(),
            &mut result,
        )
    };
    assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
    let summary = unsafe { CStr::from_ptr(sssbake_result_summary(result)) }
        .to_str()
        .unwrap();
    let summary: serde_json::Value = serde_json::from_str(summary).unwrap();
    let material = &summary["objects"][0]["material"];
    assert_eq!(material["name"], "Wax", "{summary}");
    assert_eq!(material["source"], "Principled BSDF", "{summary}");
    assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
    let none = SssbakeMaterial {
        subsurface_weight: 0.0,
        ..wax
    };
    let status = unsafe {
        sssbake_bake(
            scene.0,
            object.as_ptr(),
            &none,
            &settings(32, 1),
            None,
            null_mut(),
            null(),
            &mut result,
        )
    };
    assert_eq!(status, SssbakeStatus::BadInput);
    assert!(
        last_error().contains("Subsurface Weight is 0"),
        "{}",
        last_error()
    );
    let unknown = SssbakeMaterial {
        subsurface_method: 7,
        ..wax
    };
    let status = unsafe {
        sssbake_bake(
            scene.0,
            object.as_ptr(),
            &unknown,
            &settings(32, 1),
            None,
            null_mut(),
            null(),
            &mut result,
        )
    };
    assert_eq!(status, SssbakeStatus::InvalidArgument);
    assert!(
        last_error().contains("subsurface method 7"),
        "{}",
        last_error()
    );
}

#[test]
fn misuse_gets_a_status_and_a_message() {
    let mut scene = null_mut();
    assert_eq!(
        unsafe { sssbake_scene_new(0.0, &mut scene) },
        SssbakeStatus::InvalidArgument
    );
    assert!(last_error().contains("millimetres per unit"));
    assert_eq!(
        unsafe { sssbake_scene_new(1.0, null_mut()) },
        SssbakeStatus::InvalidArgument
    );
    let scene = lit_sphere();
    // A mesh whose index runs past its vertices.
    let name = CString::new("Broken").unwrap();
    let p = [0.0f32; 9];
    let idx = [0u32, 1, 7];
    let mesh = SssbakeMesh {
        name: name.as_ptr(),
        positions: p.as_ptr(),
        normals: null(),
        uvs: null(),
        vertex_count: 3,
        indices: idx.as_ptr(),
        index_count: 3,
        ..SssbakeMesh::default()
    };
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene.0, &mesh) },
        SssbakeStatus::BadInput
    );
    assert!(
        last_error().contains("object `Broken`: index 7"),
        "{}",
        last_error()
    );
    // A mesh without UVs: a host's maps follow its UVs, so there is nothing to bake into.
    let bare_name = CString::new("Bare").unwrap();
    let triangle = [0.0f32, 0.0, 0.0, 10.0, 0.0, 0.0, 0.0, 10.0, 0.0];
    let corners = [0u32, 1, 2];
    let bare = SssbakeMesh {
        name: bare_name.as_ptr(),
        positions: triangle.as_ptr(),
        normals: null(),
        uvs: null(),
        vertex_count: 3,
        indices: corners.as_ptr(),
        index_count: 3,
        ..SssbakeMesh::default()
    };
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene.0, &bare) },
        SssbakeStatus::Ok
    );
    let skin1 = CString::new("skin1").unwrap();
    let mut none = null_mut();
    let status = unsafe {
        sssbake_bake(
            scene.0,
            bare_name.as_ptr(),
            &preset(&skin1),
            &settings(16, 1),
            None,
            null_mut(),
            null(),
            &mut none,
        )
    };
    assert_eq!(status, SssbakeStatus::BadInput);
    assert!(
        last_error().contains("has no UVs to bake into"),
        "{}",
        last_error()
    );
    // Null arrays with a length.
    let hollow = SssbakeMesh {
        positions: null(),
        ..mesh
    };
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene.0, &hollow) },
        SssbakeStatus::InvalidArgument
    );
    // A light that is not finite, or of no kind.
    let mut light = SssbakeLight {
        size: 0.1,
        ..light(SSSBAKE_LIGHT_POINT, f32::NAN)
    };
    assert_eq!(
        unsafe { sssbake_scene_add_light(scene.0, &light) },
        SssbakeStatus::InvalidArgument
    );
    light.power = 10.0;
    light.kind = SSSBAKE_LIGHT_RECTANGLE;
    light.size_y = 0.0;
    assert_eq!(
        unsafe { sssbake_scene_add_light(scene.0, &light) },
        SssbakeStatus::InvalidArgument
    );
    assert!(last_error().contains("no area"), "{}", last_error());
    light.kind = 99;
    assert_eq!(
        unsafe { sssbake_scene_add_light(scene.0, &light) },
        SssbakeStatus::InvalidArgument
    );
    // An unknown object, an unknown preset, a bad resolution, a short buffer.
    let skin = CString::new("skin1").unwrap();
    let unknown = CString::new("Nobody").unwrap();
    let ball = CString::new("Ball").unwrap();
    let mut result = null_mut();
    let bake = |object: &CString,
                material: &SssbakeMaterial,
                settings: &SssbakeSettings,
                out: &mut *mut SssbakeResult| unsafe {
        sssbake_bake(
            scene.0,
            object.as_ptr(),
            material,
            settings,
            None,
            null_mut(),
            null(),
            out,
        )
    };
    assert_eq!(
        bake(&unknown, &preset(&skin), &settings(16, 0), &mut result),
        SssbakeStatus::BadInput
    );
    assert!(last_error().contains("Nobody"), "{}", last_error());
    let jelly = CString::new("jelly").unwrap();
    assert_eq!(
        bake(&ball, &preset(&jelly), &settings(16, 0), &mut result),
        SssbakeStatus::BadInput
    );
    assert!(last_error().contains("unknown preset `jelly`"));
    assert_eq!(
        bake(&ball, &preset(&skin), &settings(0, 0), &mut result),
        SssbakeStatus::InvalidArgument
    );
    assert_eq!(
        bake(&ball, &preset(&skin), &settings(16, 9), &mut result),
        SssbakeStatus::InvalidArgument
    );
    let nan_epsilon = SssbakeSettings {
        octree_epsilon: f32::NAN,
        ..settings(16, 2)
    };
    assert_eq!(
        bake(&ball, &preset(&skin), &nan_epsilon, &mut result),
        SssbakeStatus::InvalidArgument
    );
    assert!(result.is_null());
    assert_eq!(
        bake(&ball, &preset(&skin), &settings(16, 1), &mut result),
        SssbakeStatus::Ok
    );
    let mut short = vec![0.0f32; 10];
    let status = unsafe { sssbake_result_image(result, 0, short.as_mut_ptr(), short.len()) };
    assert_eq!(status, SssbakeStatus::InvalidArgument);
    assert!(last_error().contains("needs 1024"), "{}", last_error());
    let status = unsafe { sssbake_result_image(result, 6, short.as_mut_ptr(), short.len()) };
    assert_eq!(status, SssbakeStatus::InvalidArgument);
    assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
}

#[test]
fn hostile_arrays_get_a_status_and_a_message() {
    let scene = lit_sphere();
    let name = CString::new("Hostile").unwrap();
    let triangle = [0.0f32, 0.0, 0.0, 10.0, 0.0, 0.0, 0.0, 10.0, 0.0];
    let corners = [0u32, 1, 2];
    let good = SssbakeMesh {
        name: name.as_ptr(),
        positions: triangle.as_ptr(),
        vertex_count: 3,
        indices: corners.as_ptr(),
        index_count: 3,
        ..SssbakeMesh::default()
    };
    // Positions one byte off a float's alignment.
    let bytes = [0u8; 4 * 9 + 4];
    let offset = (1..4)
        .find(|k| !(bytes.as_ptr() as usize + k).is_multiple_of(4))
        .unwrap();
    let misaligned = SssbakeMesh {
        positions: bytes[offset..].as_ptr().cast(),
        ..good
    };
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene.0, &misaligned) },
        SssbakeStatus::InvalidArgument
    );
    assert!(
        last_error().contains("positions is not aligned to 4 bytes"),
        "{}",
        last_error()
    );
    // A vertex count whose arrays could not exist (3 × count wraps around).
    let huge = SssbakeMesh {
        vertex_count: usize::MAX / 3 + 2,
        ..good
    };
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene.0, &huge) },
        SssbakeStatus::InvalidArgument
    );
    assert!(last_error().contains("is too large"), "{}", last_error());
    // Indices not three per triangle.
    let short = SssbakeMesh {
        index_count: 2,
        ..good
    };
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene.0, &short) },
        SssbakeStatus::InvalidArgument
    );
    // NaN positions.
    let nan = [f32::NAN; 9];
    let not_finite = SssbakeMesh {
        positions: nan.as_ptr(),
        ..good
    };
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene.0, &not_finite) },
        SssbakeStatus::BadInput
    );
    assert!(
        last_error().contains("non-finite position"),
        "{}",
        last_error()
    );
    // The scene is still usable: the valid mesh goes in.
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene.0, &good) },
        SssbakeStatus::Ok
    );
}

/// A small result of `scene`'s Ball, 8² by the exact sum.
fn small_result(scene: *mut SssbakeScene) -> *mut SssbakeResult {
    let (skin, ball) = (
        CString::new("skin1").unwrap(),
        CString::new("Ball").unwrap(),
    );
    let mut result = null_mut();
    let status = unsafe {
        sssbake_bake(
            scene,
            ball.as_ptr(),
            &preset(&skin),
            &settings(8, 1),
            None,
            null_mut(),
            null(),
            &mut result,
        )
    };
    assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
    result
}

/// Asserts `status` refused a handle with a message containing `words`.
#[track_caller]
fn refused(status: SssbakeStatus, words: &str) {
    assert_eq!(status, SssbakeStatus::InvalidArgument, "{}", last_error());
    assert!(
        last_error().contains(words),
        "{words:?} not in {:?}",
        last_error()
    );
}

/// Every call taking a scene, called with `scene`: each status (a result
/// made is freed; a host's scene has no file to bake into a folder).
fn scene_calls(scene: *mut SssbakeScene) -> Vec<SssbakeStatus> {
    let (skin, ball) = (
        CString::new("skin1").unwrap(),
        CString::new("Ball").unwrap(),
    );
    let name = CString::new("Quad").unwrap();
    let p = [0.0f32, 0.0, 0.0, 10.0, 0.0, 0.0, 0.0, 10.0, 0.0];
    let idx = [0u32, 1, 2];
    let mesh = SssbakeMesh {
        name: name.as_ptr(),
        positions: p.as_ptr(),
        vertex_count: 3,
        indices: idx.as_ptr(),
        index_count: 3,
        ..SssbakeMesh::default()
    };
    let light = light(SSSBAKE_LIGHT_SUN, 1.0);
    let material = preset(&skin);
    let settings = settings(8, 1);
    let out_dir = CString::new("never-written").unwrap();
    let (mut result, mut summary) = (null_mut(), null_mut());
    let mut statuses = Vec::new();
    let mut call = |status: SssbakeStatus, words: &str| {
        if status != SssbakeStatus::Ok {
            assert!(
                last_error().contains(words),
                "{words:?} not in {:?}",
                last_error()
            );
        }
        statuses.push(status);
    };
    let scene_words = "scene";
    call(unsafe { sssbake_scene_add_mesh(scene, &mesh) }, scene_words);
    call(
        unsafe { sssbake_scene_add_light(scene, &light) },
        scene_words,
    );
    let world = [0.1f32; 3];
    call(
        unsafe { sssbake_scene_set_world(scene, world.as_ptr(), 1.0) },
        scene_words,
    );
    let bake = unsafe {
        sssbake_bake(
            scene,
            ball.as_ptr(),
            &material,
            &settings,
            None,
            null_mut(),
            null(),
            &mut result,
        )
    };
    call(bake, scene_words);
    let bake = unsafe {
        sssbake_bake_materials(
            scene,
            ball.as_ptr(),
            &material,
            1,
            &settings,
            None,
            null_mut(),
            null(),
            &mut result,
        )
    };
    call(bake, scene_words);
    let folder = unsafe {
        sssbake_bake_to_folder(
            scene,
            &material,
            &settings,
            out_dir.as_ptr(),
            0,
            None,
            null_mut(),
            null(),
            &mut summary,
        )
    };
    call(folder, scene_words);
    if !result.is_null() {
        assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
    }
    assert!(summary.is_null());
    assert!(!Path::new("never-written").exists());
    statuses
}

/// Every call taking a result, called with `result`: each status, with
/// the resolution and summary calls' failure read as invalid argument.
fn result_calls(result: *mut SssbakeResult) -> Vec<SssbakeStatus> {
    let mut statuses = Vec::new();
    let mut pixels = vec![0.0f32; 4 * 8 * 8];
    statuses.push(unsafe { sssbake_result_image(result, 0, pixels.as_mut_ptr(), pixels.len()) });
    let path = std::env::temp_dir().join(format!("sssbake-handle-{}.exr", std::process::id()));
    let c_path = CString::new(path.to_str().unwrap()).unwrap();
    statuses.push(unsafe { sssbake_result_write_exr(result, 0, c_path.as_ptr(), 0) });
    let written = path.exists();
    let _ = std::fs::remove_file(&path);
    assert_eq!(written, statuses[1] == SssbakeStatus::Ok);
    let as_status = |ok: bool| {
        if ok {
            SssbakeStatus::Ok
        } else {
            SssbakeStatus::InvalidArgument
        }
    };
    statuses.push(as_status(sssbake_result_resolution(result) == 8));
    statuses.push(as_status(!sssbake_result_summary(result).is_null()));
    statuses
}

#[test]
fn scene_handles_freed_made_up_or_null_are_refused_and_never_freed_twice() {
    let live = lit_sphere();
    let mut fresh = null_mut();
    assert_eq!(
        unsafe { sssbake_scene_new(1.0, &mut fresh) },
        SssbakeStatus::Ok
    );
    assert!(fresh.addr().is_multiple_of(std::mem::align_of::<usize>()));
    assert_eq!(sssbake_scene_free(fresh), SssbakeStatus::Ok);
    // Freed twice, and used after it is freed.
    refused(sssbake_scene_free(fresh), "was freed already");
    let freed = scene_calls(fresh);
    assert!(freed.iter().all(|&s| s == SssbakeStatus::InvalidArgument));
    refused(
        unsafe { sssbake_scene_add_light(fresh, null()) },
        "is a scene that was freed already",
    );
    // Made up: an address on the stack, a live handle one byte off, a
    // result's handle.
    let mut stack = [0u64; 4];
    let made_up = stack.as_mut_ptr().cast::<SssbakeScene>();
    refused(
        sssbake_scene_free(made_up),
        "not a scene handle this library handed out",
    );
    assert!(
        scene_calls(made_up)
            .iter()
            .all(|&s| s == SssbakeStatus::InvalidArgument)
    );
    assert_eq!(stack, [0; 4], "a made-up handle was written through");
    let off = live.0.wrapping_byte_add(1);
    refused(sssbake_scene_free(off), "misaligned");
    let result = small_result(live.0);
    refused(
        sssbake_scene_free(result.cast()),
        "is a result handle, not a scene",
    );
    // Null: refused by every call but the free, which frees nothing.
    assert!(
        scene_calls(null_mut())
            .iter()
            .all(|&s| s == SssbakeStatus::InvalidArgument)
    );
    refused(
        unsafe { sssbake_scene_add_mesh(null_mut(), null()) },
        "scene is null",
    );
    assert_eq!(sssbake_scene_free(null_mut()), SssbakeStatus::Ok);
    // None of it touched the live scene and its result.
    assert_eq!(sssbake_result_resolution(result), 8);
    assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
    use SssbakeStatus::{InvalidArgument, Ok};
    assert_eq!(scene_calls(live.0), [Ok, Ok, Ok, Ok, Ok, InvalidArgument]);
}

#[test]
fn result_handles_freed_made_up_or_null_are_refused_and_never_freed_twice() {
    let scene = lit_sphere();
    let result = small_result(scene.0);
    assert_eq!(result_calls(result), [SssbakeStatus::Ok; 4]);
    let summary = sssbake_result_summary(result);
    assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
    // Freed twice, and used after it is freed.
    refused(
        sssbake_result_free(result),
        "is a result that was freed already",
    );
    assert_eq!(result_calls(result), [SssbakeStatus::InvalidArgument; 4]);
    assert!(last_error().contains("freed already"), "{}", last_error());
    // Made up: a stack address, a scene's handle, a summary's text.
    let mut stack = [0u64; 4];
    let made_up = stack.as_mut_ptr().cast::<SssbakeResult>();
    refused(sssbake_result_free(made_up), "not a result handle");
    assert_eq!(result_calls(made_up), [SssbakeStatus::InvalidArgument; 4]);
    refused(
        sssbake_result_free(scene.0.cast()),
        "is a scene handle, not a result",
    );
    refused(sssbake_result_free(summary.cast_mut().cast()), "result");
    // Null: refused by every call but the free, which frees nothing.
    assert_eq!(
        result_calls(null_mut()),
        [SssbakeStatus::InvalidArgument; 4]
    );
    assert!(last_error().contains("result is null"), "{}", last_error());
    assert_eq!(sssbake_result_free(null_mut()), SssbakeStatus::Ok);
    assert_eq!(stack, [0; 4]);
}

#[test]
fn strings_freed_twice_made_up_or_a_summary_are_refused_and_never_freed() {
    let mut names = null_mut();
    assert_eq!(
        unsafe { sssbake_names(SSSBAKE_NAMES_OUTPUTS, &mut names) },
        SssbakeStatus::Ok
    );
    assert_eq!(sssbake_string_free(names), SssbakeStatus::Ok);
    refused(
        sssbake_string_free(names),
        "not a live string of this library",
    );
    // A string of the host's own, and a result's summary: not the library's
    // to free, and still whole after the refusal.
    let own = CString::new("the host's").unwrap().into_raw();
    refused(sssbake_string_free(own), "never handed out");
    assert_eq!(unsafe { CString::from_raw(own) }.to_str(), Ok("the host's"));
    let scene = lit_sphere();
    let result = small_result(scene.0);
    let summary = sssbake_result_summary(result);
    refused(
        sssbake_string_free(summary.cast_mut()),
        "a result's summary belongs to its result",
    );
    let text = unsafe { CStr::from_ptr(sssbake_result_summary(result)) };
    assert!(text.to_str().unwrap().starts_with('{'));
    assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
    assert_eq!(sssbake_string_free(null_mut()), SssbakeStatus::Ok);
}

/// What the progress callback of a bake did to its own scene.
struct Meddler {
    scene: *mut SssbakeScene,
    /// The status and message of adding a light during the bake, and of
    /// freeing the scene.
    seen: std::sync::Mutex<Vec<(SssbakeStatus, String)>>,
}

unsafe extern "C" fn meddle(user: *mut c_void, _fraction: f32) {
    let meddler = unsafe { &*(user as *const Meddler) };
    let mut seen = meddler.seen.lock().unwrap();
    if !seen.is_empty() {
        return;
    }
    let world = [1.0f32; 3];
    let status = unsafe { sssbake_scene_set_world(meddler.scene, world.as_ptr(), 1.0) };
    seen.push((status, last_error()));
    let status = sssbake_scene_free(meddler.scene);
    seen.push((status, last_error()));
}

#[test]
fn a_scene_freed_during_its_bake_lives_until_the_bake_returns() {
    let scene = lit_sphere();
    let meddler = Meddler {
        scene: scene.0,
        seen: std::sync::Mutex::new(Vec::new()),
    };
    let (skin, ball) = (
        CString::new("skin1").unwrap(),
        CString::new("Ball").unwrap(),
    );
    let mut result = null_mut();
    let status = unsafe {
        sssbake_bake(
            scene.0,
            ball.as_ptr(),
            &preset(&skin),
            &settings(16, 1),
            Some(meddle),
            &meddler as *const Meddler as *mut c_void,
            null(),
            &mut result,
        )
    };
    assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
    let seen = meddler.seen.lock().unwrap();
    assert_eq!(seen[0].0, SssbakeStatus::InvalidArgument);
    assert!(seen[0].1.contains("being baked"), "{}", seen[0].1);
    assert_eq!(seen[1], (SssbakeStatus::Ok, String::new()));
    // The bake finished with the scene; the handle is gone after it.
    assert_eq!(sssbake_result_resolution(result), 16);
    assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
    refused(sssbake_scene_free(scene.0), "freed already");
}

#[test]
fn limits_in_the_settings_refuse_a_bake_before_it_starts() {
    let scene = lit_sphere();
    let defaults = settings(8, 1);
    assert_eq!(defaults.max_memory_bytes, 16 << 30);
    assert_eq!(defaults.max_evaluations, 3e10);
    let (skin, ball) = (
        CString::new("skin1").unwrap(),
        CString::new("Ball").unwrap(),
    );
    let bake = |settings: &SssbakeSettings| {
        let seen = std::sync::Mutex::new(Vec::<f32>::new());
        let mut result = null_mut();
        let status = unsafe {
            sssbake_bake(
                scene.0,
                ball.as_ptr(),
                &preset(&skin),
                settings,
                Some(record),
                &seen as *const _ as *mut c_void,
                null(),
                &mut result,
            )
        };
        let message = last_error();
        let done = seen.into_inner().unwrap();
        if !result.is_null() {
            assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
        }
        (status, message, result.is_null(), done)
    };
    // 1 MiB is less than the bake's fixed 16 MiB, whatever its size; 10⁴
    // evaluations are fewer than the exact sum over a 64² map needs.
    let tight_memory = SssbakeSettings {
        max_memory_bytes: 1 << 20,
        ..settings(64, 1)
    };
    let tight_work = SssbakeSettings {
        max_evaluations: 1e4,
        ..settings(64, 1)
    };
    for (tight, limit, named, raised) in [
        (
            tight_memory,
            "max_memory: ",
            "over the limit of 1.0 MiB",
            "raise the limit (max_memory_bytes in SssbakeSettings)",
        ),
        (
            tight_work,
            "max_evaluations: ",
            "over the limit of 1.0e4",
            "raise the limit (max_evaluations in SssbakeSettings)",
        ),
    ] {
        let (status, message, empty, progress) = bake(&tight);
        // A setting's error: the library's Setting kind.
        assert_eq!(status, SssbakeStatus::InvalidArgument, "{message}");
        assert!(message.starts_with(limit), "{message}");
        assert!(message.contains(named), "{message}");
        // How to raise it, in the ABI's terms rather than the command line's.
        assert!(message.ends_with(raised), "{message}");
        assert!(empty);
        // Refused by the plan: no part of the bake ran or was reported done.
        assert!(progress.iter().all(|&f| f == 0.0), "{progress:?}");
    }
    // 0 is the default, and the defaults bake; a negative or NaN count is
    // refused.
    let zero = SssbakeSettings {
        max_memory_bytes: 0,
        max_evaluations: 0.0,
        ..settings(8, 1)
    };
    let (status, message, _, progress) = bake(&zero);
    assert_eq!(status, SssbakeStatus::Ok, "{message}");
    assert_eq!(progress.last(), Some(&1.0));
    for bad in [-1.0, f64::NAN] {
        let (status, message, _, _) = bake(&SssbakeSettings {
            max_evaluations: bad,
            ..settings(8, 1)
        });
        assert_eq!(status, SssbakeStatus::InvalidArgument);
        assert!(message.starts_with("max_evaluations: "), "{message}");
    }
}

/// Options set by name, as the text the command line takes.
struct Options(*mut SssbakeOptions);

impl Options {
    fn new(pairs: &[(&str, &str)]) -> Options {
        let mut options = null_mut();
        assert_eq!(
            unsafe { sssbake_options_new(&mut options) },
            SssbakeStatus::Ok
        );
        let options = Options(options);
        for (key, value) in pairs {
            assert_eq!(
                options.set(key, value),
                SssbakeStatus::Ok,
                "{}",
                last_error()
            );
        }
        options
    }

    fn set(&self, key: &str, value: &str) -> SssbakeStatus {
        let (key, value) = (CString::new(key).unwrap(), CString::new(value).unwrap());
        unsafe { sssbake_options_set(self.0, key.as_ptr(), value.as_ptr()) }
    }

    /// The sphere baked with these options in skin1, or the status.
    fn bake(&self, scene: &Scene) -> Result<*mut SssbakeResult, SssbakeStatus> {
        let (skin, ball) = (
            CString::new("skin1").unwrap(),
            CString::new("Ball").unwrap(),
        );
        let mut result = null_mut();
        let status = unsafe {
            sssbake_bake_options(
                scene.0,
                ball.as_ptr(),
                &preset(&skin),
                1,
                self.0,
                None,
                null_mut(),
                null(),
                &mut result,
            )
        };
        if status == SssbakeStatus::Ok {
            Ok(result)
        } else {
            Err(status)
        }
    }
}

impl Drop for Options {
    fn drop(&mut self) {
        sssbake_options_free(self.0);
    }
}

fn pixels(result: *mut SssbakeResult, output: u32) -> Vec<f32> {
    let n = sssbake_result_resolution(result) as usize;
    let mut pixels = vec![f32::NAN; 4 * n * n];
    let status = unsafe { sssbake_result_image(result, output, pixels.as_mut_ptr(), pixels.len()) };
    assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
    pixels
}

#[test]
fn options_set_by_name_bake_as_the_settings_struct_does() {
    let scene = lit_sphere();
    let by_struct = small_result(scene.0);
    let options = Options::new(&[
        ("resolution", "8"),
        ("method", "brute"),
        ("light_samples", "4"),
        (
            "outputs",
            "subsurface,irradiance,diffuse,thickness,stretch,area",
        ),
    ]);
    let by_name = options
        .bake(&scene)
        .unwrap_or_else(|_| panic!("{}", last_error()));
    assert_eq!(sssbake_result_resolution(by_name), 8);
    for output in 0..6 {
        assert_eq!(
            pixels(by_struct, output),
            pixels(by_name, output),
            "output {output}"
        );
    }
    // A setting the struct has no field for: the octree's threshold.
    let octree = Options::new(&[
        ("resolution", "8"),
        ("method", "octree"),
        ("octree_epsilon", "0.25"),
    ]);
    let result = octree
        .bake(&scene)
        .unwrap_or_else(|_| panic!("{}", last_error()));
    let summary = unsafe { CStr::from_ptr(sssbake_result_summary(result)) }
        .to_str()
        .unwrap();
    let summary: serde_json::Value = serde_json::from_str(summary).unwrap();
    assert_eq!(
        summary["objects"][0]["accuracy"]["octree_epsilon"], 0.25,
        "{summary}"
    );
    for result in [by_struct, by_name, result] {
        assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
    }
}

#[test]
fn options_refuse_unknown_names_and_values_out_of_range_naming_them() {
    let scene = lit_sphere();
    let options = Options::new(&[
        ("resolution", "8"),
        ("method", "brute"),
        ("light_samples", "2"),
    ]);
    refused(
        options.set("resolutoin", "16"),
        "no setting is called `resolutoin`",
    );
    for (key, value, words) in [
        ("resolution", "0", "0 must be between 1 and 16384"),
        ("resolution", "eight", "`eight` is not a whole number"),
        ("method", "fast", "unknown name `fast`"),
        ("colour_split", "2", "2 must be between 0 and 1"),
        ("max_memory", "lots", "lots"),
    ] {
        assert_ne!(options.set(key, value), SssbakeStatus::Ok);
        assert!(last_error().contains(key), "{key}: {}", last_error());
        assert!(
            last_error().contains(words),
            "{words:?} not in {}",
            last_error()
        );
    }
    // The refused values left the options as they were.
    let result = options
        .bake(&scene)
        .unwrap_or_else(|_| panic!("{}", last_error()));
    assert_eq!(sssbake_result_resolution(result), 8);
    assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
    // A host's scene has its own units: the bake refuses the file's.
    assert_eq!(options.set("unit_scale", "10"), SssbakeStatus::Ok);
    assert!(options.bake(&scene).is_err());
    assert!(last_error().contains("unit_scale"), "{}", last_error());
    // Null and freed handles are refused, never freed twice.
    let key = CString::new("resolution").unwrap();
    refused(
        unsafe { sssbake_options_set(null_mut(), key.as_ptr(), key.as_ptr()) },
        "options",
    );
    let mut freed = null_mut();
    assert_eq!(
        unsafe { sssbake_options_new(&mut freed) },
        SssbakeStatus::Ok
    );
    assert_eq!(sssbake_options_free(freed), SssbakeStatus::Ok);
    refused(sssbake_options_free(freed), "options");
}

#[test]
fn the_settings_struct_refuses_what_the_options_refuse_with_the_same_words() {
    let scene = lit_sphere();
    let (skin, ball) = (
        CString::new("skin1").unwrap(),
        CString::new("Ball").unwrap(),
    );
    let base = settings(8, 1);
    for (key, value, bad) in [
        (
            "resolution",
            "0",
            SssbakeSettings {
                resolution: 0,
                ..base
            },
        ),
        (
            "gaussians",
            "99",
            SssbakeSettings {
                gaussians: 99,
                ..base
            },
        ),
        (
            "light_samples",
            "0",
            SssbakeSettings {
                light_samples: 0,
                ..base
            },
        ),
        (
            "walk_samples",
            "1",
            SssbakeSettings {
                walk_samples: 1,
                ..base
            },
        ),
        (
            "tolerance",
            "-1",
            SssbakeSettings {
                tolerance: -1.0,
                ..base
            },
        ),
    ] {
        let options = Options::new(&[]);
        assert_eq!(options.set(key, value), SssbakeStatus::InvalidArgument);
        let by_name = last_error();
        let mut result = null_mut();
        let status = unsafe {
            sssbake_bake(
                scene.0,
                ball.as_ptr(),
                &preset(&skin),
                &bad,
                None,
                null_mut(),
                null(),
                &mut result,
            )
        };
        assert_eq!(status, SssbakeStatus::InvalidArgument, "{key}");
        assert!(result.is_null());
        assert_eq!(last_error(), by_name, "{key}");
    }
}
