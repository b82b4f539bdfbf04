//! A copy of the input glTF in which the baked objects show their bake,
//! lit once, in any viewer: each gets a material that only emits, its
//! `emissiveTexture` the look's emissive PNG (`crate::look`, the map over
//! its strength, sRGB as glTF requires), read through the UV set it was
//! baked into, with `emissiveFactor` 1 and
//! `KHR_materials_emissive_strength` restoring the range; base colour
//! black, metallic 0, roughness 1 and `KHR_materials_specular` with
//! `specularFactor` 0 (no specular lobe at all), so lights add nothing.
//! Neither extension is required: a viewer without emissive strength
//! shows the bake's colours 1/strength as bright, one without specular
//! adds a highlight; refusing the file would show nothing.
//! `asset.generator` names sssbake. Everything else is kept as it was;
//! buffers and images the input names by relative path are copied beside
//! the new file (those outside the input's folder as `external_<name>`,
//! with the URI changed to match).
//!
//! An object that was unwrapped gets a new mesh on its node, carrying its
//! new UVs (seams split vertices, so positions and normals are new too),
//! in a buffer `<stem>_sssbake.bin` beside the copy.
//!
//! The PNG's rows run top to bottom with glTF's v running down, so the
//! same image serves glTF and USD without a flip.

use gltf::Glb;
use serde_json::{Value, json};
use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// One baked object to show in the copy.
#[derive(Clone, Debug)]
pub struct Baked {
    /// The glTF node the object came from.
    pub node: usize,
    /// The object's name, for the material's.
    pub object: String,
    /// The emissive PNG's file name, beside the new asset.
    pub image: String,
    /// What the PNG's linear values are multiplied by (the emissive
    /// strength).
    pub strength: f32,
    /// The TEXCOORD set the bake used.
    pub uv_set: usize,
    /// For an unwrapped object, its new mesh (read through TEXCOORD_0).
    pub geometry: Option<Geometry>,
}

/// A new mesh for a node, in the node's own frame and the file's units.
#[derive(Clone, Debug, Default)]
pub struct Geometry {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals.
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates, glTF's convention (v runs down the image).
    pub uvs: Vec<[f32; 2]>,
    /// Three vertex indices per triangle, counter-clockwise.
    pub indices: Vec<u32>,
}

/// A file to write, relative to the output folder.
pub type OutputFile = (PathBuf, Vec<u8>);

/// The extensions the baked materials use, listed in `extensionsUsed`.
pub const EXTENSIONS_USED: [&str; 2] =
    ["KHR_materials_emissive_strength", "KHR_materials_specular"];

/// The extensions a viewer must have to open the copy: none (see the
/// module's documentation), so nothing is added to `extensionsRequired`.
pub const EXTENSIONS_REQUIRED: [&str; 0] = [];

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
    let mut files = copied_references(&mut document, folder)?;
    let stem = name
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let geometry_file = format!("{stem}_sssbake.bin");
    if let Some(buffer) = add_geometry(&mut document, baked, &geometry_file) {
        files.push((PathBuf::from(geometry_file), buffer));
    }
    show_bake(&mut document, baked)?;
    let text = serde_json::to_vec_pretty(&document).map_err(|e| e.to_string())?;
    let main = if glb { join_glb(text, binary)? } else { text };
    files.push((name, main));
    Ok(files)
}

/// Buffers and images the document names by a relative path, to copy.
/// A path that leaves the input's folder (`..`) is copied beside the new
/// file under its own name, and the copy's URI says so.
fn copied_references(document: &mut Value, folder: &Path) -> Result<Vec<OutputFile>, String> {
    let mut files: Vec<OutputFile> = Vec::new();
    for key in ["buffers", "images"] {
        let items = document.get_mut(key).and_then(Value::as_array_mut);
        for item in items.into_iter().flatten() {
            let Some(uri) = item["uri"].as_str().map(crate::gltf_uri::percent_decode) else {
                continue;
            };
            if uri.starts_with("data:") || uri.contains("://") || Path::new(&uri).is_absolute() {
                continue;
            }
            let path = folder.join(&uri);
            let bytes = std::fs::read(&path)
                .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
            let mut target = PathBuf::from(&uri);
            if Path::new(&uri)
                .components()
                .any(|c| c == std::path::Component::ParentDir)
            {
                let name = Path::new(&uri).file_name().ok_or("a URI names no file")?;
                let name = name.to_string_lossy();
                target = PathBuf::from(format!("external_{name}"));
                let mut n = 1;
                while files.iter().any(|(f, _)| *f == target) {
                    n += 1;
                    target = PathBuf::from(format!("external{n}_{name}"));
                }
                item["uri"] = json!(uri_of(&target.to_string_lossy()));
            }
            if !files.iter().any(|(f, _)| *f == target) {
                files.push((target, bytes));
            }
        }
    }
    Ok(files)
}

