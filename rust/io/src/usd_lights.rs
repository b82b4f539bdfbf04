//! UsdLux lights in the bake's radiometric units, as the UsdLux schema
//! defines them, and as Blender's USD exporter means them where it departs
//! from the schema (detected from the layer's documentation string, which
//! Blender sets to `Blender vX.Y.Z`). [`USD_LIGHTS`] is the table, shown in
//! docs/lights.md.
//!
//! I' = intensity × 2^exposure; every light is also multiplied by
//! C = color × diffuse × (the blackbody colour of colorTemperature when
//! enableColorTemperature, [`sssbake::blackbody`]).
//!
//! Blender 5.0's exporter writes `enableColorTemperature = 1` on every
//! light whether or not its temperature is in use, and `colorTemperature`
//! only when it is not 6500 K; so in its files 6500 K reads as white and
//! any other temperature is applied (Blender's own importer turns the
//! temperature on for every light), with a note.

use crate::usd_reader::LightJson;
use glam::Vec3;
use sssbake::blackbody::blackbody_rgb;
use sssbake::scene::spot_cone;
use sssbake::{ConeFalloff, Light, LightKind, LightRow};
use std::f32::consts::PI;

/// The column titles of [`USD_LIGHTS`] in docs/lights.md.
pub const USD_HEADER: [&str; 3] = [
    "UsdLux prim",
    "read as",
    "irradiance at a point of the plane, × C",
];

/// The UsdLux table: one row per case, each with a test in
/// `rust/io/tests/light_tables.rs`. d is the distance in metres, θ the
/// angle of incidence, φ the angle from a spot's axis.
pub const USD_LIGHTS: &[LightRow] = &[
    LightRow {
        source: "`DistantLight`, `normalize` on or `angle` 0",
        read_as: "directional, angular diameter `angle`",
        irradiance: "I'·cos θ",
    },
    LightRow {
        source: "`DistantLight`, `normalize` off, `angle` α > 0",
        read_as: "directional, angular diameter α",
        irradiance: "I'·π sin²(α/2)·cos θ",
    },
    LightRow {
        source: "`DistantLight` written by Blender",
        read_as: "directional, angular diameter 2·`angle` (Blender writes a sun's strength ÷ 4 and half its angle)",
        irradiance: "4·I'·cos θ",
    },
    LightRow {
        source: "`SphereLight`, `normalize` on, or `treatAsPoint`, or `radius` 0",
        read_as: "sphere of `radius` (a point when `treatAsPoint`)",
        irradiance: "(I'/4)·cos θ/d²",
    },
    LightRow {
        source: "`SphereLight`, `normalize` off, `radius` r > 0",
        read_as: "sphere of radius r",
        irradiance: "π r² I'·cos θ/d²",
    },
    LightRow {
        source: "`SphereLight` with `ShapingAPI` cone angle a, softness s",
        read_as: "spot fading from a(1 − s) to a",
        irradiance: "the sphere's × (1 − smoothstep((φ − a(1 − s))/(a s)))",
    },
    LightRow {
        source: "`SphereLight` with `ShapingAPI`, written by Blender",
        read_as: "Blender's spot of size 2a and blend s",
        irradiance: "the sphere's × smoothstep((cos φ − cos a)/(s(1 − cos a)))",
    },
    LightRow {
        source: "`RectLight` w × h",
        read_as: "rectangle emitting along its −Z",
        irradiance: "∫ L cos θ cos θₗ/d² dA, L = I'/(w h) when normalized, else I'",
    },
    LightRow {
        source: "`DiskLight` of radius r",
        read_as: "disk emitting along its −Z",
        irradiance: "∫ L cos θ cos θₗ/d² dA, L = I'/(π r²) when normalized, else I'",
    },
    LightRow {
        source: "`CylinderLight` of length l and radius r",
        read_as: "cylinder along its X emitting from its side",
        irradiance: "∫ L cos θ cos θₗ/d² dA, L = I'/(2π r l) when normalized, else I'",
    },
    LightRow {
        source: "`CylinderLight` with `treatAsLine`",
        read_as: "line along its X with the cylinder's emission",
        irradiance: "∫ 2r L sin ψ cos θ/d² dx, ψ the angle from the line",
    },
    LightRow {
        source: "`DomeLight`, `texture:format` `latlong` or `automatic` (texture T, or none: T = 1)",
        read_as: "environment",
        irradiance: "I' ∫ T(ω) cos θ dω (π I' for T = 1)",
    },
];

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

