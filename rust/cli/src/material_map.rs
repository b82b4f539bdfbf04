//! `--materials FILE`: a TOML sidecar that gives objects their materials.
//!
//! ```toml
//! [objects]
//! Head = "skin3layer"              # a preset
//! Ball = "materials/marble.toml"   # a material file, relative to this one
//! "*" = "skin1"                    # every object not named above
//! ```

use crate::Failure;
use crate::material_choice;
use sssbake_profile::Material;
use std::collections::BTreeMap;
use std::path::Path;

/// Objects' materials as the sidecar names them; `*` is every other object.
pub struct MaterialMap {
    /// Object name (or `*`) → material.
    pub by_object: BTreeMap<String, Material>,
    /// The sidecar file, for reports.
    pub path: std::path::PathBuf,
}

impl MaterialMap {
    /// Reads `path`; every named object must be one of `known`.
    pub fn read(path: &Path, known: &[String]) -> Result<Self, Failure> {
        let error = |message: String| Failure::Input(format!("{}: {message}", path.display()));
        let text = std::fs::read_to_string(path).map_err(|e| error(format!("cannot read: {e}")))?;
        let table: toml::Table = text.parse().map_err(|e| error(format!("not TOML: {e}")))?;
        let objects = table
            .get("objects")
            .and_then(|o| o.as_table())
            .ok_or_else(|| {
                error("needs an [objects] table mapping object names to materials".into())
            })?;
        let folder = path.parent().unwrap_or(Path::new("."));
        let mut by_object = BTreeMap::new();
        for (object, value) in objects {
            if object != "*" && !known.contains(object) {
                return Err(error(format!(
                    "objects.{object}: no object of that name in the scene (objects: {})",
                    known.join(", ")
                )));
            }
            let name = value.as_str().ok_or_else(|| {
                error(format!(
                    "objects.{object}: give a preset name or a .toml file"
                ))
            })?;
            let material = if name.ends_with(".toml") {
                material_choice::load(None, Some(&folder.join(name)))
            } else {
                material_choice::load(Some(name), None)
            }
            .map_err(|failure| match failure {
                Failure::Input(m) | Failure::Output(m) => error(format!("objects.{object}: {m}")),
            })?;
            by_object.insert(object.clone(), material);
        }
        Ok(MaterialMap {
            by_object,
            path: path.to_path_buf(),
        })
    }

    /// The material for `object`, if the sidecar gives one.
    pub fn for_object(&self, object: &str) -> Option<&Material> {
        self.by_object
            .get(object)
            .or_else(|| self.by_object.get("*"))
    }
}
