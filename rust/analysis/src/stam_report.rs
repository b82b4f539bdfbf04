//! `sssbake profile --model stam`: a layer's reflectance and transmittance
//! per incidence angle, and its BRDF and BTDF in the plane of incidence.

use crate::angle_plot::degrees;
use serde_json::{Value, json};
use sssbake::Error;
use sssbake_profile::Material;
use sssbake_profile::models::stam::material::solve_material;
use sssbake_profile::models::stam::{StamResponse, StamSettings};
use std::f64::consts::PI;

/// The layer's response per channel, or why the material has none.
pub fn solve(material: &Material) -> Result<[StamResponse; 3], Error> {
    solve_material(material, &StamSettings::default())
        .map_err(|e| Error::input(format!("material `{}`: model stam: {e}", material.name)))
}

/// The report of `responses`, as a table or (with `json`) one JSON object.
pub fn report(material: &Material, responses: &[StamResponse; 3], json: bool) -> String {
    if json {
        format!(
            "{}\n",
            serde_json::to_string_pretty(&as_json(material, responses)).unwrap_or_default()
        )
    } else {
        table(material, responses)
    }
}

fn table(material: &Material, responses: &[StamResponse; 3]) -> String {
    let first = &responses[0];
    let mut text = format!(
        "material {}, model stam (one layer between air, roughness {}; per unit irradiance)\n",
        material.name, material.roughness
    );
    text += &format!(
        "{:>8} {:>9} {:>9} {:>9}   {:>9} {:>9} {:>9}   {:>9}\n",
        "θi [°]", "R red", "R green", "R blue", "T red", "T green", "T blue", "surface"
    );
    for e in (0..first.cosines.len()).rev() {
        text += &format!(
            "{:>8.2} {:>9.5} {:>9.5} {:>9.5}   {:>9.5} {:>9.5} {:>9.5}   {:>9.5}\n",
            degrees(first.cosines[e]),
            responses[0].reflectance[e],
            responses[1].reflectance[e],
            responses[2].reflectance[e],
            responses[0].transmittance[e],
            responses[1].transmittance[e],
            responses[2].transmittance[e],
            first.surface_reflectance[e],
        );
    }
    text
}

/// In-plane slices [channel][incidence][exit] at Δφ = `delta_phi`.
fn slices(responses: &[StamResponse; 3], brdf: bool, delta_phi: f64) -> Value {
    let per_channel: Vec<Vec<Vec<f64>>> = responses
        .iter()
        .map(|r| {
            let n = r.cosines.len();
            (0..n)
                .map(|e| {
                    (0..n)
                        .map(|o| {
                            if brdf {
                                r.brdf_at(o, e, delta_phi)
                            } else {
                                r.btdf_at(o, e, delta_phi)
                            }
                        })
                        .collect()
                })
                .collect()
        })
        .collect();
    json!(per_channel)
}

/// Values per channel, `channels[c][e]` at ordinate `e`, as one `[r, g, b]`
/// per ordinate.
pub fn per_angle(channels: [&[f64]; 3]) -> Vec<[f64; 3]> {
    (0..channels[0].len())
        .map(|e| channels.map(|values| values[e]))
        .collect()
}

fn as_json(material: &Material, responses: &[StamResponse; 3]) -> Value {
    let first = &responses[0];
    let per_angle = |pick: fn(&StamResponse) -> &Vec<f64>| {
        per_angle(std::array::from_fn(|c| &pick(&responses[c])[..]))
    };
    json!({
        "material": material.name,
        "model": "stam",
        "roughness": material.roughness,
        "cosines": first.cosines,
        "angles_deg": first.cosines.iter().map(|&c| degrees(c)).collect::<Vec<_>>(),
        "weights": first.weights,
        "reflectance": per_angle(|r| &r.reflectance),
        "transmittance": per_angle(|r| &r.transmittance),
        "surface_reflectance": first.surface_reflectance,
        "brdf_forward": slices(responses, true, 0.0),
        "brdf_backward": slices(responses, true, PI),
        "btdf_forward": slices(responses, false, 0.0),
        "btdf_backward": slices(responses, false, PI),
    })
}