/// Appends the unwrapped objects' meshes, reading one new buffer, and
/// points their nodes at them; the buffer's bytes, if there were any.
fn add_geometry(document: &mut Value, baked: &[Baked], file: &str) -> Option<Vec<u8>> {
    let mut bytes = Vec::new();
    let buffer = document["buffers"].as_array().map_or(0, Vec::len);
    let mut any = false;
    for b in baked {
        let Some(g) = &b.geometry else { continue };
        any = true;
        let mut view = |document: &mut Value, data: &[u8], target: u32| {
            let offset = bytes.len();
            bytes.extend_from_slice(data);
            while !bytes.len().is_multiple_of(4) {
                bytes.push(0);
            }
            push(
                document,
                "bufferViews",
                json!({ "buffer": buffer, "byteOffset": offset, "byteLength": data.len(), "target": target }),
            )
        };
        let floats = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
        let flat_positions: Vec<f32> = g.positions.iter().flatten().copied().collect();
        let (min, max) = g.positions.iter().fold(
            ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
            |(lo, hi), p| {
                (
                    [0, 1, 2].map(|k| lo[k].min(p[k])),
                    [0, 1, 2].map(|k| hi[k].max(p[k])),
                )
            },
        );
        let count = g.positions.len();
        let positions = view(document, &floats(&flat_positions), 34962);
        let normals_flat: Vec<f32> = g.normals.iter().flatten().copied().collect();
        let normals = view(document, &floats(&normals_flat), 34962);
        let uvs_flat: Vec<f32> = g.uvs.iter().flatten().copied().collect();
        let uvs = view(document, &floats(&uvs_flat), 34962);
        let index_bytes: Vec<u8> = g.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let indices = view(document, &index_bytes, 34963);
        let accessor = |document: &mut Value, view: usize, kind: &str, extra: Value| {
            let mut a =
                json!({ "bufferView": view, "componentType": 5126, "count": count, "type": kind });
            if let (Some(a), Some(extra)) = (a.as_object_mut(), extra.as_object()) {
                a.extend(extra.clone());
            }
            push(document, "accessors", a)
        };
        let position = accessor(
            document,
            positions,
            "VEC3",
            json!({ "min": min, "max": max }),
        );
        let normal = accessor(document, normals, "VEC3", json!({}));
        let uv = accessor(document, uvs, "VEC2", json!({}));
        let index = push(
            document,
            "accessors",
            json!({ "bufferView": indices, "componentType": 5125, "count": g.indices.len(), "type": "SCALAR" }),
        );
        let mesh = push(
            document,
            "meshes",
            json!({
                "name": format!("{} (sssbake unwrap)", b.object),
                "primitives": [{
                    "attributes": { "POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv },
                    "indices": index
                }]
            }),
        );
        document["nodes"][b.node]["mesh"] = json!(mesh);
    }
    if !any {
        return None;
    }
    push(
        document,
        "buffers",
        json!({ "uri": uri_of(file), "byteLength": bytes.len() }),
    );
    Some(bytes)
}

/// Adds a baked material per baked object and points its mesh's
/// primitives at it.
fn show_bake(document: &mut Value, baked: &[Baked]) -> Result<(), String> {
    for b in baked {
        let mesh = own_mesh(document, b.node)?;
        let image = push(
            document,
            "images",
            json!({ "uri": uri_of(&b.image), "name": b.image }),
        );
        let texture = push(document, "textures", json!({ "source": image }));
        let material = push(document, "materials", baked_material(b, texture));
        for primitive in document["meshes"][mesh]["primitives"]
            .as_array_mut()
            .into_iter()
            .flatten()
        {
            primitive["material"] = json!(material);
        }
    }
    if !baked.is_empty() {
        name_generator(document)?;
        let root = document
            .as_object_mut()
            .ok_or("the document is not an object")?;
        for (key, names) in [
            ("extensionsUsed", &EXTENSIONS_USED[..]),
            ("extensionsRequired", &EXTENSIONS_REQUIRED[..]),
        ] {
            if names.is_empty() {
                continue;
            }
            let list = root.entry(key).or_insert_with(|| json!([]));
            if let Some(list) = list.as_array_mut() {
                for name in names {
                    if !list.iter().any(|e| e == name) {
                        list.push(json!(name));
                    }
                }
            }
        }
    }
    Ok(())
}

/// The mesh of `node`, made its own: a mesh other nodes also show (an
/// instance) is copied for it, so its baked material shows on it alone
/// (each instance has its own bake) and the other nodes keep theirs. The
/// copy names the same accessors; no geometry is duplicated.
fn own_mesh(document: &mut Value, node: usize) -> Result<usize, String> {
    let mesh = document["nodes"][node]["mesh"]
        .as_u64()
        .ok_or_else(|| format!("node {node} has no mesh"))? as usize;
    let shown_by = document["nodes"].as_array().map_or(0, |nodes| {
        nodes.iter().filter(|n| n["mesh"] == json!(mesh)).count()
    });
    if shown_by < 2 {
        return Ok(mesh);
    }
    let copy = document["meshes"][mesh].clone();
    let own = push(document, "meshes", copy);
    document["nodes"][node]["mesh"] = json!(own);
    Ok(own)
}

/// The material of a baked object whose emissive PNG is `texture`: it
/// emits the PNG × strength and reflects nothing.
fn baked_material(b: &Baked, texture: usize) -> Value {
    json!({
        "name": format!("{} (sssbake)", b.object),
        "pbrMetallicRoughness": {
            "baseColorFactor": [0.0, 0.0, 0.0, 1.0],
            "metallicFactor": 0.0,
            "roughnessFactor": 1.0
        },
        "emissiveTexture": {
            "index": texture,
            "texCoord": if b.geometry.is_some() { 0 } else { b.uv_set }
        },
        "emissiveFactor": [1.0, 1.0, 1.0],
        "extensions": {
            "KHR_materials_emissive_strength": { "emissiveStrength": b.strength },
            "KHR_materials_specular": { "specularFactor": 0.0 }
        }
    })
}

/// `asset.generator`: sssbake and its version, then what made the input.
fn name_generator(document: &mut Value) -> Result<(), String> {
    let asset = document
        .get_mut("asset")
        .and_then(Value::as_object_mut)
        .ok_or("the document has no asset object")?;
    let ours = format!("sssbake {}", crate::VERSION);
    let generator = match asset.get("generator").and_then(Value::as_str) {
        Some(input) if !input.is_empty() => format!("{ours} (from a file by {input})"),
        _ => ours,
    };
    asset.insert("generator".into(), json!(generator));
    Ok(())
}

/// Appends `item` to the array `key` (made if missing or not an array:
/// the input was read as glTF, so that is a `null` at most); its index.
fn push(document: &mut Value, key: &str, item: Value) -> usize {
    let list = &mut document[key];
    if !list.is_array() {
        *list = json!([]);
    }
    match list {
        Value::Array(array) => {
            array.push(item);
            array.len() - 1
        }
        _ => unreachable!("made an array above"),
    }
}

/// The JSON and binary chunks of a GLB.
fn split_glb(bytes: &[u8]) -> Result<(Value, Option<Vec<u8>>), String> {
    // gltf 1.4 subtracts the 12-byte header from the declared total length
    // without checking it first, which overflows on a length below 12.
    let declared = bytes
        .get(8..12)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    if declared.is_some_and(|length| length < 12) {
        return Err("not a valid GLB: its length is shorter than its header".into());
    }
    let glb = Glb::from_slice(bytes).map_err(|e| format!("not a valid GLB: {e}"))?;
    let document: Value =
        serde_json::from_slice(&glb.json).map_err(|e| format!("the GLB's JSON: {e}"))?;
    Ok((document, glb.bin.map(Cow::into_owned)))
}

/// A GLB of `json` and `binary`; the gltf crate pads the JSON chunk with
/// spaces and the binary chunk with zeros to the 4-byte boundaries the
/// format requires, and writes the total length itself.
fn join_glb(json: Vec<u8>, binary: Option<Vec<u8>>) -> Result<Vec<u8>, String> {
    Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: 0,
        },
        json: Cow::Owned(json),
        bin: binary.map(Cow::Owned),
    }
    .to_vec()
    .map_err(|e| format!("cannot write the GLB: {e}"))
}

/// A file name as a URI path segment (spaces, `%` and non-ASCII escaped),
/// for the URIs the copy writes.
fn uri_of(file_name: &str) -> String {
    urlencoding::encode(file_name).into_owned()
}
