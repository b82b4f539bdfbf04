//! Files handed in beside a valid scene, broken: material TOML (values
//! negative, NaN, infinite, of the wrong type or shape), sidecars, and the
//! images read for irradiance, environment and base colour (not images,
//! cut short, claiming more texels than any image may have).

use super::{Case, quad};
use sssbake::image::Image;
use sssbake_io::image_writer::{Precision, exr_bytes, png_bytes};

/// The valid quad's files.
fn scene() -> Vec<(&'static str, Vec<u8>)> {
    let document = quad::document(Some("quad.bin"));
    vec![
        ("quad.gltf", serde_json::to_vec_pretty(&document).unwrap()),
        ("quad.bin", quad::bin()),
    ]
}

/// The quad baked with `option` naming `file`, which holds `bytes`.
fn beside(name: &str, option: &str, file: &str, bytes: Vec<u8>, words: &[&str]) -> Case {
    let mut files = scene();
    files.push((file, bytes));
    let at = format!("@{file}");
    Case::new(name, files, "quad.gltf", &[option, &at], file, words)
}

/// A material file whose only layer is `layer` (TOML lines).
fn material(name: &str, text: &str, words: &[&str]) -> Case {
    beside(
        name,
        "--material",
        "broken.toml",
        text.as_bytes().to_vec(),
        words,
    )
}

const GOOD_LAYER: &str = "[[layers]]\nsigma_a = [0.03, 0.15, 0.45]\nsigma_s = 4.0\n";

/// A sidecar of `text`, with a broken material file beside it.
fn sidecar(name: &str, text: &str, words: &[&str]) -> Case {
    let mut case = beside(
        name,
        "--materials",
        "sidecar.toml",
        text.as_bytes().to_vec(),
        words,
    );
    case.files.push((
        "negative.toml".into(),
        b"[[layers]]\nsigma_a = -1.0\nsigma_s = 4.0\n".to_vec(),
    ));
    case
}

/// A 4×4 grey image.
fn grey() -> Image {
    Image::new(4, 4, vec![[0.5; 3]; 16]).unwrap()
}

/// `exr` with its data window's corner moved to (`x`, `y`).
fn exr_claiming(x: i32, y: i32) -> Vec<u8> {
    let mut bytes = exr_bytes(&grey(), Precision::Float).unwrap();
    let key = b"dataWindow\0box2i\0";
    let at = bytes
        .windows(key.len())
        .position(|w| w == key)
        .expect("an EXR has a data window")
        + key.len()
        + 4;
    bytes[at + 8..at + 12].copy_from_slice(&x.to_le_bytes());
    bytes[at + 12..at + 16].copy_from_slice(&y.to_le_bytes());
    bytes
}

