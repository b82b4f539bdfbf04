//! A scene a Python host builds from its own arrays (numpy), and its bakes:
//! one object with a material per face slot into maps held in memory, or
//! every object into a folder. The arrays and the material and light tables
//! are converted here; `sssbake_host` reads them, as it does for the C ABI.

use crate::errors::{or_raise, to_python};
use crate::watch::{Watchers, finish, run_watched};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use serde_json::Value;
use sssbake::colour::Wrap;
use sssbake::control::Control;
use sssbake::{BakeRequest, Error, Output};
use sssbake_host::{
    Composite, HOST_SCENE, HostImage, HostLight, HostMaterial, HostMaterialKind, HostMesh,
    HostPrincipled, HostScene, PartRunner, bake_materials, host_options, object_request,
    scene_request, unwrap_corners,
};
use sssbake_io::atomic_write::write_atomically;
use sssbake_io::image_writer::{Precision, exr_bytes};
use sssbake_io::{BakeOptions, bake_to_folder};
use std::path::{Path, PathBuf};

/// A contiguous float32 or uint32 array's values, or an error naming it.
fn values<'a, T: numpy::Element>(
    array: &'a PyReadonlyArray1<'_, T>,
    what: &str,
) -> Result<&'a [T], Error> {
    array
        .as_slice()
        .map_err(|_| Error::field(what, "the array is not contiguous"))
}

/// A scene a host builds: meshes, lights and a world.
#[pyclass(name = "Scene", module = "sssbake._native")]
pub struct PyScene {
    host: HostScene,
}

#[pymethods]
impl PyScene {
    /// An empty scene whose unit is `millimetres_per_unit` mm.
    #[new]
    fn new(py: Python<'_>, millimetres_per_unit: f64) -> PyResult<Self> {
        let host = or_raise(py, HostScene::new(millimetres_per_unit))?;
        Ok(PyScene { host })
    }

    /// The objects' names, in the order they were added.
    fn objects(&self) -> Vec<String> {
        self.host
            .scene
            .objects
            .iter()
            .map(|o| o.mesh.name.clone())
            .collect()
    }

    /// Adds a mesh from contiguous float32 and uint32 arrays (see
    /// `sssbake_host::HostMesh`).
    #[pyo3(signature = (name, positions, indices, normals=None, uvs=None, material_indices=None, texture_uvs=Vec::new()))]
    #[allow(clippy::too_many_arguments)] // one per array of a mesh
    fn add_mesh(
        &mut self,
        py: Python<'_>,
        name: &str,
        positions: PyReadonlyArray1<'_, f32>,
        indices: PyReadonlyArray1<'_, u32>,
        normals: Option<PyReadonlyArray1<'_, f32>>,
        uvs: Option<PyReadonlyArray1<'_, f32>>,
        material_indices: Option<PyReadonlyArray1<'_, u32>>,
        texture_uvs: Vec<PyReadonlyArray1<'_, f32>>,
    ) -> PyResult<()> {
        let added = (|| {
            let sets = texture_uvs
                .iter()
                .map(|s| values(s, "texture_uvs"))
                .collect::<Result<Vec<_>, _>>()?;
            let mesh = HostMesh {
                name,
                positions: values(&positions, "positions")?,
                normals: normals.as_ref().map(|a| values(a, "normals")).transpose()?,
                uvs: uvs.as_ref().map(|a| values(a, "uvs")).transpose()?,
                indices: values(&indices, "indices")?,
                material_indices: material_indices
                    .as_ref()
                    .map(|a| values(a, "material_indices"))
                    .transpose()?,
                texture_uvs: &sets,
            };
            self.host.add_mesh(&mesh)
        })();
        or_raise(py, added)
    }

    /// Adds a light from the JSON of its fields (`sssbake_host::HostLight`).
    fn add_light(&mut self, py: Python<'_>, light_json: &str) -> PyResult<()> {
        let added = serde_json::from_str::<HostLight>(light_json)
            .map_err(|e| Error::field("light", e.to_string()))
            .and_then(|light| self.host.add_light(&light));
        or_raise(py, added)
    }

    /// Sets a uniform world: `colour` × `strength`, W/(m²·sr).
    fn set_world(&mut self, py: Python<'_>, colour: [f32; 3], strength: f32) -> PyResult<()> {
        or_raise(py, self.host.set_world(colour, strength))
    }

