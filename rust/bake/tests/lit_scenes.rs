//! Scenes built by hand for the transport tests: lit squares and spheres.
#![allow(dead_code)]

#[path = "shapes.rs"]
mod shapes;

use glam::Vec3;
use sssbake::control::Control;
use sssbake::pipeline::{BakeSettings, Lighting, Prepared, prepare};
use sssbake::{Light, LightKind, Mesh, Scene, SceneObject};
use sssbake_profile::material::Material;
use sssbake_profile::model::{Model, build_profile};
use sssbake_profile::presets::preset;
use sssbake_profile::profile::Profile;

#[allow(unused_imports)]
pub use shapes::{quad, sphere};

/// A light from straight above (−Z), 1 W/m², no angular size.
pub fn sun_from(direction: Vec3) -> Light {
    Light {
        name: "sun".into(),
        kind: LightKind::Directional { angle: 0.0 },
        color: [1.0; 3],
        intensity: 1.0,
        position: Vec3::ZERO,
        direction: direction.normalize(),
        tangent: Vec3::X,
    }
}

/// A square of `size` mm centred on the origin in the xy plane, facing +Z.
pub fn centred_square(size: f32, name: &str) -> Mesh {
    let mut mesh = quad(size);
    for p in &mut mesh.positions {
        *p -= Vec3::new(size / 2.0, size / 2.0, 0.0);
    }
    mesh.name = name.into();
    mesh
}

/// A scene of `meshes` (objects in order) and `lights`.
pub fn scene(meshes: Vec<Mesh>, lights: Vec<Light>) -> Scene {
    Scene {
        source: "test scene".into(),
        millimetres_per_unit: 1.0,
        objects: meshes
            .into_iter()
            .map(|mesh| SceneObject {
                uv_sets: mesh.uvs.clone().into_iter().collect(),
                mesh,
                ..SceneObject::default()
            })
            .collect(),
        lights,
        notes: vec![],
    }
}

/// The profile of preset `name` by `model`.
pub fn profile_of(name: &str, model: Model) -> Box<dyn Profile> {
    let material: Material = preset(name).unwrap();
    build_profile(&material, model, 6).unwrap()
}

/// Prepares object `object` of `scene` at `resolution`² lit by its lights.
pub fn prepared(scene: &Scene, object: &str, resolution: u32, mean_free_path_mm: f64) -> Prepared {
    let settings = BakeSettings {
        resolution,
        mean_free_path_mm,
        ..BakeSettings::default()
    };
    prepare(
        scene,
        object,
        Lighting::SceneLights,
        &settings,
        &Control::new(),
    )
    .unwrap()
}

/// Indices of surfels at least `margin` mm inside a centred square of
/// half-width `half` mm.
pub fn interior(prepared: &Prepared, half: f32, margin: f32) -> Vec<usize> {
    (0..prepared.surfels.len())
        .filter(|&s| {
            let p = prepared.surfels.position[s];
            p.x.abs() < half - margin && p.y.abs() < half - margin
        })
        .collect()
}
