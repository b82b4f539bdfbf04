//! `--preset NAME | --material FILE`, shared by the commands that take a material.

use crate::Failure;
use sssbake_profile::Material;
use sssbake_profile::presets;
use std::path::Path;

/// The preset or material file asked for.
pub fn load(preset_name: Option<&str>, file: Option<&Path>) -> Result<Material, Failure> {
    match (preset_name, file) {
        (Some(name), _) => presets::named(name).map_err(Failure::Input),
        (None, Some(path)) => Material::from_file(path).map_err(|e| Failure::Input(e.to_string())),
        (None, None) => Err(Failure::Input(
            "give --preset NAME or --material FILE".into(),
        )),
    }
}
