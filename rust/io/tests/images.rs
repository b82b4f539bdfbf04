//! Images written by sssbake read back as written.

use sssbake::image::Image;
use sssbake_io::image_writer::{Precision, exr_bytes, png_bytes};
use sssbake_io::read_image;

fn gradient() -> Image {
    let (w, h) = (37, 23);
    let texels = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 / w as f32, (i / w) as f32 / h as f32);
            [x, y, 0.25 + 3.0 * x * y]
        })
        .collect();
    Image::new(w, h, texels).unwrap()
}

fn round_trip(name: &str, bytes: &[u8]) -> Image {
    let path = std::env::temp_dir().join(format!("sssbake-images-{}-{name}", std::process::id()));
    std::fs::write(&path, bytes).unwrap();
    let image = read_image(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    image
}

#[test]
fn exr_keeps_linear_values_in_float_and_to_three_digits_in_half() {
    let original = gradient();
    let float = round_trip(
        "float.exr",
        &exr_bytes(&original, Precision::Float).unwrap(),
    );
    assert_eq!(float, original);
    let half = round_trip("half.exr", &exr_bytes(&original, Precision::Half).unwrap());
    assert_eq!((half.width, half.height), (original.width, original.height));
    for (a, b) in half.texels.iter().zip(&original.texels) {
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= 1e-3 * b[c].abs().max(1e-3),
                "{a:?} {b:?}"
            );
        }
    }
}

/// A 32-bit map is run-length encoded: long runs (the black outside the
/// charts, flat plateaus), noisy low bits and extreme values all come back
/// bit for bit.
#[test]
fn exr_float_keeps_runs_noise_and_extremes_bit_for_bit() {
    let (w, h) = (61, 19);
    let mut state = 0x9e37_79b9u32;
    let texels = (0..w * h)
        .map(|i| match (i / w) % 4 {
            0 => [0.0; 3],
            1 => [0.5, 0.5, 0.5],
            2 => [f32::MAX, f32::MIN_POSITIVE, 1e-42],
            _ => std::array::from_fn(|_| {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                f32::from_bits(0x3e00_0000 | (state & 0x00ff_ffff))
            }),
        })
        .collect();
    let original = Image::new(w, h, texels).unwrap();
    let read = round_trip("runs.exr", &exr_bytes(&original, Precision::Float).unwrap());
    let bits = |image: &Image| -> Vec<u32> {
        image.texels.iter().flatten().map(|v| v.to_bits()).collect()
    };
    assert_eq!(bits(&read), bits(&original));
}

#[test]
fn png_is_srgb_within_a_step_and_clamps_above_one() {
    let original = gradient();
    let png = round_trip("map.png", &png_bytes(&original).unwrap());
    for (a, b) in png.texels.iter().zip(&original.texels) {
        for c in 0..3 {
            let encode = sssbake_io::image_writer::linear_to_srgb;
            let expected = encode(b[c]);
            let got = encode(a[c]);
            assert!(
                (got - expected).abs() <= 1.0 / 255.0 + 1e-6,
                "{got} vs {expected}"
            );
        }
    }
    // Values above one clamp to white.
    assert!(png.texels.iter().any(|t| (t[2] - 1.0).abs() < 1e-6));
}

#[test]
fn an_unknown_extension_is_named() {
    let error = read_image(std::path::Path::new("lightmap.tiff")).unwrap_err();
    assert!(error.to_string().contains("lightmap.tiff"));
    let missing = read_image(std::path::Path::new("/nonexistent/map.exr")).unwrap_err();
    assert!(missing.to_string().contains("map.exr"));
}

/// `bytes` (an EXR) with its data window's far corner moved to (`x`, `y`):
/// a header that claims texels its small display window does not show.
fn with_data_window(mut bytes: Vec<u8>, x: i32, y: i32) -> Vec<u8> {
    let key = b"dataWindow\0box2i\0";
    let at = bytes.windows(key.len()).position(|w| w == key).unwrap() + key.len() + 4;
    bytes[at + 8..at + 12].copy_from_slice(&x.to_le_bytes());
    bytes[at + 12..at + 16].copy_from_slice(&y.to_le_bytes());
    bytes
}

/// Found by fuzzing: a 426-byte EXR texture whose data window claimed
/// about 3.8 billion texels made the decoder ask for 45 GB and abort the
/// process. Its size is now checked against the header first, by both
/// readers.
#[test]
fn an_exr_claiming_more_texels_than_it_holds_is_refused_before_decoding() {
    let small = exr_bytes(&gradient(), Precision::Float).unwrap();
    let hostile = with_data_window(small, 939_524_099, 3);
    let error =
        sssbake_io::colour_texture::decode(&hostile, sssbake_io::colour_texture::ColourSpace::Auto)
            .unwrap_err();
    assert!(error.contains("939524100×4 texels, more than"), "{error}");
    let path = std::env::temp_dir().join(format!("sssbake-images-{}-huge.exr", std::process::id()));
    std::fs::write(&path, &hostile).unwrap();
    let error = read_image(&path).unwrap_err();
    std::fs::remove_file(&path).unwrap();
    assert!(
        error.to_string().contains("939524100×4 texels, more than"),
        "{error}"
    );
}

/// The EXR fuzz run's memory peaked at 9.7 GB: a mutated header may claim a
/// data window under the texel cap, 16384² here, that the decoders then
/// allocate whole (several GB) before finding the file holds a few hundred
/// bytes. Its samples are now checked against what the file's length can
/// hold, by both readers, before decoding.
#[test]
fn an_exr_header_claiming_more_samples_than_its_bytes_can_hold_is_refused() {
    let small = exr_bytes(&gradient(), Precision::Float).unwrap();
    let hostile = with_data_window(small.clone(), 16383, 16383);
    let expected = format!(
        "16384×16384 texels of 12 bytes (3072.0 MiB of samples), more than its {} bytes",
        hostile.len()
    );
    let error =
        sssbake_io::colour_texture::decode(&hostile, sssbake_io::colour_texture::ColourSpace::Auto)
            .unwrap_err();
    assert!(error.contains(&expected), "{error}");
    let path = std::env::temp_dir().join(format!("sssbake-images-{}-wide.exr", std::process::id()));
    std::fs::write(&path, &hostile).unwrap();
    let error = read_image(&path).unwrap_err();
    std::fs::remove_file(&path).unwrap();
    assert!(error.to_string().contains(&expected), "{error}");
    assert!(error.to_string().contains("wide.exr"), "{error}");
    // The image as written, whose samples its bytes hold, still reads.
    assert_eq!(round_trip("whole.exr", &small), gradient());
}
