//! A material's reflectance profile as numpy arrays.

use crate::errors::or_raise;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sssbake::Error;
use sssbake_analysis::profile_report::{ProfileRequest, analyse, material as material_of};
use sssbake_profile::{Material, Model, Rgb};
use std::path::PathBuf;

/// The profile of a preset or TOML material under `model` (the
/// material's own when `None`), sampled at `radii` (mm, increasing; sixty
/// radii over its reach when `None`): a dict of numpy arrays, R(r) and
/// T(r) in 1/mm² per channel, with the totals and d_max (mm) at `epsilon`.
/// The `montecarlo` model simulates `photons` per channel from `seed`.
#[pyfunction]
#[pyo3(signature = (preset=None, material=None, model=None, radii=None, epsilon=1e-3, gaussians=6, photons=100_000, seed=1))]
#[allow(clippy::too_many_arguments)]
pub fn profile<'py>(
    py: Python<'py>,
    preset: Option<String>,
    material: Option<PathBuf>,
    model: Option<String>,
    radii: Option<Vec<f64>>,
    epsilon: f64,
    gaussians: usize,
    photons: u64,
    seed: u64,
) -> PyResult<Bound<'py, PyDict>> {
    let (material, request) = request(py, preset, material, model, radii, epsilon, gaussians)?;
    let request = ProfileRequest {
        photons,
        seed,
        ..request
    };
    let analysis = or_raise(py, py.detach(|| analyse(&material, &request)))?;
    let profile = analysis.profile.as_ref();
    let radii = &analysis.radii;
    let table = |f: &dyn Fn(f64) -> Rgb| -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = radii.iter().flat_map(|&r| f(r)).collect();
        PyArray1::from_vec(py, flat).reshape([radii.len(), 3])
    };
    let rgb = |v: Rgb| PyArray1::from_vec(py, v.to_vec());
    let out = PyDict::new(py);
    out.set_item("material", &analysis.material.name)?;
    out.set_item("model", analysis.model.name())?;
    out.set_item("radii_mm", PyArray1::from_vec(py, radii.clone()))?;
    out.set_item("reflectance", table(&|r| profile.reflectance(r))?)?;
    out.set_item("transmittance", table(&|r| profile.transmittance(r))?)?;
    out.set_item("total_reflectance", rgb(profile.total_reflectance()))?;
    out.set_item("total_transmittance", rgb(profile.total_transmittance()))?;
    out.set_item("d_max_mm", rgb(profile.d_max(epsilon)))?;
    out.set_item("epsilon", epsilon)?;
    Ok(out)
}

/// The profile's plot as SVG (R(r) and r·R(r) per channel), as `sssbake
/// profile --plot` draws it; `compare_montecarlo` simulates the reference
/// beside it with `photons` per channel.
#[pyfunction]
#[pyo3(signature = (preset=None, material=None, model=None, radii=None, epsilon=1e-3, gaussians=6, compare_montecarlo=false, photons=100_000, seed=1))]
#[allow(clippy::too_many_arguments)]
pub fn profile_plot(
    py: Python<'_>,
    preset: Option<String>,
    material: Option<PathBuf>,
    model: Option<String>,
    radii: Option<Vec<f64>>,
    epsilon: f64,
    gaussians: usize,
    compare_montecarlo: bool,
    photons: u64,
    seed: u64,
) -> PyResult<String> {
    let (material, request) = request(py, preset, material, model, radii, epsilon, gaussians)?;
    let request = ProfileRequest {
        compare_montecarlo,
        photons,
        seed,
        ..request
    };
    let analysis = py.detach(|| analyse(&material, &request));
    Ok(or_raise(py, analysis)?.svg())
}

/// The material and the library's request for a profile of it, as both
/// functions take them (the request's checks are the library's, in
/// [`analyse`]).
fn request(
    py: Python<'_>,
    preset: Option<String>,
    material: Option<PathBuf>,
    model: Option<String>,
    radii: Option<Vec<f64>>,
    epsilon: f64,
    gaussians: usize,
) -> PyResult<(Material, ProfileRequest)> {
    let material = or_raise(py, material_of(preset.as_deref(), material.as_deref()))?;
    let model = match model.as_deref() {
        Some(name) => or_raise(py, model_named(name))?,
        None => Model::default_for(&material),
    };
    let request = ProfileRequest {
        model,
        radii,
        epsilon,
        gaussians,
        compare_montecarlo: false,
        photons: 0,
        seed: 0,
    };
    Ok((material, request))
}

/// The model called `name`, or an error naming the models there are.
fn model_named(name: &str) -> Result<Model, Error> {
    name.parse::<Model>().map_err(|_| {
        Error::field(
            "model",
            format!(
                "unknown name `{name}` (one of {})",
                <Model as strum::VariantNames>::VARIANTS.join(", ")
            ),
        )
    })
}
