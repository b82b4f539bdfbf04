//! Lights, shadows and entry Fresnel against closed forms.

mod lit_scenes;

use glam::Vec3;
use lit_scenes::*;
use sssbake::control::Control;
use sssbake::irradiance::emitters::Emitter;
use sssbake::irradiance::entry::{Boundary, EntryTransmittance};
use sssbake::irradiance::environment::EnvironmentMap;
use sssbake::irradiance::{IrradianceSettings, Receivers, transmitted_irradiance};
use sssbake::rays::RayScene;
use sssbake::{Light, LightKind, Mesh};
use sssbake_profile::boundary::fresnel::dielectric_reflectance;
use std::f64::consts::PI;

const ETA: f64 = 1.3;

fn light(kind: LightKind, intensity: f32, position: Vec3, direction: Vec3) -> Light {
    Light {
        name: "light".into(),
        kind,
        color: [1.0; 3],
        intensity,
        position,
        direction: direction.normalize(),
        tangent: Vec3::X,
        casts_shadow: true,
    }
}

/// Irradiance at points of a square facing +Z at the origin (no occluders
/// but the square itself), with `samples` per light.
fn irradiance_at(
    points: &[Vec3],
    normal: Vec3,
    lights: &[Light],
    map: Option<EnvironmentMap>,
    samples: u32,
) -> Vec<[f32; 3]> {
    let floor = centred_square(1.0, "floor");
    let far = floor
        .positions
        .iter()
        .map(|p| *p + Vec3::new(0.0, 0.0, -1e4))
        .collect();
    let floor = Mesh {
        positions: far,
        ..floor
    };
    let rays = RayScene::new(&[&floor]);
    let emitters: Vec<Emitter> = lights
        .iter()
        .map(|l| Emitter::new(l, map.clone().map(std::sync::Arc::new)))
        .collect();
    let normals = vec![normal; points.len()];
    let triangles = vec![0u32; points.len()];
    transmitted_irradiance(
        Receivers {
            mesh: 1,
            position: points,
            normal: &normals,
            triangle: &triangles,
        },
        &emitters,
        &rays,
        &EntryTransmittance::new(ETA, Boundary::Smooth),
        &IrradianceSettings {
            samples,
            shadows: true,
        },
        &Control::new(),
    )
    .unwrap()
}

fn rho_t(cos: f64) -> f64 {
    1.0 - dielectric_reflectance(cos, 1.0, ETA)
}

/// ∫ ρt(θ) cos θ dω over the hemisphere, by the midpoint rule in θ.
fn hemisphere_transmittance() -> f64 {
    let n = 20000;
    (0..n)
        .map(|i| {
            let theta = (i as f64 + 0.5) / n as f64 * PI / 2.0;
            rho_t(theta.cos()) * theta.cos() * theta.sin() * 2.0 * PI * (PI / 2.0 / n as f64)
        })
        .sum()
}

fn close(a: f32, b: f64, tolerance: f64) -> bool {
    ((a as f64) - b).abs() <= tolerance * b.abs().max(1e-12)
}

#[test]
fn a_point_light_falls_off_with_the_square_of_distance_in_metres() {
    // 2 W/sr, 500 mm above and 300 mm across: E = I cos θ / d² · ρt(θ).
    let l = light(
        LightKind::Point { radius_mm: 0.0 },
        2.0,
        Vec3::new(300.0, 0.0, 500.0),
        Vec3::NEG_Z,
    );
    let e = irradiance_at(&[Vec3::ZERO], Vec3::Z, &[l], None, 1)[0][0];
    let d2 = 0.3f64 * 0.3 + 0.5 * 0.5;
    let cos = 0.5 / d2.sqrt();
    assert!(close(e, 2.0 * cos / d2 * rho_t(cos), 1e-4), "{e}");
}

