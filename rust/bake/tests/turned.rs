//! A bake belongs to the object, not to the world's axes: the same scene
//! turned from a Blender scene's Z-up to a glTF's Y-up finds the same
//! light through a thin part's rim.

mod lit_scenes;

use glam::{Quat, Vec3};
use lit_scenes::*;
use sssbake::Scene;
use sssbake::transport::rim_light::{RimTexel, rim_sights};

/// `scene` with its meshes and lights turned by `turn` about the origin.
fn turned(mut scene: Scene, turn: Quat) -> Scene {
    for object in &mut scene.objects {
        let mesh = &mut object.mesh;
        for p in &mut mesh.positions {
            *p = turn * *p;
        }
        for n in &mut mesh.normals {
            *n = turn * *n;
        }
    }
    for light in &mut scene.lights {
        light.position = turn * light.position;
        light.direction = turn * light.direction;
        light.tangent = turn * light.tangent;
    }
    scene
}

/// A 12 × 12 × 3 mm tile, set at an angle in its plane: the texels of its
/// broad faces seek its rim along eight rays in their tangent plane. Those
/// rays were laid from the world's axes, so the tile turned to Y-up met
/// its rim at other texels (on Suzanne's eyes a thin texel's light moved
/// by a tenth between the add-on's bake and the CLI's of its glTF). Each
/// rim texel's light is told apart here by the surfel's own number.
#[test]
fn a_thin_part_meets_its_rim_at_the_same_texels_in_a_y_up_world() {
    let tile = stretched(cube(1.0), Vec3::new(12.0, 12.0, 3.0), "tile");
    let lit = scene(vec![tile], vec![sun_from(Vec3::NEG_Z)]);
    let z_up = turned(lit, Quat::from_rotation_z(0.3));
    let y_up = turned(
        z_up.clone(),
        Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2),
    );
    let sights = |scene: &Scene, up: Vec3| {
        let prepared = prepared(scene, "tile", 48);
        let faces: Vec<RimTexel> = (0..prepared.surfels.len())
            .filter(|&i| prepared.surfels.normal[i].dot(up).abs() > 0.9)
            .map(|texel| RimTexel {
                texel,
                thickness: 3.0,
                reach: 8.0,
                through_rim: [1.0; 3],
            })
            .collect();
        let found = rim_sights(&prepared, &faces, &|_, d: f32| [(-d / 3.0).exp(); 3]);
        let numbered = |s: usize| [s as f32 + 1.0; 3];
        (0..faces.len())
            .map(|k| found.light(k, &prepared.surfels, numbered)[0])
            .collect::<Vec<f64>>()
    };
    let (z_up, y_up) = (sights(&z_up, Vec3::Z), sights(&y_up, Vec3::Y));
    assert_eq!(z_up.len(), y_up.len());
    let lit = z_up.iter().filter(|&&l| l > 0.0).count();
    assert!(lit > z_up.len() / 2, "{lit} of {} meet the rim", z_up.len());
    for (k, (a, b)) in z_up.iter().zip(&y_up).enumerate() {
        assert!(
            (a - b).abs() <= 1e-4 * a.max(1.0),
            "texel {k}: {a} in Z-up, {b} in Y-up"
        );
    }
}
