//! Every row of the UsdLux and glTF light tables against its closed-form
//! irradiance at a point of a plane (or a quadrature of its own where the
//! light has an area), and the tables of docs/lights.md against the code's.

use glam::Vec3;
use serde_json::{Value, json};
use sssbake::control::Control;
use sssbake::irradiance::emitters::Emitter;
use sssbake::irradiance::entry::{Boundary, EntryTransmittance};
use sssbake::irradiance::environment::EnvironmentMap;
use sssbake::irradiance::{IrradianceSettings, Receivers, transmitted_irradiance};
use sssbake::rays::RayScene;
use sssbake::scene::light_table_markdown;
use sssbake::{Light, LightRow, Mesh};
use sssbake_io::ReadOptions;
use sssbake_io::gltf_reader::GLTF_LIGHTS;
use sssbake_io::usd_lights::USD_LIGHTS;
use sssbake_io::usd_reader::scene_from_json;
use std::f64::consts::PI;

/// Irradiance (red channel, W/m²) at `point` (mm) with unit `normal`, from
/// `light` alone, without entry Fresnel (η = 1), with `samples` per light.
fn irradiance(light: &Light, map: Option<EnvironmentMap>, point: Vec3, normal: Vec3) -> f64 {
    // A blocker far below everything, so the ray scene has a mesh.
    let far = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
        .iter()
        .map(|&[x, y]| Vec3::new(x, y, -1e6))
        .collect();
    let (floor, _) = Mesh::new("floor", far, None, None, vec![[0, 1, 2], [0, 2, 3]]).unwrap();
    let rays = RayScene::new(&[&floor]);
    let emitters = [Emitter::new(light, map.map(std::sync::Arc::new))];
    let e = transmitted_irradiance(
        Receivers {
            mesh: 1,
            position: &[point],
            normal: &[normal],
            triangle: &[0],
        },
        &emitters,
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

/// The one light of a USD stage in metres holding `light`.
fn usd(light: Value, documentation: &str) -> Light {
    let mut light = light;
    for (key, value) in [("name", json!("L")), ("exposure", json!(0.0))] {
        if light.get(key).is_none() {
            light[key] = value;
        }
    }
    let stage = json!({
        "meters_per_unit": 1.0,
        "documentation": documentation,
        "lights": [light],
    });
    let scene = scene_from_json(&stage, "lights.usda", &ReadOptions::default()).unwrap();
    scene.lights.into_iter().next().expect("one light")
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

/// A unit vector at `degrees` from −Z towards +X: light coming down at θ.
fn tilted(degrees: f64) -> [f64; 3] {
    let a = degrees.to_radians();
    [a.sin(), 0.0, -a.cos()]
}

/// Midpoint quadrature of ∫ L cos θ cos θₗ / d² dA over a surface given as
/// `n × n` patches by `patch(i, j)` → (centre in m, unit normal, area m²),
/// seen from `p` (m) with normal `n_p`.
fn quadrature(
    n: usize,
    radiance: f64,
    p: [f64; 3],
    n_p: [f64; 3],
    patch: impl Fn(usize, usize) -> ([f64; 3], [f64; 3], f64),
) -> f64 {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let (q, n_q, area) = patch(i, j);
            let to = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            let d2 = dot(to, to);
            let d = d2.sqrt();
            let w = [to[0] / d, to[1] / d, to[2] / d];
            let cos_p = dot(w, n_p);
            let cos_q = -dot(w, n_q);
            if cos_p > 0.0 && cos_q > 0.0 {
                sum += radiance * cos_p * cos_q / d2 * area;
            }
        }
    }
    sum
}

const UP: [f64; 3] = [0.0, 0.0, 1.0];

#[test]
fn usd_distant_lights_give_their_irradiance() {
    let cos = 30f64.to_radians().cos();
    // Normalized, or of no angle: I' × cos θ (I' = 3 × 2¹).
    for (normalize, angle) in [(true, 10.0), (false, 0.0)] {
        let light = usd(
            json!({"type": "DistantLight", "intensity": 3.0, "exposure": 1.0,
                   "normalize": normalize, "angle": angle, "direction": tilted(30.0)}),
            "",
        );
        let e = irradiance(&light, None, Vec3::ZERO, Vec3::Z);
        assert_close(e, 6.0 * cos, 5e-3, "DistantLight, normalized");
    }
    // Not normalized: radiance I' over a disk of angular diameter α.
    let light = usd(
        json!({"type": "DistantLight", "intensity": 3.0, "angle": 10.0,
               "direction": tilted(30.0)}),
        "",
    );
    let want = 3.0 * PI * 5f64.to_radians().sin().powi(2) * cos;
    let e = irradiance(&light, None, Vec3::ZERO, Vec3::Z);
    assert_close(e, want, 5e-3, "DistantLight, not normalized");
    // Blender's: 4 × I'.
    let light = usd(
        json!({"type": "DistantLight", "intensity": 0.75, "normalize": true, "angle": 5.0,
               "direction": tilted(30.0)}),
        "Blender v5.0.1",
    );
    let e = irradiance(&light, None, Vec3::ZERO, Vec3::Z);
    assert_close(e, 3.0 * cos, 5e-3, "DistantLight by Blender");
}

#[test]
fn usd_sphere_lights_give_their_irradiance() {
    // A sphere 2 m away along a direction 30° off the plane's normal.
    let d = 2.0;
    let at = tilted(30.0).map(|c| -c * d);
    let cos = 30f64.to_radians().cos();
    for (radius, normalize, point) in [(0.05, true, false), (0.0, true, false), (0.05, false, true)]
    {
        let light = usd(
            json!({"type": "SphereLight", "intensity": 100.0, "normalize": normalize,
                   "radius": radius, "treat_as_point": point, "position": at}),
            "",
        );
        let e = irradiance(&light, None, Vec3::ZERO, Vec3::Z);
        let what = format!("SphereLight r {radius}, normalized {normalize}, point {point}");
        assert_close(e, 100.0 / 4.0 * cos / (d * d), 5e-3, &what);
    }
    let light = usd(
        json!({"type": "SphereLight", "intensity": 100.0, "radius": 0.05, "position": at}),
        "",
    );
    let e = irradiance(&light, None, Vec3::ZERO, Vec3::Z);
    let want = PI * 0.05 * 0.05 * 100.0 * cos / (d * d);
    assert_close(e, want, 5e-3, "SphereLight, not normalized");
}

#[test]
fn usd_spots_fade_by_the_schema_or_as_blender_means() {
    // A spot 1 m above the origin pointing down, cone 30°, softness 0.5;
    // the point seen at φ = 20° from its axis, facing the light.
    let phi = 20f64.to_radians();
    let point = Vec3::new(1000.0 * phi.tan() as f32, 0.0, 0.0);
    let facing = (Vec3::new(0.0, 0.0, 1000.0) - point).normalize();
    let d2 = 1.0 / phi.cos().powi(2);
    let spot = json!({"type": "SphereLight", "intensity": 100.0, "normalize": true,
                      "radius": 0.0, "position": [0, 0, 1], "direction": [0, 0, -1],
                      "cone_angle": 30.0, "cone_softness": 0.5});
    let light = usd(spot.clone(), "");
    let e = irradiance(&light, None, point, facing);
    let fade = 1.0 - smoothstep((20.0 - 15.0) / 15.0);
    assert_close(e, 25.0 / d2 * fade, 1e-3, "ShapingAPI spot");
    let light = usd(spot, "Blender v5.0.1");
    let e = irradiance(&light, None, point, facing);
    let c = 30f64.to_radians().cos();
    let fade = smoothstep((phi.cos() - c) / (0.5 * (1.0 - c)));
    assert_close(e, 25.0 / d2 * fade, 1e-3, "ShapingAPI spot by Blender");
    // Outside the cone, nothing.
    let outside = Vec3::new(1000.0 * 31f32.to_radians().tan(), 0.0, 0.0);
    assert_eq!(irradiance(&light, None, outside, Vec3::Z), 0.0);
}

#[test]
fn usd_area_lights_match_a_quadrature() {
    // Each light 0.3 m above a point 0.1 m off its centre, facing down.
    let p = [0.1, 0.05, 0.0];
    let point = Vec3::new(100.0, 50.0, 0.0);
    let down = [0.0, 0.0, -1.0];
    let n = 400;
    for normalize in [true, false] {
        let (w, h) = (0.4, 0.2);
        let light = usd(
            json!({"type": "RectLight", "intensity": 5.0, "normalize": normalize,
                   "width": w, "height": h, "position": [0, 0, 0.3], "direction": down}),
            "",
        );
        let radiance = if normalize { 5.0 / (w * h) } else { 5.0 };
        let want = quadrature(n, radiance, p, UP, |i, j| {
            let x = (i as f64 + 0.5) / n as f64 * w - w / 2.0;
            let y = (j as f64 + 0.5) / n as f64 * h - h / 2.0;
            ([x, y, 0.3], down, w * h / (n * n) as f64)
        });
        let e = irradiance(&light, None, point, Vec3::Z);
        assert_close(e, want, 5e-3, "RectLight");

        let r = 0.15;
        let light = usd(
            json!({"type": "DiskLight", "intensity": 5.0, "normalize": normalize,
                   "radius": r, "position": [0, 0, 0.3], "direction": down}),
            "",
        );
        let radiance = if normalize { 5.0 / (PI * r * r) } else { 5.0 };
        let want = quadrature(n, radiance, p, UP, |i, j| {
            let (s0, s1) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
            let rho = r * (0.5 * (s0 * s0 + s1 * s1)).sqrt();
            let a = 2.0 * PI * (j as f64 + 0.5) / n as f64;
            let ring = PI * r * r * (s1 * s1 - s0 * s0) / n as f64;
            ([rho * a.cos(), rho * a.sin(), 0.3], down, ring)
        });
        let e = irradiance(&light, None, point, Vec3::Z);
        assert_close(e, want, 5e-3, "DiskLight");
    }
}

#[test]
fn usd_cylinders_and_lines_match_a_quadrature() {
    // A cylinder along X, 0.3 m above a point off its middle.
    let (l, r) = (0.6, 0.03);
    let p = [0.1, 0.05, 0.0];
    let point = Vec3::new(100.0, 50.0, 0.0);
    let n = 600;
    for normalize in [true, false] {
        let light = usd(
            json!({"type": "CylinderLight", "intensity": 2.0, "normalize": normalize,
                   "length": l, "radius": r, "position": [0, 0, 0.3], "tangent": [1, 0, 0]}),
            "",
        );
        let radiance = if normalize {
            2.0 / (2.0 * PI * r * l)
        } else {
            2.0
        };
        let want = quadrature(n, radiance, p, UP, |i, j| {
            let x = (i as f64 + 0.5) / n as f64 * l - l / 2.0;
            let a = 2.0 * PI * (j as f64 + 0.5) / n as f64;
            let normal = [0.0, a.cos(), a.sin()];
            let q = [x, r * a.cos(), 0.3 + r * a.sin()];
            (q, normal, 2.0 * PI * r * l / (n * n) as f64)
        });
        let e = irradiance(&light, None, point, Vec3::Z);
        assert_close(e, want, 1e-2, "CylinderLight");

        // treatAsLine: the same emission from a line, ∫ 2rL sin ψ cos θ/d² dx.
        let light = usd(
            json!({"type": "CylinderLight", "intensity": 2.0, "normalize": normalize,
                   "length": l, "radius": r, "treat_as_line": true,
                   "position": [0, 0, 0.3], "tangent": [1, 0, 0]}),
            "",
        );
        let mut want = 0.0;
        let m = 20_000;
        for i in 0..m {
            let x = (i as f64 + 0.5) / m as f64 * l - l / 2.0;
            let to = [x - p[0], -p[1], 0.3];
            let d2 = to[0] * to[0] + to[1] * to[1] + to[2] * to[2];
            let sin = (1.0 - to[0] * to[0] / d2).sqrt();
            let cos = to[2] / d2.sqrt();
            want += 2.0 * r * radiance * sin * cos / d2 * l / m as f64;
        }
        let e = irradiance(&light, None, point, Vec3::Z);
        assert_close(e, want, 5e-3, "CylinderLight treatAsLine");
    }
}

#[test]
fn usd_domes_give_pi_times_their_radiance() {
    let light = usd(
        json!({"type": "DomeLight", "intensity": 1.5, "exposure": 1.0, "texture": ""}),
        "",
    );
    let e = irradiance(&light, None, Vec3::ZERO, Vec3::Z);
    assert_close(e, PI * 3.0, 5e-3, "DomeLight without a texture");
    // A latlong texture T: 2 over the upper half, 0 below (+Y up): a
    // receiver facing +Y gets π I' · 2, one facing −Y nothing.
    let light = usd(
        json!({"type": "DomeLight", "intensity": 1.5, "texture": "sky.exr",
               "texture_format": "latlong"}),
        "",
    );
    let (w, h) = (64, 32);
    let texels = (0..w * h)
        .map(|i| if i / w < h / 2 { [2.0; 3] } else { [0.0; 3] })
        .collect();
    let map = EnvironmentMap::new(w, h, texels).unwrap();
    let e = irradiance(&light, Some(map.clone()), Vec3::ZERO, Vec3::Y);
    assert_close(e, PI * 1.5 * 2.0, 1e-2, "DomeLight latlong, facing up");
    let e = irradiance(&light, Some(map), Vec3::ZERO, Vec3::NEG_Y);
    assert!(e < 1e-3, "facing down: {e}");
}

#[test]
fn colour_temperature_sets_the_ratio_of_the_channels() {
    let light = usd(
        json!({"type": "SphereLight", "intensity": 100.0, "radius": 0.0,
               "color_temperature": 3000.0, "position": [0, 0, 1]}),
        "",
    );
    let want = sssbake::blackbody::blackbody_rgb(3000.0);
    let emitter = Emitter::new(&light, None);
    let sample = emitter
        .sample(Vec3::ZERO, Vec3::Z, glam::Vec2::splat(0.5), 0)
        .unwrap();
    let w = sample.weight.map(f64::from);
    assert_close(w[0] / w[1], want[0] / want[1], 1e-5, "red/green");
    assert_close(w[2] / w[1], want[2] / want[1], 1e-5, "blue/green");
}

/// The lights of a glTF file in metres holding `lights` on nodes at
/// `positions` pointing down −Z, written by `generator`.
fn gltf(lights: Value, nodes: Value, generator: &str) -> Vec<Light> {
    let dir = std::env::temp_dir().join(format!(
        "sssbake-light-tables-{}-{}",
        std::process::id(),
        generator.len()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("lights.gltf");
    let doc = json!({
        "asset": {"version": "2.0", "generator": generator},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": lights}},
        "scenes": [{"nodes": (0..nodes.as_array().unwrap().len()).collect::<Vec<_>>()}],
        "scene": 0,
        "nodes": nodes,
    });
    std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
    let scene = sssbake_io::read_gltf(&path, &ReadOptions::default()).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    scene.lights
}

#[test]
fn gltf_lights_give_their_irradiance() {
    let lights = json!([
        {"type": "directional", "intensity": 683.0 * 3.0},
        {"type": "point", "intensity": 683.0 * 8.0},
        {"type": "spot", "intensity": 683.0 * 8.0,
         "spot": {"innerConeAngle": 0.25, "outerConeAngle": 0.5}},
    ]);
    let nodes = json!([
        {"extensions": {"KHR_lights_punctual": {"light": 0}},
         "rotation": [0.0, 0.2588190451, 0.0, 0.9659258263]},
        {"extensions": {"KHR_lights_punctual": {"light": 1}}, "translation": [0.0, 0.0, 2.0]},
        {"extensions": {"KHR_lights_punctual": {"light": 2}}, "translation": [0.0, 0.0, 1.0]},
    ]);
    let phi: f64 = 0.4;
    let point = Vec3::new(1000.0 * phi.tan() as f32, 0.0, 0.0);
    let facing = (Vec3::new(0.0, 0.0, 1000.0) - point).normalize();
    let d2 = 1.0 / phi.cos().powi(2);
    for (generator, blender) in [
        ("a test", false),
        ("Khronos glTF Blender I/O v5.0.21", true),
    ] {
        let lights = gltf(lights.clone(), nodes.clone(), generator);
        let by_name = |kind: &str| {
            lights
                .iter()
                .find(|l| l.kind.name() == kind)
                .unwrap_or_else(|| panic!("{kind}"))
        };
        // A sun turned 30° about Y.
        let e = irradiance(by_name("directional"), None, Vec3::ZERO, Vec3::Z);
        assert_close(e, 3.0 * 30f64.to_radians().cos(), 1e-4, "directional");
        let e = irradiance(by_name("point"), None, Vec3::ZERO, Vec3::Z);
        assert_close(e, 8.0 / 4.0, 1e-4, "point");
        let e = irradiance(by_name("spot"), None, point, facing);
        let fade = if blender {
            let blend = 1.0 - 0.25 / 0.5;
            smoothstep((phi.cos() - 0.5f64.cos()) / (blend * (1.0 - 0.5f64.cos())))
        } else {
            let t = (phi.cos() - 0.5f64.cos()) / (0.25f64.cos() - 0.5f64.cos());
            t * t
        };
        assert_close(e, 8.0 / d2 * fade, 1e-3, generator);
    }
}

/// The rows of the docs/lights.md table whose header row is `header`, as cells.
fn page_rows(header: [&str; 3]) -> Vec<[String; 3]> {
    let page = include_str!("../../../docs/lights.md");
    let head = format!("| {} | {} | {} |", header[0], header[1], header[2]);
    let start = page
        .find(&head)
        .unwrap_or_else(|| panic!("docs/lights.md has no table headed {head}"));
    page[start..]
        .lines()
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let cells: Vec<String> = l
                .trim_matches('|')
                .split(" | ")
                .map(|c| c.trim().to_string())
                .collect();
            assert_eq!(cells.len(), 3, "{l}");
            [cells[0].clone(), cells[1].clone(), cells[2].clone()]
        })
        .collect()
}

fn check_page(header: [&str; 3], rows: &[LightRow]) {
    let want: Vec<[String; 3]> = rows
        .iter()
        .map(|r| [r.source, r.read_as, r.irradiance].map(String::from))
        .collect();
    assert_eq!(
        page_rows(header),
        want,
        "the table in docs/lights.md differs from the code's; it should read:\n{}",
        light_table_markdown(header, rows)
    );
}

#[test]
fn the_usd_and_gltf_light_tables_of_the_docs_are_the_codes() {
    check_page(sssbake_io::usd_lights::USD_HEADER, USD_LIGHTS);
    check_page(sssbake_io::gltf_reader::GLTF_HEADER, GLTF_LIGHTS);
}
