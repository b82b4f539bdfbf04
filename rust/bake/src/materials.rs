//! Which material each object bakes with, and where it came from.
//!
//! The first that applies: a sidecar's entry for the object (or its `*`),
//! the material a caller names for every object (`--preset` or
//! `--material`), the object's own material in the scene (translated as
//! docs/materials.md "Materials from the asset" says), then the fallback (`skin1`).
//!
//! A sidecar is TOML that names each object's preset or material file
//! (relative to the sidecar):
//!
//! ```toml
//! [objects]
//! Head = "skin3layer"              # a preset
//! Ball = "materials/marble.toml"   # a material file, relative to this one
//! "*" = "skin1"                    # every object not named above
//! ```

use crate::error::{Error, InputError};
use crate::scene::SceneObject;
use serde::Deserialize;
use sssbake_profile::appearance::channel_mean_free_paths;
pub use sssbake_profile::appearance::cycles::{
    AlbedoMapping, PrincipledSubsurface, SubsurfaceMethod,
};
use sssbake_profile::presets;
use sssbake_profile::{Appearance, Material};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The preset objects bake with when nothing else names a material.
pub const FALLBACK_PRESET: &str = "skin1";

/// A material and the words that say where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Sourced {
    /// The material.
    pub material: Material,
    /// Where it came from, for summaries: `--preset`, `sidecar FILE`, …
    pub source: String,
    /// For a material a shader describes by its colour (an asset's, or
    /// Blender's Principled BSDF), how to build it for another colour: the
    /// nominal colour of a colour map (crate::colour). `None` for a
    /// material given by coefficients (a preset or material file).
    pub recipe: Option<ColourRecipe>,
}

/// A material described by a colour, kept so that it can be built again
/// for the nominal colour of a colour map.
#[derive(Clone, Debug, PartialEq)]
pub enum ColourRecipe {
    /// An asset's shader, as sssbake reads it (docs/materials.md, "Materials from the
    /// asset").
    Appearance(Appearance),
    /// Blender's Principled BSDF (docs/materials.md, "Materials from Blender").
    Principled(Principled),
}

impl ColourRecipe {
    /// The colour the material states, linear RGB.
    pub fn colour(&self) -> [f64; 3] {
        match self {
            ColourRecipe::Appearance(a) => a.colour,
            ColourRecipe::Principled(p) => p.base_colour.map(f64::from),
        }
    }

    /// The same material with colour `colour`.
    pub fn with_colour(&self, colour: [f64; 3]) -> Result<Material, Error> {
        match self {
            ColourRecipe::Appearance(a) => Appearance {
                colour,
                ..a.clone()
            }
            .to_material()
            .map_err(|e| {
                Error::Input(InputError {
                    field: Some(format!("material `{}`", a.name)),
                    message: format!("at the colour map's mean colour {colour:?}: {e}"),
                    ..InputError::default()
                })
            }),
            ColourRecipe::Principled(p) => Principled {
                base_colour: colour.map(|c| c as f32),
                ..p.clone()
            }
            .to_material(),
        }
    }
}

/// How objects get their materials (see the module's documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialAssignment {
    /// Per-object materials from a sidecar.
    pub sidecar: Option<Sidecar>,
    /// One material for every object the sidecar does not name.
    pub every_object: Option<Sourced>,
    /// Read an object's own material from the scene when nothing above
    /// names one.
    pub from_scene: bool,
    /// The material of last resort; its scattering distance also serves
    /// scene materials that give only a colour.
    pub fallback: Material,
}

impl Default for MaterialAssignment {
    fn default() -> Self {
        MaterialAssignment {
            sidecar: None,
            every_object: None,
            from_scene: true,
            fallback: presets::preset(FALLBACK_PRESET)
                .expect("the fallback preset is one of the presets"),
        }
    }
}

/// A preset to bake with by name, or an error listing the names there are
/// (or saying that an angular-only preset has no length scale).
pub fn preset(name: &str) -> Result<Material, Error> {
    if presets::ANGULAR_ONLY.contains(&name) {
        return Err(Error::input(format!(
            "preset `{name}` has no length scale to bake with; it is for `sssbake profile \
             --preset {name} --model stam`"
        )));
    }
    presets::named(name).map_err(Error::input)
}

