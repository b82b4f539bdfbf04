//! The glTF copy the bake writes: URIs with escapes are decoded to find
//! the files they name and escaped again where the copy writes its own, and
//! a GLB keeps its binary chunk and the format's padding.

use serde_json::{Value, json};
use sssbake_io::gltf_writer::{Baked, EXTENSIONS_REQUIRED, EXTENSIONS_USED, gltf_copy};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sssbake-io-copy-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// One triangle: three positions and three u16 indices (42 bytes, so a
/// binary chunk of it needs padding).
fn triangle_bytes() -> Vec<u8> {
    let mut bytes = Vec::new();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        bytes.extend(v.to_le_bytes());
    }
    for i in [0u16, 1, 2] {
        bytes.extend(i.to_le_bytes());
    }
    bytes
}

/// A document with one triangle node reading `buffer` (with its `uri`, if
/// any) and the extra `images`.
fn triangle_document(buffer: Value, images: Value) -> Value {
    json!({
        "asset": {"version": "2.0"},
        "buffers": [buffer],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 6}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}
        ],
        "images": images,
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"name": "Tile", "mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0
    })
}

fn baked(image: &str) -> Baked {
    Baked {
        node: 0,
        object: "Tile".into(),
        image: image.into(),
        strength: 2.5,
        uv_set: 0,
        geometry: None,
    }
}

fn file<'a>(files: &'a [(PathBuf, Vec<u8>)], name: &str) -> &'a [u8] {
    files
        .iter()
        .find(|(f, _)| f == Path::new(name))
        .map(|(_, bytes)| bytes.as_slice())
        .unwrap_or_else(|| {
            let names: Vec<_> = files.iter().map(|(f, _)| f.display().to_string()).collect();
            panic!("no {name} among {names:?}")
        })
}

#[test]
fn escaped_uris_find_their_files_and_written_uris_are_escaped() {
    let root = scratch("uris");
    let scenes = root.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let bytes = triangle_bytes();
    // `%` before a multi-byte character is no escape: the name is literal.
    std::fs::write(scenes.join("tri%é.bin"), &bytes).unwrap();
    std::fs::write(scenes.join("tex one.png"), b"png").unwrap();
    // Escapes that do not spell UTF-8: the URI is the file's name as written.
    std::fs::write(scenes.join("raw%FF.png"), b"raw").unwrap();
    std::fs::write(root.join("upé.png"), b"up").unwrap();
    let document = triangle_document(
        json!({"uri": "tri%é.bin", "byteLength": bytes.len()}),
        json!([{"uri": "tex%20one.png"}, {"uri": "raw%FF.png"}, {"uri": "../up%C3%A9.png"}]),
    );
    let input = scenes.join("tri.gltf");
    std::fs::write(&input, serde_json::to_vec(&document).unwrap()).unwrap();

    let files = gltf_copy(&input, &[baked("Tile ä_diffuse.png")]).unwrap();
    assert_eq!(file(&files, "tri%é.bin"), bytes);
    assert_eq!(file(&files, "tex one.png"), b"png");
    assert_eq!(file(&files, "raw%FF.png"), b"raw");
    assert_eq!(file(&files, "external_upé.png"), b"up");
    let copy: Value = serde_json::from_slice(file(&files, "tri.gltf")).unwrap();
    // URIs the input wrote stay as written; the ones the copy makes are escaped.
    assert_eq!(copy["buffers"][0]["uri"], "tri%é.bin");
    assert_eq!(copy["images"][0]["uri"], "tex%20one.png");
    assert_eq!(copy["images"][2]["uri"], "external_up%C3%A9.png");
    assert_eq!(copy["images"][3]["uri"], "Tile%20%C3%A4_diffuse.png");
    assert_eq!(copy["images"][3]["name"], "Tile ä_diffuse.png");
    let _ = std::fs::remove_dir_all(&root);
}

/// A GLB assembled by hand, with chunk lengths as given (no padding).
fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

