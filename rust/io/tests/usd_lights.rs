//! UsdLux lights as the schema defines them, row by row of the table in
//! `usd_lights.rs`, and Blender's exports as Blender means them.

use serde_json::{Value, json};
use sssbake::LightKind;
use sssbake_io::ReadOptions;
use sssbake_io::usd_reader::scene_from_json;
use std::f32::consts::PI;

/// A stage in metres holding `light` alone, documented as `documentation`.
fn lit(light: Value, documentation: &str) -> sssbake::Scene {
    let mut light = light;
    for (key, value) in [
        ("name", json!("L")),
        ("exposure", json!(0.0)),
        ("direction", json!([0, 0, -1])),
    ] {
        if light.get(key).is_none() {
            light[key] = value;
        }
    }
    let stage = json!({
        "meters_per_unit": 1.0,
        "documentation": documentation,
        "meshes": [],
        "lights": [light],
    });
    scene_from_json(&stage, "lights.usda", &ReadOptions::default()).unwrap()
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-5 * b.abs().max(1e-12)
}

#[test]
fn a_normalized_sphere_gives_the_same_intensity_at_any_radius() {
    // Normalized: radiance I'/(4πr²) over a disk of πr² seen from afar.
    for radius in [0.0, 0.01, 0.05, 2.0] {
        let scene = lit(
            json!({"type": "SphereLight", "intensity": 100.0, "exposure": 1.0,
                   "normalize": true, "radius": radius}),
            "",
        );
        let light = &scene.lights[0];
        assert!(
            close(light.intensity, 200.0 / 4.0),
            "r {radius}: {}",
            light.intensity
        );
    }
    // Not normalized: radiance I' from a sphere of radius r.
    let scene = lit(
        json!({"type": "SphereLight", "intensity": 100.0, "radius": 0.05}),
        "",
    );
    assert!(close(scene.lights[0].intensity, PI * 0.05 * 0.05 * 100.0));
    assert_eq!(scene.lights[0].kind, LightKind::Point { radius_mm: 50.0 });
    // A point (treatAsPoint, or radius 0) is the normalized sphere's limit.
    let scene = lit(
        json!({"type": "SphereLight", "intensity": 100.0, "radius": 0.05, "treat_as_point": true}),
        "",
    );
    assert!(close(scene.lights[0].intensity, 25.0));
    assert_eq!(scene.lights[0].kind, LightKind::Point { radius_mm: 0.0 });
}

#[test]
fn a_blender_point_light_gives_cycles_intensity() {
    // Blender writes P watts as intensity P/π, normalized; Cycles gives P/(4π) W/sr.
    let power = 100.0;
    let scene = lit(
        json!({"type": "SphereLight", "intensity": power / PI, "normalize": true, "radius": 0.05}),
        "Blender v5.0.1",
    );
    assert!(close(scene.lights[0].intensity, power / (4.0 * PI)));
}

#[test]
fn a_shaping_cone_makes_a_spot_that_fades_as_usdlux_says_or_as_cycles_for_blender() {
    let scene = lit(
        json!({"type": "SphereLight", "intensity": 10.0, "normalize": true, "radius": 0.02,
               "cone_angle": 30.0, "cone_softness": 0.25}),
        "",
    );
    let LightKind::Spot {
        radius_mm,
        inner_cone,
        outer_cone,
        falloff,
    } = scene.lights[0].kind
    else {
        panic!("{:?}", scene.lights[0].kind);
    };
    assert!(close(radius_mm, 20.0));
    assert!(close(outer_cone, 30f32.to_radians()));
    // UsdLux: the fade covers the last quarter of the cone's angle.
    assert!(close(inner_cone, 0.75 * 30f32.to_radians()));
    assert_eq!(falloff, sssbake::ConeFalloff::UsdLux);
    // Blender's spot: the last quarter of the cone's cosine range, as
    // Cycles fades it.
    let scene = lit(
        json!({"type": "SphereLight", "intensity": 10.0, "normalize": true, "radius": 0.02,
               "cone_angle": 30.0, "cone_softness": 0.25}),
        "Blender v5.0.1",
    );
    let LightKind::Spot {
        inner_cone,
        falloff,
        ..
    } = scene.lights[0].kind
    else {
        panic!("{:?}", scene.lights[0].kind);
    };
    let c = 30f32.to_radians().cos();
    assert!(close(inner_cone.cos(), c + 0.25 * (1.0 - c)));
    assert_eq!(falloff, sssbake::ConeFalloff::Cycles);
    // A cone of 180° shapes nothing.
    let scene = lit(
        json!({"type": "SphereLight", "intensity": 10.0, "radius": 0.0, "cone_angle": 180.0}),
        "",
    );
    assert_eq!(scene.lights[0].kind, LightKind::Point { radius_mm: 0.0 });
}

