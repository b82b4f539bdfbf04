//! A USD surface shader, as `usd/read_stage.py` reports it, translated into
//! the bake's material hint (docs/materials.md, "Materials from the asset").
//!
//! - OpenPBR (`ND_open_pbr_surface_surfaceshader`) with a positive
//!   subsurface_weight: colour = subsurface_color, mean free path = subsurface_radius ×
//!   subsurface_radius_scale (stage units, so × mm per unit), g =
//!   subsurface_scatter_anisotropy, index = specular_ior; OpenPBR's
//!   defaults for inputs not authored.
//! - OpenPBR without subsurface: its base_color; UsdPreviewSurface: its
//!   diffuseColor. Both with `ior`, and no scattering distance of their own.

use serde::Deserialize;
use serde::de::IgnoredAny;
use serde_json::Value;
use sssbake::MaterialHint;
use sssbake::scene::Subsurface;
use std::collections::HashMap;

const OPEN_PBR: &str = "ND_open_pbr_surface_surfaceshader";

/// A mesh's bound material as `usd/read_stage.py` reports it (its
/// `material` entry; `null` when nothing is bound).
#[derive(Deserialize)]
pub(crate) struct ShaderJson {
    /// The Material prim's name.
    name: String,
    /// The surface shader's `info:id` (the MaterialX context's first, then
    /// the universal one); empty when the material has no surface.
    #[serde(default)]
    shader: String,
    /// The authored values of the shader's unconnected inputs, by base name.
    #[serde(default)]
    inputs: HashMap<String, InputJson>,
    /// The base names of the inputs a connection (a texture) drives.
    #[serde(default)]
    connected: Vec<String>,
    /// For connected inputs, what drives them: a UsdUVTexture read, or
    /// another shader named by its id.
    #[serde(default)]
    textures: HashMap<String, TextureJson>,
}

/// The colour input a texture drives, and that texture.
pub(crate) type ColourInput = (String, TextureJson);

/// What drives a connected input, as `usd/read_stage.py` reports it.
#[derive(Clone, Debug, Deserialize)]
pub(crate) struct TextureJson {
    /// The source shader's id (`UsdUVTexture` for a texture sssbake reads).
    #[serde(default)]
    pub(crate) shader: String,
    /// The output connected (`rgb`, `r`, …).
    #[serde(default)]
    pub(crate) output: String,
    /// `inputs:file`, resolved where the resolver could.
    #[serde(default)]
    pub(crate) file: String,
    /// `inputs:sourceColorSpace` (`auto`, `sRGB`, `raw`).
    #[serde(default)]
    pub(crate) source_colour_space: String,
    /// `inputs:wrapS`.
    #[serde(default)]
    pub(crate) wrap_s: String,
    /// `inputs:wrapT`.
    #[serde(default)]
    pub(crate) wrap_t: String,
    /// `inputs:scale`, RGB.
    pub(crate) scale: Option<[f32; 3]>,
    /// `inputs:bias`, RGB.
    pub(crate) bias: Option<[f32; 3]>,
    /// A UsdTransform2d between the primvar reader and the texture.
    pub(crate) transform: Option<TransformJson>,
    /// The primvar the texture's st reads.
    pub(crate) primvar: Option<String>,
    /// That primvar per face corner, when it is not the one the mesh's
    /// UVs came from.
    pub(crate) uvs: Option<Vec<[f32; 2]>>,
    /// The primvar is not on the mesh.
    #[serde(default)]
    pub(crate) missing: bool,
}

/// A UsdTransform2d's inputs.
#[derive(Clone, Debug, Deserialize)]
pub(crate) struct TransformJson {
    /// Degrees, counter-clockwise.
    pub(crate) rotation: f32,
    /// Scale along s and t.
    pub(crate) scale: [f32; 2],
    /// Translation.
    pub(crate) translation: [f32; 2],
}

impl TextureJson {
    /// True for a UsdUVTexture whose colour output drives the input.
    fn is_colour_texture(&self) -> bool {
        self.shader == "UsdUVTexture" && matches!(self.output.as_str(), "rgb" | "")
    }

    /// How the texture is named in notes.
    fn describe(&self) -> String {
        if self.shader == "UsdUVTexture" {
            format!("the texture {}", self.file)
        } else {
            format!("a {} shader", self.shader)
        }
    }
}