impl MaterialAssignment {
    /// Every object (the sidecar's aside) bakes with `material` from
    /// `source`.
    pub fn everywhere(material: Material, source: impl Into<String>) -> Self {
        MaterialAssignment {
            every_object: Some(Sourced {
                material,
                source: source.into(),
                recipe: None,
            }),
            ..MaterialAssignment::default()
        }
    }

    /// Every object (the sidecar's aside) bakes with Blender's Principled
    /// BSDF `principled`, kept as a recipe so a colour map can rebuild it.
    pub fn principled(principled: Principled, source: impl Into<String>) -> Result<Self, Error> {
        Ok(MaterialAssignment {
            every_object: Some(Sourced {
                material: principled.to_material()?,
                source: source.into(),
                recipe: Some(ColourRecipe::Principled(principled)),
            }),
            ..MaterialAssignment::default()
        })
    }

    /// The material of `object` of a scene read from `scene_source`.
    pub fn resolve(&self, object: &SceneObject, scene_source: &str) -> Result<Sourced, Error> {
        let name = &object.mesh.name;
        if let Some(sidecar) = &self.sidecar
            && let Some(material) = sidecar.for_object(name)
        {
            return Ok(Sourced {
                material: material.clone(),
                source: format!("sidecar {}", sidecar.path.display()),
                recipe: None,
            });
        }
        if let Some(every) = &self.every_object {
            return Ok(every.clone());
        }
        let hint = object.material.as_ref().filter(|_| self.from_scene);
        let Some(hint) = hint else {
            let why = if self.from_scene {
                "the asset gives no material"
            } else {
                "the scene's materials are not read"
            };
            return Ok(Sourced {
                material: self.fallback.clone(),
                source: format!("default ({why})"),
                recipe: None,
            });
        };
        let (appearance, from) = hint.appearance(channel_mean_free_paths(&self.fallback));
        let material = appearance.to_material().map_err(|e| {
            Error::Input(InputError {
                file: Some(scene_source.to_string()),
                object: Some(name.clone()),
                field: Some(format!("material `{}`", hint.name)),
                message: e.to_string(),
            })
        })?;
        let source = match from {
            Some(inputs) => format!("asset: {inputs}"),
            None => format!(
                "asset: base colour, with {}'s scattering distance",
                self.fallback.name
            ),
        };
        Ok(Sourced {
            material,
            source,
            recipe: Some(ColourRecipe::Appearance(appearance)),
        })
    }
}

/// Objects' materials as a sidecar names them; `*` is every other object.
#[derive(Clone, Debug, PartialEq)]
pub struct Sidecar {
    /// The sidecar file, for reports and messages.
    pub path: PathBuf,
    /// Object name (or `*`) → material.
    pub by_object: BTreeMap<String, Material>,
}

/// A sidecar's text as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SidecarFile {
    objects: BTreeMap<String, String>,
}

