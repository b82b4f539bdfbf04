//! Base-colour textures a scene's materials name: the image decoded (PNG,
//! JPEG, EXR, HDR, by content) into linear RGB by its colour space. A
//! texture that cannot be read keeps its error, which stops only a bake
//! whose colour it drives (docs/materials.md, "Colour maps").

use sssbake::image::Image;
use std::io::Cursor;
use std::path::Path;
use std::sync::Arc;

/// How a texture's texels are encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourSpace {
    /// The sRGB transfer (glTF's base colour; USD `sRGB`).
    Srgb,
    /// Linear values as stored (USD `raw`).
    Raw,
    /// sRGB for 8- and 16-bit integer images, linear for float ones (USD
    /// `auto`).
    Auto,
}

impl ColourSpace {
    /// The name reports use.
    pub fn name(self) -> &'static str {
        match self {
            ColourSpace::Srgb => "sRGB",
            ColourSpace::Raw => "raw",
            ColourSpace::Auto => "auto",
        }
    }
}

/// Decodes an image file's bytes into linear RGB (rows top to bottom), or
/// says why not. A panic inside the decoder on hostile bytes is caught and
/// becomes the error.
pub fn decode(bytes: &[u8], space: ColourSpace) -> Result<(Image, &'static str), String> {
    use image::ImageDecoder;
    let decoded = std::panic::catch_unwind(|| {
        let reader = image::ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())?;
        // The size the header claims, checked before the decoder allocates
        // for it (an EXR's data window, which its display window hides).
        if reader.format() == Some(image::ImageFormat::OpenExr) {
            crate::image_reader::check_exr_size(Cursor::new(bytes), bytes.len() as u64)?;
        }
        let decoder = reader.into_decoder().map_err(|e| e.to_string())?;
        let (width, height) = decoder.dimensions();
        crate::image_reader::check_size(width as usize, height as usize)?;
        image::DynamicImage::from_decoder(decoder).map_err(|e| e.to_string())
    })
    .unwrap_or_else(|_| Err("its decoder failed".to_string()))
    .map_err(|e| format!("cannot decode the image: {e}"))?;
    let float = matches!(
        decoded.color(),
        image::ColorType::Rgb32F | image::ColorType::Rgba32F
    );
    let srgb = match space {
        ColourSpace::Srgb => true,
        ColourSpace::Raw => false,
        ColourSpace::Auto => !float,
    };
    let (width, height) = (decoded.width() as usize, decoded.height() as usize);
    let texels = crate::linear_rgb::linear_rgb(decoded, srgb);
    let image = Image::new(width, height, texels).map_err(|e| e.to_string())?;
    Ok((image, if srgb { "sRGB" } else { "raw" }))
}

/// Reads and decodes the image file at `path`.
pub fn read(path: &Path, space: ColourSpace) -> Result<(Arc<Image>, &'static str), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    decode(&bytes, space).map(|(image, used)| (Arc::new(image), used))
}
