//! A host's bake options: the library's [`BakeOptions`] (every setting of
//! `sssbake_io::settings`), less what a host's scene decides itself, made
//! into the request for one object or for the whole scene. The C ABI and
//! the Python package both come here.

use crate::scene::HostScene;
use sssbake::{BakeRequest, Error, UvPolicy};
use sssbake_io::BakeOptions;
use std::path::Path;

/// The name a host's scene goes by in summaries and errors: no file has it,
/// so a folder bake writes the maps alone.
pub const HOST_SCENE: &str = "host scene";

/// The options of a bake of a host's scene: a `BakeOptions` without the
/// ones that read a file's scene (its units and UV set are the host's).
pub fn host_options(options: BakeOptions) -> Result<BakeOptions, Error> {
    if options.unit_scale.is_some() {
        return Err(Error::field(
            "unit_scale",
            "a host's scene has the units it was made with (millimetres_per_unit)",
        ));
    }
    if options.uv_set.is_some() {
        return Err(Error::field(
            "uv_set",
            "a host's scene bakes into each mesh's `uvs`",
        ));
    }
    Ok(options)
}

/// The request for one object's bake: `options` (without materials, which
/// come per face slot), the object's own UVs kept as they are unless the
/// options say otherwise (the host shows the maps through them).
pub fn object_request(options: BakeOptions, host: &HostScene) -> Result<BakeRequest, Error> {
    let mut options = host_options(options)?;
    for (given, field) in [
        (options.preset.is_some(), "preset"),
        (options.material.is_some(), "material"),
        (options.materials.is_some(), "materials"),
        (options.objects.is_some(), "objects"),
    ] {
        if given {
            return Err(Error::field(
                field,
                "an object's bake takes its materials (and the object) as arguments",
            ));
        }
    }
    options
        .uvs
        .get_or_insert_with(|| UvPolicy::Keep.to_string());
    scene_request(&options, host)
}

/// The request `options` make for the host's scene. Only the request is
/// wanted of `BakeOptions::load_with`, and the one thing it reads of the
/// scene is its lights (a host's scene names no environment file), so it
/// gets a scene of those alone rather than a copy of the meshes.
pub fn scene_request(options: &BakeOptions, host: &HostScene) -> Result<BakeRequest, Error> {
    let lights = sssbake::Scene {
        lights: host.scene.lights.clone(),
        ..sssbake::Scene::default()
    };
    let (_, request) = options.load_with(Path::new(HOST_SCENE), |_| Ok(lights))?;
    Ok(request)
}
