//! Lights in Blender's terms, converted to the library's radiometric units
//! as Cycles defines them (`intern/cycles/blender/light.cpp` and
//! `scene/light.cpp`). [`BLENDER_LIGHTS`] is the table, shown in docs/lights.md.

use glam::Vec3;
use serde::Deserialize;
use sssbake::scene::spot_cone;
use sssbake::{ConeFalloff, Error, Light, LightKind, LightRow};
use std::f32::consts::PI;

/// The column titles of [`BLENDER_LIGHTS`] in docs/lights.md.
pub const BLENDER_HEADER: [&str; 3] = [
    "C ABI kind: Blender light",
    "read as",
    "irradiance at a point of the plane, × F",
];

/// The Blender table, by the C ABI's kinds (the Python package names them
/// `sun`, `point`, `spot`, `rectangle`, `disk`): one row per case, each with a test in this
/// module's tests. P is the power (W) or a sun's strength
/// (W/m²) times 2^exposure, d the distance in metres, θ the angle of
/// incidence, φ the angle from a spot's axis.
pub const BLENDER_LIGHTS: &[LightRow] = &[
    LightRow {
        source: "`SSSBAKE_LIGHT_SUN`: Sun, strength P, angle α",
        read_as: "directional, angular diameter α",
        irradiance: "P·cos θ; `normalize` off: P·π sin²(α/2)·cos θ",
    },
    LightRow {
        source: "`SSSBAKE_LIGHT_POINT`: Point, power P, radius r",
        read_as: "sphere of radius r",
        irradiance: "P/(4π)·cos θ/d²; `normalize` off: P r²·cos θ/d² (P/π·cos θ/d² at r = 0)",
    },
    LightRow {
        source: "`SSSBAKE_LIGHT_SPOT`: Spot, as a point, size 2a, blend b",
        read_as: "spot",
        irradiance: "the point's × smoothstep((cos φ − cos a)/(b(1 − cos a)))",
    },
    LightRow {
        source: "`SSSBAKE_LIGHT_RECTANGLE`: Area (square, rectangle) w × h, spread s",
        read_as: "rectangle emitting along its −Z",
        irradiance: "∫ L S(θₗ) cos θ cos θₗ/d² dA, L = P/(π w h); `normalize` off: L = P/π",
    },
    LightRow {
        source: "`SSSBAKE_LIGHT_DISK`: Area (disk, ellipse) of diameter D, spread s",
        read_as: "disk emitting along its −Z",
        irradiance: "∫ L S(θₗ) cos θ cos θₗ/d² dA, L = P/(π² D²/4); `normalize` off: L = P/π",
    },
];

/// The kinds of Blender light, each read as [`BLENDER_LIGHTS`] says.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LightShape {
    /// A sun: `power` is its strength, W/m² on a surface facing it.
    #[default]
    Sun,
    /// A point light: `power` in W, emitted evenly (P / 4π W/sr).
    Point,
    /// A spot: `power` in W as if it were a point light, cut to its cone.
    Spot,
    /// A rectangular area light, `size` × `size_y`: `power` in W leaving
    /// its front face (radiance P / (π · area)).
    Rectangle,
    /// A disk area light of diameter `size`: `power` as for a rectangle.
    Disk,
}

/// A light as Blender describes it. Lengths are in scene units. Every field
/// left out (by a host that reads it from JSON) takes Blender's default.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HostLight {
    /// Which kind of light.
    pub kind: LightShape,
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
    /// Whether the power does not depend on the light's size (Blender's
    /// `normalize`, on by default).
    pub normalize: bool,
    /// Whether objects block the light (Blender's `use_shadow`).
    pub casts_shadow: bool,
}

impl Default for HostLight {
    /// Blender's defaults for a new light (a sun of strength 1 shining
    /// down), white and unexposed.
    fn default() -> Self {
        HostLight {
            kind: LightShape::Sun,
            colour: [1.0; 3],
            power: 1.0,
            position: [0.0; 3],
            direction: [0.0, 0.0, -1.0],
            tangent: [1.0, 0.0, 0.0],
            size: 0.0,
            size_y: 0.0,
            angle: 0.0,
            spot_size: PI / 4.0,
            spot_blend: 0.15,
            exposure: 0.0,
            temperature_colour: [1.0; 3],
            diffuse_factor: 1.0,
            spread: PI,
            normalize: true,
            casts_shadow: true,
        }
    }
}

