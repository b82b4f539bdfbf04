//! UsdLux lights in the bake's radiometric units, as the UsdLux schema
//! defines them, and as Blender's USD exporter means them where it departs
//! from the schema (detected from the layer's documentation string, which
//! Blender sets to `Blender vX.Y.Z`).
//!
//! I' = intensity × 2^exposure × colour. Per prim (r radius, A area, θ the
//! DistantLight's angular diameter):
//!
//! | prim | the bake's light | strength |
//! |---|---|---|
//! | DistantLight | directional, angular diameter θ | irradiance I' when normalized or θ = 0; else I'·π·sin²(θ/2) (radiance over the sun's disk) |
//! | DistantLight written by Blender | directional, angular diameter 2θ | irradiance 4·I' (Blender writes a sun's strength ÷ 4 and half its angle; its importer reads them back so) |
//! | SphereLight | point (spot with a ShapingAPI cone under 180°), radius r | intensity I'/4 W/sr when normalized (radiance I'/(4πr²) times πr²) or r = 0; else πr²·I' |
//! | DiskLight | disk, radius r | radiance I'/(πr²) when normalized, else I' |
//! | RectLight | rectangle w × h | radiance I'/(w·h) when normalized, else I' |
//! | DomeLight | environment, its texture | radiance I' |
//!
//! A ShapingAPI cone (half-angle, softness) fades as Cycles fades a spot of
//! that half-angle and blend, which is how Blender writes and reads spots.
//! Colour temperature is not applied (a note says so when it is not the
//! white point's 6500 K); CylinderLights and lights of other kinds are left
//! out with a note.

use crate::usd_reader::LightJson;
use glam::Vec3;
use sssbake::scene::spot_cone;
use sssbake::{Light, LightKind};
use std::f32::consts::PI;

/// Who wrote a stage, where a writer reads UsdLux its own way.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Writer {
    /// Blender's USD exporter.
    Blender,
    /// Anyone else: the schema as written.
    Other,
}

impl Writer {
    /// The writer of a layer whose documentation string is `documentation`.
    pub(crate) fn of(documentation: Option<&str>) -> Self {
        match documentation {
            Some(doc) if doc.starts_with("Blender v") => Writer::Blender,
            _ => Writer::Other,
        }
    }
}

/// The bake's light for `light` in a stage of `mm_per_unit`, or `None` with
/// a note in `notes` for a kind the bake does not take.
pub(crate) fn usd_light(
    light: &LightJson,
    mm_per_unit: f64,
    writer: Writer,
    notes: &mut Vec<String>,
) -> Option<Light> {
    let name = &light.name;
    // The light's own transform scales its size; absent, it is 1.
    let own = light.scale.filter(|s| s.is_finite() && *s > 0.0);
    let scale = mm_per_unit as f32 * own.unwrap_or(1.0);
    let size = |value: Option<f32>| (value.unwrap_or(0.0) * scale).max(0.0);
    let strength = light.intensity * light.exposure.exp2();
    let kind_name = light.kind.as_deref().unwrap_or("");
    let (kind, intensity) = match kind_name {
        "DistantLight" => {
            let angle = light.angle.unwrap_or(0.0).max(0.0).to_radians();
            if writer == Writer::Blender {
                notes.push(format!(
                    "light `{name}`: read as Blender's USD exporter writes suns (intensity × 4, angle × 2)"
                ));
                (
                    LightKind::Directional { angle: 2.0 * angle },
                    4.0 * strength,
                )
            } else {
                let irradiance = if light.normalize || angle == 0.0 {
                    strength
                } else {
                    strength * PI * (0.5 * angle).sin().powi(2)
                };
                (LightKind::Directional { angle }, irradiance)
            }
        }
        "SphereLight" => {
            let radius_mm = size(light.radius);
            let point = light.treat_as_point.unwrap_or(false) || radius_mm == 0.0;
            let intensity = if light.normalize || point {
                // π r² · I'/(4π r²): the same at any radius, a point's too.
                0.25 * strength
            } else {
                let r_m = radius_mm * 1e-3;
                PI * r_m * r_m * strength
            };
            let radius_mm = if point { 0.0 } else { radius_mm };
            let kind = match light.cone_angle.filter(|&a| a < 180.0) {
                Some(half_angle) => {
                    let blend = light.cone_softness.unwrap_or(0.0).clamp(0.0, 1.0);
                    let (inner_cone, outer_cone) =
                        spot_cone(half_angle.max(0.0).to_radians(), blend);
                    LightKind::Spot {
                        radius_mm,
                        inner_cone,
                        outer_cone,
                    }
                }
                None => LightKind::Point { radius_mm },
            };
            (kind, intensity)
        }
        "DiskLight" => {
            let radius_mm = size(light.radius);
            let area_m2 = PI * (radius_mm * 1e-3).powi(2);
            let radiance = normalized(strength, area_m2, light.normalize);
            (LightKind::Disk { radius_mm }, radiance)
        }
        "RectLight" => {
            let (width_mm, height_mm) = (size(light.width), size(light.height));
            let area_m2 = width_mm * height_mm * 1e-6;
            let radiance = normalized(strength, area_m2, light.normalize);
            let kind = LightKind::Rectangle {
                width_mm,
                height_mm,
            };
            (kind, radiance)
        }
        "DomeLight" => (
            LightKind::Environment {
                texture: light.texture.clone().filter(|t| !t.is_empty()),
            },
            strength,
        ),
        _ => {
            let what = if kind_name.is_empty() {
                "light of no type"
            } else {
                kind_name
            };
            notes.push(format!(
                "light `{name}`: a {what} is not a kind sssbake bakes; left out"
            ));
            return None;
        }
    };
    if let Some(kelvin) = light
        .color_temperature
        .filter(|k| (k - 6500.0).abs() > 50.0)
    {
        notes.push(format!(
            "light `{name}`: its colour temperature ({kelvin} K) is not applied"
        ));
    }
    let direction = light.direction.map_or(Vec3::NEG_Z, Vec3::from);
    Some(Light {
        name: name.clone(),
        kind,
        color: light.color.unwrap_or([1.0; 3]),
        intensity,
        position: light.position.map_or(Vec3::ZERO, Vec3::from) * mm_per_unit as f32,
        direction: direction.normalize_or(Vec3::NEG_Z),
        tangent: light
            .tangent
            .map_or(Vec3::X, |t| Vec3::from(t).normalize_or(Vec3::X)),
    })
}

/// Radiance of an area light of `strength` over `area_m2`: divided by the
/// area when `normalize` asks (a zero area keeps the strength).
fn normalized(strength: f32, area_m2: f32, normalize: bool) -> f32 {
    if normalize && area_m2 > 0.0 {
        strength / area_m2
    } else {
        strength
    }
}
