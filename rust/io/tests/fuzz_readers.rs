//! Property-based fuzzing of everything that reads a file a user hands in:
//! glTF (its JSON mutated value by value, and its bytes), GLB, material
//! TOML, sidecars and images. Each target mutates a valid input and asserts
//! that reading it never panics, that a refusal names the file, and that
//! what is accepted is usable (finite, in range). A short seeded run is
//! part of the test command; `SSSBAKE_FUZZ_CASES=1000000 cargo test
//! --release -p sssbake-io --test fuzz_readers` is the long one.

mod fuzz;

// The same quad the CLI's malformed-input corpus breaks.
#[path = "../../cli/tests/malformed/quad.rs"]
#[allow(dead_code)]
mod quad;

use fuzz::{mutated_bytes, mutated_json, run};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use serde_json::{Value, json};
use sssbake::Scene;
use sssbake::image::Image;
use sssbake::materials::Sidecar;
use sssbake_io::colour_texture::{ColourSpace, decode};
use sssbake_io::image_writer::{Precision, exr_bytes, png_bytes};
use sssbake_io::{InputError, ReadOptions, read_gltf_bytes, read_image};
use sssbake_profile::Material;
use std::path::{Path, PathBuf};

/// Where the fuzzed glTF claims to live: relative URIs resolve in a folder
/// that does not exist.
const GLTF_PATH: &str = "/nonexistent-sssbake-fuzz/quad.gltf";

fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, b)| n | u32::from(*b) << (16 - 8 * i));
        for k in 0..=chunk.len() {
            out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
        }
        out.push_str(&"=".repeat(3 - chunk.len()));
    }
    out
}

fn grey() -> Image {
    Image::new(4, 4, vec![[0.5; 3]; 16]).unwrap()
}

/// The quad with everything the reader reads: its buffer as a data URI, a
/// second UV set sparse over the first, a base colour texture (an embedded
/// PNG, transformed, sampled), volume, scatter and transmission
/// extensions, a child node and a spot light.
fn rich_document() -> Value {
    let mut d = quad::document(Some(&format!(
        "data:application/octet-stream;base64,{}",
        base64(&quad::bin())
    )));
    d["accessors"].as_array_mut().unwrap().push(json!({
        "bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2",
        "sparse": {"count": 1, "indices": {"bufferView": 3, "componentType": 5123},
                   "values": {"bufferView": 2, "byteOffset": 8}}
    }));
    d["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = 4.into();
    d["images"] =
        json!([{"uri": format!("data:image/png;base64,{}", base64(&png_bytes(&grey()).unwrap()))}]);
    d["samplers"] = json!([{"magFilter": 9728, "wrapS": 33648}]);
    d["textures"] = json!([{"source": 0, "sampler": 0}]);
    d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({
        "index": 0, "texCoord": 0,
        "extensions": {"KHR_texture_transform": {"offset": [0.1, 0.2], "rotation": 0.3, "scale": [2, 2]}}
    });
    d["materials"][0]["extensions"] = json!({
        "KHR_materials_volume": {"attenuationDistance": 0.01, "attenuationColor": [0.9, 0.5, 0.3],
                                 "thicknessFactor": 0.02},
        "KHR_materials_volume_scatter": {"multiscatterColor": [0.8, 0.6, 0.5], "scatterAnisotropy": 0.2},
        "KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.5,
                                               "diffuseTransmissionColorFactor": [1, 0.9, 0.8]},
        "KHR_materials_ior": {"ior": 1.4}
    });
    d["extensionsUsed"] = json!([
        "KHR_materials_volume",
        "KHR_lights_punctual",
        "KHR_texture_transform"
    ]);
    d["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "spot", "intensity": 100, "color": [1, 0.9, 0.8],
         "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}
    ]}});
    d["nodes"] = json!([
        {"name": "Tile", "mesh": 0, "children": [1], "scale": [2, 2, 2]},
        {"name": "Lamp", "translation": [0, 0, 1], "extensions": {"KHR_lights_punctual": {"light": 0}}}
    ]);
    d
}

