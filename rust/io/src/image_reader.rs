//! Reading images callers hand in: a lightmap used as the irradiance, an
//! environment, a base colour. EXR is linear; PNG is sRGB-encoded and is
//! linearised here.

use crate::InputError;
use sssbake::image::Image;
use std::path::Path;

/// The most texels an image handed in may have (16384², 3 GiB as linear
/// RGB): an EXR header's size is checked against it before anything the
/// size of the image is allocated.
pub const MAX_IMAGE_TEXELS: usize = 1 << 28;

/// The most bytes of samples an EXR's header may claim per byte of the
/// file. No compression EXR has packs more: deflate (ZIP) expands at most
/// 1032 times, PXR24 (deflate of 24-bit floats) 1376, PIZ's Huffman runs
/// about 450, RLE 64, B44A 11. A header claiming more than this times the
/// file's length describes texels the file cannot hold; it is refused
/// before the decoder allocates for them.
pub const MAX_EXR_EXPANSION: u64 = 4096;

/// Reads `path` (.exr or .png) into linear RGB, rows top to bottom. A panic
/// inside a decoder on hostile bytes is refused as bad input.
pub fn read_image(path: &Path) -> Result<Image, InputError> {
    let error = |message: String| InputError {
        file: path.display().to_string(),
        message,
    };
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let read = match extension.as_deref() {
        Some("exr") => read_exr,
        Some("png") => read_png,
        _ => {
            return Err(error("is neither an .exr nor a .png image".to_string()));
        }
    };
    let (width, height, texels) = std::panic::catch_unwind(|| read(path))
        .unwrap_or_else(|_| Err("its decoder failed on the file's bytes".to_string()))
        .map_err(error)?;
    Image::new(width, height, texels).map_err(|e| error(e.to_string()))
}

fn read_exr(path: &Path) -> Result<(usize, usize, Vec<[f32; 3]>), String> {
    use exr::prelude::*;
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read the EXR image: {e}"))?;
    let length = file
        .metadata()
        .map_err(|e| format!("cannot read the EXR image: {e}"))?
        .len();
    check_exr_size(std::io::BufReader::new(file), length)?;
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
        .map_err(|e| format!("cannot decode the PNG image: {e}"))?;
    let (width, height) = (decoded.width() as usize, decoded.height() as usize);
    Ok((width, height, crate::linear_rgb::linear_rgb(decoded, true)))
}

/// Refuses an image whose header claims more than [`MAX_IMAGE_TEXELS`].
pub fn check_size(width: usize, height: usize) -> Result<(), String> {
    match width.checked_mul(height) {
        Some(texels) if texels <= MAX_IMAGE_TEXELS => Ok(()),
        _ => Err(format!(
            "its header says {width}×{height} texels, more than the {MAX_IMAGE_TEXELS} an \
             image may have"
        )),
    }
}

/// Refuses an EXR of `length` bytes any of whose layers' data windows (the
/// texels it stores, which its display window need not show) is larger
/// than [`check_size`] allows, or whose samples (data window × the bytes of
/// its channels) are more than [`MAX_EXR_EXPANSION`] times `length`.
pub fn check_exr_size(bytes: impl std::io::Read, length: u64) -> Result<(), String> {
    let meta = exr::meta::MetaData::read_from_buffered(bytes, false)
        .map_err(|e| format!("cannot read the EXR image: {e}"))?;
    for header in meta.headers.iter() {
        let (width, height) = (header.layer_size.width(), header.layer_size.height());
        check_size(width, height)?;
        let samples =
            (width as u64 * height as u64).saturating_mul(header.channels.bytes_per_pixel as u64);
        if samples > length.saturating_mul(MAX_EXR_EXPANSION) {
            return Err(format!(
                "its header says {width}×{height} texels of {} bytes ({:.1} MiB of samples), \
                 more than its {length} bytes can hold (at most {MAX_EXR_EXPANSION} times \
                 the file's size)",
                header.channels.bytes_per_pixel,
                samples as f64 / (1u64 << 20) as f64
            ));
        }
    }
    Ok(())
}

/// The sRGB transfer function's inverse.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}
