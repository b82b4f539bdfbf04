//! The baked look: how the glTF copy and the USD layer show a bake, lit
//! once. The assets show one map, [`LOOK`], as emission (a renderer adds
//! it to the pixel as it is, with no light falling on it), never as a
//! colour to be lit again.
//!
//! USD reads the linear EXR itself. glTF's `emissiveTexture` is an 8-bit
//! sRGB image holding [0, 1], so the copy gets its own encoding: the map
//! divided by its [`emissive_strength`], which the material's
//! `KHR_materials_emissive_strength` multiplies back, so nothing clips.

use crate::image_writer::png_texture_bytes;
use sssbake::Output;
use sssbake::image::Image;

/// The map the assets show: `diffuse`, the radiance M·ρt(0)/π leaving the
/// surface (W/(m²·sr)), which is what an emission shader emits.
pub const LOOK: Output = Output::Diffuse;

/// The name of the look's emissive encoding for an object's maps named
/// `<file_stem>_<output>`: `<file_stem>_diffuse_emissive.png`.
pub fn emissive_png_name(file_stem: &str) -> String {
    format!("{file_stem}_{}_emissive.png", LOOK.name())
}

/// A map encoded for glTF's `emissiveTexture`.
#[derive(Clone, Debug, PartialEq)]
pub struct Emissive {
    /// What the PNG's linear values are multiplied by to give the map:
    /// `KHR_materials_emissive_strength.emissiveStrength`.
    pub strength: f32,
    /// The map divided by `strength`, as an 8-bit sRGB PNG.
    pub png: Vec<u8>,
}

/// The largest finite value of any channel of `image`, the strength that
/// maps the image into [0, 1]; 1 for an image with nothing above zero.
/// Margins copy covered texels and the rest of the layout is black, so
/// this is the maximum over the covered texels.
pub fn emissive_strength(image: &Image) -> f32 {
    let max = image
        .texels
        .iter()
        .flatten()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max);
    if max > 0.0 { max } else { 1.0 }
}

/// `image` (linear) as the emissive texture and its strength.
pub fn emissive(image: &Image) -> Result<Emissive, String> {
    let strength = emissive_strength(image);
    let scaled = Image {
        width: image.width,
        height: image.height,
        texels: image
            .texels
            .iter()
            .map(|t| t.map(|v| (v / strength).min(1.0)))
            .collect(),
    };
    Ok(Emissive {
        strength,
        png: png_texture_bytes(&scaled)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(texels: Vec<[f32; 3]>) -> Image {
        Image {
            width: texels.len(),
            height: 1,
            texels,
        }
    }

    fn srgb_to_linear(code: u8) -> f32 {
        let s = code as f32 / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    }

    fn decoded(png: &[u8]) -> Vec<[u8; 3]> {
        let rgb = image::load_from_memory(png).unwrap().to_rgb8();
        rgb.pixels().map(|p| p.0).collect()
    }

    #[test]
    fn the_strength_is_the_largest_channel_of_any_texel() {
        let map = image(vec![[0.0; 3], [2.0, 7.5, 1.0], [7.25, 0.5, 0.0]]);
        assert_eq!(emissive_strength(&map), 7.5);
        assert_eq!(emissive_strength(&image(vec![[0.25, 0.5, 0.125]])), 0.5);
    }

    #[test]
    fn a_black_or_broken_map_has_strength_one() {
        assert_eq!(emissive_strength(&image(vec![[0.0; 3]; 4])), 1.0);
        let broken = image(vec![[f32::NAN, f32::INFINITY, 0.0]]);
        assert_eq!(emissive_strength(&broken), 1.0);
    }

    #[test]
    fn the_png_times_the_strength_gives_the_map_back_unclipped() {
        // Values up to 40: an sRGB preview would clip everything above 1.
        let values: Vec<[f32; 3]> = (0..200)
            .map(|i| {
                let v = 0.2 * (i + 1) as f32;
                [v, 0.5 * v, 0.1 * v]
            })
            .collect();
        let map = image(values.clone());
        let encoded = emissive(&map).unwrap();
        assert_eq!(encoded.strength, 40.0);
        let codes = decoded(&encoded.png);
        for (texel, (code, value)) in codes.iter().zip(&values).enumerate() {
            for c in 0..3 {
                let back = srgb_to_linear(code[c]) * encoded.strength;
                // Half an 8-bit step of the sRGB curve, relative, at 5% of the maximum.
                let tolerance = if value[c] > 0.05 * 40.0 { 0.016 } else { 0.5 };
                let relative = (back - value[c]).abs() / value[c];
                assert!(
                    relative < tolerance,
                    "texel {texel} channel {c}: {back} for {}",
                    value[c]
                );
            }
            let at_max = texel == values.len() - 1;
            assert_eq!(code[0] == 255, at_max, "texel {texel}");
        }
    }

    #[test]
    fn the_encoding_has_no_dither() {
        // Half the maximum is 187.51 in 8-bit sRGB: a dither of one step
        // would make some of these 187; the nearest code is 188 for all.
        let mut texels = vec![[0.25f32; 3]; 256];
        texels.push([0.5; 3]);
        let codes = decoded(&emissive(&image(texels)).unwrap().png);
        assert!(codes[..256].iter().all(|c| *c == [188; 3]));
        assert_eq!(codes[256], [255; 3]);
    }

    #[test]
    fn the_png_is_named_after_the_look_map() {
        assert_eq!(emissive_png_name("Head"), "Head_diffuse_emissive.png");
    }
}