/// A read that did not panic: refused naming the file, or a scene whose
/// every object is finite and indexed in range.
fn check_read(result: Result<Scene, InputError>, file: &str) -> Result<(), TestCaseError> {
    match result {
        Err(e) => {
            prop_assert_eq!(&e.file, file);
            prop_assert!(!e.message.is_empty());
        }
        Ok(scene) => {
            for object in &scene.objects {
                let mesh = &object.mesh;
                prop_assert!(mesh.positions.iter().all(|p| p.is_finite()));
                prop_assert!(mesh.normals.iter().all(|n| n.is_finite()));
                let n = mesh.positions.len();
                prop_assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
                if let Some(uvs) = &mesh.uvs {
                    prop_assert!(uvs.len() == n && uvs.iter().all(|uv| uv.is_finite()));
                }
            }
        }
    }
    Ok(())
}

fn run_gltf(target: &str, strategy: impl Strategy<Value = Vec<u8>>) {
    let path = Path::new(GLTF_PATH);
    run(target, strategy, |bytes: Vec<u8>| {
        check_read(
            read_gltf_bytes(&bytes, path, &ReadOptions::default()),
            GLTF_PATH,
        )
    });
}

#[test]
fn the_rich_base_reads_so_mutations_start_from_a_valid_file() {
    let bytes = serde_json::to_vec(&rich_document()).unwrap();
    let scene = read_gltf_bytes(&bytes, Path::new(GLTF_PATH), &ReadOptions::default()).unwrap();
    assert_eq!(scene.objects.len(), 1);
    assert_eq!(scene.objects[0].uv_sets.len(), 2);
    assert!(
        scene.objects[0]
            .colour_texture
            .as_ref()
            .unwrap()
            .image
            .is_ok()
    );
    assert_eq!(scene.lights.len(), 1);
    let glb = quad::glb(&quad::document(None), &quad::bin());
    let scene = read_gltf_bytes(
        &glb,
        Path::new("/nonexistent/quad.glb"),
        &ReadOptions::default(),
    );
    assert_eq!(scene.unwrap().objects.len(), 1);
}

#[test]
fn gltf_json_mutated_value_by_value_never_panics() {
    let strategy = mutated_json(rich_document(), 4).prop_map(|d| serde_json::to_vec(&d).unwrap());
    run_gltf("gltf-json", strategy);
}

#[test]
fn gltf_text_mutated_byte_by_byte_never_panics() {
    let base = serde_json::to_vec(&rich_document()).unwrap();
    run_gltf("gltf-bytes", mutated_bytes(base, 6));
}

#[test]
fn glb_mutated_byte_by_byte_never_panics() {
    let base = quad::glb(&quad::document(None), &quad::bin());
    run_gltf("glb-bytes", mutated_bytes(base, 6));
}

#[test]
fn glb_json_mutated_value_by_value_never_panics() {
    let strategy = mutated_json(quad::document(None), 4).prop_map(|d| quad::glb(&d, &quad::bin()));
    run_gltf("glb-json", strategy);
}

const MATERIAL: &str = include_str!("../../../examples/materials/skin_two_layer.toml");

/// A TOML value a hostile material file puts in place of a number.
fn toml_value() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "nan",
            "-nan",
            "inf",
            "-inf",
            "0",
            "-0.0",
            "-1",
            "1",
            "0.999999",
            "1e-300",
            "1e300",
            "1e400",
            "\"x\"",
            "[]",
            "[1, 2]",
            "[nan, 1, 1]",
            "[1, 1, 1, 1]",
            "{a = 1}",
            "true",
        ])
        .prop_map(String::from),
        any::<f64>().prop_map(|x| format!("{x:?}")),
    ]
}