/// The bake's light for `light` in a stage of `mm_per_unit`: `Ok(None)`
/// with a note in `notes` for a kind the bake does not take, an error for
/// a dome texture in a format it cannot read.
pub(crate) fn usd_light(
    light: &LightJson,
    mm_per_unit: f64,
    writer: Writer,
    notes: &mut Vec<String>,
) -> Result<Option<Light>, String> {
    let name = &light.name;
    let blender = writer == Writer::Blender;
    // The light's own transform scales its size; absent, it is 1.
    let own = light.scale.filter(|s| s.is_finite() && *s > 0.0);
    let scale = mm_per_unit as f32 * own.unwrap_or(1.0);
    let size = |value: Option<f32>| (value.unwrap_or(0.0) * scale).max(0.0);
    let strength = light.intensity * light.exposure.exp2();
    let kind_name = light.kind.as_deref().unwrap_or("");
    let (kind, intensity) = match kind_name {
        "DistantLight" => {
            let angle = light.angle.unwrap_or(0.0).max(0.0).to_radians();
            if blender {
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
                    let half_angle = half_angle.max(0.0).to_radians();
                    let softness = light.cone_softness.unwrap_or(0.0).clamp(0.0, 1.0);
                    let (inner_cone, outer_cone, falloff) = if blender {
                        let (inner, outer) = spot_cone(half_angle, softness);
                        (inner, outer, ConeFalloff::Cycles)
                    } else {
                        (
                            half_angle * (1.0 - softness),
                            half_angle,
                            ConeFalloff::UsdLux,
                        )
                    };
                    LightKind::Spot {
                        radius_mm,
                        inner_cone,
                        outer_cone,
                        falloff,
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
            let kind = LightKind::Disk {
                radius_mm,
                spread: PI,
            };
            (kind, radiance)
        }
        "RectLight" => {
            let (width_mm, height_mm) = (size(light.width), size(light.height));
            let area_m2 = width_mm * height_mm * 1e-6;
            let radiance = normalized(strength, area_m2, light.normalize);
            let kind = LightKind::Rectangle {
                width_mm,
                height_mm,
                spread: PI,
            };
            (kind, radiance)
        }
        "CylinderLight" => {
            let (length_mm, radius_mm) = (size(light.length), size(light.radius));
            let area_m2 = 2.0 * PI * radius_mm * length_mm * 1e-6;
            let radiance = normalized(strength, area_m2, light.normalize);
            if light.treat_as_line.unwrap_or(false) {
                // Each metre of a cylinder seen broadside shows 2r of it.
                let per_metre = radiance * 2.0 * radius_mm * 1e-3;
                (LightKind::Line { length_mm }, per_metre)
            } else {
                let kind = LightKind::Cylinder {
                    length_mm,
                    radius_mm,
                };
                (kind, radiance)
            }
        }
        "DomeLight" => {
            let format = light.texture_format.as_deref().unwrap_or("automatic");
            let texture = light.texture.clone().filter(|t| !t.is_empty());
            if texture.is_some() && !matches!(format, "latlong" | "automatic") {
                return Err(format!(
                    "light `{name}`: a DomeLight texture in `{format}` format cannot be read; \
                     sssbake reads `latlong` (and `automatic`, taken as latlong)"
                ));
            }
            (LightKind::Environment { texture }, strength)
        }
        _ => {
            let what = if kind_name.is_empty() {
                "light of no type"
            } else {
                kind_name
            };
            notes.push(format!(
                "light `{name}`: a {what} is not a kind sssbake bakes; left out"
            ));
            return Ok(None);
        }
    };
    let tint = match light.color_temperature {
        Some(kelvin) if blender && kelvin == 6500.0 => [1.0; 3],
        Some(kelvin) => {
            if blender {
                notes.push(format!(
                    "light `{name}`: its colour temperature ({kelvin} K) is applied \
                     (Blender's USD files mark every light's temperature as in use)"
                ));
            }
            blackbody_rgb(f64::from(kelvin)).map(|c| c as f32)
        }
        None => [1.0; 3],
    };
    let colour = light.color.unwrap_or([1.0; 3]);
    let diffuse = light.diffuse.unwrap_or(1.0).max(0.0);
    let direction = light.direction.map_or(Vec3::NEG_Z, Vec3::from);
    Ok(Some(Light {
        name: name.clone(),
        kind,
        color: [0, 1, 2].map(|c| colour[c] * tint[c] * diffuse),
        intensity,
        position: light.position.map_or(Vec3::ZERO, Vec3::from) * mm_per_unit as f32,
        direction: direction.normalize_or(Vec3::NEG_Z),
        tangent: light
            .tangent
            .map_or(Vec3::X, |t| Vec3::from(t).normalize_or(Vec3::X)),
        casts_shadow: true,
    }))
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
