//! `sssbake bake` end to end on the bundled marble, and its refusals.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn sssbake(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sssbake"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../examples/{name}/{name}.gltf"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sssbake-bake-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Adds a copy of the marble's `Ball` node named `name` to the scene; the copy.
fn add_twin<'a>(document: &'a mut serde_json::Value, name: &str) -> &'a mut serde_json::Value {
    let nodes = document["nodes"].as_array_mut().unwrap();
    let ball = nodes.iter().position(|n| n["name"] == "Ball").unwrap();
    let mut twin = nodes[ball].clone();
    twin["name"] = name.into();
    nodes.push(twin);
    let index = nodes.len() - 1;
    document["scenes"][0]["nodes"]
        .as_array_mut()
        .unwrap()
        .push(index.into());
    &mut document["nodes"][index]
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

#[test]
fn a_bake_writes_every_map_and_its_numbers_are_the_librarys() {
    let out = scratch("marble");
    let scene = example("marble");
    let result = sssbake(&[
        "bake",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--resolution",
        "64",
        "--preset",
        "marble",
        "--method",
        "brute",
        "--outputs",
        "subsurface,irradiance,diffuse,thickness,stretch,area",
        "--json",
    ]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let summary: serde_json::Value = serde_json::from_slice(&result.stdout).unwrap();
    assert_eq!(summary["objects"][0]["integrator"]["method"], "brute");
    assert_eq!(
        files_in(&out),
        [
            "Ball_area.exr",
            "Ball_diffuse.exr",
            "Ball_diffuse.png",
            "Ball_diffuse_emissive.png",
            "Ball_irradiance.exr",
            "Ball_irradiance.png",
            "Ball_stretch.exr",
            "Ball_subsurface.exr",
            "Ball_subsurface.png",
            "Ball_thickness.exr",
            "marble.bin",
            "marble.gltf",
        ]
    );
    // The glTF copy shows the diffuse map on the ball as emission, through
    // its own encoding; the input is untouched.
    let copy: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("marble.gltf")).unwrap()).unwrap();
    let material = copy["materials"].as_array().unwrap().last().unwrap();
    let texture =
        &copy["textures"][material["emissiveTexture"]["index"].as_u64().unwrap() as usize];
    let image = &copy["images"][texture["source"].as_u64().unwrap() as usize];
    assert_eq!(image["uri"], "Ball_diffuse_emissive.png");
    let strength = material["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"]
        .as_f64()
        .unwrap();
    let diffuse = sssbake_io::read_image(&out.join("Ball_diffuse.exr")).unwrap();
    let max = diffuse
        .texels
        .iter()
        .flatten()
        .fold(0.0f32, |a, &b| a.max(b));
    assert!(
        (strength as f32 - max).abs() <= 1e-6 * max,
        "{strength} against {max}"
    );
    assert!(!std::fs::read_to_string(&scene).unwrap().contains("sssbake"));
    let read = |name: &str| sssbake_io::read_image(&out.join(name)).unwrap();
    let (subsurface, irradiance, area, thickness) = (
        read("Ball_subsurface.exr"),
        read("Ball_irradiance.exr"),
        read("Ball_area.exr"),
        read("Ball_thickness.exr"),
    );
    assert_eq!((subsurface.width, subsurface.height), (64, 64));
    // Energy: exitance × area never exceeds irradiance × area, and marble
    // returns most of it.
    let total = |image: &sssbake::image::Image| -> f64 {
        image
            .texels
            .iter()
            .zip(&area.texels)
            .map(|(t, a)| t[1] as f64 * a[0] as f64)
            .sum()
    };
    let (out_flux, in_flux) = (total(&subsurface), total(&irradiance));
    assert!(
        in_flux > 0.0 && out_flux < in_flux && out_flux > 0.5 * in_flux,
        "{out_flux} / {in_flux}"
    );
    // The maps' areas (margins excluded: they copy texels) sum to the ball's.
    let ball_area = 4.0 * std::f64::consts::PI * 50.0f64.powi(2);
    let covered: f64 = area.texels.iter().map(|a| a[0] as f64).sum();
    assert!(covered > 0.9 * ball_area, "{covered} vs {ball_area}");
    // A ball 100 mm across is at most 100 mm thick.
    let thickest = thickness.texels.iter().map(|t| t[0]).fold(0.0, f32::max);
    assert!(thickest > 90.0 && thickest < 100.5, "{thickest}");
    // The file holds exactly what the library computes for the same bake.
    let library = {
        use sssbake::materials::{MaterialAssignment, preset};
        let read = sssbake_io::read_scene(&scene, &Default::default()).unwrap();
        let request = sssbake::BakeRequest {
            objects: vec!["Ball".into()],
            materials: MaterialAssignment::everywhere(preset("marble").unwrap(), "test"),
            resolution: 64,
            method: sssbake::Method::Brute,
            ..Default::default()
        };
        let plan = sssbake::plan(&read, &request).unwrap();
        let (objects, _) = sssbake::bake(&read, &plan, &sssbake::control::Control::new()).unwrap();
        objects[0].render(sssbake::Output::Subsurface).unwrap()
    };
    assert_eq!(library.texels, subsurface.texels);
    // Refuses to replace without --force; leaves the maps as they were.
    let before = std::fs::read(out.join("Ball_subsurface.exr")).unwrap();
    let again = sssbake(&[
        "bake",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--resolution",
        "32",
    ]);
    assert_eq!(again.status.code(), Some(3));
    assert_eq!(
        std::fs::read(out.join("Ball_subsurface.exr")).unwrap(),
        before
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bad_inputs_name_the_problem_and_leave_nothing_behind() {
    let scene = example("marble");
    let scene = scene.to_str().unwrap();
    let truncated_dir = scratch("truncated-input");
    std::fs::create_dir_all(&truncated_dir).unwrap();
    let truncated = truncated_dir.join("cut.gltf");
    let text = std::fs::read_to_string(example("marble")).unwrap();
    std::fs::write(&truncated, &text[..text.len() / 2]).unwrap();
    let unwritable = Path::new("/proc/sssbake-cannot-be-here");
    let input_folder = example("marble").parent().unwrap().to_path_buf();
    let cases: Vec<(Vec<String>, i32, &str)> = vec![
        (vec![truncated.display().to_string()], 1, "cut.gltf"),
        (
            vec![scene.into(), "--object".into(), "Nobody".into()],
            1,
            "Nobody",
        ),
        (
            vec![scene.into(), "--preset".into(), "granite".into()],
            2,
            "granite",
        ),
        (
            vec![scene.into(), "--resolution".into(), "0".into()],
            2,
            "--resolution",
        ),
        (
            vec![scene.into(), "--resolution".into(), "-5".into()],
            2,
            "'--resolution <RESOLUTION>': -5 must be between 1 and 16384",
        ),
        (
            vec![scene.into(), "--resolution".into(), "16385".into()],
            2,
            "--resolution",
        ),
        (
            vec![scene.into(), "--outputs".into(), "glow".into()],
            2,
            "glow",
        ),
        (
            vec![
                scene.into(),
                "--base-color".into(),
                "/nonexistent/skin.png".into(),
            ],
            1,
            "skin.png",
        ),
        (
            vec![
                scene.into(),
                "--irradiance".into(),
                "/nonexistent/light.exr".into(),
            ],
            1,
            "light.exr",
        ),
    ];
    for (i, (extra, code, named)) in cases.into_iter().enumerate() {
        let out = scratch(&format!("bad-{i}"));
        // Every case fails before any baking, so the default size is fine.
        let mut args: Vec<String> = vec!["bake".into(), "--out".into(), out.display().to_string()];
        args.extend(extra);
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let result = sssbake(&refs);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(code), "{args:?}: {stderr}");
        assert!(stderr.contains(named), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} left {}", out.display());
    }
    let result = sssbake(&[
        "bake",
        scene,
        "--out",
        unwritable.to_str().unwrap(),
        "--resolution",
        "32",
    ]);
    assert_eq!(
        result.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let result = sssbake(&[
        "bake",
        scene,
        "--out",
        input_folder.to_str().unwrap(),
        "--resolution",
        "32",
    ]);
    assert_eq!(result.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&result.stderr).contains("folder of the input"));
    assert!(
        !files_in(&input_folder)
            .iter()
            .any(|f| f.ends_with(".exr") || f.ends_with(".png"))
    );
    let _ = std::fs::remove_dir_all(&truncated_dir);
}

