//! glTF files written by the test, read back: geometry in millimetres,
//! transforms, UV sets, material hints, lights, and every kind of bad input.

use glam::Vec3;
use serde_json::{Value, json};
use sssbake::LightKind;
use sssbake_io::{ReadOptions, read_scene};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sssbake-io-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A 0.1 m square quad: positions, normals, two UV sets and indices in one
/// buffer, with `extra` merged into the document.
fn quad_document(dir: &Path, extra: Value, bin: Option<Vec<u8>>) -> PathBuf {
    let mut bytes = Vec::new();
    let floats = |bytes: &mut Vec<u8>, values: &[f32]| {
        values.iter().for_each(|v| bytes.extend(v.to_le_bytes()))
    };
    floats(
        &mut bytes,
        &[0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 0.1, 0.1, 0.0, 0.0, 0.1, 0.0],
    );
    floats(&mut bytes, &[0.0, 0.0, 1.0].repeat(4));
    floats(&mut bytes, &[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0]);
    floats(&mut bytes, &[0.0, 0.0, 0.5, 0.0, 0.5, 0.5, 0.0, 0.5]);
    for i in [0u16, 1, 2, 0, 2, 3] {
        bytes.extend(i.to_le_bytes());
    }
    let bin = bin.unwrap_or(bytes);
    std::fs::write(dir.join("quad.bin"), &bin).unwrap();
    let mut document = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"uri": "quad.bin", "byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 32},
            {"buffer": 0, "byteOffset": 128, "byteLength": 32},
            {"buffer": 0, "byteOffset": 160, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [0.1, 0.1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 4, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ],
        "materials": [{"name": "wax", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.7, 1.0]}}],
        "meshes": [{"name": "quad", "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TEXCOORD_1": 3},
            "indices": 4, "material": 0
        }]}],
        "nodes": [{"name": "Tile", "mesh": 0, "translation": [1.0, 0.0, 0.0], "scale": [2.0, 2.0, 2.0]}],
        "scenes": [{"nodes": [0]}],
        "scene": 0
    });
    merge(&mut document, extra);
    let path = dir.join("quad.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&document).unwrap()).unwrap();
    path
}

fn merge(target: &mut Value, extra: Value) {
    if let (Value::Object(t), Value::Object(e)) = (target, extra) {
        for (k, v) in e {
            t.insert(k, v);
        }
    }
}

#[test]
fn a_quad_arrives_in_millimetres_with_its_transform() {
    let path = quad_document(&scratch("quad"), json!({}), None);
    let scene = read_scene(&path, &ReadOptions::default()).unwrap();
    assert_eq!(scene.millimetres_per_unit, 1000.0);
    assert_eq!(scene.objects.len(), 1);
    let object = &scene.objects[0];
    assert_eq!(object.mesh.name, "Tile");
    assert_eq!(object.mesh.triangles.len(), 2);
    // 0.1 m scaled by 2 is 200 mm a side; the node moved it 1 m along x.
    assert!(
        (object.mesh.area() - 200.0 * 200.0).abs() < 1e-2,
        "{}",
        object.mesh.area()
    );
    assert!(object.mesh.positions[1].distance(Vec3::new(1200.0, 0.0, 0.0)) < 1e-3);
    assert_eq!(object.mesh.normals[0], Vec3::Z);
    assert_eq!(object.uv_sets.len(), 2);
    // TEXCOORD_0 (1, 1) with v flipped to run up.
    assert_eq!(
        object.mesh.uvs.as_ref().unwrap()[2],
        glam::Vec2::new(1.0, 0.0)
    );
    let material = object.material.as_ref().unwrap();
    assert_eq!(
        (material.name.as_str(), material.base_color),
        ("wax", [0.9, 0.8, 0.7, 1.0])
    );
    assert!(!material.is_translucent());

    let second = read_scene(
        &path,
        &ReadOptions {
            uv_set: 1,
            unit_scale: Some(10.0),
        },
    )
    .unwrap();
    assert_eq!(
        second.objects[0].mesh.uvs.as_ref().unwrap()[2],
        glam::Vec2::splat(0.5)
    );
    assert!((second.objects[0].mesh.area() - 2.0 * 2.0).abs() < 1e-4);
    let missing_set = read_scene(
        &path,
        &ReadOptions {
            uv_set: 4,
            unit_scale: None,
        },
    )
    .unwrap();
    assert!(missing_set.objects[0].mesh.uvs.is_none());
    assert!(missing_set.notes.iter().any(|n| n.contains("TEXCOORD_4")));
}