#[test]
fn a_sphere_light_lights_like_its_point_and_a_disk_by_its_solid_angle() {
    // A sphere of radiant intensity I gives I/d² on a surface facing it.
    let sphere = light(
        LightKind::Point { radius_mm: 50.0 },
        3.0,
        Vec3::new(0.0, 0.0, 400.0),
        Vec3::NEG_Z,
    );
    let e = irradiance_at(&[Vec3::ZERO], Vec3::Z, &[sphere], None, 64)[0][0];
    // ρt varies a little over the cone the sphere fills.
    assert!(close(e, 3.0 / 0.16 * rho_t(1.0), 2e-3), "sphere {e}");
    // A disk of radiance L and radius r at height h: E = L π r²/(r² + h²),
    // times ρt averaged over its cone.
    let disk = light(
        LightKind::Disk {
            radius_mm: 100.0,
            spread: std::f32::consts::PI,
        },
        5.0,
        Vec3::new(0.0, 0.0, 200.0),
        Vec3::NEG_Z,
    );
    let e = irradiance_at(&[Vec3::ZERO], Vec3::Z, &[disk], None, 256)[0][0];
    let expected = 5.0 * PI * 1e4 / (1e4 + 4e4);
    assert!(
        close(e, expected * rho_t(0.95), 1e-2),
        "disk {e} vs {expected}"
    );
    // A square of the same area far away shines like the disk.
    let side = (PI as f32).sqrt() * 10.0;
    let far_square = light(
        LightKind::Rectangle {
            width_mm: side,
            height_mm: side,
            spread: std::f32::consts::PI,
        },
        5.0,
        Vec3::new(0.0, 0.0, 2000.0),
        Vec3::NEG_Z,
    );
    let far_disk = light(
        LightKind::Disk {
            radius_mm: 10.0,
            spread: std::f32::consts::PI,
        },
        5.0,
        Vec3::new(0.0, 0.0, 2000.0),
        Vec3::NEG_Z,
    );
    let a = irradiance_at(&[Vec3::ZERO], Vec3::Z, &[far_square], None, 16)[0][0];
    let b = irradiance_at(&[Vec3::ZERO], Vec3::Z, &[far_disk], None, 16)[0][0];
    assert!(close(a, b as f64, 1e-3), "{a} vs {b}");
}

#[test]
fn a_sun_with_a_diameter_gives_its_irradiance() {
    let sun = light(
        LightKind::Directional {
            angle: 0.53f32.to_radians(),
        },
        4.0,
        Vec3::ZERO,
        Vec3::NEG_Z,
    );
    let e = irradiance_at(&[Vec3::ZERO], Vec3::Z, &[sun], None, 16)[0][0];
    assert!(close(e, 4.0 * rho_t(1.0), 1e-3), "{e}");
}

#[test]
fn a_spot_light_is_dark_outside_its_cone() {
    let spot = light(
        LightKind::Spot {
            radius_mm: 0.0,
            inner_cone: 0.2,
            outer_cone: 0.3,
            falloff: sssbake::ConeFalloff::Gltf,
        },
        1.0,
        Vec3::new(0.0, 0.0, 1000.0),
        Vec3::NEG_Z,
    );
    let points = [Vec3::ZERO, Vec3::new(1000.0 * 0.35f32.tan(), 0.0, 0.0)];
    let e = irradiance_at(&points, Vec3::Z, &[spot], None, 1);
    assert!(close(e[0][0], rho_t(1.0), 1e-4));
    assert_eq!(e[1][0], 0.0);
}