/// The library's light for a host light in a scene of `mm_per_unit`.
pub fn light_from_host(light: &HostLight, mm_per_unit: f64) -> Result<Light, Error> {
    let numbers = [
        light.power,
        light.size,
        light.size_y,
        light.angle,
        light.spot_size,
        light.spot_blend,
        light.exposure,
        light.diffuse_factor,
        light.spread,
    ];
    let vectors = [
        light.colour,
        light.position,
        light.direction,
        light.tangent,
        light.temperature_colour,
    ];
    if numbers
        .iter()
        .chain(vectors.iter().flatten())
        .any(|v| !v.is_finite())
    {
        return Err(Error::field(
            "light",
            "a light has a value that is not finite",
        ));
    }
    if light.power < 0.0
        || light.diffuse_factor < 0.0
        || light
            .colour
            .iter()
            .chain(&light.temperature_colour)
            .any(|&c| c < 0.0)
    {
        return Err(Error::field(
            "light",
            "a light's power, colour, temperature colour and diffuse factor must not be negative",
        ));
    }
    let scale = mm_per_unit as f32;
    let size = light.size.max(0.0) * scale;
    let normalize = light.normalize;
    let power = light.power * light.exposure.exp2() * light.diffuse_factor;
    // Cycles: a sphere's radiance is P/(π·4πr²) normalized, P/π not; seen
    // from afar that is P/(4π) or P·r² W/sr, and P/π for a point that is
    // not normalized (r in metres).
    let r_m = size * 1e-3;
    let point = if normalize {
        power / (4.0 * PI)
    } else if r_m > 0.0 {
        power * r_m * r_m
    } else {
        power / PI
    };
    // A spread of 0 would emit along the normal alone; 0 (a host that
    // leaves it unset) means Lambertian, as π does.
    let spread = if light.spread > 0.0 {
        light.spread.min(PI)
    } else {
        PI
    };
    let (kind, intensity, name) = match light.kind {
        LightShape::Sun => {
            let angle = light.angle.max(0.0);
            let irradiance = if normalize || angle == 0.0 {
                power
            } else {
                power * PI * (0.5 * angle).sin().powi(2)
            };
            (LightKind::Directional { angle }, irradiance, "sun")
        }
        LightShape::Point => (LightKind::Point { radius_mm: size }, point, "point"),
        LightShape::Spot => {
            let (inner, outer) = spot_cone(0.5 * light.spot_size, light.spot_blend);
            let kind = LightKind::Spot {
                radius_mm: size,
                inner_cone: inner,
                outer_cone: outer,
                falloff: ConeFalloff::Cycles,
            };
            (kind, point, "spot")
        }
        LightShape::Rectangle => {
            let (width_mm, height_mm) = (size, light.size_y.max(0.0) * scale);
            let area_m2 = width_mm * height_mm * 1e-6;
            let radiance = area_radiance(power, area_m2, normalize)?;
            (
                LightKind::Rectangle {
                    width_mm,
                    height_mm,
                    spread,
                },
                radiance,
                "rectangle",
            )
        }
        LightShape::Disk => {
            let radius_mm = 0.5 * size;
            let area_m2 = PI * (radius_mm * 1e-3).powi(2);
            let radiance = area_radiance(power, area_m2, normalize)?;
            (LightKind::Disk { radius_mm, spread }, radiance, "disk")
        }
    };
    Ok(Light {
        name: name.into(),
        kind,
        color: [0, 1, 2].map(|c| light.colour[c] * light.temperature_colour[c]),
        intensity,
        position: Vec3::from(light.position) * scale,
        direction: Vec3::from(light.direction).normalize_or(Vec3::NEG_Z),
        tangent: Vec3::from(light.tangent).normalize_or(Vec3::X),
        casts_shadow: light.casts_shadow,
    })
}

/// The radiance of a Lambertian emitter of `power` W and `area_m2` m²:
/// P / (π A), or P / π when not `normalize`d. An area light needs an area.
fn area_radiance(power: f32, area_m2: f32, normalize: bool) -> Result<f32, Error> {
    let radiance = if normalize {
        power / (PI * area_m2)
    } else {
        power / PI
    };
    if area_m2 > 0.0 && radiance.is_finite() {
        Ok(radiance)
    } else {
        Err(Error::field(
            "light",
            format!("an area light of {area_m2} m² has no area to emit {power} W from"),
        ))
    }
}