#[test]
fn translucent_materials_and_lights_are_read() {
    let half_turn = std::f64::consts::FRAC_1_SQRT_2;
    let extra = json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_volume", "KHR_materials_diffuse_transmission", "KHR_materials_ior"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "color": [1.0, 0.9, 0.8], "intensity": 3.0, "name": "sun"},
            {"type": "spot", "intensity": 50.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}
        ]}},
        "materials": [{"name": "skin", "extensions": {
            "KHR_materials_volume": {"thicknessFactor": 0.01, "attenuationDistance": 0.002, "attenuationColor": [0.9, 0.4, 0.3]},
            "KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.5, "diffuseTransmissionColorFactor": [1.0, 0.5, 0.4]},
            "KHR_materials_ior": {"ior": 1.4}
        }}],
        "nodes": [
            {"name": "Tile", "mesh": 0},
            {"name": "Sun", "rotation": [-half_turn, 0.0, 0.0, half_turn], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "Spot", "translation": [0.0, 0.0, 2.0], "extensions": {"KHR_lights_punctual": {"light": 1}}}
        ],
        "scenes": [{"nodes": [0, 1, 2]}]
    });
    let scene = read_scene(
        &quad_document(&scratch("lights"), extra, None),
        &ReadOptions::default(),
    )
    .unwrap();
    let material = scene.objects[0].material.as_ref().unwrap();
    assert!(material.is_translucent());
    assert_eq!(material.ior, Some(1.4));
    let volume = material.volume.as_ref().unwrap();
    assert!(
        (volume.attenuation_distance_mm - 2.0).abs() < 1e-4
            && (volume.thickness_mm - 10.0).abs() < 1e-4
    );
    assert_eq!(material.diffuse_transmission, Some(([1.0, 0.5, 0.4], 0.5)));
    // Extinction −ln(colour) / distance: each channel's mean free path.
    let subsurface = material.subsurface.as_ref().unwrap();
    for (c, colour) in [0.9f64, 0.4, 0.3].into_iter().enumerate() {
        let expected = 2.0 / -(colour as f32 as f64).ln();
        let got = subsurface.mean_free_path_mm[c];
        assert!(
            (got - expected).abs() < 1e-3 * expected,
            "{c}: {got} vs {expected}"
        );
    }
    assert!(subsurface.from.contains("KHR_materials_volume"));
    assert_eq!(scene.lights.len(), 2);
    let sun = scene.lights.iter().find(|l| l.name == "sun").unwrap();
    assert_eq!(sun.kind, LightKind::Directional { angle: 0.0 });
    // Blender's exporter writes W/m² × 683 lm/W as lux; read back as W/m².
    assert!((sun.intensity - 3.0 / 683.0).abs() < 1e-7);
    assert!(
        sun.direction.distance(Vec3::NEG_Y) < 1e-5,
        "{:?}",
        sun.direction
    );
    let spot = scene
        .lights
        .iter()
        .find(|l| matches!(l.kind, LightKind::Spot { .. }))
        .unwrap();
    assert!(spot.position.distance(Vec3::new(0.0, 0.0, 2000.0)) < 1e-3);
    assert!(
        (spot.intensity - 50.0 / 683.0).abs() < 1e-6,
        "W/sr from candela"
    );
}

#[test]
fn a_glb_reads_like_the_gltf() {
    let dir = scratch("glb");
    let gltf = quad_document(&dir, json!({}), None);
    let mut document: Value = serde_json::from_slice(&std::fs::read(&gltf).unwrap()).unwrap();
    let bin = std::fs::read(dir.join("quad.bin")).unwrap();
    document["buffers"] = json!([{"byteLength": bin.len()}]);
    let mut json_chunk = serde_json::to_vec(&document).unwrap();
    while !json_chunk.len().is_multiple_of(4) {
        json_chunk.push(b' ');
    }
    let mut bin_chunk = bin.clone();
    while !bin_chunk.len().is_multiple_of(4) {
        bin_chunk.push(0);
    }
    let total = 12 + 8 + json_chunk.len() + 8 + bin_chunk.len();
    let mut glb = Vec::new();
    glb.extend(b"glTF");
    glb.extend(2u32.to_le_bytes());
    glb.extend((total as u32).to_le_bytes());
    glb.extend((json_chunk.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(&json_chunk);
    glb.extend((bin_chunk.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(&bin_chunk);
    let path = dir.join("quad.glb");
    std::fs::write(&path, glb).unwrap();
    let (a, b) = (
        read_scene(&gltf, &ReadOptions::default()).unwrap(),
        read_scene(&path, &ReadOptions::default()).unwrap(),
    );
    assert_eq!(a.objects[0].mesh.positions, b.objects[0].mesh.positions);
    assert_eq!(a.objects[0].mesh.triangles, b.objects[0].mesh.triangles);
}

fn assert_refused(path: &Path, words: &[&str]) {
    let error = read_scene(path, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(error.starts_with(&path.display().to_string()), "{error}");
    for w in words {
        assert!(error.contains(w), "`{w}` not in: {error}");
    }
}

#[test]
fn bad_input_is_refused_with_the_file_and_what_is_wrong() {
    let dir = scratch("bad");
    assert_refused(&dir.join("absent.gltf"), &["cannot read"]);
    let malformed = dir.join("malformed.gltf");
    std::fs::write(
        &malformed,
        "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [",
    )
    .unwrap();
    assert_refused(&malformed, &["not a valid glTF"]);
    let unknown = dir.join("scene.obj");
    std::fs::write(&unknown, "v 0 0 0").unwrap();
    assert_refused(&unknown, &["unknown scene format"]);

    // A buffer shorter than its views.
    let short = quad_document(&scratch("short"), json!({}), Some(vec![0u8; 100]));
    assert_refused(&short, &["buffer"]);

    // An index past the last vertex.
    let dir = scratch("index");
    let mut bytes =
        std::fs::read(quad_document(&dir, json!({}), None).with_file_name("quad.bin")).unwrap();
    bytes[160..162].copy_from_slice(&9u16.to_le_bytes());
    let path = quad_document(&dir, json!({}), Some(bytes));
    assert_refused(&path, &["object `Tile`", "index 9"]);

    // A NaN position.
    let dir = scratch("nan");
    let mut bytes =
        std::fs::read(quad_document(&dir, json!({}), None).with_file_name("quad.bin")).unwrap();
    bytes[12..16].copy_from_slice(&f32::NAN.to_le_bytes());
    let path = quad_document(&dir, json!({}), Some(bytes));
    assert_refused(&path, &["object `Tile`", "non-finite position"]);
}
