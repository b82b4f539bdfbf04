//! What the `gltf` crate takes on trust, checked before it is used: its
//! validation indexes the accessor list with a primitive's POSITION, and its
//! readers slice buffers with an accessor's offset, stride and count and
//! decode them by the type the reader expects. A file that lies about any of
//! these is refused here, naming the mesh, accessor or buffer view and what
//! is wrong, so that no number from the file reaches an unchecked index.

use gltf::accessor::{DataType, Dimensions};
use gltf::json::validation::Checked;
use gltf::mesh::Semantic;

/// Parses a .gltf or .glb file's bytes and validates the document; the GLB
/// binary chunk comes back with it.
pub(crate) fn parse(bytes: &[u8]) -> Result<(gltf::Document, Option<Vec<u8>>), String> {
    let json = if bytes.starts_with(b"glTF") {
        glb_frame(bytes).map_err(|e| format!("not a valid glTF file: {e}"))?;
        glb_json_chunk(bytes)
    } else {
        bytes
    };
    check_version(json)?;
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| format!("not a valid glTF file: {e}"))?;
    let root = document.into_json();
    positions_exist(&root)?;
    check_images(&root)?;
    let document =
        gltf::Document::from_json(root).map_err(|e| format!("not a valid glTF file: {e}"))?;
    Ok((document, blob))
}

/// The JSON chunk of a GLB whose frame [`glb_frame`] has checked (empty
/// when the first chunk is cut short).
fn glb_json_chunk(bytes: &[u8]) -> &[u8] {
    let length = bytes
        .get(12..16)
        .map_or(0, |w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]) as usize);
    bytes.get(20..20 + length).unwrap_or_default()
}

/// The document says it is glTF 2.x (`asset.version`, and `asset.minVersion`
/// when given): glTF 1.0 differs in meaning as well as shape (its meshes,
/// materials and techniques are not 2.0's), so reading it as 2.0 would bake
/// something the file does not say. A document whose `asset` cannot be read
/// at all is left to the parser, whose message says where it breaks.
fn check_version(json: &[u8]) -> Result<(), String> {
    #[derive(serde::Deserialize)]
    struct Head {
        asset: Asset,
    }
    #[derive(serde::Deserialize)]
    struct Asset {
        version: String,
        #[serde(rename = "minVersion")]
        min_version: Option<String>,
    }
    let Ok(Head { asset }) = serde_json::from_slice::<Head>(json) else {
        return Ok(());
    };
    let major = |version: &str| version.split('.').next().map(str::trim).map(String::from);
    if major(&asset.version).as_deref() != Some("2") {
        return Err(format!(
            "asset.version is \"{}\": sssbake reads glTF 2.x (convert the file to glTF 2.0 first)",
            asset.version
        ));
    }
    if let Some(min) = asset
        .min_version
        .filter(|min| major(min).as_deref() != Some("2"))
    {
        return Err(format!(
            "asset.minVersion is \"{min}\": sssbake reads glTF 2.x"
        ));
    }
    Ok(())
}

/// A GLB's header and chunk lengths agree with each other and with the
/// file (the crate subtracts them unchecked: a length under the header's
/// overflows).
fn glb_frame(bytes: &[u8]) -> Result<(), String> {
    let word = |at: usize| {
        bytes
            .get(at..at + 4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]) as usize)
    };
    let length = word(8).ok_or("a GLB header needs 12 bytes")?;
    if length < 12 + 8 || length > bytes.len() {
        return Err(format!(
            "the GLB header says {length} bytes, but the file has {} and a header and chunk need 20",
            bytes.len()
        ));
    }
    let mut at = 12usize;
    while at < length {
        let chunk = word(at)
            .filter(|_| at + 8 <= length)
            .ok_or(format!("a GLB chunk header at byte {at} is cut short"))?;
        at = at
            .checked_add(8 + chunk)
            .filter(|&end| end <= length)
            .ok_or(format!(
                "a GLB chunk at byte {at} runs past the file's {length} bytes"
            ))?;
    }
    Ok(())
}

/// Every primitive's POSITION names an accessor that exists (the crate's
/// validation looks it up without checking).
fn positions_exist(root: &gltf::json::Root) -> Result<(), String> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive
                .attributes
                .get(&Checked::Valid(gltf::json::mesh::Semantic::Positions));
            if let Some(index) = position.filter(|i| i.value() >= root.accessors.len()) {
                return Err(format!(
                    "{}, primitive {p}: POSITION names accessor {}, but the file has {} accessors",
                    mesh_name(mesh.name.as_deref(), m),
                    index.value(),
                    root.accessors.len()
                ));
            }
        }
    }
    Ok(())
}

fn mesh_name(name: Option<&str>, index: usize) -> String {
    match name {
        Some(name) => format!("mesh `{name}` (mesh {index})"),
        None => format!("mesh {index}"),
    }
}