#[cfg(test)]
mod tests {
    //! Each row of [`BLENDER_LIGHTS`] against its closed form or a
    //! quadrature at a point of a plane, and the table of docs/lights.md.
    use super::*;
    use sssbake::control::Control;
    use sssbake::irradiance::emitters::Emitter;
    use sssbake::irradiance::entry::{Boundary, EntryTransmittance};
    use sssbake::irradiance::{IrradianceSettings, Receivers, transmitted_irradiance};
    use sssbake::rays::RayScene;
    use sssbake::{Mesh, scene::light_table_markdown};
    use std::f64::consts::PI as PI64;

    /// A light of `kind` at `position` (m) pointing down, Blender's defaults.
    fn host(kind: LightShape, power: f32, position: [f32; 3]) -> HostLight {
        HostLight {
            kind,
            power,
            position,
            spot_size: 0.0,
            spot_blend: 0.0,
            ..HostLight::default()
        }
    }

    /// Irradiance (red, W/m²) at `point` (mm) with `normal` from `light` in
    /// a scene in metres, without entry Fresnel, with a blocker at z = 0.5 m
    /// over x ∈ [5, 6] m that only the shadow test below reaches.
    fn irradiance(light: &HostLight, point: glam::Vec3, normal: glam::Vec3) -> f64 {
        let Ok(light) = light_from_host(light, 1000.0) else {
            panic!("a light the library refuses");
        };
        let square = [[5.0, -1.0], [6.0, -1.0], [6.0, 1.0], [5.0, 1.0]]
            .iter()
            .map(|&[x, y]| glam::Vec3::new(1000.0 * x, 1000.0 * y, 500.0))
            .collect();
        // Facing down, towards the points it shadows.
        let (blocker, _) =
            Mesh::new("blocker", square, None, None, vec![[0, 2, 1], [0, 3, 2]]).unwrap();
        let rays = RayScene::new(&[&blocker]);
        let e = transmitted_irradiance(
            Receivers {
                mesh: 1,
                position: &[point],
                normal: &[normal],
                triangle: &[0],
            },
            &[Emitter::new(&light, None)],
            &rays,
            &EntryTransmittance::new(1.0, Boundary::Smooth),
            &IrradianceSettings {
                samples: 4096,
                shadows: true,
            },
            &Control::new(),
        )
        .unwrap();
        f64::from(e[0][0])
    }

    fn assert_close(got: f64, want: f64, tolerance: f64, what: &str) {
        assert!(
            (got - want).abs() <= tolerance * want.abs().max(1e-12),
            "{what}: {got} against {want}"
        );
    }

    fn smoothstep(t: f64) -> f64 {
        let t = t.clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }

    const ORIGIN: glam::Vec3 = glam::Vec3::ZERO;
    const UP: glam::Vec3 = glam::Vec3::Z;

    #[test]
    fn a_sun_gives_its_strength_or_its_radiance_over_its_disk() {
        let mut sun = host(LightShape::Sun, 3.0, [0.0; 3]);
        sun.angle = 10f32.to_radians();
        sun.exposure = 1.0;
        assert_close(irradiance(&sun, ORIGIN, UP), 6.0, 5e-3, "normalized");
        sun.normalize = false;
        let want = 6.0 * PI64 * 5f64.to_radians().sin().powi(2);
        assert_close(irradiance(&sun, ORIGIN, UP), want, 5e-3, "not normalized");
    }

    #[test]
    fn a_point_gives_cycles_intensity_normalized_or_not() {
        let mut point = host(LightShape::Point, 100.0, [0.0, 0.0, 2.0]);
        point.size = 0.05;
        let e = irradiance(&point, ORIGIN, UP);
        assert_close(e, 100.0 / (4.0 * PI64) / 4.0, 5e-3, "normalized");
        point.normalize = false;
        let e = irradiance(&point, ORIGIN, UP);
        assert_close(e, 100.0 * 0.05 * 0.05 / 4.0, 5e-3, "not normalized");
        point.size = 0.0;
        let e = irradiance(&point, ORIGIN, UP);
        assert_close(e, 100.0 / PI64 / 4.0, 1e-5, "not normalized, r = 0");
    }

    #[test]
    fn a_spot_fades_as_cycles_fades_it() {
        let mut spot = host(LightShape::Spot, 100.0, [0.0, 0.0, 1.0]);
        spot.spot_size = 60f32.to_radians();
        spot.spot_blend = 0.5;
        let phi = 25f64.to_radians();
        let point = glam::Vec3::new(1000.0 * phi.tan() as f32, 0.0, 0.0);
        let facing = (glam::Vec3::new(0.0, 0.0, 1000.0) - point).normalize();
        let c = 30f64.to_radians().cos();
        let fade = smoothstep((phi.cos() - c) / (0.5 * (1.0 - c)));
        let want = 100.0 / (4.0 * PI64) * phi.cos().powi(2) * fade;
        assert_close(irradiance(&spot, point, facing), want, 1e-4, "spot");
    }

