//! Reading scenes into sssbake's model (glTF and USD) and, later, writing
//! textures and assets. Scene units become millimetres here, once.

pub mod assets;
pub mod atomic_write;
pub mod batch;
pub mod colour_texture;
pub mod folder;
mod gltf_checks;
pub mod gltf_reader;
mod gltf_uri;
pub mod gltf_writer;
pub mod image_reader;
pub mod image_writer;
pub mod lighting;
pub mod linear_rgb;
pub mod look;
pub mod options;
pub mod python;
pub mod settings;
pub mod staging;
pub mod usd_lights;
pub mod usd_material;
pub mod usd_reader;
pub mod usd_writer;

pub use folder::{FolderOptions, bake_to_folder};
pub use gltf_reader::{read_gltf, read_gltf_bytes};
pub use image_reader::read_image;
pub use lighting::scene_lighting;
pub use options::BakeOptions;
pub use usd_reader::read_usd;

use sssbake::Scene;
use std::path::Path;

/// sssbake's version, as the assets record it.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// How to read a scene.
#[derive(Clone, Debug, Default)]
pub struct ReadOptions {
    /// Which texture-coordinate set the bake uses.
    pub uv_set: usize,
    /// Millimetres per scene unit, overriding what the file says
    /// [default: the file's unit].
    pub unit_scale: Option<f64>,
}

/// A scene that could not be read; the message names the file and, where
/// it can, the object and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{file}: {message}")]
pub struct InputError {
    /// The input file.
    pub file: String,
    /// What is wrong.
    pub message: String,
}

/// Reads any supported scene file, chosen by its extension.
pub fn read_scene(path: &Path, options: &ReadOptions) -> Result<Scene, InputError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("gltf" | "glb") => caught(path, "glTF", || read_gltf(path, options)),
        Some("usd" | "usda" | "usdc" | "usdz") => read_usd(path, options),
        _ => Err(InputError {
            file: path.display().to_string(),
            message: "unknown scene format (expected .gltf, .glb, .usd, .usda, .usdc or .usdz)"
                .into(),
        }),
    }
}

/// Runs a reader, turning a panic inside a dependency (the `gltf` crate's
/// validation indexes its own arrays with a file's numbers) into bad input
/// naming the file.
fn caught(
    path: &Path,
    format: &str,
    read: impl FnOnce() -> Result<Scene, InputError>,
) -> Result<Scene, InputError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(read)).unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(InputError {
            file: path.display().to_string(),
            message: format!("not a valid {format} file (its reader failed: {what})"),
        })
    })
}

impl From<InputError> for sssbake::Error {
    fn from(e: InputError) -> Self {
        sssbake::Error::Input(sssbake::InputError {
            file: Some(e.file),
            message: e.message,
            ..sssbake::InputError::default()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_inside_a_reader_is_refused_as_bad_input_naming_the_file() {
        let path = Path::new("folder/broken.gltf");
        let error =
            caught(path, "glTF", || panic!("index out of bounds: the len is 0")).unwrap_err();
        assert_eq!(error.file, "folder/broken.gltf");
        assert_eq!(
            error.message,
            "not a valid glTF file (its reader failed: index out of bounds: the len is 0)"
        );
        let formatted = caught(path, "glTF", || panic!("accessor {}", 99)).unwrap_err();
        assert!(
            formatted
                .message
                .ends_with("(its reader failed: accessor 99)")
        );
    }
}
