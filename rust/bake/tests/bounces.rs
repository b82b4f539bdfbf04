//! The light an object sends onto itself, against closed forms: inside a
//! sphere every point sees the whole of it, so each bounce multiplies the
//! light by the same share; a convex body sees none of itself.

mod lit_scenes;

use glam::Vec3;
use lit_scenes::*;
use sssbake::control::Control;
use sssbake::irradiance::entry::EntryTransmittance;
use sssbake::prepared::Prepared;
use sssbake::{BakeRequest, Light, Mesh, plan};

/// A sphere of `radius` mm seen from inside: its faces and normals turned
/// to the centre.
fn inside_out_sphere(radius: f32) -> Mesh {
    let outside = sphere(radius, 48, 96);
    let triangles = outside
        .triangles
        .iter()
        .map(|&[a, b, c]| [a, c, b])
        .collect();
    let normals = outside.normals.iter().map(|n| -*n).collect();
    Mesh::new(
        "inside",
        outside.positions,
        Some(normals),
        outside.uvs,
        triangles,
    )
    .unwrap()
    .0
}

fn lit(mesh: Mesh, lights: Vec<Light>, bounces: u32) -> (Prepared, BakeRequest) {
    let name = mesh.name.clone();
    let request = BakeRequest {
        bounces,
        ..request(96)
    };
    let scene = scene(vec![mesh], lights);
    let prepared = prepare_with(&scene, &name, &request, &Control::new()).unwrap();
    (prepared, request)
}

/// The share of the light entering one texel that a bounce brings into
/// another inside a sphere: the light leaving (the material's diffuse
/// albedo) times the entry transmittance averaged over a cosine-weighted
/// hemisphere.
fn share_per_bounce(mesh: &Mesh, request: &BakeRequest) -> [f64; 3] {
    let scene = scene(vec![mesh.clone()], vec![]);
    let request = BakeRequest {
        objects: vec![mesh.name.clone()],
        ..request.clone()
    };
    let plan = plan(&scene, &request).unwrap();
    let scattering = &plan.objects[0].scattering_profile;
    let albedo = scattering.diffuse_albedo();
    let entry = EntryTransmittance::of_surface(&scattering.surface);
    // ∫ T(μ) 2μ dμ by the midpoint rule.
    let steps = 20_000;
    let mean_entry: [f64; 3] = std::array::from_fn(|c| {
        (0..steps)
            .map(|i| {
                let mu = (i as f64 + 0.5) / steps as f64;
                f64::from(entry.at_rgb(mu as f32)[c]) * 2.0 * mu / steps as f64
            })
            .sum()
    });
    std::array::from_fn(|c| albedo[c] * mean_entry[c])
}

#[test]
fn inside_a_sphere_each_bounce_adds_the_same_share_again() {
    let mesh = inside_out_sphere(40.0);
    let (direct, request) = lit(mesh.clone(), vec![point_light_at(Vec3::ZERO)], 0);
    let q = share_per_bounce(&mesh, &request);
    assert!(
        q.iter().all(|&q| q > 0.05 && q < 1.0),
        "share per bounce {q:?}"
    );
    for bounces in [1u32, 3] {
        let (bounced, _) = lit(mesh.clone(), vec![point_light_at(Vec3::ZERO)], bounces);
        let expected: [f64; 3] =
            std::array::from_fn(|c| (0..=bounces).map(|k| q[c].powi(k as i32)).sum());
        // Away from the poles, where the sphere's texels are slivers.
        let z = |s: usize| direct.surfels.position[s].z.abs();
        let mut ratios = vec![Vec::new(); 3];
        for s in (0..direct.surfels.len()).filter(|&s| z(s) < 30.0) {
            for (c, ratio) in ratios.iter_mut().enumerate() {
                let d = f64::from(direct.irradiance[s][c]);
                ratio.push(f64::from(bounced.irradiance[s][c]) / d);
            }
        }
        for c in 0..3 {
            let r = &mut ratios[c];
            r.sort_by(f64::total_cmp);
            let (low, high) = (r[r.len() / 100], r[r.len() * 99 / 100]);
            assert!(
                (low / expected[c] - 1.0).abs() < 0.02 && (high / expected[c] - 1.0).abs() < 0.02,
                "{bounces} bounces, channel {c}: texels' gain {low:.4}..{high:.4}, expected {:.4}",
                expected[c]
            );
        }
    }
}

#[test]
fn a_convex_body_sends_itself_nothing() {
    let sun = sun_from(Vec3::new(-0.3, -0.2, -1.0));
    let (direct, _) = lit(sphere(20.0, 24, 48), vec![sun.clone()], 0);
    let (bounced, _) = lit(sphere(20.0, 24, 48), vec![sun], 3);
    assert_eq!(direct.irradiance, bounced.irradiance);
}

#[test]
fn more_bounces_than_the_most_are_refused_by_name() {
    let mut request = BakeRequest {
        bounces: 17,
        ..request(16)
    };
    let error = request.validate().unwrap_err().to_string();
    assert!(error.contains("bounces"), "{error}");
}