    /// ∫ L S(θₗ) cos θ cos θₗ / d² dA over a w × h rectangle (or the disk
    /// inscribed in it) at height z, facing down, seen from the origin.
    fn area_quadrature(w: f64, h: f64, z: f64, disk: bool, spread: f64, radiance: f64) -> f64 {
        let n = 600;
        let half = 0.5 * spread;
        let shape = |cos: f64| {
            if half >= 0.5 * PI64 - 1e-9 {
                return 1.0;
            }
            let tan = (1.0 - cos * cos).sqrt() / cos;
            (half.tan() - tan).max(0.0) / (half.tan() - half)
        };
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let x = ((i as f64 + 0.5) / n as f64 - 0.5) * w;
                let y = ((j as f64 + 0.5) / n as f64 - 0.5) * h;
                if disk && (2.0 * x / w).powi(2) + (2.0 * y / h).powi(2) > 1.0 {
                    continue;
                }
                let d2 = x * x + y * y + z * z;
                let cos = z / d2.sqrt();
                sum += radiance * shape(cos) * cos * cos / d2 * (w * h) / (n * n) as f64;
            }
        }
        sum
    }

    #[test]
    fn area_lights_match_a_quadrature_with_their_spread() {
        for (kind, disk) in [(LightShape::Rectangle, false), (LightShape::Disk, true)] {
            let mut area = host(kind, 20.0, [0.0, 0.0, 0.3]);
            area.size = 0.4;
            area.size_y = 0.4;
            let a = if disk { PI64 * 0.04 } else { 0.16 };
            for (normalize, spread) in [(true, PI64), (false, PI64), (true, 1.0)] {
                area.normalize = normalize;
                area.spread = spread as f32;
                let radiance = if normalize {
                    20.0 / (PI64 * a)
                } else {
                    20.0 / PI64
                };
                let want = area_quadrature(0.4, 0.4, 0.3, disk, spread, radiance);
                let e = irradiance(&area, ORIGIN, UP);
                let what = format!("kind {kind:?}, normalize {normalize}, spread {spread}");
                assert_close(e, want, 1e-2, &what);
            }
        }
    }

    #[test]
    fn exposure_temperature_diffuse_and_shadows_apply() {
        // Behind the blocker (z = 0.5 m over x ∈ [5, 6]), the sun is shadowed.
        let mut sun = host(LightShape::Sun, 2.0, [0.0; 3]);
        let behind = glam::Vec3::new(5500.0, 0.0, 0.0);
        assert_eq!(irradiance(&sun, behind, UP), 0.0);
        sun.casts_shadow = false;
        assert_close(irradiance(&sun, behind, UP), 2.0, 1e-6, "no shadow");
        sun.exposure = 2.0;
        sun.diffuse_factor = 0.5;
        sun.temperature_colour = [1.5, 1.0, 0.5];
        let Ok(light) = light_from_host(&sun, 1000.0) else {
            panic!("refused");
        };
        assert_eq!(light.color, [1.5, 1.0, 0.5]);
        assert_close(
            f64::from(light.intensity),
            2.0 * 4.0 * 0.5,
            1e-6,
            "P × 2^e × diffuse",
        );
    }

    #[test]
    fn the_blender_light_table_of_the_docs_is_the_codes() {
        let page = include_str!("../../../docs/lights.md");
        let table = light_table_markdown(BLENDER_HEADER, BLENDER_LIGHTS);
        let head = table.lines().next().unwrap();
        let start = page
            .find(head)
            .unwrap_or_else(|| panic!("docs/lights.md has no table headed {head}"));
        let rows: Vec<Vec<&str>> = page[start..]
            .lines()
            .skip(2)
            .take_while(|l| l.starts_with('|'))
            .map(|l| l.trim_matches('|').split(" | ").map(str::trim).collect())
            .collect();
        let want: Vec<Vec<&str>> = BLENDER_LIGHTS
            .iter()
            .map(|r| vec![r.source, r.read_as, r.irradiance])
            .collect();
        assert_eq!(
            rows, want,
            "the table in docs/lights.md should read:\n{table}"
        );
    }
}
