//! A file's lighting: the environment image its dome light names, one
//! given instead, or a lightmap in place of the lights.

use glam::Vec3;
use sssbake::image::Image;
use sssbake::{Error, Light, LightKind, Lighting, Scene};
use sssbake_io::image_writer::{Precision, exr_bytes};
use sssbake_io::scene_lighting;

fn dome(texture: Option<&str>) -> Scene {
    Scene {
        source: "sky.usda".into(),
        millimetres_per_unit: 1.0,
        lights: vec![Light {
            name: "Dome".into(),
            kind: LightKind::Environment {
                texture: texture.map(String::from),
            },
            color: [1.0; 3],
            intensity: 1.0,
            position: Vec3::ZERO,
            direction: Vec3::NEG_Z,
            tangent: Vec3::X,
            casts_shadow: true,
        }],
        ..Scene::default()
    }
}

fn write_sky(path: &std::path::Path, value: f32) {
    let image = Image::new(4, 2, vec![[value; 3]; 8]).unwrap();
    std::fs::write(path, exr_bytes(&image, Precision::Float).unwrap()).unwrap();
}

#[test]
fn the_dome_lights_image_is_read_beside_the_scene() {
    let folder = tempfile::tempdir().unwrap();
    write_sky(&folder.path().join("sky.exr"), 2.0);
    let scene_file = folder.path().join("sky.usda");
    match scene_lighting(&dome(Some("sky.exr")), &scene_file, None, None).unwrap() {
        Lighting::SceneLightsWith { environment } => {
            assert_eq!(
                environment.radiance(Vec3::new(0.3, 0.6, 0.2).normalize()),
                [2.0; 3]
            );
        }
        other => panic!("{other:?}"),
    }
    // An image given instead wins; a lightmap replaces the lights.
    write_sky(&folder.path().join("other.exr"), 5.0);
    let other = folder.path().join("other.exr");
    let given = scene_lighting(&dome(Some("sky.exr")), &scene_file, None, Some(&other)).unwrap();
    assert!(
        matches!(given, Lighting::SceneLightsWith { environment } if environment.radiance(Vec3::Y) == [5.0; 3])
    );
    let lightmap = scene_lighting(&dome(Some("sky.exr")), &scene_file, Some(&other), None);
    assert!(matches!(lightmap, Ok(Lighting::Irradiance(_))));
    // No image named: the scene's lights alone.
    let plain = scene_lighting(&dome(None), &scene_file, None, None).unwrap();
    assert!(matches!(plain, Lighting::SceneLights));
}

#[test]
fn a_missing_environment_image_is_named() {
    let folder = tempfile::tempdir().unwrap();
    let scene_file = folder.path().join("sky.usda");
    match scene_lighting(&dome(Some("gone.exr")), &scene_file, None, None) {
        Err(Error::Input(e)) => {
            assert!(e.to_string().contains("gone.exr"), "{e}");
        }
        other => panic!("{:?}", other.map(|_| ())),
    }
}