#[test]
fn an_environment_gives_pi_times_its_radiance_through_fresnel() {
    let expected = hemisphere_transmittance();
    let constant = light(
        LightKind::Environment { texture: None },
        1.0,
        Vec3::ZERO,
        Vec3::NEG_Z,
    );
    let e = irradiance_at(
        &[Vec3::ZERO],
        Vec3::Z,
        std::slice::from_ref(&constant),
        None,
        64,
    )[0][0];
    assert!(close(e, expected, 5e-3), "{e} vs {expected}");
    // An image bright above the horizon only (Y up): a face looking up sees
    // the same; a face looking down sees nothing.
    let (w, h) = (64, 32);
    let texels = (0..w * h)
        .map(|i| if i / w < h / 2 { [1.0; 3] } else { [0.0; 3] })
        .collect();
    let map = EnvironmentMap::new(w, h, texels).unwrap();
    let up = irradiance_at(
        &[Vec3::ZERO],
        Vec3::Y,
        std::slice::from_ref(&constant),
        Some(map.clone()),
        1024,
    )[0][0];
    assert!(close(up, expected, 1e-2), "{up} vs {expected}");
    let down = irradiance_at(&[Vec3::ZERO], Vec3::NEG_Y, &[constant], Some(map), 256)[0][0];
    assert!(down < 1e-3 * expected as f32, "{down}");
}

#[test]
fn a_lit_sphere_follows_the_cosine_law_without_shadow_acne() {
    let scene = scene(vec![sphere(10.0, 48, 96)], vec![sun_from(Vec3::NEG_Z)]);
    let prepared = prepared(&scene, "sphere", 128);
    let mut checked = 0;
    for (s, e) in prepared.irradiance.iter().enumerate() {
        let cos = prepared.surfels.normal[s].z as f64;
        if cos > 0.05 {
            assert!(close(e[0], cos * rho_t(cos), 1e-3), "cos {cos}: {}", e[0]);
            checked += 1;
        } else if cos < -0.05 {
            assert_eq!(e[0], 0.0);
        }
    }
    assert!(checked > 1000);
}

/// The Torrance–Sparrow boundary of Donner & Jensen 2005 §2.4 turns
/// facets towards grazing light, so a rough surface lets more of it in
/// than a smooth one, and more the rougher it is (the light its shadowing
/// term removes counts as transmitted, as eq. 26 assumes); nearly smooth,
/// it is the smooth boundary.
#[test]
fn a_rough_boundary_lets_in_more_at_grazing_and_none_is_lost_without_one() {
    let smooth = EntryTransmittance::new(ETA, Boundary::Smooth);
    let nearly = EntryTransmittance::new(ETA, Boundary::Rough { roughness: 0.02 });
    let rough = EntryTransmittance::new(ETA, Boundary::Rough { roughness: 0.5 });
    let rougher = EntryTransmittance::new(ETA, Boundary::Rough { roughness: 1.0 });
    for cos in [0.1, 0.5, 1.0] {
        assert!((nearly.at(cos) - smooth.at(cos)).abs() < 1e-2, "{cos}");
    }
    for i in 0..=20 {
        let cos = i as f32 / 20.0;
        let r = rough.at(cos);
        assert!(r.is_finite() && (0.0..=1.0).contains(&r), "{cos}: {r}");
    }
    let grazing = [&smooth, &rough, &rougher].map(|t| t.at(0.1));
    assert!(
        grazing[0] + 0.2 < grazing[1] && grazing[1] < grazing[2],
        "roughness turns grazing facets towards the light: {grazing:?}"
    );
    let none = EntryTransmittance::new(1.0, Boundary::Rough { roughness: 0.5 });
    assert!((none.at(0.5) - 1.0).abs() < 1e-6);
}

#[test]
fn a_ray_along_an_axis_with_negative_zeros_still_finds_its_blocker() {
    let mut blocker = centred_square(10.0, "blocker");
    for p in &mut blocker.positions {
        p.z = 5.0;
    }
    let rays = RayScene::new(&[&blocker]);
    let origin = Vec3::new(1.0, 2.0, 0.0);
    assert!(rays.occluded(origin, Vec3::new(-0.0, -0.0, 1.0), f32::INFINITY, u32::MAX));
    assert!(!rays.occluded(origin, Vec3::new(-0.0, -0.0, -1.0), f32::INFINITY, u32::MAX));
}
