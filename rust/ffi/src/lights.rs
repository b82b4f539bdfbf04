//! Lights in Blender's terms as C passes them; the library reads them
//! (`sssbake_host::lights`, whose table docs/lights.md shows).

use crate::errors::Failure;
use sssbake_host::{HostLight, LightShape};

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
    /// Stops: the power is multiplied by 2^exposure (Blender's `exposure`).
    pub exposure: f32,
    /// Multiplies the colour: Blender's `temperature_color` when
    /// `use_temperature` is on, else (1, 1, 1).
    pub temperature_colour: [f32; 3],
    /// Multiplies the power: Blender's `diffuse_factor` (Cycles counts
    /// subsurface scattering as diffuse); 1 for all of it.
    pub diffuse_factor: f32,
    /// Area lights: the angle of the cone the emission fills, radians
    /// (Blender's `spread`; π, or 0 when unset, is Lambertian).
    pub spread: f32,
    /// 1 when the power does not depend on the light's size (Blender's
    /// `normalize`, on by default), 0 when it does.
    pub normalize: u32,
    /// 1 when objects block the light (Blender's `use_shadow`), 0 when not.
    pub casts_shadow: u32,
}

/// The library's view of a host's light.
pub(crate) fn host_light(light: &SssbakeLight) -> Result<HostLight, Failure> {
    let kind = match light.kind {
        SSSBAKE_LIGHT_SUN => LightShape::Sun,
        SSSBAKE_LIGHT_POINT => LightShape::Point,
        SSSBAKE_LIGHT_SPOT => LightShape::Spot,
        SSSBAKE_LIGHT_RECTANGLE => LightShape::Rectangle,
        SSSBAKE_LIGHT_DISK => LightShape::Disk,
        other => {
            return Err(Failure::argument(format!(
                "light kind {other} is not one of SSSBAKE_LIGHT_*"
            )));
        }
    };
    Ok(HostLight {
        kind,
        colour: light.colour,
        power: light.power,
        position: light.position,
        direction: light.direction,
        tangent: light.tangent,
        size: light.size,
        size_y: light.size_y,
        angle: light.angle,
        spot_size: light.spot_size,
        spot_blend: light.spot_blend,
        exposure: light.exposure,
        temperature_colour: light.temperature_colour,
        diffuse_factor: light.diffuse_factor,
        spread: light.spread,
        normalize: light.normalize != 0,
        casts_shadow: light.casts_shadow != 0,
    })
}