#[test]
fn a_distant_light_is_irradiance_when_normalized_and_radiance_when_not() {
    let scene = lit(
        json!({"type": "DistantLight", "intensity": 3.0, "normalize": true, "angle": 10.0}),
        "",
    );
    assert!(close(scene.lights[0].intensity, 3.0));
    assert_eq!(
        scene.lights[0].kind,
        LightKind::Directional {
            angle: 10f32.to_radians()
        }
    );
    // Radiance over a disk of angular radius 5°: E = L·π·sin²(5°).
    let scene = lit(
        json!({"type": "DistantLight", "intensity": 3.0, "angle": 10.0}),
        "",
    );
    let expected = 3.0 * PI * 5f32.to_radians().sin().powi(2);
    assert!(close(scene.lights[0].intensity, expected));
    // With no size the intensity is the irradiance.
    let scene = lit(
        json!({"type": "DistantLight", "intensity": 3.0, "angle": 0.0}),
        "",
    );
    assert!(close(scene.lights[0].intensity, 3.0));
}

#[test]
fn a_blender_sun_is_read_as_blender_wrote_it() {
    // Blender writes a sun of strength 3 and angle 10° as 0.75 and 5°.
    let scene = lit(
        json!({"type": "DistantLight", "intensity": 0.75, "normalize": true, "angle": 5.0}),
        "Blender v5.0.1",
    );
    assert!(close(scene.lights[0].intensity, 3.0));
    assert_eq!(
        scene.lights[0].kind,
        LightKind::Directional {
            angle: 10f32.to_radians()
        }
    );
    assert!(
        scene
            .notes
            .iter()
            .any(|n| n.contains("Blender's USD exporter")),
        "{:?}",
        scene.notes
    );
}

#[test]
fn area_lights_divide_by_their_area_when_normalized() {
    let scene = lit(
        json!({"type": "RectLight", "intensity": 100.0 / PI, "normalize": true,
               "width": 0.5, "height": 0.25}),
        "Blender v5.0.1",
    );
    // Blender's area light of P watts has radiance P/(π A).
    assert!(close(scene.lights[0].intensity, 100.0 / (PI * 0.125)));
    let scene = lit(
        json!({"type": "DiskLight", "intensity": 7.0, "radius": 0.25}),
        "",
    );
    assert!(close(scene.lights[0].intensity, 7.0));
    let scene = lit(
        json!({"type": "DiskLight", "intensity": 7.0, "normalize": true, "radius": 0.25}),
        "",
    );
    assert!(close(scene.lights[0].intensity, 7.0 / (PI * 0.0625)));
}

#[test]
fn lights_the_bake_does_not_take_are_left_out_with_a_note() {
    let scene = lit(json!({"type": "PortalLight", "intensity": 1.0}), "");
    assert!(scene.lights.is_empty());
    assert!(scene.notes.iter().any(|n| n.contains("PortalLight")));
}

#[test]
fn a_dome_texture_in_another_format_is_refused_naming_the_light() {
    let stage = json!({
        "meters_per_unit": 1.0,
        "lights": [{"name": "Sky", "type": "DomeLight", "intensity": 1.0, "exposure": 0.0,
                    "texture": "sky.exr", "texture_format": "mirroredBall"}],
    });
    let error = scene_from_json(&stage, "sky.usda", &ReadOptions::default()).unwrap_err();
    assert!(
        error.message.contains("`Sky`") && error.message.contains("mirroredBall"),
        "{}",
        error.message
    );
}

#[test]
fn colour_temperature_multiplies_the_colour_and_blenders_6500_k_is_white() {
    let scene = lit(
        json!({"type": "SphereLight", "intensity": 1.0, "radius": 0.0, "color": [0.5, 1.0, 1.0],
               "color_temperature": 3200.0, "diffuse": 0.5}),
        "",
    );
    let want = sssbake::blackbody::blackbody_rgb(3200.0);
    let colour = scene.lights[0].color;
    for c in 0..3 {
        let base = [0.25, 0.5, 0.5][c];
        assert!(close(colour[c], base * want[c] as f32), "{colour:?}");
    }
    // Blender marks every light's temperature as in use; at its default
    // 6500 K (which it leaves unwritten) the light stays white.
    let scene = lit(
        json!({"type": "SphereLight", "intensity": 1.0, "radius": 0.0,
               "color_temperature": 6500.0}),
        "Blender v5.0.1",
    );
    assert_eq!(scene.lights[0].color, [1.0; 3]);
}
