//! `sssbake plan` on a small glTF written by the test.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn sssbake(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sssbake"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// Two triangles of a 10 cm square, without UVs, and a point light.
fn write_scene(dir: &Path) -> PathBuf {
    let mut bin = Vec::new();
    for v in [
        0.0f32, 0.0, 0.0, 0.1, 0.0, 0.0, 0.1, 0.1, 0.0, 0.0, 0.1, 0.0,
    ] {
        bin.extend(v.to_le_bytes());
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend(i.to_le_bytes());
    }
    std::fs::write(dir.join("square.bin"), &bin).unwrap();
    let document = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 0.0, "name": "off"}]}},
        "buffers": [{"uri": "square.bin", "byteLength": bin.len()}],
        "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [0.1, 0.1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"name": "Square", "mesh": 0}, {"name": "Lamp", "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "scenes": [{"nodes": [0, 1]}]
    });
    let path = dir.join("square.gltf");
    std::fs::write(&path, serde_json::to_vec(&document).unwrap()).unwrap();
    path
}

#[test]
fn the_plan_says_what_it_will_do_and_leave_out() {
    let dir = std::env::temp_dir().join(format!("sssbake-plan-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = write_scene(&dir);
    let out = sssbake(&[
        "plan",
        scene.to_str().unwrap(),
        "--json",
        "--preset",
        "marble",
        "--method",
        "octree",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let plan: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(plan["millimetres_per_unit"], 1000.0);
    let square = &plan["objects"][0];
    assert_eq!(square["name"], "Square");
    assert!((square["area_mm2"].as_f64().unwrap() - 10_000.0).abs() < 1e-2);
    assert_eq!(square["uvs"]["unwrap"], true);
    assert_eq!(square["topology"], "1 part, 4 open edges");
    assert!(
        square["uvs"]["verdict"]
            .as_str()
            .unwrap()
            .contains("no UVs")
    );
    assert_eq!(square["material"]["name"], "marble");
    assert_eq!(square["material"]["source"], "--preset");
    assert_eq!(square["integrator"]["method"], "octree");
    let left_out: Vec<&str> = plan["left_out"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(
        left_out
            .iter()
            .any(|r| r.contains("light `off`: gives no light")),
        "{left_out:?}"
    );

    let text = sssbake(&["plan", scene.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("unwrap: its UVs are not usable") && text.contains("material `skin1`"),
        "{text}"
    );
    // After the unwrap the square's texels stand for its whole area.
    let texel_area = square["texel_area_mm2"].as_f64().unwrap();
    assert!((texel_area - 10_000.0).abs() < 100.0, "{texel_area}");
    assert!(square["texels"].as_u64().unwrap() > 0);
    // Auto names its integrator and says why.
    let auto = sssbake(&["plan", scene.to_str().unwrap(), "--json"]);
    let auto: Value = serde_json::from_slice(&auto.stdout).unwrap();
    let integrator = &auto["objects"][0]["integrator"];
    let method = integrator["method"].as_str().unwrap();
    assert!(["brute", "octree", "texture"].contains(&method), "{method}");
    assert!(integrator["reason"].as_str().unwrap().len() > 20);

    let unknown = sssbake(&["plan", scene.to_str().unwrap(), "--object", "Cube"]);
    assert_eq!(unknown.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&unknown.stderr);
    assert!(
        stderr.contains("no object named `Cube`") && stderr.contains("Square"),
        "{stderr}"
    );
    let zero = sssbake(&["plan", scene.to_str().unwrap(), "--resolution", "0"]);
    assert_eq!(zero.status.code(), Some(2));
    let negative = sssbake(&["plan", scene.to_str().unwrap(), "--resolution", "-5"]);
    assert_eq!(negative.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&negative.stderr).contains("--resolution"));
}

#[test]
fn a_gltf_naming_an_accessor_that_is_not_there_is_refused_as_bad_input() {
    let dir = std::env::temp_dir().join(format!("sssbake-plan-panic-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // The primitive names accessor 99 of none: the gltf crate's validation
    // would index out of bounds, so the reader checks first.
    let path = dir.join("broken.gltf");
    let text = r#"{"asset":{"version":"2.0"},
"meshes":[{"primitives":[{"attributes":{"POSITION":99}}]}],
"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]}"#;
    std::fs::write(&path, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_sssbake"))
        .args(["plan", path.to_str().unwrap()])
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("broken.gltf")
            && stderr.contains("mesh 0, primitive 0: POSITION names accessor 99"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
    let _ = std::fs::remove_dir_all(&dir);
}
