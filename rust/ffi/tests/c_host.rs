//! A third door: a C program (tests/c/bake.c) that includes sssbake.h,
//! links the built libsssbake and bakes a lit quad, writes the same
//! subsurface map, byte for byte, as the Rust library baking that quad.

use glam::{Vec2, Vec3};
use sssbake::control::Control;
use sssbake::materials::{MaterialAssignment, preset};
use sssbake::{BakeRequest, Light, LightKind, Mesh, Method, Output, Scene, SceneObject, UvPolicy};
use sssbake_io::image_writer::{Precision, exr_bytes};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The folder holding the cdylib cargo built with this test: beside the
/// test binary in target/<profile>/deps/ (`cargo test` leaves it there;
/// `cargo build` copies it up to target/<profile>/, which may be older).
fn library_folder() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let folder = exe.parent().unwrap().to_path_buf();
    let library = folder.join(format!(
        "{}sssbake_ffi{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    ));
    assert!(library.exists(), "{} was not built", library.display());
    folder
}

/// The quad of bake.c, baked by the library: its arrays in mm, its sun in
/// W/m², skin1, 32², brute force, into its own UVs.
fn library_bake() -> Vec<u8> {
    let corners = [[-20.0, -20.0], [20.0, -20.0], [20.0, 20.0], [-20.0, 20.0]];
    let positions: Vec<Vec3> = corners.iter().map(|&[x, y]| Vec3::new(x, y, 0.0)).collect();
    let uvs = vec![
        Vec2::new(0.125, 0.125),
        Vec2::new(0.875, 0.125),
        Vec2::new(0.875, 0.875),
        Vec2::new(0.125, 0.875),
    ];
    let (mesh, _) = Mesh::new(
        "Quad",
        positions,
        Some(vec![Vec3::Z; 4]),
        Some(uvs.clone()),
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap();
    let scene = Scene {
        source: "test".into(),
        millimetres_per_unit: 1.0,
        objects: vec![SceneObject {
            mesh,
            uv_sets: vec![uvs],
            ..SceneObject::default()
        }],
        lights: vec![Light {
            name: "sun".into(),
            kind: LightKind::Directional { angle: 0.0 },
            color: [1.0, 0.9, 0.8],
            intensity: 3.0,
            position: Vec3::ZERO,
            direction: Vec3::new(0.0, -0.6, -0.8).normalize_or(Vec3::NEG_Z),
            tangent: Vec3::X,
            casts_shadow: true,
        }],
        ..Scene::default()
    };
    let request = BakeRequest {
        objects: vec!["Quad".into()],
        materials: MaterialAssignment::everywhere(preset("skin1").unwrap(), "preset"),
        resolution: 32,
        method: Method::Brute,
        outputs: vec![Output::Subsurface],
        uvs: UvPolicy::Keep,
        ..BakeRequest::default()
    };
    let plan = sssbake::plan(&scene, &request).unwrap();
    let (objects, _) = sssbake::bake(&scene, &plan, &Control::new()).unwrap();
    let image = objects[0].render(Output::Subsurface).unwrap();
    exr_bytes(&image, Precision::Float).unwrap()
}

#[test]
fn a_c_program_bakes_what_the_library_bakes() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let work = std::env::temp_dir().join(format!("sssbake-c-host-{}", std::process::id()));
    std::fs::create_dir_all(&work).unwrap();
    let program = work.join("bake");
    let folder = library_folder();
    let compiled = Command::new("cc")
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror"])
        .arg("-I")
        .arg(crate_dir.join("include"))
        .arg(crate_dir.join("tests/c/bake.c"))
        .arg("-o")
        .arg(&program)
        .arg("-L")
        .arg(&folder)
        .arg("-lsssbake_ffi")
        .arg(format!("-Wl,-rpath,{}", folder.display()))
        .output()
        .expect("a C compiler (the build needs one for xatlas)");
    assert!(
        compiled.status.success(),
        "bake.c does not compile: {}",
        String::from_utf8_lossy(&compiled.stderr)
    );
    let map = work.join("Quad_subsurface.exr");
    // cargo's LD_LIBRARY_PATH lists target/<profile>/ too, whose copy may be
    // older; the program finds this test's library by its rpath alone.
    let ran = Command::new(&program)
        .arg(&map)
        .env_remove("LD_LIBRARY_PATH")
        .output()
        .unwrap();
    assert!(
        ran.status.success(),
        "bake.c failed: {}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let written = std::fs::read(&map).unwrap();
    let expected = library_bake();
    assert!(written.len() > 1000, "{} bytes", written.len());
    assert!(
        written == expected,
        "the C program's map ({} bytes) differs from the library's ({} bytes)",
        written.len(),
        expected.len()
    );
    std::fs::remove_dir_all(&work).unwrap();
}