#[test]
fn a_glb_copy_keeps_its_binary_chunk_and_the_padding() {
    let dir = scratch("glb");
    let bytes = triangle_bytes();
    let document = triangle_document(json!({"byteLength": bytes.len()}), json!([]));
    // Neither chunk of the input is padded: the copy must pad both.
    let mut json_chunk = serde_json::to_vec(&document).unwrap();
    if json_chunk.len().is_multiple_of(4) {
        json_chunk.push(b' ');
    }
    let input = dir.join("tri.glb");
    std::fs::write(&input, glb(&json_chunk, &bytes)).unwrap();

    let files = gltf_copy(&input, &[baked("Tile_diffuse.png")]).unwrap();
    assert_eq!(files.len(), 1, "a GLB carries its buffer inside");
    let out = file(&files, "tri.glb");
    assert_eq!(out.len() % 4, 0);
    let declared = u32::from_le_bytes(out[8..12].try_into().unwrap()) as usize;
    assert_eq!(declared, out.len());
    let json_length = u32::from_le_bytes(out[12..16].try_into().unwrap()) as usize;
    assert_eq!(json_length % 4, 0);
    let json_end = 20 + json_length;
    let written = String::from_utf8(out[20..json_end].to_vec()).unwrap();
    assert!(written.trim_end_matches(' ').ends_with('}'), "{written}");
    let bin_length = u32::from_le_bytes(out[json_end..json_end + 4].try_into().unwrap()) as usize;
    assert_eq!(bin_length, bytes.len().next_multiple_of(4));
    assert_eq!(&out[json_end + 4..json_end + 8], b"BIN\0");
    let bin = &out[json_end + 8..];
    assert_eq!(&bin[..bytes.len()], bytes);
    assert!(bin[bytes.len()..].iter().all(|&b| b == 0));

    let copy: Value = serde_json::from_str(written.trim_end()).unwrap();
    assert_eq!(copy["images"][0]["uri"], "Tile_diffuse.png");
    assert_eq!(copy["meshes"][0]["primitives"][0]["material"], 0);
    // The copy is a glTF the gltf crate reads, with the same geometry.
    let read = gltf::Gltf::from_slice(out).unwrap();
    assert_eq!(
        read.blob.as_deref().map(|b| &b[..bytes.len()]),
        Some(&bytes[..])
    );
    assert_eq!(read.document.materials().count(), 1);

    // With nothing more baked, a copy of the copy is the same file.
    std::fs::write(&input, out).unwrap();
    std::fs::write(dir.join("Tile_diffuse.png"), b"png").unwrap();
    let again = gltf_copy(&input, &[]).unwrap();
    assert_eq!(file(&again, "tri.glb"), out);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_glb_shorter_than_its_header_is_refused() {
    let dir = scratch("short-glb");
    let mut bytes = glb(b"{}  ", b"");
    bytes[8..12].copy_from_slice(&8u32.to_le_bytes());
    let input = dir.join("short.glb");
    std::fs::write(&input, bytes).unwrap();
    let error = gltf_copy(&input, &[]).unwrap_err();
    assert!(error.contains("not a valid GLB"), "{error}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_baked_material_only_emits_the_map_at_its_strength() {
    let dir = scratch("look");
    let bytes = triangle_bytes();
    std::fs::write(dir.join("tri.bin"), &bytes).unwrap();
    let mut document = triangle_document(
        json!({"uri": "tri.bin", "byteLength": bytes.len()}),
        json!([]),
    );
    // The input already uses one of the extensions and requires another.
    document["extensionsUsed"] = json!(["KHR_materials_specular", "KHR_texture_transform"]);
    document["extensionsRequired"] = json!(["KHR_texture_transform"]);
    document["asset"]["generator"] = json!("Khronos glTF Blender I/O v5.0.21");
    let input = dir.join("tri.gltf");
    std::fs::write(&input, serde_json::to_vec(&document).unwrap()).unwrap();

    let mut tile = baked("Tile_diffuse_emissive.png");
    tile.uv_set = 1;
    let files = gltf_copy(&input, &[tile]).unwrap();
    let copy: Value = serde_json::from_slice(file(&files, "tri.gltf")).unwrap();
    let material = &copy["materials"][0];
    assert_eq!(copy["meshes"][0]["primitives"][0]["material"], 0);
    assert_eq!(material["name"], "Tile (sssbake)");
    let pbr = &material["pbrMetallicRoughness"];
    assert_eq!(pbr["baseColorFactor"], json!([0.0, 0.0, 0.0, 1.0]));
    assert_eq!(pbr["metallicFactor"], 0.0);
    assert_eq!(pbr["roughnessFactor"], 1.0);
    assert!(pbr.get("baseColorTexture").is_none());
    assert_eq!(material["emissiveFactor"], json!([1.0, 1.0, 1.0]));
    assert_eq!(
        material["emissiveTexture"],
        json!({"index": 0, "texCoord": 1})
    );
    assert_eq!(copy["textures"][0]["source"], 0);
    assert_eq!(copy["images"][0]["uri"], "Tile_diffuse_emissive.png");
    let extensions = &material["extensions"];
    assert_eq!(
        extensions["KHR_materials_emissive_strength"]["emissiveStrength"],
        2.5
    );
    assert_eq!(extensions["KHR_materials_specular"]["specularFactor"], 0.0);
    assert!(extensions.get("KHR_materials_unlit").is_none());
    // Listed once each, after what the input listed; nothing more required.
    assert_eq!(
        copy["extensionsUsed"],
        json!([
            "KHR_materials_specular",
            "KHR_texture_transform",
            "KHR_materials_emissive_strength"
        ])
    );
    assert_eq!(copy["extensionsRequired"], json!(["KHR_texture_transform"]));
    assert_eq!(
        copy["asset"]["generator"],
        format!(
            "sssbake {} (from a file by Khronos glTF Blender I/O v5.0.21)",
            sssbake_io::VERSION
        )
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_copy_of_a_file_without_extensions_lists_the_ones_it_uses_and_requires_none() {
    let dir = scratch("look-bare");
    let bytes = triangle_bytes();
    std::fs::write(dir.join("tri.bin"), &bytes).unwrap();
    let document = triangle_document(
        json!({"uri": "tri.bin", "byteLength": bytes.len()}),
        json!([]),
    );
    let input = dir.join("tri.gltf");
    std::fs::write(&input, serde_json::to_vec(&document).unwrap()).unwrap();

    let files = gltf_copy(&input, &[baked("Tile_diffuse_emissive.png")]).unwrap();
    let copy: Value = serde_json::from_slice(file(&files, "tri.gltf")).unwrap();
    assert_eq!(copy["extensionsUsed"], json!(EXTENSIONS_USED));
    assert!(EXTENSIONS_REQUIRED.is_empty());
    assert!(copy.get("extensionsRequired").is_none());
    assert_eq!(
        copy["asset"]["generator"],
        format!("sssbake {}", sssbake_io::VERSION)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two nodes showing one mesh (instances) are two objects, each with its
/// own bake: each shows its own look, and a third instance that was not
/// baked keeps the input's material.
#[test]
fn instances_of_one_mesh_each_show_their_own_bake() {
    let dir = scratch("instances");
    let bytes = triangle_bytes();
    std::fs::write(dir.join("tri.bin"), &bytes).unwrap();
    let mut document = triangle_document(
        json!({"uri": "tri.bin", "byteLength": bytes.len()}),
        json!([]),
    );
    document["materials"] = json!([{"name": "Skin"}]);
    document["meshes"][0]["primitives"][0]["material"] = json!(0);
    document["nodes"] = json!([
        {"name": "Tile", "mesh": 0},
        {"name": "Copy", "mesh": 0, "translation": [2, 0, 0]},
        {"name": "Unbaked", "mesh": 0, "translation": [4, 0, 0]}
    ]);
    document["scenes"] = json!([{"nodes": [0, 1, 2]}]);
    let input = dir.join("tri.gltf");
    std::fs::write(&input, serde_json::to_vec(&document).unwrap()).unwrap();

    let tile = baked("Tile_diffuse_emissive.png");
    let copy_of_tile = Baked {
        node: 1,
        object: "Copy".into(),
        ..baked("Copy_diffuse_emissive.png")
    };
    let files = gltf_copy(&input, &[tile, copy_of_tile]).unwrap();
    let copy: Value = serde_json::from_slice(file(&files, "tri.gltf")).unwrap();
    let shown = |node: usize| {
        let mesh = copy["nodes"][node]["mesh"].as_u64().unwrap() as usize;
        let material = copy["meshes"][mesh]["primitives"][0]["material"]
            .as_u64()
            .unwrap() as usize;
        let material = &copy["materials"][material];
        let image = material["emissiveTexture"]["index"]
            .as_u64()
            .map(|t| copy["images"][copy["textures"][t as usize]["source"].as_u64().unwrap() as usize]["uri"].clone());
        (material["name"].clone(), image)
    };
    assert_eq!(
        shown(0),
        (
            json!("Tile (sssbake)"),
            Some(json!("Tile_diffuse_emissive.png"))
        )
    );
    assert_eq!(
        shown(1),
        (
            json!("Copy (sssbake)"),
            Some(json!("Copy_diffuse_emissive.png"))
        )
    );
    assert_eq!(shown(2), (json!("Skin"), None));
    // The copies name the input's accessors: no geometry is duplicated.
    assert_eq!(copy["accessors"].as_array().unwrap().len(), 2);
    assert_eq!(copy["meshes"].as_array().unwrap().len(), 3);
    let _ = std::fs::remove_dir_all(&dir);
}
