//! A USD stage a Python host holds in memory: read with the package's
//! usd-core through `usd/read_stage.py`'s `stage_json` (no file, no second
//! Python), and its layer written by `usd/write_layer.py`'s `layer_text`
//! over that same stage.

use pyo3::prelude::*;
use sssbake::{Error, Scene};
use sssbake_io::usd_writer::LayerWriter;
use sssbake_io::{ReadOptions, usd_reader};
use std::path::Path;
use std::sync::Arc;

/// The primvars UV set `uv_set` is read from, in the order a mesh's are
/// tried (what `stage_json` takes as `uv_primvars`).
#[pyfunction]
pub fn uv_primvars(uv_set: usize) -> Vec<String> {
    usd_reader::uv_primvars(uv_set)
}

/// The scene in `json` (what `stage_json` returned for the stage named
/// `input`).
pub fn scene_from_stage(json: &str, input: &Path, read: &ReadOptions) -> Result<Scene, Error> {
    let file = input.display().to_string();
    let value: serde_json::Value = serde_json::from_str(json).map_err(|e| {
        Error::from(sssbake_io::InputError {
            file: file.clone(),
            message: format!("the stage's contents are not JSON: {e}"),
        })
    })?;
    Ok(usd_reader::scene_from_json(&value, &file, read)?)
}

/// The layer writer that calls `callable(request_json) -> str` (the
/// package's `layer_text` over the stage in memory), taking the GIL for it.
pub fn layer_writer(callable: Py<PyAny>) -> LayerWriter {
    LayerWriter(Arc::new(move |request| {
        Python::attach(|py| {
            callable
                .call1(py, (request.to_string(),))
                .and_then(|text| text.extract::<String>(py))
                .map(String::into_bytes)
                .map_err(|e| e.value(py).to_string())
        })
    }))
}