/// A material file of up to four layers whose fields are drawn from
/// [`toml_value`] or left out.
fn material_text() -> impl Strategy<Value = String> {
    let field = |name: &'static str| {
        prop::option::of(toml_value()).prop_map(move |v| v.map(|v| format!("{name} = {v}\n")))
    };
    let layer = (
        field("sigma_a"),
        field("sigma_s"),
        field("g"),
        field("ior"),
        field("thickness_mm"),
    )
        .prop_map(|(a, s, g, i, t)| {
            let fields: String = [a, s, g, i, t].into_iter().flatten().collect();
            format!("[[layers]]\n{fields}")
        });
    (field("coat_ior"), prop::collection::vec(layer, 0..4))
        .prop_map(|(coat, layers)| format!("{}{}", coat.unwrap_or_default(), layers.concat()))
}

fn check_material(text: &str) -> Result<(), TestCaseError> {
    match Material::from_toml(text, "fuzz.toml", "fuzz") {
        Err(e) => prop_assert!(e.to_string().starts_with("fuzz.toml")),
        Ok(material) => {
            let layers = material.layers().unwrap();
            prop_assert!(!layers.is_empty());
            for layer in layers {
                let coefficients = layer.sigma_a.iter().chain(&layer.sigma_s);
                prop_assert!(coefficients.clone().all(|v| v.is_finite() && *v >= 0.0));
                prop_assert!(layer.g > -1.0 && layer.g < 1.0);
                prop_assert!(layer.ior.is_finite() && layer.ior > 0.0);
            }
            prop_assert!(material.finest_mean_free_path_mm() > 0.0);
        }
    }
    Ok(())
}

#[test]
fn material_files_of_hostile_values_never_panic_and_what_loads_is_physical() {
    run("material-values", material_text(), |text| {
        check_material(&text)
    });
}

#[test]
fn material_files_mutated_byte_by_byte_never_panic() {
    let strategy = mutated_bytes(MATERIAL.as_bytes().to_vec(), 6)
        .prop_map(|b| String::from_utf8_lossy(&b).into_owned());
    run("material-bytes", strategy, |text| check_material(&text));
}

#[test]
fn sidecars_mutated_never_panic() {
    let folder = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/materials");
    let base =
        "[objects]\nHead = \"skin3layer\"\nBall = \"skin_two_layer.toml\"\n\"*\" = \"skin1\"\n";
    let path = folder.join("fuzz-sidecar.toml");
    run(
        "sidecar",
        mutated_bytes(base.as_bytes().to_vec(), 6),
        |bytes| {
            let text = String::from_utf8_lossy(&bytes);
            if let Err(e) = Sidecar::parse(&text, &path, &folder) {
                prop_assert!(e.to_string().contains("fuzz-sidecar.toml"), "{}", e);
            }
            Ok(())
        },
    );
}

/// Reading mutated images: decoded from bytes as textures are, and from a
/// file as `--irradiance` reads it; either refuses or gives a finite,
/// non-negative image of the size it says.
fn run_images(target: &str, base: Vec<u8>, extension: &str) {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join(format!("fuzz.{extension}"));
    run(target, mutated_bytes(base, 4), |bytes| {
        // Written first: a case that aborts the process (an allocation
        // failure cannot be caught) is left in the file.
        std::fs::write(&path, &bytes).unwrap();
        let decoded = decode(&bytes, ColourSpace::Auto).ok().map(|(i, _)| i);
        for image in [decoded, read_image(&path).ok()].into_iter().flatten() {
            prop_assert_eq!(image.texels.len(), image.width * image.height);
            prop_assert!(
                image
                    .texels
                    .iter()
                    .flatten()
                    .all(|v| v.is_finite() && *v >= 0.0)
            );
        }
        Ok(())
    });
}

#[test]
fn exr_images_mutated_never_panic() {
    run_images("exr", exr_bytes(&grey(), Precision::Float).unwrap(), "exr");
}

#[test]
fn png_images_mutated_never_panic() {
    run_images("png", png_bytes(&grey()).unwrap(), "png");
}
