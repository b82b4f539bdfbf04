//! A material as Stam's layer: its top layer, per channel, between air
//! above and below, with the material's roughness on both faces.

use super::{StamError, StamLayer, StamResponse, StamSettings};
use crate::material::{Material, Optics, TopLayer};

/// The top layer of `material` as one [`StamLayer`] per channel: albedo
/// σs/σt, optical depth σt·thickness (infinite for a semi-infinite layer),
/// its g and index, the material's roughness. Refuses a measured sum of
/// Gaussians (no coefficients), a stack of several layers unless its top
/// layer is declared stam (the model has one layer between air, and the
/// layers below would change what comes back; a declared top layer is
/// solved alone, and [`crate::models::stam::topped`] puts the rest under it), and a
/// coat (a face of another index).
pub fn layers_for(material: &Material) -> Result<[StamLayer; 3], String> {
    let layers = match &material.optics {
        Optics::Gaussians(_) => {
            return Err("a measured sum of Gaussians has no optical coefficients to solve".into());
        }
        Optics::Layers(layers) => layers,
    };
    let top = match (material.top_layer, layers.as_slice()) {
        (TopLayer::Stam, [top, ..])
        | (TopLayer::Diffusion | TopLayer::PrincipledSpecular, [top]) => top,
        _ => {
            return Err(format!(
                "stam solves one layer between air above and below; this material has {} layers \
                 (declare its top layer `model = \"stam\"` to bake it over the rest)",
                layers.len()
            ));
        }
    };
    if material.coat_ior.is_some() {
        return Err(
            "stam's faces are the layer's own; a coat of another index is not modelled".into(),
        );
    }
    Ok(std::array::from_fn(|c| {
        let sigma_t = top.sigma_a[c] + top.sigma_s[c];
        StamLayer {
            albedo: if sigma_t > 0.0 {
                top.sigma_s[c] / sigma_t
            } else {
                0.0
            },
            optical_depth: top.thickness_mm.map_or(f64::INFINITY, |t| sigma_t * t),
            g: top.g,
            eta: top.ior,
            roughness: material.roughness,
        }
    }))
}

/// Solves `material`'s layer in each channel.
pub fn solve_material(
    material: &Material,
    settings: &StamSettings,
) -> Result<[StamResponse; 3], String> {
    let [r, g, b] = layers_for(material)?;
    let solve = |l: StamLayer| l.solve(settings).map_err(|StamError(e)| e);
    Ok([solve(r)?, solve(g)?, solve(b)?])
}