#[test]
fn a_sidecar_gives_objects_their_materials() {
    let dir = scratch("sidecar");
    std::fs::create_dir_all(&dir).unwrap();
    let sidecar = dir.join("materials.toml");
    std::fs::write(&sidecar, "[objects]\nBall = \"ketchup\"\n").unwrap();
    let out = dir.join("maps");
    let scene = example("marble");
    let result = sssbake(&[
        "bake",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--resolution",
        "32",
        "--materials",
        sidecar.to_str().unwrap(),
        "--json",
    ]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let summary: serde_json::Value = serde_json::from_slice(&result.stdout).unwrap();
    assert_eq!(summary["objects"][0]["material"]["name"], "ketchup");
    // A sidecar naming an object the scene lacks says which, and where.
    std::fs::write(&sidecar, "[objects]\nBal = \"ketchup\"\n").unwrap();
    let result = sssbake(&[
        "bake",
        scene.to_str().unwrap(),
        "--out",
        dir.join("other").to_str().unwrap(),
        "--materials",
        sidecar.to_str().unwrap(),
    ]);
    assert_eq!(result.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(
        stderr.contains("materials.toml") && stderr.contains("objects.Bal"),
        "{stderr}"
    );
    assert!(!dir.join("other").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_gltf_copy_brings_files_from_outside_the_inputs_folder_and_names_stay_apart() {
    let dir = scratch("outside");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::create_dir_all(dir.join("data")).unwrap();
    let marble = example("marble");
    let buffer = std::fs::read(marble.with_extension("bin")).unwrap();
    std::fs::write(dir.join("data/marble.bin"), &buffer).unwrap();
    let mut document: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&marble).unwrap()).unwrap();
    document["buffers"][0]["uri"] = "../data/marble.bin".into();
    // Two objects whose names differ only in characters a file name cannot hold.
    let twin = add_twin(&mut document, "Ball*");
    twin["translation"] = serde_json::json!([5.0, 0.0, 0.0]);
    let ball = document["nodes"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|n| n["name"] == "Ball")
        .unwrap();
    ball["name"] = "Ball?".into();
    let scene = scenes.join("twins.gltf");
    std::fs::write(&scene, serde_json::to_vec(&document).unwrap()).unwrap();
    let out = dir.join("out");
    let result = sssbake(&[
        "bake",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--resolution",
        "16",
        "--outputs",
        "diffuse",
    ]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let copy: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("twins.gltf")).unwrap()).unwrap();
    assert_eq!(copy["buffers"][0]["uri"], "external_marble.bin");
    assert_eq!(
        std::fs::read(out.join("external_marble.bin")).unwrap(),
        buffer
    );
    let files = files_in(&out);
    for stem in ["Ball_", "Ball_-2"] {
        assert!(files.contains(&format!("{stem}_diffuse.png")), "{files:?}");
        assert!(
            files.contains(&format!("{stem}_diffuse_emissive.png")),
            "{files:?}"
        );
    }
    // Each object's material shows its own map.
    let images: Vec<&str> = copy["images"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|i| i["uri"].as_str())
        .collect();
    assert!(
        images.contains(&"Ball__diffuse_emissive.png")
            && images.contains(&"Ball_-2_diffuse_emissive.png")
    );
}

#[test]
fn a_failure_after_the_first_object_leaves_nothing_behind() {
    let dir = scratch("midway");
    std::fs::create_dir_all(&dir).unwrap();
    let marble = example("marble");
    std::fs::copy(marble.with_extension("bin"), dir.join("marble.bin")).unwrap();
    let mut document: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&marble).unwrap()).unwrap();
    // A second ball whose mesh has no UVs: with an irradiance image, which
    // needs the object's own UVs, it fails after the first is baked.
    let mut bare = document["meshes"][0].clone();
    bare["primitives"][0]["attributes"]
        .as_object_mut()
        .unwrap()
        .remove("TEXCOORD_0");
    document["meshes"].as_array_mut().unwrap().push(bare);
    add_twin(&mut document, "Ball2")["mesh"] = 1.into();
    let scene = dir.join("two.gltf");
    std::fs::write(&scene, serde_json::to_vec(&document).unwrap()).unwrap();
    let out = dir.join("out");
    let result = sssbake(&[
        "bake",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--resolution",
        "16",
        "--irradiance",
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../docs/head_subsurface.png")
            .to_str()
            .unwrap(),
    ]);
    assert_eq!(result.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(stderr.contains("Ball2"), "{stderr}");
    assert!(!out.exists(), "{:?}", files_in(&out));
}

