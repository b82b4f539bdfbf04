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
