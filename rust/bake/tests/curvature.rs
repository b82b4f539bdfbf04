//! The mean curvature the bake reads to raise small convex parts.

mod shapes;

use glam::Quat;
use sssbake::surface::curvature::{mean_curvature, mean_curvatures};
use sssbake::surface::texels::rasterize;
use std::collections::BTreeMap;

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

/// The mean curvature over the texels within 1.5 mm of each of a 60 mm
/// cube's twelve edges, by the edge's two faces (axis and sign of each).
fn along_each_edge(cube: &sssbake::Mesh, turn: Quat) -> Vec<(String, f32)> {
    let surfels = rasterize(cube, cube.uvs.as_ref().unwrap(), 256);
    let h = mean_curvature(&surfels, 3.0);
    let mut edges: BTreeMap<String, (f32, usize)> = BTreeMap::new();
    for (i, &h) in h.iter().enumerate() {
        // Read in the cube's own frame, whichever way it is turned.
        let p = turn.inverse() * surfels.position[i];
        let n = turn.inverse() * surfels.normal[i];
        let face = (0..3)
            .max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
            .unwrap();
        let side = (0..3)
            .filter(|&b| b != face)
            .max_by(|&a, &b| p[a].abs().total_cmp(&p[b].abs()))
            .unwrap();
        if 30.0 - p[side].abs() > 1.5 {
            continue;
        }
        let name = |axis: usize, value: f32| {
            format!(
                "{}{}",
                if value < 0.0 { '-' } else { '+' },
                ["x", "y", "z"][axis]
            )
        };
        let mut pair = [name(face, n[face]), name(side, p[side])];
        pair.sort();
        let sum = edges.entry(pair.join("")).or_default();
        sum.0 += h;
        sum.1 += 1;
    }
    edges
        .into_iter()
        .map(|(edge, (sum, count))| (edge, sum / count as f32))
        .collect()
}

/// A cube's twelve edges bend alike, and alike again with the cube turned
/// from Z-up to Y-up. Texels were gathered into patches by the octant
/// their normal points into, so the faces facing the world's positive axes
/// shared patches along their edges (+x with +y, not −x with +y) and those
/// edges bent by a tenth more (0.136 against 0.120 per mm).
#[test]
fn a_cube_is_as_curved_at_every_edge_and_however_it_is_turned() {
    let cube = shapes::cube(60.0);
    let y_up = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    let mut turned = cube.clone();
    for p in &mut turned.positions {
        *p = y_up * *p;
    }
    for n in &mut turned.normals {
        *n = y_up * *n;
    }
    let z_up = along_each_edge(&cube, Quat::IDENTITY);
    let y_up = along_each_edge(&turned, y_up);
    eprintln!("Z-up: {z_up:.4?}\nY-up: {y_up:.4?}");
    assert_eq!(z_up.len(), 12);
    let all: Vec<f32> = z_up.iter().chain(&y_up).map(|(_, h)| *h).collect();
    let (least, most) = all
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &h| (lo.min(h), hi.max(h)));
    assert!(least > 0.05 && most < least * 1.05, "{least} .. {most}");
}
