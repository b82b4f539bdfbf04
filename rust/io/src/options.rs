//! A bake's options as a pipeline writes them (a batch manifest's
//! `[defaults]` and asset tables, the CLI's flags), turned into the scene
//! and the library's [`BakeRequest`]. An option left out keeps the
//! library's default: nothing here restates one.
//!
//! | option | type | meaning |
//! |---|---|---|
//! | `objects` | list of names | objects to bake [every object] |
//! | `preset` / `material` | name / TOML file | material for objects the sidecar does not name |
//! | `materials` | TOML sidecar | each object's preset or material file |
//! | `model` | name | the profile model [chosen for the material] |
//! | `resolution` | texels | side of each map |
//! | `uv_set` | index | texture-coordinate set baked into |
//! | `uvs` | `auto`, `unwrap`, `keep` | what to do with the objects' UVs |
//! | `margin` | texels | fill beyond each chart's edge |
//! | `outputs` | list of names | the maps to make |
//! | `method` | name | the integrator, or `auto` |
//! | `octree_epsilon` | sr | octree opening angle |
//! | `gaussians` | count | Gaussians of the texture-space fit |
//! | `samples` | count | importance probes per texel |
//! | `walk_samples` | count | walks per texel and channel of `method = "walk"` |
//! | `seed` | integer | the seed of importance sampling and of the walk |
//! | `unit_scale` | mm per scene unit | overrides the file's unit |
//! | `irradiance`, `environment`, `base_color` | image files | as `sssbake bake` |
//! | `colour_split` | [0, 1] | α of the colour split |
//! | `light_samples` | count | samples per soft light, per texel |
//! | `roughness` | RMS slope | a rough boundary [smooth] |
//! | `tolerance` | relative RMSE | what `auto` holds each object to |
//! | `light_check` | texels | texels walked to check the bake against light [256; 0 off] |
//! | `max_memory` | size (`16G`, `512M`) | memory a bake may hold [16G] |
//! | `max_evaluations` | count | shadow rays and kernel evaluations a bake may take [3e10] |
//! | `half` | bool | 16-bit EXRs |
//! | `exposure` | stops | exposure of the PNG previews |

use crate::image_writer::Precision;
use crate::{FolderOptions, ReadOptions, read_image, read_scene, scene_lighting};
use serde::{Deserialize, Serialize};
use sssbake::limits::parse_bytes;
use sssbake::materials::{MaterialAssignment, Sidecar, Sourced, preset};
use sssbake::request::MAX_RESOLUTION;
use sssbake::{BakeRequest, Error, Method, Output, Scene, UvPolicy};
use sssbake_profile::Material;
use sssbake_profile::model::Model;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A bake's options; `None` keeps the library's default.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BakeOptions {
    /// Objects to bake by name [every object].
    pub objects: Option<Vec<String>>,
    /// A material preset for objects the sidecar does not name.
    pub preset: Option<String>,
    /// A TOML material file for objects the sidecar does not name.
    pub material: Option<PathBuf>,
    /// A TOML sidecar naming each object's preset or material file.
    pub materials: Option<PathBuf>,
    /// The profile model's name.
    pub model: Option<String>,
    /// Texels per side of each map.
    pub resolution: Option<u32>,
    /// The texture-coordinate set to bake into.
    pub uv_set: Option<usize>,
    /// Keep, unwrap or trust the objects' UVs.
    pub uvs: Option<UvPolicy>,
    /// Texels filled beyond each chart's edge.
    pub margin: Option<u32>,
    /// The maps to make, by name.
    pub outputs: Option<Vec<String>>,
    /// The integrator's name, or `auto`.
    pub method: Option<String>,
    /// Octree: the solid angle (sr) below which a node is taken whole.
    pub octree_epsilon: Option<f32>,
    /// Texture space: Gaussians in the fit.
    pub gaussians: Option<usize>,
    /// Importance: probes per texel.
    pub samples: Option<u32>,
    /// Walk: walks per texel and channel.
    pub walk_samples: Option<u32>,
    /// Importance and walk: the seed of their Monte Carlo.
    pub seed: Option<u64>,
    /// Millimetres per scene unit, overriding the file's units.
    pub unit_scale: Option<f64>,
    /// An image in the objects' UVs used as the transmitted irradiance.
    pub irradiance: Option<PathBuf>,
    /// An equirectangular image for the scene's environment light.
    pub environment: Option<PathBuf>,
    /// A base colour image in the objects' UVs.
    pub base_color: Option<PathBuf>,
    /// α of the colour split, in [0, 1].
    pub colour_split: Option<f32>,
    /// Samples per soft light and for the environment, per texel.
    pub light_samples: Option<u32>,
    /// RMS slope of a rough boundary.
    pub roughness: Option<f64>,
    /// Relative RMSE against the exact sum that `auto` holds each object to.
    pub tolerance: Option<f64>,
    /// Texels at which the bake is checked against a volumetric random
    /// walk (0 turns the check off).
    pub light_check: Option<u32>,
    /// Memory a bake may hold, such as `16G` or `512M` (binary units).
    pub max_memory: Option<String>,
    /// Shadow rays, kernel evaluations and probes a bake may take.
    pub max_evaluations: Option<f64>,
    /// Write EXRs as 16-bit half floats.
    pub half: Option<bool>,
    /// Exposure of the PNG previews, stops.
    pub exposure: Option<f32>,
}

