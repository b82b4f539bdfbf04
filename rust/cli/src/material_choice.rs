//! `--preset NAME | --material FILE`, shared by the commands that take a material.

use crate::Failure;
use sssbake_profile::presets::{self, preset};
use sssbake_profile::{Material, Optics};
use std::path::Path;

/// The preset or material file asked for.
pub fn load(preset_name: Option<&str>, file: Option<&Path>) -> Result<Material, Failure> {
    match (preset_name, file) {
        (Some(name), _) => preset(name).ok_or_else(|| {
            let names: Vec<&str> = presets::list().into_iter().map(|(n, _)| n).collect();
            Failure::Input(format!(
                "unknown preset `{name}` (known: {})",
                names.join(", ")
            ))
        }),
        (None, Some(path)) => Material::from_file(path).map_err(|e| Failure::Input(e.to_string())),
        (None, None) => Err(Failure::Input(
            "give --preset NAME or --material FILE".into(),
        )),
    }
}

/// The shortest transport mean free path 1/σt' of the top layer over the
/// channels, mm (for a measured Gaussian profile, its narrowest spread):
/// the finest spacing the material's light transport resolves.
pub fn mean_free_path(material: &Material) -> f64 {
    match &material.optics {
        Optics::Layers(layers) => (0..3)
            .map(|c| layers[0].medium(c).mean_free_path())
            .fold(f64::INFINITY, f64::min),
        Optics::Gaussians(g) => g
            .terms
            .iter()
            .flatten()
            .map(|&(_, v)| v.sqrt())
            .fold(f64::INFINITY, f64::min),
    }
}