/// One input's value: a number (the script writes scalars and booleans as
/// floats) or three numbers (a colour or vector). Other shapes, such as
/// a token the script spelt out as a list of characters, belong to inputs
/// the bake does not read; they are kept out rather than refused, so an
/// unusual shader never stops a scene from loading.
#[derive(Deserialize)]
#[serde(untagged)]
enum InputJson {
    Number(f64),
    Triple([f64; 3]),
    Other(IgnoredAny),
}

/// The hint for one mesh's `material` entry, and notes on inputs that a
/// texture drives (their authored defaults are used); `None` for an entry
/// that is `null`, is not a material as `usd/read_stage.py` writes one,
/// or has a shader the bake does not translate.
pub fn usd_material(value: &Value, mm_per_unit: f64) -> Option<(MaterialHint, Vec<String>)> {
    let shader = ShaderJson::deserialize(value).ok()?;
    material_hint(&shader, mm_per_unit).map(|(hint, notes, _)| (hint, notes))
}

/// The hint for one bound material, as [`usd_material`] describes.
///
/// Also returns the texture that drives the colour the profile is built for
/// (`subsurface_color` of an OpenPBR with subsurface, else `base_color`;
/// UsdPreviewSurface's `diffuseColor`), with that input's name, when a
/// UsdUVTexture's colour drives it.
pub(crate) fn material_hint(
    material: &ShaderJson,
    mm_per_unit: f64,
) -> Option<(MaterialHint, Vec<String>, Option<ColourInput>)> {
    let name = material.name.clone();
    let number = |key: &str, default: f64| match material.inputs.get(key) {
        Some(InputJson::Number(x)) => *x,
        _ => default,
    };
    let colour = |key: &str, default: [f64; 3]| match material.inputs.get(key) {
        Some(InputJson::Triple(c)) => *c,
        _ => default,
    };
    let shader = material.shader.as_str();
    let (base, ior, subsurface) = if shader == OPEN_PBR {
        let base = colour("base_color", [0.8; 3]);
        let weight = number("subsurface_weight", 0.0);
        let subsurface = (weight > 0.0).then(|| {
            let radius = number("subsurface_radius", 1.0);
            let scale = colour("subsurface_radius_scale", [1.0, 0.5, 0.25]);
            Subsurface {
                colour: colour("subsurface_color", [0.8; 3]),
                mean_free_path_mm: scale.map(|s| radius * s * mm_per_unit),
                anisotropy: number("subsurface_scatter_anisotropy", 0.0),
                from: "OpenPBR subsurface_color, subsurface_radius × subsurface_radius_scale"
                    .to_string(),
            }
        });
        (base, number("specular_ior", 1.5), subsurface)
    } else if shader == "UsdPreviewSurface" {
        (colour("diffuseColor", [0.18; 3]), number("ior", 1.5), None)
    } else {
        return None;
    };
    let colour_input = match (shader, &subsurface) {
        (OPEN_PBR, Some(_)) => "subsurface_color",
        (OPEN_PBR, None) => "base_color",
        _ => "diffuseColor",
    };
    let colour_texture = material
        .textures
        .get(colour_input)
        .filter(|t| t.is_colour_texture())
        .map(|t| (colour_input.to_string(), t.clone()));
    let notes = material
        .connected
        .iter()
        .filter(|n| {
            ["base_color", "diffuseColor", "ior", "specular_ior"].contains(&n.as_str())
                || n.starts_with("subsurface")
        })
        .filter(|n| !(colour_texture.is_some() && n.as_str() == colour_input))
        .map(|n| {
            let by = material
                .textures
                .get(n)
                .map_or_else(|| "a texture".to_string(), TextureJson::describe);
            let what = if n.as_str() == colour_input {
                "sssbake reads only a UsdUVTexture's rgb there"
            } else if n.starts_with("subsurface_radius") {
                "the texture is reported, not yet applied"
            } else if ["base_color", "diffuseColor"].contains(&n.as_str()) {
                "it is not the colour the subsurface scatters"
            } else {
                "the texture is not applied"
            };
            format!("material `{name}`: `{n}` is driven by {by}; its default is used ({what})")
        })
        .collect();
    let hint = MaterialHint {
        name,
        base_color: [base[0] as f32, base[1] as f32, base[2] as f32, 1.0],
        ior: Some(ior as f32),
        subsurface,
        ..Default::default()
    };
    Some((hint, notes, colour_texture))
}
