//! Lights in Blender's terms, converted to the library's radiometric units
//! as Cycles defines them.

use crate::errors::Failure;
use glam::Vec3;
use sssbake::scene::spot_cone;
use sssbake::{Light, LightKind};
use std::f32::consts::PI;

/// A sun: `power` is its strength, W/m² on a surface facing it.
pub const SSSBAKE_LIGHT_SUN: u32 = 0;
/// A point light: `power` in W, emitted evenly (P / 4π W/sr).
pub const SSSBAKE_LIGHT_POINT: u32 = 1;
/// A spot: `power` in W as if it were a point light, cut to its cone.
pub const SSSBAKE_LIGHT_SPOT: u32 = 2;
/// A rectangular area light, `size` × `size_y`: `power` in W leaving its
/// front face (radiance P / (π · area)).
pub const SSSBAKE_LIGHT_RECTANGLE: u32 = 3;
/// A disk area light of diameter `size`: `power` as for a rectangle.
pub const SSSBAKE_LIGHT_DISK: u32 = 4;

/// A light as Blender describes it. Lengths are in scene units.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct SssbakeLight {
    /// One of the `SSSBAKE_LIGHT_*` kinds.
    pub kind: u32,
    /// Linear RGB colour.
    pub colour: [f32; 3],
    /// Strength (sun, W/m²) or power (W), as the kind says.
    pub power: f32,
    /// World position.
    pub position: [f32; 3],
    /// The direction it shines (its −Z axis), world space.
    pub direction: [f32; 3],
    /// Its X axis, world space (orients rectangles).
    pub tangent: [f32; 3],
    /// Point and spot: the radius (soft size); rectangle: width along X;
    /// disk: diameter.
    pub size: f32,
    /// Rectangle: height along Y.
    pub size_y: f32,
    /// Sun: angular diameter, radians.
    pub angle: f32,
    /// Spot: the cone's full angle, radians.
    pub spot_size: f32,
    /// Spot: the share of the cone that fades, in [0, 1].
    pub spot_blend: f32,
}

/// The library's light for a host light in a scene of `mm_per_unit`.
pub(crate) fn light_from_host(light: &SssbakeLight, mm_per_unit: f64) -> Result<Light, Failure> {
    let numbers = [
        light.power,
        light.size,
        light.size_y,
        light.angle,
        light.spot_size,
        light.spot_blend,
    ];
    let vectors = [light.colour, light.position, light.direction, light.tangent];
    if numbers
        .iter()
        .chain(vectors.iter().flatten())
        .any(|v| !v.is_finite())
    {
        return Err(Failure::argument("a light has a value that is not finite"));
    }
    if light.power < 0.0 || light.colour.iter().any(|&c| c < 0.0) {
        return Err(Failure::argument(
            "a light's power and colour must not be negative",
        ));
    }
    let scale = mm_per_unit as f32;
    let size = light.size.max(0.0) * scale;
    let point = light.power / (4.0 * PI);
    let (kind, intensity, name) = match light.kind {
        SSSBAKE_LIGHT_SUN => (
            LightKind::Directional {
                angle: light.angle.max(0.0),
            },
            light.power,
            "sun",
        ),
        SSSBAKE_LIGHT_POINT => (LightKind::Point { radius_mm: size }, point, "point"),
        SSSBAKE_LIGHT_SPOT => {
            let (inner, outer) = spot_cone(0.5 * light.spot_size, light.spot_blend);
            let kind = LightKind::Spot {
                radius_mm: size,
                inner_cone: inner,
                outer_cone: outer,
            };
            (kind, point, "spot")
        }
        SSSBAKE_LIGHT_RECTANGLE => {
            let (width_mm, height_mm) = (size, light.size_y.max(0.0) * scale);
            let area_m2 = width_mm * height_mm * 1e-6;
            let radiance = area_radiance(light.power, area_m2)?;
            (
                LightKind::Rectangle {
                    width_mm,
                    height_mm,
                },
                radiance,
                "rectangle",
            )
        }
        SSSBAKE_LIGHT_DISK => {
            let radius_mm = 0.5 * size;
            let area_m2 = PI * (radius_mm * 1e-3).powi(2);
            let radiance = area_radiance(light.power, area_m2)?;
            (LightKind::Disk { radius_mm }, radiance, "disk")
        }
        other => {
            return Err(Failure::argument(format!(
                "light kind {other} is not one of SSSBAKE_LIGHT_*"
            )));
        }
    };
    Ok(Light {
        name: name.into(),
        kind,
        color: light.colour,
        intensity,
        position: Vec3::from(light.position) * scale,
        direction: Vec3::from(light.direction).normalize_or(Vec3::NEG_Z),
        tangent: Vec3::from(light.tangent).normalize_or(Vec3::X),
    })
}

/// The radiance of a Lambertian emitter of `power` W and `area_m2` m²:
/// P / (π A). An area light needs an area.
fn area_radiance(power: f32, area_m2: f32) -> Result<f32, Failure> {
    let radiance = power / (PI * area_m2);
    if area_m2 > 0.0 && radiance.is_finite() {
        Ok(radiance)
    } else {
        Err(Failure::argument(format!(
            "an area light of {area_m2} m² has no area to emit {power} W from"
        )))
    }
}
