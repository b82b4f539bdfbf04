//! A bake's options ([`BakeOptions`], declared with every setting in
//! [`crate::settings`]) turned into the scene and the library's
//! [`BakeRequest`]. An option left out keeps the library's default: nothing
//! here restates one.

use crate::image_writer::Precision;
pub use crate::settings::BakeOptions;
use crate::{FolderOptions, ReadOptions, read_image, read_scene, scene_lighting};
use sssbake::limits::parse_bytes;
use sssbake::materials::{MaterialAssignment, Sidecar, Sourced, preset};
use sssbake::{BakeRequest, Error, Method, Output, Scene, UvPolicy};
use sssbake_profile::Material;
use sssbake_profile::model::Model;
use std::path::{Path, PathBuf};
use std::sync::Arc;

impl BakeOptions {
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
        self.validate()?;
        let resolution = self.resolution.unwrap_or(defaults.resolution);
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
        let uvs = match &self.uvs {
            Some(name) => named::<UvPolicy>("uvs", name)?,
            None => defaults.uvs,
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
            uvs,
            margin: self.margin.unwrap_or(defaults.margin),
            outputs,
            method,
            integrators,
            lighting,
            light_samples: self.light_samples.unwrap_or(defaults.light_samples),
            bounces: self.bounces.unwrap_or(defaults.bounces),
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