impl BakeOptions {
    /// These options with every option `self` leaves out taken from
    /// `defaults`.
    pub fn or(&self, defaults: &BakeOptions) -> BakeOptions {
        macro_rules! merged {
            ($($field:ident),*) => {
                BakeOptions { $($field: self.$field.clone().or_else(|| defaults.$field.clone())),* }
            };
        }
        merged!(
            objects,
            preset,
            material,
            materials,
            model,
            resolution,
            uv_set,
            uvs,
            margin,
            outputs,
            method,
            octree_epsilon,
            gaussians,
            samples,
            walk_samples,
            seed,
            unit_scale,
            irradiance,
            environment,
            base_color,
            colour_split,
            light_samples,
            roughness,
            tolerance,
            light_check,
            max_memory,
            max_evaluations,
            half,
            exposure
        )
    }

    /// These options with every relative file path taken as relative to
    /// `folder` (a manifest's own folder).
    pub fn relative_to(&self, folder: &Path) -> BakeOptions {
        let join = |p: &Option<PathBuf>| p.as_ref().map(|p| folder.join(p));
        BakeOptions {
            material: join(&self.material),
            materials: join(&self.materials),
            irradiance: join(&self.irradiance),
            environment: join(&self.environment),
            base_color: join(&self.base_color),
            ..self.clone()
        }
    }

