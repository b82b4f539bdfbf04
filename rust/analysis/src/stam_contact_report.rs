//! `sssbake profile --model stam` on a stack whose top layer is declared
//! `model = "stam"`: that layer as a bake uses it, in optical contact with
//! the layer beneath (not between air above and below): R(θi) back to air
//! and T(θi) into the layer beneath, and its response to the diffuse light
//! coming back up.

use crate::angle_plot::degrees;
use crate::stam_report::per_angle;
use serde_json::json;
use sssbake::Error;
use sssbake_profile::Material;
use sssbake_profile::models::stam::contact::ContactTotals;
use sssbake_profile::models::stam::epidermis::Epidermis;

/// The top layer of `material` solved in contact, per channel.
pub fn solve(material: &Material) -> Result<Epidermis, Error> {
    Epidermis::solve(material).map_err(|e| {
        Error::input(format!(
            "material `{}`: its stam top layer: {e}",
            material.name
        ))
    })
}

/// The report of `epidermis`, as a table or (with `json`) one JSON object.
pub fn report(material: &Material, epidermis: &Epidermis, json: bool) -> String {
    if json {
        let value = as_json(material, epidermis);
        format!(
            "{}\n",
            serde_json::to_string_pretty(&value).unwrap_or_default()
        )
    } else {
        table(material, epidermis)
    }
}

fn table(material: &Material, epidermis: &Epidermis) -> String {
    let channel = |c: usize| epidermis.channel(c);
    let mut text = format!(
        "material {}, model stam: its top layer in contact with the layer beneath, as a bake \
         uses it (roughness {}; per unit irradiance)\n",
        material.name, material.roughness
    );
    text += &format!(
        "{:>8} {:>9} {:>9} {:>9}   {:>9} {:>9} {:>9}\n",
        "θi [°]", "R red", "R green", "R blue", "T↓ red", "T↓ green", "T↓ blue"
    );
    for e in (0..channel(0).cosines.len()).rev() {
        text += &format!(
            "{:>8.2} {:>9.5} {:>9.5} {:>9.5}   {:>9.5} {:>9.5} {:>9.5}\n",
            degrees(channel(0).cosines[e]),
            channel(0).reflectance[e],
            channel(1).reflectance[e],
            channel(2).reflectance[e],
            channel(0).transmittance[e],
            channel(1).transmittance[e],
            channel(2).transmittance[e],
        );
    }
    let below = epidermis.reflectance_from_below();
    let out = epidermis.transmittance_from_below();
    text += &format!(
        "diffuse light from below: {:.5} {:.5} {:.5} returns below, {:.5} {:.5} {:.5} leaves into air\n",
        below[0], below[1], below[2], out[0], out[1], out[2]
    );
    text
}

fn as_json(material: &Material, epidermis: &Epidermis) -> serde_json::Value {
    let first = epidermis.channel(0);
    let per_angle = |pick: fn(&ContactTotals) -> &Vec<f64>| {
        per_angle(std::array::from_fn(|c| &pick(epidermis.channel(c))[..]))
    };
    json!({
        "material": material.name,
        "model": "stam",
        "form": "contact",
        "roughness": material.roughness,
        "cosines": first.cosines,
        "angles_deg": first.cosines.iter().map(|&c| degrees(c)).collect::<Vec<_>>(),
        "weights": first.weights,
        "reflectance": per_angle(|t| &t.reflectance),
        "transmittance": per_angle(|t| &t.transmittance),
        "reflectance_from_below": epidermis.reflectance_from_below(),
        "transmittance_from_below": epidermis.transmittance_from_below(),
        "exit_distribution": per_angle(|t| &t.exit_distribution),
    })
}
