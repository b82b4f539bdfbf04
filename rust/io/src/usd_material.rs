//! A USD surface shader, as `usd/read_stage.py` reports it, translated into
//! the bake's material hint (README, "Materials from the asset").
//!
//! - OpenPBR (`ND_open_pbr_surface_surfaceshader`) with a positive
//!   subsurface_weight: colour = subsurface_color, mean free path = subsurface_radius ×
//!   subsurface_radius_scale (stage units, so × mm per unit), g =
//!   subsurface_scatter_anisotropy, index = specular_ior; OpenPBR's
//!   defaults for inputs not authored.
//! - OpenPBR without subsurface: its base_color; UsdPreviewSurface: its
//!   diffuseColor. Both with `ior`, and no scattering distance of their own.

use serde_json::Value;
use sssbake::MaterialHint;
use sssbake::scene::Subsurface;

const OPEN_PBR: &str = "ND_open_pbr_surface_surfaceshader";

/// The hint for one mesh's `material` entry, and notes on inputs that a
/// texture drives (their authored defaults are used).
pub fn usd_material(value: &Value, mm_per_unit: f64) -> Option<(MaterialHint, Vec<String>)> {
    let name = value["name"].as_str()?.to_string();
    let shader = value["shader"].as_str().unwrap_or("");
    let inputs = &value["inputs"];
    let number = |key: &str, default: f64| inputs[key].as_f64().unwrap_or(default);
    let colour = |key: &str, default: [f64; 3]| {
        inputs[key]
            .as_array()
            .filter(|c| c.len() == 3)
            .map_or(default, |c| {
                [0, 1, 2].map(|i| c[i].as_f64().unwrap_or(default[i]))
            })
    };
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
    let notes = value["connected"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|n| n.as_str())
        .filter(|n| {
            ["base_color", "diffuseColor", "ior", "specular_ior"].contains(n)
                || n.starts_with("subsurface")
        })
        .map(|n| format!("material `{name}`: `{n}` is driven by a texture; its default is used"))
        .collect();
    let hint = MaterialHint {
        name,
        base_color: [base[0] as f32, base[1] as f32, base[2] as f32, 1.0],
        ior: Some(ior as f32),
        subsurface,
        ..Default::default()
    };
    Some((hint, notes))
}