    /// Bakes object `object` with `materials_json` (a list of materials,
    /// one per material index its faces use) and `images` (each material's
    /// base-colour texels or None), under `options_json` (a `BakeOptions`).
    #[pyo3(signature = (object, materials_json, images, options_json, progress=None, cancel=None))]
    #[allow(clippy::too_many_arguments)] // the bake's parts, as Python passes them
    fn bake_object(
        &self,
        py: Python<'_>,
        object: &str,
        materials_json: &str,
        images: Vec<Option<PyReadonlyArray1<'_, f32>>>,
        options_json: &str,
        progress: Option<Bound<'_, PyAny>>,
        cancel: Option<Bound<'_, PyAny>>,
    ) -> PyResult<PyBakeResult> {
        let specs: Vec<Value> = or_raise(
            py,
            serde_json::from_str(materials_json)
                .map_err(|e| Error::field("materials", e.to_string())),
        )?;
        if specs.len() != images.len() {
            return or_raise(
                py,
                Err(Error::field(
                    "materials",
                    format!("{} materials but {} images", specs.len(), images.len()),
                )),
            );
        }
        let pixels = images
            .iter()
            .map(|i| i.as_ref().map(|a| values(a, "image pixels")).transpose())
            .collect::<Result<Vec<_>, _>>();
        let pixels = or_raise(py, pixels)?;
        let materials = specs
            .iter()
            .zip(&pixels)
            .enumerate()
            .map(|(i, (spec, pixels))| host_material(spec, *pixels, i))
            .collect::<Result<Vec<_>, _>>();
        let materials = or_raise(py, materials)?;
        let request = or_raise(
            py,
            options_of(options_json).and_then(|o| object_request(o, &self.host)),
        )?;
        let mut runner = WatchedParts {
            py,
            progress: progress.clone(),
            cancel,
        };
        let (composite, summary) =
            bake_materials(&self.host, object, &materials, &request, &mut runner)
                .map_err(|stop| stop.into_py(py))?;
        finish(&Watchers::whole(progress, None), "done")?;
        Ok(PyBakeResult {
            composite,
            summary: summary.to_string(),
        })
    }

    /// Bakes every object (or `options`' `objects`) into the folder `out`
    /// as `sssbake bake --json` does, with `options`' materials; returns
    /// the summary's JSON. Only maps are written: a host's scene has no
    /// file for a glTF copy or USD layer.
    #[pyo3(signature = (out, options_json, force, progress=None, cancel=None))]
    fn bake(
        &self,
        py: Python<'_>,
        out: PathBuf,
        options_json: &str,
        force: bool,
        progress: Option<Bound<'_, PyAny>>,
        cancel: Option<Bound<'_, PyAny>>,
    ) -> PyResult<String> {
        let options = or_raise(py, options_of(options_json).and_then(host_options))?;
        let folder = options.folder(&out, force);
        let control = Control::new();
        let watchers = Watchers::whole(progress, cancel);
        let host = &self.host;
        let summary = run_watched(py, &control, &watchers, || {
            let request = scene_request(&options, host)?;
            let plan = sssbake::plan(&host.scene, &request)?;
            bake_to_folder(Path::new(HOST_SCENE), &host.scene, &plan, &folder, &control)
        })?;
        let summary = or_raise(py, summary)?;
        finish(&watchers, "done")?;
        Ok(serde_json::to_string(&summary).unwrap_or_else(|_| "null".into()))
    }
}

/// The library's material of `spec` (a JSON object: `kind`, `name`, `toml`,
/// `image`, and for `principled` its inputs), the `index`th given, with the
/// texels of its image.
fn host_material<'a>(
    spec: &'a Value,
    pixels: Option<&'a [f32]>,
    index: usize,
) -> Result<HostMaterial<'a>, Error> {
    let field = |name: &str| format!("materials[{index}].{name}");
    let Some(map) = spec.as_object() else {
        return Err(Error::field(field("kind"), "a material is a dict"));
    };
    let text = |key: &str| -> Result<Option<&'a str>, Error> {
        match map.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(Value::String(s)) => Ok(Some(s.as_str())),
            Some(other) => Err(Error::field(field(key), format!("{other} is not text"))),
        }
    };
    let kind_name = text("kind")?.ok_or_else(|| {
        Error::field(
            field("kind"),
            "a material needs its kind: principled, preset, toml or none",
        )
    })?;
    let name = text("name")?;
    let mut rest = map.clone();
    for key in ["kind", "name", "toml", "image"] {
        rest.remove(key);
    }
    let toml = || {
        text("toml")?
            .map(str::to_string)
            .ok_or_else(|| Error::field(field("toml"), "a `toml` material needs its text"))
    };
    let kind = match kind_name {
        "principled" => HostMaterialKind::Principled(
            serde_json::from_value::<HostPrincipled>(Value::Object(std::mem::take(&mut rest)))
                .map_err(|e| Error::field(field("principled"), e.to_string()))?,
        ),
        "preset" => HostMaterialKind::Preset,
        "toml" => HostMaterialKind::Toml(toml()?),
        "none" => HostMaterialKind::NoSubsurface,
        other => {
            return Err(Error::field(
                field("kind"),
                format!("`{other}` is not principled, preset, toml or none"),
            ));
        }
    };
    if let Some(key) = rest.keys().next() {
        return Err(Error::field(
            field(key),
            format!("a `{kind_name}` material takes no `{key}`"),
        ));
    }
    let image = match (map.get("image"), pixels) {
        (None | Some(Value::Null), None) => None,
        (Some(Value::Object(image)), Some(pixels)) => Some(host_image(image, pixels, &field)?),
        _ => {
            return Err(Error::field(
                field("image"),
                "an image needs its size and its pixels together",
            ));
        }
    };
    Ok(HostMaterial { kind, name, image })
}

