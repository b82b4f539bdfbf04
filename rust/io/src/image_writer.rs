//! Encoding baked maps: EXR (linear, 32- or 16-bit float) and PNG (8-bit
//! sRGB, dithered), into bytes the caller writes atomically.

use sssbake::image::Image;

/// Bits per channel of an EXR.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// 32-bit float.
    Float,
    /// 16-bit half float (smaller; 3 significant digits).
    Half,
}

/// `image` (rows top to bottom) as a lossless-compressed RGB EXR, in scan
/// lines.
///
/// 32-bit maps are run-length encoded: the low bits of a baked value are
/// noise, which deflate cannot shrink, so on a 4096² map ZIP saved 8% of
/// the file for six times the encoding (2.2 s against 0.38 s on one map of
/// the head). 16-bit maps keep ZIP, which halves them against run-lengths
/// for about twice the time.
pub fn exr_bytes(image: &Image, precision: Precision) -> Result<Vec<u8>, String> {
    use exr::prelude::*;
    let width = image.width;
    let texel = move |p: Vec2<usize>| image.texels[p.y() * width + p.x()];
    let mut bytes = std::io::Cursor::new(Vec::new());
    let size = (image.width, image.height);
    let result = match precision {
        Precision::Float => Image::from_layer(Layer::new(
            size,
            LayerAttributes::named("rgb"),
            Encoding {
                compression: Compression::RLE,
                blocks: Blocks::ScanLines,
                line_order: LineOrder::Increasing,
            },
            SpecificChannels::rgb(|p| {
                let c = texel(p);
                (c[0], c[1], c[2])
            }),
        ))
        .write()
        .to_buffered(&mut bytes),
        Precision::Half => Image::from_layer(Layer::new(
            size,
            LayerAttributes::named("rgb"),
            Encoding::SMALL_LOSSLESS,
            SpecificChannels::rgb(|p| {
                let c = texel(p).map(f16::from_f32);
                (c[0], c[1], c[2])
            }),
        ))
        .write()
        .to_buffered(&mut bytes),
    };
    result.map_err(|e| format!("cannot encode the EXR image: {e}"))?;
    Ok(bytes.into_inner())
}

/// `image` (linear, rows top to bottom) as an 8-bit sRGB preview PNG. A
/// fixed, position-hashed dither of one step keeps smooth gradients from
/// banding.
pub fn png_bytes(image: &Image) -> Result<Vec<u8>, String> {
    encode_png(image, true)
}

/// `image` (linear, rows top to bottom, values in [0, 1]) as an 8-bit sRGB
/// PNG for a renderer to read: each texel the nearest code, no dither, so
/// no texel is more than half a step from its value.
pub fn png_texture_bytes(image: &Image) -> Result<Vec<u8>, String> {
    encode_png(image, false)
}

fn encode_png(image: &Image, dithered: bool) -> Result<Vec<u8>, String> {
    use image::ImageEncoder;
    let mut rgb = Vec::with_capacity(image.texels.len() * 3);
    for (i, texel) in image.texels.iter().enumerate() {
        let (x, y) = (i % image.width, i / image.width);
        for (c, &v) in texel.iter().enumerate() {
            let dither = if dithered {
                hash01(x as u32, y as u32, c as u32) - 0.5
            } else {
                0.0
            };
            let encoded = linear_to_srgb(v) * 255.0 + dither;
            rgb.push(encoded.round().clamp(0.0, 255.0) as u8);
        }
    }
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(
            &rgb,
            image.width as u32,
            image.height as u32,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| format!("cannot encode the PNG image: {e}"))?;
    Ok(bytes)
}

/// The sRGB transfer function, for values clamped to [0, 1].
pub fn linear_to_srgb(v: f32) -> f32 {
    let v = if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    };
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// A uniform number in [0, 1) from a texel and channel.
fn hash01(x: u32, y: u32, c: u32) -> f32 {
    let mut h =
        x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841) ^ c.wrapping_mul(0xcb1a_b31f);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    (h >> 8) as f32 / 16_777_216.0
}
