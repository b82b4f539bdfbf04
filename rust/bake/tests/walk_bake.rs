//! `--method walk` through the library's plan and bake, against the exact
//! sum of the profile where the two models should agree: the middle of a
//! thick block's lit face, far from its edges.

mod lit_scenes;

use glam::Vec3;
use lit_scenes::*;
use sssbake::control::Control;
use sssbake::{BakeRequest, Method, Output};

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