    /// The files these options read besides the scene: material, sidecar
    /// (and the material files it names) and images.
    pub fn files(&self) -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = [
            &self.material,
            &self.materials,
            &self.irradiance,
            &self.environment,
            &self.base_color,
        ]
        .into_iter()
        .flatten()
        .cloned()
        .collect();
        if let Some(sidecar) = &self.materials {
            files.extend(Sidecar::material_files(sidecar));
        }
        files
    }

    /// Reads the scene at `input`, the materials and the images, and makes
    /// the request; errors name the option.
    pub fn load(&self, input: &Path) -> Result<(Scene, BakeRequest), Error> {
        self.load_with(input, |read| Ok(read_scene(input, read)?))
    }

    /// As [`BakeOptions::load`], with the scene from `read` given how to
    /// read it (a stage a host holds in memory); `input` names it and is
    /// where its relative files are found from.
    pub fn load_with(
        &self,
        input: &Path,
        read: impl FnOnce(&ReadOptions) -> Result<Scene, Error>,
    ) -> Result<(Scene, BakeRequest), Error> {
        let defaults = BakeRequest::default();
        if let Some(s) = self.unit_scale.filter(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(Error::field(
                "unit_scale",
                format!("{s} must be a positive number of millimetres"),
            ));
        }
        let resolution = self.resolution.unwrap_or(defaults.resolution);
        if !(1..=MAX_RESOLUTION).contains(&resolution) {
            // Checked again by the library; here before the scene is read.
            return Err(Error::field(
                "resolution",
                format!("{resolution} must be between 1 and {MAX_RESOLUTION}"),
            ));
        }
        if self.preset.is_some() && self.material.is_some() {
            return Err(Error::field(
                "preset",
                "give a preset or a material file, not both",
            ));
        }
        let mut materials = MaterialAssignment::default();
        if let Some(name) = &self.preset {
            materials.every_object = Some(sourced(preset(name)?, "--preset"));
        }
        if let Some(path) = &self.material {
            materials.every_object = Some(sourced(Material::from_file(path)?, "--material"));
        }
        if let Some(path) = &self.materials {
            materials.sidecar = Some(Sidecar::read(path)?);
        }
        let model = match &self.model {
            Some(name) => Some(named::<Model>("model", name)?),
            None => None,
        };
        let outputs = match &self.outputs {
            Some(names) => names
                .iter()
                .map(|n| named::<Output>("outputs", n))
                .collect::<Result<_, _>>()?,
            None => defaults.outputs.clone(),
        };
        let method = match &self.method {
            Some(name) => named::<Method>("method", name)?,
            None => defaults.method,
        };
        let mut limits = defaults.limits;
        if let Some(text) = &self.max_memory {
            limits.max_memory_bytes =
                parse_bytes(text).map_err(|message| Error::field("max_memory", message))?;
        }
        if let Some(evaluations) = self.max_evaluations {
            limits.max_evaluations = evaluations;
        }
        let how = ReadOptions {
            uv_set: self.uv_set.unwrap_or(0),
            unit_scale: self.unit_scale,
        };
        let scene = read(&how)?;
        let mut integrators = defaults.integrators.clone();
        if let Some(epsilon) = self.octree_epsilon {
            integrators.octree.epsilon = epsilon;
        }
        if let Some(gaussians) = self.gaussians {
            integrators.texture.gaussians = gaussians;
        }
        if let Some(samples) = self.samples {
            integrators.importance.samples = samples;
        }
        if let Some(walks) = self.walk_samples {
            integrators.walk.samples = walks;
        }
        if let Some(seed) = self.seed {
            integrators.seed(seed);
        }
        let base_colour = match &self.base_color {
            Some(path) => Some(Arc::new(read_image(path)?)),
            None => None,
        };
        let lighting = scene_lighting(
            &scene,
            input,
            self.irradiance.as_deref(),
            self.environment.as_deref(),
        )?;
        let request = BakeRequest {
            objects: self.objects.clone().unwrap_or_default(),
            materials,
            model,
            resolution,
            uvs: self.uvs.unwrap_or(defaults.uvs),
            margin: self.margin.unwrap_or(defaults.margin),
            outputs,
            method,
            integrators,
            lighting,
            light_samples: self.light_samples.unwrap_or(defaults.light_samples),
            roughness: self.roughness.or(defaults.roughness),
            base_colour,
            colour_split: self.colour_split.unwrap_or(defaults.colour_split),
            tolerance: self.tolerance.unwrap_or(defaults.tolerance),
            light_check: self.light_check.unwrap_or(defaults.light_check),
            limits,
            ..defaults
        };
        Ok((scene, request))
    }

    /// How a bake with these options is written into `out`.
    pub fn folder(&self, out: &Path, force: bool) -> FolderOptions {
        FolderOptions {
            out: out.to_path_buf(),
            force,
            precision: if self.half.unwrap_or(false) {
                Precision::Half
            } else {
                Precision::Float
            },
            exposure: self.exposure.unwrap_or(0.0),
            uv_set: self.uv_set.unwrap_or(0),
            layer_writer: None,
        }
    }
}

/// Parses `name` as a `T` (a model, an output, a method), or says which
/// `field` it was and what the names are.
fn named<T>(field: &str, name: &str) -> Result<T, Error>
where
    T: std::str::FromStr + strum::VariantNames,
{
    name.parse::<T>().map_err(|_| {
        Error::field(
            field,
            format!("unknown name `{name}` (one of {})", T::VARIANTS.join(", ")),
        )
    })
}

fn sourced(material: Material, flag: &str) -> Sourced {
    Sourced {
        material,
        source: flag.to_string(),
        recipe: None,
    }
}
