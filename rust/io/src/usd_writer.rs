//! The USD layer of a bake: written by `usd/write_layer.py` through
//! usd-core, it sublayers the input and gives each baked mesh a variant
//! set `sssbakeLook` (`original`, `baked`; `baked` selected) whose `baked`
//! variant binds a UsdPreviewSurface showing the look's linear EXR as
//! emission, with `sssbake:` attributes recording the bake.

use serde_json::{Value, json};
use std::fmt;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// `usd/write_layer.py`: run as a script by [`usd_layer`], or loaded as a
/// module by a host that holds the stage in memory (the Python package).
pub const WRITE_LAYER: &str = include_str!("../../../usd/write_layer.py");

/// Writes the layer in the caller's own usd-core instead of a Python
/// process: given the request `usd/write_layer.py` reads, it returns the
/// layer's text, as that script's `layer_text` does over the caller's
/// stage (which may exist only in memory).
#[derive(Clone)]
pub struct LayerWriter(pub Arc<WriteLayer>);

/// Given the request, the layer's text or why it could not be written.
pub type WriteLayer = dyn Fn(&Value) -> Result<Vec<u8>, String> + Send + Sync;

impl fmt::Debug for LayerWriter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("LayerWriter")
    }
}

/// One baked object for the layer.
#[derive(Clone, Debug)]
pub struct UsdBaked {
    /// The object's name.
    pub object: String,
    /// Its mesh prim's path in the input stage.
    pub prim: String,
    /// The file name of the look's linear EXR, beside the layer.
    pub emission: String,
    /// Every map written for it, by file name.
    pub maps: Vec<String>,
    /// How it was baked (material, model, method), as `sssbake:` attributes.
    pub attributes: Value,
    /// For an unwrapped object, its UVs per face corner, written as
    /// `primvars:sssbake_st` and read by its material instead of `st`.
    pub st: Option<Vec<[f32; 2]>>,
}

/// The layer's text (usda) for a layer in `folder` over the stage `input`;
/// the materials of objects baked in their own UVs read the first of
/// `uv_primvars` their mesh has, as the reader did. `writer` writes it in
/// the caller's usd-core; without one `usd/write_layer.py` runs in Python.
pub fn usd_layer(
    input: &Path,
    folder: &Path,
    objects: &[UsdBaked],
    settings: Value,
    uv_primvars: &[String],
    writer: Option<&LayerWriter>,
) -> Result<Vec<u8>, String> {
    // A stage only in memory has no file to sublayer: its writer says so
    // by the request's `input_from_layer` being null.
    let input = match (input.canonicalize(), writer) {
        (Ok(path), _) => Some(path),
        (Err(_), Some(_)) => None,
        (Err(e), None) => return Err(format!("cannot find the input: {e}")),
    };
    // The folder may not exist yet: the bake writes it last.
    let folder = folder
        .canonicalize()
        .or_else(|_| std::path::absolute(folder))
        .map_err(|e| format!("{}: {e}", folder.display()))?;
    let request = json!({
        "input": input,
        "input_from_layer": input.as_ref().map(|input| relative(&folder, input)),
        "objects": objects.iter().map(|o| json!({
            "object": o.object,
            "prim": o.prim,
            "emission": o.emission,
            "maps": o.maps,
            "attributes": o.attributes,
            "st": o.st,
        })).collect::<Vec<_>>(),
        "settings": settings,
        "uv_primvars": uv_primvars,
    });
    if let Some(LayerWriter(write)) = writer {
        return write(&request);
    }
    // The request can hold a UV per face corner: too long for an argument.
    let mut file =
        tempfile::NamedTempFile::new().map_err(|e| format!("cannot make a temporary file: {e}"))?;
    std::io::Write::write_all(&mut file, request.to_string().as_bytes())
        .map_err(|e| format!("cannot write a temporary file: {e}"))?;
    crate::python::run_script(WRITE_LAYER, [file.path()], "write the layer")
}

/// The path from folder `from` to file `to`, both absolute.
fn relative(from: &Path, to: &Path) -> String {
    let a: Vec<Component> = from.components().collect();
    let b: Vec<Component> = to.components().collect();
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut path = PathBuf::new();
    for _ in common..a.len() {
        path.push("..");
    }
    for part in &b[common..] {
        path.push(part.as_os_str());
    }
    path.to_string_lossy().replace('\\', "/")
}