impl Sidecar {
    /// Reads the sidecar at `path`; material files are relative to it.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::input(format!("cannot read: {e}")).in_file(path.display().to_string())
        })?;
        let folder = path.parent().unwrap_or(Path::new("."));
        Sidecar::parse(&text, path, folder)
    }

    /// Parses sidecar `text` that names material files relative to
    /// `folder`; `path` names it in messages.
    pub fn parse(text: &str, path: &Path, folder: &Path) -> Result<Self, Error> {
        let file = path.display().to_string();
        let at = |field: String, message: String| {
            Error::Input(InputError {
                file: Some(file.clone()),
                field: Some(field),
                message,
                ..InputError::default()
            })
        };
        let parsed: SidecarFile = toml::from_str(text).map_err(|e| {
            at(
                "objects".into(),
                format!(
                    "{} (a sidecar is an [objects] table naming each object's preset or .toml file)",
                    e.message()
                ),
            )
        })?;
        let mut by_object = BTreeMap::new();
        for (object, name) in parsed.objects {
            let material = if name.ends_with(".toml") {
                Material::from_file(&folder.join(&name)).map_err(Error::from)
            } else {
                preset(&name)
            }
            .map_err(|e| at(format!("objects.{object}"), e.to_string()))?;
            by_object.insert(object, material);
        }
        Ok(Sidecar {
            path: path.to_path_buf(),
            by_object,
        })
    }

    /// The material files the sidecar at `path` names (relative to it),
    /// for a caller that records what a bake read; none when it cannot be
    /// read or parsed ([`Sidecar::read`] says why).
    pub fn material_files(path: &Path) -> Vec<PathBuf> {
        let folder = path.parent().unwrap_or(Path::new("."));
        std::fs::read_to_string(path)
            .ok()
            .and_then(|text| toml::from_str::<SidecarFile>(&text).ok())
            .map(|parsed| {
                parsed
                    .objects
                    .into_values()
                    .filter(|name| name.ends_with(".toml"))
                    .map(|name| folder.join(name))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Refuses entries naming objects not among `known`.
    pub fn check_objects(&self, known: &[&str]) -> Result<(), Error> {
        match self
            .by_object
            .keys()
            .find(|o| *o != "*" && !known.contains(&o.as_str()))
        {
            Some(object) => Err(Error::Input(InputError {
                file: Some(self.path.display().to_string()),
                field: Some(format!("objects.{object}")),
                message: format!(
                    "no object of that name in the scene (objects: {})",
                    known.join(", ")
                ),
                ..InputError::default()
            })),
            None => Ok(()),
        }
    }

    /// The material for `object`, if the sidecar gives one.
    pub fn for_object(&self, object: &str) -> Option<&Material> {
        self.by_object
            .get(object)
            .or_else(|| self.by_object.get("*"))
    }
}

/// Blender's Principled BSDF subsurface inputs, read as Cycles reads them
/// ([`PrincipledSubsurface`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Principled {
    /// The material's name, for reports.
    pub name: String,
    /// Base Color, linear RGB.
    pub base_colour: [f32; 3],
    /// Subsurface Weight; must be positive.
    pub subsurface_weight: f32,
    /// Subsurface Radius per channel (multiplies the scale).
    pub radius: [f32; 3],
    /// Subsurface Scale, mm.
    pub scale_mm: f64,
    /// The node's subsurface method.
    pub method: SubsurfaceMethod,
    /// IOR (of the specular layer).
    pub ior: f32,
    /// Specular IOR Level (0.5: the IOR as it is).
    pub specular_ior_level: f32,
    /// Subsurface IOR (Random Walk (Skin) only).
    pub subsurface_ior: f32,
    /// Subsurface Anisotropy (Henyey–Greenstein g).
    pub anisotropy: f32,
    /// Roughness of the specular layer over the subsurface, in [0, 1]:
    /// Blender's GGX takes α = Roughness², which the bake uses as the
    /// surface's Beckmann RMS facet slope m (the two lobes agree closely
    /// for equal α and m).
    pub roughness: f32,
    /// How the colour becomes an albedo.
    pub albedo: AlbedoMapping,
}

impl Principled {
    /// The material Cycles renders for these inputs (docs/materials.md, "Materials
    /// from Blender").
    pub fn to_material(&self) -> Result<Material, Error> {
        let at = |message: String| {
            Error::Input(InputError {
                field: Some(format!("material `{}`", self.name)),
                message,
                ..InputError::default()
            })
        };
        if self.subsurface_weight.is_nan() || self.subsurface_weight <= 0.0 {
            return Err(at(format!(
                "Subsurface Weight is {}; there is no subsurface scattering to bake",
                self.subsurface_weight
            )));
        }
        if !(0.0..=1.0).contains(&self.roughness) {
            return Err(at(format!(
                "Roughness is {}; it must lie between 0 and 1",
                self.roughness
            )));
        }
        let mut material = PrincipledSubsurface {
            name: self.name.clone(),
            colour: self.base_colour.map(f64::from),
            radius_mm: self.radius.map(|r| f64::from(r) * self.scale_mm),
            method: self.method,
            ior: f64::from(self.ior),
            specular_ior_level: f64::from(self.specular_ior_level),
            subsurface_ior: f64::from(self.subsurface_ior),
            anisotropy: f64::from(self.anisotropy),
            albedo: self.albedo,
        }
        .to_material()
        .map_err(|e| at(e.to_string()))?;
        material.roughness = f64::from(self.roughness).powi(2);
        Ok(material)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_angular_only_preset_is_refused_for_a_bake_with_where_it_serves() {
        for name in presets::ANGULAR_ONLY {
            assert!(presets::named(name).is_ok(), "{name} is a preset");
            let message = preset(name).unwrap_err().to_string();
            assert!(message.contains("--model stam"), "{message}");
        }
        assert!(preset("skin1").is_ok());
    }
}