/// `--model montecarlo` bakes from a simulation kept in the cache folder
/// `SSSBAKE_CACHE_DIR` names; the second bake reads it back.
#[test]
fn the_monte_carlo_model_bakes_through_its_cache() {
    let out = scratch("montecarlo");
    let cache = scratch("montecarlo-cache");
    let scene = example("marble");
    let bake = || {
        Command::new(env!("CARGO_BIN_EXE_sssbake"))
            .args([
                "bake",
                scene.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--force",
                "--resolution",
                "32",
                // Ketchup: a low albedo, where diffusion fails.
                "--preset",
                "ketchup",
                "--model",
                "montecarlo",
            ])
            .env("SSSBAKE_CACHE_DIR", &cache)
            .output()
            .expect("the binary runs")
    };
    let first = bake();
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    // The profile's tallies, and the ball and slab totals of the
    // corrected model.
    let cached = files_in(&cache);
    assert!(
        cached.len() == 3
            && cached[0].starts_with("ball-")
            && cached[1].starts_with("montecarlo-")
            && cached[2].starts_with("slab-")
            && cached.iter().all(|name| name.ends_with(".json")),
        "{cached:?}"
    );
    let modified = |name: &str| {
        std::fs::metadata(cache.join(name))
            .unwrap()
            .modified()
            .unwrap()
    };
    let first_written: Vec<_> = cached.iter().map(|name| modified(name)).collect();
    assert!(bake().status.success());
    assert_eq!(
        files_in(&cache),
        cached,
        "the second bake simulates nothing new"
    );
    assert_eq!(
        cached.iter().map(|name| modified(name)).collect::<Vec<_>>(),
        first_written,
        "the second bake reads the cache and leaves it alone"
    );
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&cache);
}
