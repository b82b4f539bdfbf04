//! A copy of the input glTF in which the baked objects show their bake in
//! any viewer: each gets an unlit material (`KHR_materials_unlit`) whose
//! base colour is its `diffuse` PNG, read through the UV set it was baked
//! into. Everything else is kept as it was; buffers and images the input
//! names by relative path are copied beside the new file.
//!
//! The PNG's rows run top to bottom with glTF's v running down, so the
//! same image serves glTF and USD without a flip.

use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// One baked object to show in the copy.
#[derive(Clone, Debug)]
pub struct Baked {
    /// The glTF node the object came from.
    pub node: usize,
    /// The object's name, for the material's.
    pub object: String,
    /// The diffuse PNG's file name, beside the new asset.
    pub image: String,
    /// The TEXCOORD set the bake used.
    pub uv_set: usize,
}

/// A file to write, relative to the output folder.
pub type OutputFile = (PathBuf, Vec<u8>);

/// The files of a copy of `input` (.gltf or .glb) named like it, with the
/// `baked` objects' materials replaced.
pub fn gltf_copy(input: &Path, baked: &[Baked]) -> Result<Vec<OutputFile>, String> {
    let bytes = std::fs::read(input).map_err(|e| format!("cannot read: {e}"))?;
    let name = PathBuf::from(input.file_name().ok_or("not a file name")?);
    let folder = input.parent().unwrap_or(Path::new("."));
    let glb = bytes.starts_with(b"glTF");
    let (mut document, binary) = if glb {
        split_glb(&bytes)?
    } else {
        let value: Value = serde_json::from_slice(&bytes).map_err(|e| format!("not JSON: {e}"))?;
        (value, None)
    };
    let mut files = copied_references(&document, folder)?;
    show_bake(&mut document, baked)?;
    let text = serde_json::to_vec_pretty(&document).map_err(|e| e.to_string())?;
    let main = if glb {
        join_glb(text, binary.as_deref())
    } else {
        text
    };
    files.push((name, main));
    Ok(files)
}

/// Buffers and images the document names by a relative path, to copy.
fn copied_references(document: &Value, folder: &Path) -> Result<Vec<OutputFile>, String> {
    let mut files = Vec::new();
    for key in ["buffers", "images"] {
        for item in document[key].as_array().into_iter().flatten() {
            let Some(uri) = item["uri"].as_str() else {
                continue;
            };
            if uri.starts_with("data:")
                || uri.contains("://")
                || Path::new(uri).is_absolute()
                || uri.contains("..")
            {
                continue;
            }
            let path = folder.join(percent_decode(uri));
            let bytes = std::fs::read(&path)
                .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
            files.push((PathBuf::from(percent_decode(uri)), bytes));
        }
    }
    Ok(files)
}

/// Adds an unlit material per baked object and points its mesh's
/// primitives at it.
fn show_bake(document: &mut Value, baked: &[Baked]) -> Result<(), String> {
    for b in baked {
        let mesh = document["nodes"][b.node]["mesh"]
            .as_u64()
            .ok_or_else(|| format!("node {} has no mesh", b.node))? as usize;
        let image = push(
            document,
            "images",
            json!({ "uri": b.image, "name": b.image }),
        );
        let texture = push(document, "textures", json!({ "source": image }));
        let material = push(
            document,
            "materials",
            json!({
                "name": format!("{} (sssbake)", b.object),
                "pbrMetallicRoughness": {
                    "baseColorTexture": { "index": texture, "texCoord": b.uv_set },
                    "metallicFactor": 0.0,
                    "roughnessFactor": 1.0
                },
                "extensions": { "KHR_materials_unlit": {} }
            }),
        );
        for primitive in document["meshes"][mesh]["primitives"]
            .as_array_mut()
            .into_iter()
            .flatten()
        {
            primitive["material"] = json!(material);
        }
    }
    if !baked.is_empty() {
        let used = document
            .as_object_mut()
            .ok_or("the document is not an object")?
            .entry("extensionsUsed")
            .or_insert_with(|| json!([]));
        if let Some(list) = used.as_array_mut()
            && !list.iter().any(|e| e == "KHR_materials_unlit")
        {
            list.push(json!("KHR_materials_unlit"));
        }
    }
    Ok(())
}

/// Appends `item` to the array `key` (made if missing); its index.
fn push(document: &mut Value, key: &str, item: Value) -> usize {
    let object = document.as_object_mut().expect("checked by the caller");
    let list = object.entry(key).or_insert_with(|| json!([]));
    let array = list.as_array_mut().expect("glTF arrays are arrays");
    array.push(item);
    array.len() - 1
}

/// The JSON and binary chunks of a GLB.
fn split_glb(bytes: &[u8]) -> Result<(Value, Option<Vec<u8>>), String> {
    let word = |at: usize| -> Result<u32, String> {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .ok_or_else(|| "the GLB is cut short".to_string())
    };
    let json_length = word(12)? as usize;
    let json_bytes = bytes
        .get(20..20 + json_length)
        .ok_or("the GLB's JSON chunk is cut short")?;
    let document: Value =
        serde_json::from_slice(json_bytes).map_err(|e| format!("the GLB's JSON: {e}"))?;
    let binary_start = 20 + json_length;
    let binary = if bytes.len() >= binary_start + 8 {
        let length = word(binary_start)? as usize;
        Some(
            bytes
                .get(binary_start + 8..binary_start + 8 + length)
                .ok_or("the GLB's binary chunk is cut short")?
                .to_vec(),
        )
    } else {
        None
    };
    Ok((document, binary))
}

/// A GLB of `json` (padded with spaces) and `binary` (padded with zeros).
fn join_glb(mut json: Vec<u8>, binary: Option<&[u8]>) -> Vec<u8> {
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut binary = binary.map(<[u8]>::to_vec);
    if let Some(b) = &mut binary {
        while !b.len().is_multiple_of(4) {
            b.push(0);
        }
    }
    let total = 12 + 8 + json.len() + binary.as_ref().map_or(0, |b| 8 + b.len());
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    if let Some(b) = binary {
        out.extend((b.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(&b);
    }
    out
}

/// `%20`-style escapes decoded, as glTF URIs may carry them.
fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%'
            && i + 2 < bytes.len()
            && let Ok(v) = u8::from_str_radix(&uri[i + 1..i + 3], 16)
        {
            out.push(v);
            i += 3;
            continue;
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}