/// A material's base-colour image: `width`, `height`, `channels`, and
/// optionally `uv_set`, `extension` (Blender's REPEAT, EXTEND, CLIP,
/// MIRROR), `nearest` and `name`.
fn host_image<'a>(
    image: &'a serde_json::Map<String, Value>,
    pixels: &'a [f32],
    field: &dyn Fn(&str) -> String,
) -> Result<HostImage<'a>, Error> {
    let count = |key: &str, default: Option<u64>| {
        image
            .get(key)
            .map_or(default, Value::as_u64)
            .map(|v| v as usize)
            .ok_or_else(|| Error::field(field(&format!("image.{key}")), "a whole number is needed"))
    };
    let wrap = match image
        .get("extension")
        .and_then(Value::as_str)
        .unwrap_or("REPEAT")
    {
        "REPEAT" => Wrap::Repeat,
        "EXTEND" => Wrap::Clamp,
        "CLIP" => Wrap::Black,
        "MIRROR" => Wrap::Mirror,
        other => {
            return Err(Error::field(
                field("image.extension"),
                format!("`{other}` is not REPEAT, EXTEND, CLIP or MIRROR"),
            ));
        }
    };
    if let Some(key) = image.keys().find(|k| {
        ![
            "width",
            "height",
            "channels",
            "uv_set",
            "extension",
            "nearest",
            "name",
        ]
        .contains(&k.as_str())
    }) {
        return Err(Error::field(
            field(&format!("image.{key}")),
            "not a field of an image",
        ));
    }
    Ok(HostImage {
        pixels,
        width: count("width", None)?,
        height: count("height", None)?,
        channels: count("channels", None)?,
        uv_set: count("uv_set", Some(0))?,
        wrap,
        nearest: image
            .get("nearest")
            .and_then(Value::as_bool)
            .unwrap_or(false),
        name: image.get("name").and_then(Value::as_str),
    })
}

/// Why an object's bake stopped: the library said so, or Python did (a
/// callback's exception, Ctrl-C).
enum Stop {
    Library(Error),
    Python(PyErr),
}

impl From<Error> for Stop {
    fn from(error: Error) -> Self {
        Stop::Library(error)
    }
}

impl Stop {
    fn into_py(self, py: Python<'_>) -> PyErr {
        match self {
            Stop::Library(error) => to_python(py, error),
            Stop::Python(error) => error,
        }
    }
}

/// Runs each part of an object's bake watched by the caller's progress
/// callback and cancel event, on a thread of its own with the GIL released.
struct WatchedParts<'py> {
    py: Python<'py>,
    progress: Option<Bound<'py, PyAny>>,
    cancel: Option<Bound<'py, PyAny>>,
}

impl PartRunner for WatchedParts<'_> {
    type Error = Stop;

    fn run<T: Send>(
        &mut self,
        part: (usize, usize),
        work: impl FnOnce(&Control) -> Result<T, Error> + Send,
    ) -> Result<T, Stop> {
        let control = Control::new();
        let watchers = Watchers {
            progress: self.progress.clone(),
            cancel: self.cancel.clone(),
            part,
        };
        let value = run_watched(self.py, &control, &watchers, || work(&control))
            .map_err(Stop::Python)??;
        control.check().map_err(Error::from)?;
        Ok(value)
    }
}

/// One object's finished bake: its maps, rendered on request.
#[pyclass(name = "BakeResult", module = "sssbake._native")]
pub struct PyBakeResult {
    composite: Composite,
    summary: String,
}

