//! Where a file's bake gets its light: a lightmap image in place of the
//! lights, or the scene's lights with the environment image its dome light
//! names (relative to the scene file) or one given instead.

use crate::read_image;
use sssbake::irradiance::environment::EnvironmentMap;
use sssbake::scene::LightKind;
use sssbake::{Error, Lighting, Scene};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The lighting of `scene`, read from `scene_file`: `irradiance` (an image
/// in the objects' UVs) replaces the lights; otherwise `environment`, or
/// else the image the scene's environment light names, is read.
pub fn scene_lighting(
    scene: &Scene,
    scene_file: &Path,
    irradiance: Option<&Path>,
    environment: Option<&Path>,
) -> Result<Lighting, Error> {
    if let Some(path) = irradiance {
        return Ok(Lighting::Irradiance(Arc::new(read_image(path)?)));
    }
    let named = scene.lights.iter().find_map(|l| match &l.kind {
        LightKind::Environment { texture: Some(t) } => Some(t.clone()),
        _ => None,
    });
    let path = match (environment, named) {
        (Some(p), _) => p.to_path_buf(),
        (None, Some(t)) => relative_to(scene_file, &t),
        (None, None) => return Ok(Lighting::SceneLights),
    };
    let image = read_image(&path)?;
    let environment = EnvironmentMap::new(image.width, image.height, image.texels)
        .map_err(|e| e.in_file(path.display().to_string()))?;
    Ok(Lighting::SceneLightsWith {
        environment: Arc::new(environment),
    })
}

/// `file` as the scene names it, relative to the scene's folder.
fn relative_to(scene: &Path, file: &str) -> PathBuf {
    let path = Path::new(file);
    if path.is_absolute() {
        return path.to_path_buf();
    }
    scene.parent().unwrap_or(Path::new(".")).join(path)
}
