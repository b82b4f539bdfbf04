//! Bake, plan and batch from Python: the options arrive as the JSON of a
//! `BakeOptions` (the batch manifest's table, the CLI's flags), the answers
//! leave as the JSON the CLI prints with `--json`.

use crate::errors::{or_raise, to_python};
use crate::stage::{layer_writer, scene_from_stage};
use crate::watch::{Watchers, finish, run_watched};
use pyo3::prelude::*;
use sssbake::control::Control;
use sssbake::{BakeRequest, Error, Scene};
use sssbake_analysis::report::{check_folder, error_against_time};
use sssbake_io::batch::{BatchOptions, Manifest, run_batch};
use sssbake_io::{BakeOptions, bake_to_folder};
use std::path::{Path, PathBuf};

/// Reads the scene (the file at `input`, or the stage JSON a host read in
/// memory and names `input`) and makes the request from `options`.
fn load(
    input: &Path,
    stage_json: Option<&str>,
    options: &BakeOptions,
) -> Result<(Scene, BakeRequest), Error> {
    match stage_json {
        Some(json) => options.load_with(input, |read| scene_from_stage(json, input, read)),
        None => options.load(input),
    }
}

fn parse_options(options_json: &str) -> Result<BakeOptions, Error> {
    serde_json::from_str(options_json).map_err(|e| Error::field("options", e.to_string()))
}

fn to_json<T: serde::Serialize>(value: &T) -> String {
    serde_json::to_string(value).unwrap_or_else(|_| "null".into())
}

/// Bakes into `out` as `sssbake bake --json` does; returns the summary's
/// JSON. `stage_json` is a stage read in memory (then `layer_writer`
/// writes its USD layer in this process).
#[pyfunction]
#[pyo3(signature = (input, out, options_json, force, stage_json=None, layer_writer_callable=None, progress=None, cancel=None))]
#[allow(clippy::too_many_arguments)]
pub fn bake(
    py: Python<'_>,
    input: PathBuf,
    out: PathBuf,
    options_json: &str,
    force: bool,
    stage_json: Option<String>,
    layer_writer_callable: Option<Py<PyAny>>,
    progress: Option<Bound<'_, PyAny>>,
    cancel: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let options = or_raise(py, parse_options(options_json))?;
    let mut folder = options.folder(&out, force);
    folder.layer_writer = layer_writer_callable.map(layer_writer);
    let control = Control::new();
    let watchers = Watchers::whole(progress, cancel);
    let summary = run_watched(py, &control, &watchers, || {
        let (scene, request) = load(&input, stage_json.as_deref(), &options)?;
        let plan = sssbake::plan(&scene, &request)?;
        bake_to_folder(&input, &scene, &plan, &folder, &control)
    })?;
    let summary = or_raise(py, summary)?;
    finish(&watchers, "done")?;
    Ok(to_json(&summary))
}

/// The plan a bake with these options runs, as `sssbake plan --json`
/// prints it.
#[pyfunction]
#[pyo3(signature = (input, options_json, stage_json=None))]
pub fn plan(
    py: Python<'_>,
    input: PathBuf,
    options_json: &str,
    stage_json: Option<String>,
) -> PyResult<String> {
    let options = or_raise(py, parse_options(options_json))?;
    let control = Control::new();
    let watchers = Watchers::whole(None, None);
    let plan = run_watched(py, &control, &watchers, || {
        let (scene, request) = load(&input, stage_json.as_deref(), &options)?;
        sssbake::plan(&scene, &request)
    })?;
    Ok(to_json(&or_raise(py, plan)?))
}

/// Runs the manifest's batch as `sssbake batch --json` does; `on_asset`
/// gets each asset's report (JSON) as it ends. Returns the batch report.
#[pyfunction]
#[pyo3(signature = (manifest, out, force=false, jobs=1, assets=Vec::new(), on_asset=None))]
pub fn batch(
    py: Python<'_>,
    manifest: PathBuf,
    out: PathBuf,
    force: bool,
    jobs: usize,
    assets: Vec<String>,
    on_asset: Option<Py<PyAny>>,
) -> PyResult<String> {
    let manifest = or_raise(py, Manifest::read(&manifest))?;
    let options = BatchOptions {
        out,
        force,
        jobs,
        only: assets,
        ..BatchOptions::default()
    };
    let control = Control::new();
    let watchers = Watchers::whole(None, None);
    // The callback runs on the batch's threads, taking the GIL for the call;
    // its first exception is kept and raised when the batch ends.
    let failed_callback = std::sync::Mutex::new(None::<PyErr>);
    let report = run_watched(py, &control, &watchers, || {
        run_batch(&manifest, &options, |asset| {
            if let Some(callback) = &on_asset {
                Python::attach(|py| {
                    if let Err(e) = callback.call1(py, (to_json(asset),)) {
                        let mut kept = failed_callback.lock().unwrap_or_else(|p| p.into_inner());
                        kept.get_or_insert(e);
                    }
                });
            }
        })
    })?;
    if let Some(error) = failed_callback
        .into_inner()
        .unwrap_or_else(|p| p.into_inner())
    {
        return Err(error);
    }
    let report = report.map_err(|e| to_python(py, e))?;
    Ok(to_json(&report))
}

/// Runs every integrator on the scene across the ladder of settings, each
/// against the exact sum, and writes the report into `out` as `sssbake
/// report` does; returns report.json's JSON.
#[pyfunction]
#[pyo3(signature = (input, out, options_json, force, stage_json=None, progress=None, cancel=None))]
#[allow(clippy::too_many_arguments)]
pub fn report(
    py: Python<'_>,
    input: PathBuf,
    out: PathBuf,
    options_json: &str,
    force: bool,
    stage_json: Option<String>,
    progress: Option<Bound<'_, PyAny>>,
    cancel: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let options = or_raise(py, parse_options(options_json))?;
    or_raise(py, check_folder(&out, force))?;
    let control = Control::new();
    let watchers = Watchers::whole(progress, cancel);
    let files = run_watched(py, &control, &watchers, || {
        let (scene, request) = load(&input, stage_json.as_deref(), &options)?;
        let name = input.display().to_string();
        let files = error_against_time(&name, &scene, &request, &mut |_| {})?;
        files.write(&out)?;
        Ok(files)
    })?;
    let files = or_raise(py, files)?;
    finish(&watchers, "done")?;
    Ok(to_json(&files.report))
}

/// Every bake setting (`sssbake_io::settings::SETTINGS`) as JSON: name, doc,
/// kind and range, unit, part, default.
#[pyfunction]
pub fn settings() -> String {
    serde_json::to_string(&*sssbake_io::settings::SETTINGS).unwrap_or_default()
}

/// Every material preset: (name, description).
#[pyfunction]
pub fn presets() -> Vec<(&'static str, &'static str)> {
    sssbake_profile::presets::list()
}