#[pymethods]
impl PyBakeResult {
    /// Texels per side.
    #[getter]
    fn resolution(&self) -> u32 {
        self.composite.resolution()
    }

    /// What the bake did, as JSON.
    #[getter]
    fn summary(&self) -> &str {
        &self.summary
    }

    /// Map `output` (by name) as resolution² × 4 float32 RGBA values, rows
    /// from v = 0 up, alpha 1 on covered and filled texels, 0 elsewhere.
    fn image<'py>(&self, py: Python<'py>, output: &str) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let output = or_raise(py, output_named(output))?;
        let n = self.composite.resolution() as usize;
        let mut pixels = vec![0.0f32; 4 * n * n];
        or_raise(py, self.composite.write_rgba(output, &mut pixels))?;
        Ok(PyArray1::from_vec(py, pixels))
    }

    /// Writes map `output` to `path` as a linear OpenEXR file (32-bit, or
    /// 16-bit when `half`), the bytes `sssbake bake` writes, whole or not
    /// at all.
    #[pyo3(signature = (output, path, half=false))]
    fn write_exr(&self, py: Python<'_>, output: &str, path: PathBuf, half: bool) -> PyResult<()> {
        let written = self.render(output).and_then(|image| {
            let precision = if half {
                Precision::Half
            } else {
                Precision::Float
            };
            let bytes =
                exr_bytes(&image, precision).map_err(|e| Error::output(path.display(), e))?;
            write_atomically(&path, &bytes)
                .map_err(|e| Error::output(path.display(), format!("cannot write: {e}")))
        });
        or_raise(py, written)
    }
}

impl PyBakeResult {
    fn render(&self, output: &str) -> Result<sssbake::image::Image, Error> {
        self.composite.render(output_named(output)?)
    }
}

/// The output called `name`.
fn output_named(name: &str) -> Result<Output, Error> {
    Output::ALL
        .into_iter()
        .find(|o| o.name() == name)
        .ok_or_else(|| {
            Error::field(
                "output",
                format!(
                    "`{name}` is not one of {}",
                    Output::ALL.map(Output::name).join(", ")
                ),
            )
        })
}

/// The UVs of each corner and the chart of each triangle.
type Unwrapped<'py> = (Bound<'py, PyArray1<f32>>, Bound<'py, PyArray1<u32>>);

/// UVs from the library's xatlas for the mesh `name` (see
/// `sssbake_host::unwrap_corners`): the UV of each index and each
/// triangle's chart, as float32 and uint32 arrays.
#[pyfunction]
pub fn unwrap<'py>(
    py: Python<'py>,
    name: &str,
    positions: PyReadonlyArray1<'py, f32>,
    indices: PyReadonlyArray1<'py, u32>,
    resolution: u32,
    padding: u32,
) -> PyResult<Unwrapped<'py>> {
    let unwrapped = (|| {
        let positions = values(&positions, "positions")?;
        let indices = values(&indices, "indices")?;
        unwrap_corners(name, positions, indices, resolution, padding)
    })();
    let (uvs, charts) = or_raise(py, unwrapped)?;
    Ok((PyArray1::from_vec(py, uvs), PyArray1::from_vec(py, charts)))
}

/// The library's defaults a host shows in its settings, as JSON: the
/// resolution, margin, light samples, tolerance, memory limit, method and outputs of
/// `BakeRequest::default()`, every output's and method's name, and the
/// presets a bake can use (name, description).
#[pyfunction]
pub fn defaults() -> String {
    let request = BakeRequest::default();
    serde_json::json!({
        "resolution": request.resolution,
        "margin": request.margin,
        "light_samples": request.light_samples,
        "tolerance": request.tolerance,
        "max_memory_bytes": request.limits.max_memory_bytes,
        "method": request.method.name(),
        "preset": sssbake::materials::FALLBACK_PRESET,
        "outputs": request.outputs.iter().map(|o| o.name()).collect::<Vec<_>>(),
        "all_outputs": Output::ALL.map(Output::name),
        "all_methods": <sssbake::Method as strum::VariantNames>::VARIANTS,
        "presets": sssbake_profile::presets::list()
            .into_iter()
            .filter(|(name, _)| !sssbake_profile::presets::ANGULAR_ONLY.contains(name))
            .collect::<Vec<_>>(),
    })
    .to_string()
}

/// The options a Python caller gave, as JSON.
fn options_of(options_json: &str) -> Result<BakeOptions, Error> {
    serde_json::from_str(options_json).map_err(|e| Error::field("options", e.to_string()))
}