/// The material, sidecar and image cases.
pub fn cases() -> Vec<Case> {
    let noise: Vec<u8> = (0..=255u8).cycle().take(777).collect();
    let png = png_bytes(&grey()).unwrap();
    let exr = exr_bytes(&grey(), Precision::Float).unwrap();
    vec![
        material(
            "toml-cut-short",
            "[[layers]]\nsigma_a = [0.1,",
            &["not valid TOML"],
        ),
        material(
            "sigma-a-negative",
            "[[layers]]\nsigma_a = -0.5\nsigma_s = 4.0\n",
            &["layers[0].sigma_a", "non-negative", "-0.5"],
        ),
        material(
            "sigma-s-nan",
            "[[layers]]\nsigma_a = 0.1\nsigma_s = nan\n",
            &["layers[0].sigma_s", "finite", "NaN"],
        ),
        material(
            "sigma-a-infinite",
            "[[layers]]\nsigma_a = [0.1, inf, 0.1]\nsigma_s = 4.0\n",
            &["layers[0].sigma_a", "finite", "inf"],
        ),
        material(
            "sigma-a-a-string",
            "[[layers]]\nsigma_a = \"red\"\nsigma_s = 4.0\n",
            &["layers[0].sigma_a"],
        ),
        material(
            "sigma-a-two-channels",
            "[[layers]]\nsigma_a = [0.1, 0.2]\nsigma_s = 4.0\n",
            &["layers[0].sigma_a"],
        ),
        material(
            "neither-scatters-nor-absorbs",
            "[[layers]]\nsigma_a = 0.0\nsigma_s = 0.0\n",
            &["layers[0].sigma_s", "neither scatters nor absorbs"],
        ),
        material(
            "g-one",
            &format!("{GOOD_LAYER}g = 1.0\n"),
            &["layers[0].g", "between -1 and 1"],
        ),
        material(
            "ior-zero",
            &format!("{GOOD_LAYER}ior = 0.0\n"),
            &["layers[0].ior", "positive"],
        ),
        material(
            "thickness-negative",
            &format!("{GOOD_LAYER}thickness_mm = -1.0\n"),
            &["layers[0].thickness_mm", "positive"],
        ),
        material(
            "upper-layer-unbounded",
            &format!("{GOOD_LAYER}{GOOD_LAYER}"),
            &["layers[0].thickness_mm", "missing"],
        ),
        material(
            "coat-ior-negative",
            &format!("coat_ior = -1.4\n{GOOD_LAYER}"),
            &["coat_ior", "positive"],
        ),
        material(
            "misspelt-key",
            &format!("{GOOD_LAYER}sigma_t = 3.0\n"),
            &["sigma_t"],
        ),
        material("no-layers", "name = \"nothing\"\n", &["layers", "missing"]),
        material("layers-a-number", "layers = 3\n", &["layers"]),
        beside(
            "material-not-utf8",
            "--material",
            "broken.toml",
            noise.clone(),
            &["cannot read"],
        ),
        sidecar("sidecar-cut-short", "[objects]\nTile = ", &["objects"]),
        sidecar(
            "sidecar-unknown-preset",
            "[objects]\nTile = \"granite\"\n",
            &["objects.Tile", "granite"],
        ),
        sidecar(
            "sidecar-material-missing",
            "[objects]\nTile = \"absent.toml\"\n",
            &["objects.Tile", "absent.toml", "cannot read"],
        ),
        sidecar(
            "sidecar-material-negative",
            "[objects]\nTile = \"negative.toml\"\n",
            &["objects.Tile", "negative.toml", "layers[0].sigma_a"],
        ),
        sidecar(
            "sidecar-unknown-object",
            "[objects]\nNobody = \"skin1\"\n",
            &["objects.Nobody", "no object of that name"],
        ),
        sidecar(
            "sidecar-value-a-number",
            "[objects]\nTile = 3\n",
            &["objects"],
        ),
        sidecar("sidecar-objects-a-number", "objects = 3\n", &["objects"]),
        sidecar(
            "sidecar-unknown-table",
            "[objects]\nTile = \"skin1\"\n[colours]\nTile = 1\n",
            &["colours"],
        ),
        beside(
            "irradiance-exr-noise",
            "--irradiance",
            "light.exr",
            noise.clone(),
            &["EXR"],
        ),
        beside(
            "irradiance-exr-cut-short",
            "--irradiance",
            "light.exr",
            exr[..exr.len() * 2 / 3].to_vec(),
            &["EXR"],
        ),
        beside(
            "irradiance-exr-claims-too-many-texels",
            "--irradiance",
            "light.exr",
            exr_claiming(999_999, 999_999),
            &["1000000×1000000", "more than"],
        ),
        beside(
            "irradiance-png-noise",
            "--irradiance",
            "light.png",
            noise.clone(),
            &["PNG"],
        ),
        beside(
            "irradiance-png-cut-short",
            "--irradiance",
            "light.png",
            png[..png.len() / 2].to_vec(),
            &["PNG"],
        ),
        beside(
            "irradiance-not-an-image-type",
            "--irradiance",
            "light.jpg",
            png.clone(),
            &["neither an .exr nor a .png"],
        ),
        beside(
            "environment-exr-noise",
            "--environment",
            "sky.exr",
            noise.clone(),
            &["EXR"],
        ),
        beside(
            "environment-exr-claims-too-many-texels",
            "--environment",
            "sky.exr",
            exr_claiming(99_999, 9_999),
            &["100000×10000", "more than"],
        ),
        beside(
            "base-colour-png-noise",
            "--base-color",
            "colour.png",
            noise,
            &["PNG"],
        ),
    ]
}
