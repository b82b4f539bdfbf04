//! Reading images callers hand in: a lightmap used as the irradiance, an
//! environment, a base colour. EXR is linear; PNG is sRGB-encoded and is
//! linearised here.

use crate::InputError;
use sssbake::image::Image;
use std::path::Path;

/// Reads `path` (.exr or .png) into linear RGB, rows top to bottom.
pub fn read_image(path: &Path) -> Result<Image, InputError> {
    let error = |message: String| InputError {
        file: path.display().to_string(),
        message,
    };
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let (width, height, texels) = match extension.as_deref() {
        Some("exr") => read_exr(path).map_err(error)?,
        Some("png") => read_png(path).map_err(error)?,
        _ => {
            return Err(error("is neither an .exr nor a .png image".to_string()));
        }
    };
    Image::new(width, height, texels).map_err(|e| error(e.to_string()))
}

fn read_exr(path: &Path) -> Result<(usize, usize, Vec<[f32; 3]>), String> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| {
            (
                resolution.width(),
                vec![[0.0f32; 3]; resolution.width() * resolution.height()],
            )
        },
        |(width, texels), position, (r, g, b, _a): (f32, f32, f32, f32)| {
            texels[position.y() * *width + position.x()] = [r, g, b];
        },
    )
    .map_err(|e| format!("cannot read the EXR image: {e}"))?;
    let size = image.layer_data.size;
    let (_, texels) = image.layer_data.channel_data.pixels;
    Ok((size.width(), size.height(), texels))
}

fn read_png(path: &Path) -> Result<(usize, usize, Vec<[f32; 3]>), String> {
    let decoded = image::ImageReader::open(path)
        .map_err(|e| format!("cannot open the PNG image: {e}"))?
        .decode()
        .map_err(|e| format!("cannot decode the PNG image: {e}"))?
        .to_rgb32f();
    let (width, height) = (decoded.width() as usize, decoded.height() as usize);
    let texels = decoded.pixels().map(|p| p.0.map(srgb_to_linear)).collect();
    Ok((width, height, texels))
}

/// The sRGB transfer function's inverse.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}
