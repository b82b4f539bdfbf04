//! A decoded image's texels as linear RGB floats, read straight from the
//! decoder's buffer: converting through `DynamicImage::to_rgb32f` first
//! would hold a third copy of the image (3 GiB more at the 16384² limit)
//! while the texels are made.

use image::DynamicImage;

/// The texels of `decoded`, rows top to bottom, each channel in [0, 1] for
/// integer images (as `to_rgb32f` scales them) and as stored for float
/// ones; grey images spread to the three channels, alpha is dropped, and
/// with `srgb` the sRGB transfer is undone. `decoded` is dropped before
/// this returns.
pub fn linear_rgb(decoded: DynamicImage, srgb: bool) -> Vec<[f32; 3]> {
    let transfer = |v: f32| {
        if srgb {
            crate::image_reader::srgb_to_linear(v)
        } else {
            v
        }
    };
    let from_u8 = |v: u8| transfer(v as f32 / u8::MAX as f32);
    let from_u16 = |v: u16| transfer(v as f32 / u16::MAX as f32);
    match &decoded {
        DynamicImage::ImageLuma8(b) => texels(b.as_raw(), 1, from_u8),
        DynamicImage::ImageLumaA8(b) => texels(b.as_raw(), 2, from_u8),
        DynamicImage::ImageRgb8(b) => texels(b.as_raw(), 3, from_u8),
        DynamicImage::ImageRgba8(b) => texels(b.as_raw(), 4, from_u8),
        DynamicImage::ImageLuma16(b) => texels(b.as_raw(), 1, from_u16),
        DynamicImage::ImageLumaA16(b) => texels(b.as_raw(), 2, from_u16),
        DynamicImage::ImageRgb16(b) => texels(b.as_raw(), 3, from_u16),
        DynamicImage::ImageRgba16(b) => texels(b.as_raw(), 4, from_u16),
        DynamicImage::ImageRgb32F(b) => texels(b.as_raw(), 3, transfer),
        DynamicImage::ImageRgba32F(b) => texels(b.as_raw(), 4, transfer),
        // A layout added to the image crate later: through its own conversion.
        other => texels(other.to_rgb32f().as_raw(), 3, transfer),
    }
}

/// One RGB texel per `channels` samples of `raw` (one or two: grey).
fn texels<T: Copy>(raw: &[T], channels: usize, value: impl Fn(T) -> f32) -> Vec<[f32; 3]> {
    raw.chunks_exact(channels)
        .map(|p| {
            if channels < 3 {
                [value(p[0]); 3]
            } else {
                [value(p[0]), value(p[1]), value(p[2])]
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{ImageBuffer, Luma, LumaA, Rgb, Rgba};

    /// Every layout gives what the image crate's own conversion gives.
    #[test]
    fn every_layout_matches_the_image_crates_conversion() {
        let (w, h) = (5u32, 3u32);
        let u8s = |x: u32, y: u32, k: u32| ((x * 53 + y * 97 + k * 31) % 256) as u8;
        let u16s = |x: u32, y: u32, k: u32| ((x * 5303 + y * 9711 + k * 3119) % 65536) as u16;
        let f32s = |x: u32, y: u32, k: u32| (x as f32 - 2.0) * 0.7 + y as f32 * 1.3 + k as f32;
        let images = [
            DynamicImage::ImageLuma8(ImageBuffer::from_fn(w, h, |x, y| Luma([u8s(x, y, 0)]))),
            DynamicImage::ImageLumaA8(ImageBuffer::from_fn(w, h, |x, y| {
                LumaA([u8s(x, y, 0), u8s(x, y, 1)])
            })),
            DynamicImage::ImageRgb8(ImageBuffer::from_fn(w, h, |x, y| {
                Rgb([u8s(x, y, 0), u8s(x, y, 1), u8s(x, y, 2)])
            })),
            DynamicImage::ImageRgba8(ImageBuffer::from_fn(w, h, |x, y| {
                Rgba([u8s(x, y, 0), u8s(x, y, 1), u8s(x, y, 2), u8s(x, y, 3)])
            })),
            DynamicImage::ImageLuma16(ImageBuffer::from_fn(w, h, |x, y| Luma([u16s(x, y, 0)]))),
            DynamicImage::ImageLumaA16(ImageBuffer::from_fn(w, h, |x, y| {
                LumaA([u16s(x, y, 0), u16s(x, y, 1)])
            })),
            DynamicImage::ImageRgb16(ImageBuffer::from_fn(w, h, |x, y| {
                Rgb([u16s(x, y, 0), u16s(x, y, 1), u16s(x, y, 2)])
            })),
            DynamicImage::ImageRgba16(ImageBuffer::from_fn(w, h, |x, y| {
                Rgba([u16s(x, y, 0), u16s(x, y, 1), u16s(x, y, 2), u16s(x, y, 3)])
            })),
            DynamicImage::ImageRgb32F(ImageBuffer::from_fn(w, h, |x, y| {
                Rgb([f32s(x, y, 0), f32s(x, y, 1), f32s(x, y, 2)])
            })),
            DynamicImage::ImageRgba32F(ImageBuffer::from_fn(w, h, |x, y| {
                Rgba([f32s(x, y, 0), f32s(x, y, 1), f32s(x, y, 2), f32s(x, y, 3)])
            })),
        ];
        for image in images {
            let layout = format!("{:?}", image.color());
            for srgb in [false, true] {
                let expected: Vec<[f32; 3]> = image
                    .to_rgb32f()
                    .pixels()
                    .map(|p| {
                        p.0.map(|v| {
                            if srgb {
                                crate::image_reader::srgb_to_linear(v)
                            } else {
                                v
                            }
                        })
                    })
                    .collect();
                let got = linear_rgb(image.clone(), srgb);
                assert_eq!(got.len(), (w * h) as usize, "{layout}");
                for (a, b) in got.iter().zip(&expected) {
                    // Grey goes through the crate's colour conversion, which
                    // may round the last bit otherwise.
                    let close = |c: usize| (a[c] - b[c]).abs() <= 1e-6 * b[c].abs().max(1e-6);
                    assert!(
                        close(0) && close(1) && close(2),
                        "{layout} srgb {srgb}: {a:?} against {b:?}"
                    );
                }
            }
        }
    }
}
