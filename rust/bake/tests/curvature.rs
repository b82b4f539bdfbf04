//! The mean curvature the bake reads to raise small convex parts.

mod shapes;

use sssbake::surface::curvature::{mean_curvature, mean_curvatures};
use sssbake::surface::texels::rasterize;

#[test]
fn a_ball_is_one_over_its_radius_at_any_scale() {
    let ball = shapes::sphere(20.0, 96, 192);
    let surfels = rasterize(&ball, ball.uvs.as_ref().unwrap(), 256);
    for scale in [2.0, 8.0, 20.0] {
        let h = mean_curvature(&surfels, scale);
        let mean = h.iter().sum::<f32>() / h.len() as f32;
        let worst = h
            .iter()
            .map(|h| (h * 20.0 - 1.0).abs())
            .fold(0.0f32, f32::max);
        assert!(
            (mean * 20.0 - 1.0).abs() < 0.02,
            "scale {scale}: 1/{}",
            1.0 / mean
        );
        assert!(worst < 0.1, "scale {scale}: worst {worst}");
    }
}

#[test]
fn a_plane_is_flat_and_a_box_bulges_only_at_its_edges() {
    let plane = shapes::quad(100.0);
    let surfels = rasterize(&plane, plane.uvs.as_ref().unwrap(), 128);
    let h = mean_curvature(&surfels, 10.0);
    assert!(h.iter().all(|h| h.abs() < 1e-4));
    // A 60 mm cube: flat mid-face, convex toward its edges, never concave.
    let cube = shapes::cube(60.0);
    let surfels = rasterize(&cube, cube.uvs.as_ref().unwrap(), 256);
    let h = mean_curvature(&surfels, 3.0);
    let (mut middle, mut edge) = (0.0f32, 0.0f32);
    for (p, h) in surfels.position.iter().zip(&h) {
        assert!(*h > -1e-3, "concave {h} at {p}");
        // Distance from the nearest edge of the face it lies on.
        let inside = p.abs().to_array();
        let mut sorted = inside;
        sorted.sort_by(f32::total_cmp);
        let from_edge = 30.0 - sorted[1];
        if from_edge > 15.0 {
            middle = middle.max(h.abs());
        } else if from_edge < 1.0 {
            edge = edge.max(*h);
        }
    }
    assert!(middle < 1e-3, "mid-face {middle}");
    assert!(edge > 0.05, "at the edges {edge}");
}

#[test]
fn nothing_is_curved_at_no_scale() {
    let ball = shapes::sphere(5.0, 16, 32);
    let surfels = rasterize(&ball, ball.uvs.as_ref().unwrap(), 32);
    for scale in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert!(mean_curvature(&surfels, scale).iter().all(|&h| h == 0.0));
    }
}

#[test]
fn scales_found_together_are_each_as_found_alone() {
    // On a 20 mm ball at 256², patches are at least 0.16 mm across (the
    // object's bound on their count): 0.2 and 0.4 mm share that size and
    // one pass, 8 mm has patches of its own, NaN is no scale.
    let ball = shapes::sphere(20.0, 48, 96);
    let surfels = rasterize(&ball, ball.uvs.as_ref().unwrap(), 256);
    for scales in [[0.2, 0.4, f32::NAN], [0.2, 8.0, 0.4]] {
        let together = mean_curvatures(&surfels, scales);
        for (k, &scale) in scales.iter().enumerate() {
            let alone = mean_curvature(&surfels, scale);
            assert!(
                together.iter().zip(&alone).all(|(t, a)| t[k] == *a),
                "scale {scale} of {scales:?}"
            );
        }
        assert!(together.iter().flatten().all(|h| h.is_finite()));
    }
    let at_half = mean_curvature(&surfels, 0.4);
    let mean = at_half.iter().sum::<f32>() / at_half.len() as f32;
    assert!((mean * 20.0 - 1.0).abs() < 0.05, "1/{}", 1.0 / mean);
}
