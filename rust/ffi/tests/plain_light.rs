//! The light the ABI tests start from, shared by the test files.
#![allow(dead_code)]

use sssbake_ffi::SssbakeLight;

/// A white light of `kind` and `power` pointing down −z, with no size, cone
/// or exposure: what a test changes it from.
pub fn light(kind: u32, power: f32) -> SssbakeLight {
    SssbakeLight {
        kind,
        colour: [1.0; 3],
        power,
        position: [0.0; 3],
        direction: [0.0, 0.0, -1.0],
        tangent: [1.0, 0.0, 0.0],
        size: 0.0,
        size_y: 0.0,
        angle: 0.0,
        spot_size: 0.0,
        spot_blend: 0.0,
        exposure: 0.0,
        temperature_colour: [1.0; 3],
        diffuse_factor: 1.0,
        spread: 0.0,
        normalize: 1,
        casts_shadow: 1,
    }
}
