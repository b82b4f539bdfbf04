//! A scene read from a file and baked whole into a folder through the C
//! ABI writes what the library's own folder bake writes; the name tables
//! are the library's; and misuse gets a status and a message.

use sssbake::control::Control;
use sssbake::{BakeRequest, Output};
use sssbake_ffi::*;
use sssbake_io::{FolderOptions, ReadOptions, bake_to_folder, read_scene};
use std::ffi::{CStr, CString, c_char};
use std::path::{Path, PathBuf};
use std::ptr::{null, null_mut};

fn last_error() -> String {
    unsafe { CStr::from_ptr(sssbake_last_error()) }
        .to_string_lossy()
        .into_owned()
}

fn marble() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/marble/marble.gltf")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sssbake-ffi-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn default_settings() -> SssbakeSettings {
    let mut s = std::mem::MaybeUninit::uninit();
    assert_eq!(
        unsafe { sssbake_settings_default(s.as_mut_ptr()) },
        SssbakeStatus::Ok
    );
    unsafe { s.assume_init() }
}

fn scene_material() -> SssbakeMaterial {
    SssbakeMaterial {
        kind: SSSBAKE_MATERIAL_SCENE,
        name: null(),
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

/// Takes a string the library handed out, freeing it.
fn take(string: *mut c_char) -> String {
    assert!(!string.is_null());
    let text = unsafe { CStr::from_ptr(string) }
        .to_str()
        .unwrap()
        .to_owned();
    assert_eq!(sssbake_string_free(string), SssbakeStatus::Ok);
    text
}

/// `sssbake_bake_to_folder` of `scene` into `out` with the scene's own
/// material, no progress and no cancel flag.
fn bake_into(
    scene: *mut SssbakeScene,
    settings: &SssbakeSettings,
    out: &CString,
    flags: u32,
    summary: &mut *mut c_char,
) -> SssbakeStatus {
    unsafe {
        sssbake_bake_to_folder(
            scene,
            &scene_material(),
            settings,
            out.as_ptr(),
            flags,
            None,
            null_mut(),
            null(),
            summary,
        )
    }
}

fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_file_baked_into_a_folder_writes_the_librarys_bytes() {
    let path = CString::new(marble().to_str().unwrap()).unwrap();
    let mut scene = null_mut();
    let status = unsafe { sssbake_scene_read(path.as_ptr(), 0, 0.0, &mut scene) };
    assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
    let ours = scratch("abi-marble");
    let out = CString::new(ours.to_str().unwrap()).unwrap();
    let settings = SssbakeSettings {
        resolution: 32,
        ..default_settings()
    };
    let mut summary = null_mut();
    let status = bake_into(scene, &settings, &out, 0, &mut summary);
    assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
    let json: serde_json::Value = serde_json::from_str(&take(summary)).unwrap();
    assert_eq!(json["objects"][0]["name"], "Ball", "{json}");
    // A second bake into the same folder is refused unless forced.
    let status = bake_into(scene, &settings, &out, 0, &mut summary);
    assert_eq!(status, SssbakeStatus::CannotWrite);
    assert!(last_error().contains("exists"), "{}", last_error());
    assert!(summary.is_null());
    assert_eq!(sssbake_scene_free(scene), SssbakeStatus::Ok);

    // What `sssbake bake marble.gltf --resolution 32` asks for: the
    // library's default request at 32², baked into a folder by the library.
    let theirs = scratch("library-marble");
    let scene = read_scene(&marble(), &ReadOptions::default()).unwrap();
    let request = BakeRequest {
        resolution: 32,
        ..BakeRequest::default()
    };
    let plan = sssbake::plan(&scene, &request).unwrap();
    let options = FolderOptions {
        out: theirs.clone(),
        ..FolderOptions::default()
    };
    bake_to_folder(&marble(), &scene, &plan, &options, &Control::new()).unwrap();

    let names = files(&ours);
    assert_eq!(names, files(&theirs));
    assert!(
        names.contains(&"Ball_subsurface.exr".to_string()),
        "{names:?}"
    );
    for name in names.iter().filter(|n| n.ends_with(".exr")) {
        let (a, b) = (
            std::fs::read(ours.join(name)).unwrap(),
            std::fs::read(theirs.join(name)).unwrap(),
        );
        assert!(a == b, "{name} differs");
    }
    std::fs::remove_dir_all(&ours).unwrap();
    std::fs::remove_dir_all(&theirs).unwrap();
}

fn names(kind: u32) -> serde_json::Value {
    let mut out = null_mut();
    let status = unsafe { sssbake_names(kind, &mut out) };
    assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
    serde_json::from_str(&take(out)).unwrap()
}

#[test]
fn the_name_tables_are_the_librarys() {
    let outputs = names(SSSBAKE_NAMES_OUTPUTS);
    let expected: Vec<&str> = Output::ALL.iter().map(|o| o.name()).collect();
    assert_eq!(outputs, serde_json::json!(expected));
    assert_eq!(outputs[0], "subsurface");
    // Bit i of the default outputs mask is output i of the table.
    let mask = default_settings().outputs;
    let defaults: Vec<&str> = Output::DEFAULT.iter().map(|o| o.name()).collect();
    let masked: Vec<&str> = (0..outputs.as_array().unwrap().len())
        .filter(|i| mask & (1 << i) != 0)
        .map(|i| outputs[i].as_str().unwrap())
        .collect();
    assert_eq!(masked, defaults);

    let methods = names(SSSBAKE_NAMES_METHODS);
    assert_eq!(
        methods,
        serde_json::json!(["auto", "brute", "octree", "texture", "importance", "walk"])
    );
    let method = default_settings().method as usize;
    assert_eq!(methods[method], BakeRequest::default().method.name());

    let presets = names(SSSBAKE_NAMES_PRESETS);
    let presets = presets.as_array().unwrap();
    // Every preset a bake can use; those with no length scale are left out.
    let bakeable: Vec<&str> = sssbake_profile::presets::list()
        .into_iter()
        .map(|(name, _)| name)
        .filter(|name| !sssbake_profile::presets::ANGULAR_ONLY.contains(name))
        .collect();
    let listed: Vec<&str> = presets
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(listed, bakeable);
    assert!(!listed.contains(&"stam-dermis"));
    let skin = presets.iter().find(|p| p["name"] == "skin1").unwrap();
    assert!(
        skin["description"].as_str().unwrap().contains("Jensen"),
        "{skin}"
    );
    assert!(presets.iter().any(|p| p["name"] == "skin3layer"));

    let mut out = null_mut();
    assert_eq!(
        unsafe { sssbake_names(3, &mut out) },
        SssbakeStatus::InvalidArgument
    );
    assert!(out.is_null());
    assert!(last_error().contains("names kind 3"), "{}", last_error());
    assert_eq!(
        unsafe { sssbake_names(0, null_mut()) },
        SssbakeStatus::InvalidArgument
    );
    assert_eq!(sssbake_string_free(null_mut()), SssbakeStatus::Ok);
}

#[test]
fn misuse_of_files_and_folders_gets_a_status_and_a_message() {
    // A host's scene has no file to write beside.
    let mut scene = null_mut();
    assert_eq!(
        unsafe { sssbake_scene_new(1.0, &mut scene) },
        SssbakeStatus::Ok
    );
    let out = scratch("host");
    let out_c = CString::new(out.to_str().unwrap()).unwrap();
    let mut summary = null_mut();
    let bake = |scene, settings: &SssbakeSettings, flags, summary: &mut *mut c_char| {
        bake_into(scene, settings, &out_c, flags, summary)
    };
    let settings = SssbakeSettings {
        resolution: 16,
        ..default_settings()
    };
    assert_eq!(
        bake(scene, &settings, 0, &mut summary),
        SssbakeStatus::InvalidArgument
    );
    assert!(
        last_error().contains("sssbake_scene_read"),
        "{}",
        last_error()
    );
    assert!(summary.is_null() && !out.exists());
    assert_eq!(sssbake_scene_free(scene), SssbakeStatus::Ok);

    // A file that is not there is named.
    let missing = CString::new("/no/such/scene.gltf").unwrap();
    let status = unsafe { sssbake_scene_read(missing.as_ptr(), 0, 0.0, &mut scene) };
    assert_eq!(status, SssbakeStatus::BadInput);
    assert!(
        last_error().contains("/no/such/scene.gltf"),
        "{}",
        last_error()
    );
    assert!(scene.is_null());
    // A unit scale that is not a length.
    let path = CString::new(marble().to_str().unwrap()).unwrap();
    let status = unsafe { sssbake_scene_read(path.as_ptr(), 0, -1.0, &mut scene) };
    assert_eq!(status, SssbakeStatus::InvalidArgument);
    assert!(last_error().contains("unit scale -1"), "{}", last_error());

    // A file's scene takes no meshes from the host, unknown flags or
    // settings are refused, and nothing is written.
    let status = unsafe { sssbake_scene_read(path.as_ptr(), 0, 0.0, &mut scene) };
    assert_eq!(status, SssbakeStatus::Ok, "{}", last_error());
    let name = CString::new("Extra").unwrap();
    let p = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let idx = [0u32, 1, 2];
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
        unsafe { sssbake_scene_add_mesh(scene, &mesh) },
        SssbakeStatus::InvalidArgument
    );
    assert!(last_error().contains("marble.gltf"), "{}", last_error());
    assert_eq!(
        bake(scene, &settings, 4, &mut summary),
        SssbakeStatus::InvalidArgument
    );
    assert!(last_error().contains("flags 0x4"), "{}", last_error());
    let bad = SssbakeSettings {
        method: 9,
        ..settings
    };
    assert_eq!(
        bake(scene, &bad, 0, &mut summary),
        SssbakeStatus::InvalidArgument
    );
    // A memory limit below what the bake needs is refused by the plan,
    // before the folder is made.
    let tight = SssbakeSettings {
        max_memory_bytes: 1 << 20,
        ..settings
    };
    assert_eq!(
        bake(scene, &tight, 0, &mut summary),
        SssbakeStatus::InvalidArgument
    );
    assert!(
        last_error().starts_with("max_memory: ") && last_error().contains("limit of 1.0 MiB"),
        "{}",
        last_error()
    );
    // The input's own folder is refused: a bake never writes beside its asset.
    let beside = CString::new(marble().parent().unwrap().to_str().unwrap()).unwrap();
    let status = bake_into(
        scene,
        &settings,
        &beside,
        SSSBAKE_FOLDER_FORCE,
        &mut summary,
    );
    assert_eq!(status, SssbakeStatus::InvalidArgument, "{}", last_error());
    assert!(
        last_error().contains("is the folder of the input"),
        "{}",
        last_error()
    );
    assert!(summary.is_null() && !out.exists());
    assert_eq!(sssbake_scene_free(scene), SssbakeStatus::Ok);
}