/// Every buffer view lies inside its buffer, and every accessor's bytes
/// (sparse ones included) inside its buffer view, computed without
/// overflow; strides are no shorter than the elements they step over; an
/// accessor without data claims no more elements than the file has bytes.
pub(crate) fn check_accessors(document: &gltf::Document, data: &[&[u8]]) -> Result<(), String> {
    for view in document.views() {
        let buffer_len = data.get(view.buffer().index()).map_or(0, |d| d.len());
        let end = view.offset().checked_add(view.length());
        if end.is_none_or(|end| end > buffer_len) {
            return Err(format!(
                "buffer view {} ends at byte {} but its buffer has {} bytes",
                view.index(),
                view.offset() as u128 + view.length() as u128,
                buffer_len
            ));
        }
    }
    let total_bytes: usize = data.iter().map(|d| d.len()).sum();
    for accessor in document.accessors() {
        let name = format!("accessor {}", accessor.index());
        if accessor.count() == 0 {
            return Err(format!("{name} has count 0 (glTF requires at least 1)"));
        }
        let element = accessor.size();
        match accessor.view() {
            Some(view) => fits(&name, accessor.offset(), accessor.count(), element, &view)?,
            None if accessor.count() > total_bytes => {
                return Err(format!(
                    "{name} has no buffer view and claims {} elements, more than the {} bytes \
                     of data in the file's buffers",
                    accessor.count(),
                    total_bytes
                ));
            }
            None => {}
        }
        if let Some(sparse) = accessor.sparse() {
            let count = sparse.count();
            if count == 0 || count > accessor.count() {
                return Err(format!(
                    "{name}: sparse.count is {count}, but it must be from 1 to the accessor's \
                     count {}",
                    accessor.count()
                ));
            }
            let indices = sparse.indices();
            fits(
                &format!("{name}'s sparse.indices"),
                indices.offset(),
                count,
                indices.index_type().size(),
                &indices.view(),
            )?;
            let values = sparse.values();
            fits(
                &format!("{name}'s sparse.values"),
                values.offset(),
                count,
                element,
                &values.view(),
            )?;
        }
    }
    Ok(())
}

/// `count` elements of `element` bytes from `offset` in `view`, at the
/// view's stride, end inside the view.
fn fits(
    name: &str,
    offset: usize,
    count: usize,
    element: usize,
    view: &gltf::buffer::View,
) -> Result<(), String> {
    let stride = view.stride().unwrap_or(element);
    if stride < element {
        return Err(format!(
            "{name}: buffer view {} has byteStride {stride}, shorter than its {element}-byte \
             elements",
            view.index()
        ));
    }
    let needed = (count as u128 - 1) * stride as u128 + element as u128 + offset as u128;
    if needed > view.length() as u128 {
        return Err(format!(
            "{name} needs {needed} bytes ({count} elements) but buffer view {} has {}",
            view.index(),
            view.length()
        ));
    }
    Ok(())
}

/// Every image has a source the crate can hand out: a URI, or a buffer
/// view with a MIME type (the crate unwraps whichever it expects).
fn check_images(root: &gltf::json::Root) -> Result<(), String> {
    for (i, image) in root.images.iter().enumerate() {
        match (&image.uri, &image.buffer_view, &image.mime_type) {
            (Some(_), _, _) | (None, Some(_), Some(_)) => {}
            (None, Some(_), None) => {
                return Err(format!("image {i} has a bufferView but no mimeType"));
            }
            (None, None, _) => {
                return Err(format!("image {i} has neither a uri nor a bufferView"));
            }
        }
    }
    Ok(())
}

/// The attributes and indices the reader decodes have the types it decodes
/// them as: POSITION and NORMAL float VEC3, TEXCOORD_n VEC2 of floats or
/// normalised unsigned bytes or shorts, indices unsigned SCALAR.
pub(crate) fn check_primitives(document: &gltf::Document) -> Result<(), String> {
    use DataType::{F32, U8, U16, U32};
    for mesh in document.meshes() {
        for primitive in mesh.primitives() {
            let at = || {
                format!(
                    "{}, primitive {}",
                    mesh_name(mesh.name(), mesh.index()),
                    primitive.index()
                )
            };
            let typed = |accessor: &gltf::Accessor| {
                format!(
                    "accessor {} is {:?} {:?}",
                    accessor.index(),
                    accessor.data_type(),
                    accessor.dimensions()
                )
            };
            for (semantic, accessor) in primitive.attributes() {
                let (ok, wanted) = match &semantic {
                    Semantic::Positions | Semantic::Normals => (
                        accessor.data_type() == F32 && accessor.dimensions() == Dimensions::Vec3,
                        "F32 Vec3",
                    ),
                    Semantic::TexCoords(_) => (
                        accessor.dimensions() == Dimensions::Vec2
                            && (accessor.data_type() == F32
                                || (matches!(accessor.data_type(), U8 | U16)
                                    && accessor.normalized())),
                        "Vec2 of F32, or of normalized U8 or U16",
                    ),
                    _ => (true, ""),
                };
                if !ok {
                    return Err(format!(
                        "{}: {} names {}, but it must be {wanted}",
                        at(),
                        semantic_name(&semantic),
                        typed(&accessor)
                    ));
                }
            }
            if let Some(indices) = primitive.indices() {
                let ok = indices.dimensions() == Dimensions::Scalar
                    && matches!(indices.data_type(), U8 | U16 | U32);
                if !ok {
                    return Err(format!(
                        "{}: indices name {}, but they must be a Scalar of U8, U16 or U32",
                        at(),
                        typed(&indices)
                    ));
                }
            }
        }
    }
    Ok(())
}

/// An attribute's name as the file spells it (`TEXCOORD_0`).
fn semantic_name(semantic: &Semantic) -> String {
    // The crate implements `ToString` without `Display`.
    semantic.to_string()
}
