//! `--method walk` through the library's plan and bake, against the exact
//! sum of the profile where the two models should agree: the middle of a
//! thick block's lit face, far from its edges.

mod lit_scenes;

use glam::{Vec2, Vec3};
use lit_scenes::*;
use sssbake::control::Control;
use sssbake::{BakeRequest, Mesh, Method, Output};

/// A cube of side `side` mm centred at the origin, its six faces each in
/// a cell of a 3 × 2 UV grid with a margin, facing out.
fn cube(side: f32) -> Mesh {
    let h = side / 2.0;
    let faces = [
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::Y, Vec3::X),
        (Vec3::X, Vec3::Y, Vec3::Z),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::Z, Vec3::X),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
    ];
    let (mut positions, mut uvs, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for (k, (n, u, v)) in faces.into_iter().enumerate() {
        let cell = Vec2::new((k % 3) as f32 / 3.0, (k / 3) as f32 / 2.0);
        let base = positions.len() as u32;
        for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            positions.push(h * (n + su * u + sv * v));
            let t = Vec2::new((su + 1.0) / 2.0, (sv + 1.0) / 2.0);
            uvs.push(cell + Vec2::new(0.03, 0.03) + t * Vec2::new(1.0 / 3.0 - 0.06, 0.5 - 0.06));
        }
        triangles.push([base, base + 1, base + 2]);
        triangles.push([base, base + 2, base + 3]);
    }
    Mesh::new("cube", positions, None, Some(uvs), triangles)
        .expect("a valid cube")
        .0
}

#[test]
fn a_walk_bake_matches_the_exact_sum_on_a_thick_lit_face() {
    let scene = scene(vec![cube(40.0)], vec![sun_from(Vec3::NEG_Z)]);
    let bake_by = |method: Method| {
        let mut request = BakeRequest {
            method,
            outputs: vec![Output::Subsurface],
            ..request(48)
        };
        request.integrators.walk.samples = 256;
        let plan = sssbake::plan(&scene, &request).expect("a plan");
        assert_eq!(plan.objects[0].integrator.as_ref().unwrap().method, method);
        sssbake::bake(&scene, &plan, &Control::new()).expect("a bake")
    };
    let (walked, summary) = bake_by(Method::Walk);
    let (exact, _) = bake_by(Method::Brute);
    let accuracy = summary.objects[0].accuracy.as_ref().unwrap();
    let noise = accuracy.walk.expect("the walk states its noise");
    eprintln!("{summary}");
    let (walked, exact) = (&walked[0], &exact[0]);
    // The middle of the top face: 12 mm or more from every edge, beyond
    // the reach of skin1's red (1/σtr ≈ 3.7 mm) three times over.
    let middle: Vec<usize> = (0..walked.prepared.surfels.len())
        .filter(|&s| {
            let p = walked.prepared.surfels.position[s];
            p.z > 19.9 && p.x.abs() < 8.0 && p.y.abs() < 8.0
        })
        .collect();
    assert!(middle.len() >= 9, "{} texels in the middle", middle.len());
    for c in 0..3 {
        let mean = |m: &[[f32; 3]]| middle.iter().map(|&s| m[s][c] as f64).sum::<f64>();
        let ratio = mean(&walked.exitance) / mean(&exact.exitance);
        // The walk's noise over these texels, relative.
        let stated = noise.relative_standard_error[c] / (middle.len() as f64).sqrt();
        eprintln!(
            "channel {c}: walk / exact sum {ratio:.4} over {} texels (walk noise {:.4})",
            middle.len(),
            stated
        );
        // The dipole against light transport in a half-space of skin1
        // (reduced albedo 0.96 to 0.99, η 1.3): diffusion's error is a few
        // percent there; the noise adds four of its standard errors.
        assert!(
            (ratio - 1.0).abs() < 0.06 + 4.0 * stated,
            "channel {c}: walk / exact sum {ratio}"
        );
        assert!(noise.truncated[c] < 0.01 && noise.lost[c] == 0.0);
    }
    // The faces the sun does not reach get light only through the cube:
    // the bottom's middle is 40 mm of skin away, dark.
    let bottom: Vec<usize> = (0..walked.prepared.surfels.len())
        .filter(|&s| walked.prepared.surfels.position[s].z < -19.9)
        .collect();
    assert!(
        bottom
            .iter()
            .all(|&s| walked.exitance[s].iter().all(|&m| m < 1e-3))
    );
}
