//! Turk points: placement by area, relaxation by repulsion, sliding over edges.

mod shapes;
use shapes::*;
use sssbake::surface::turk::{
    nearest_neighbour_spread, place_points, point_count, points_at, relax,
};
use std::collections::HashSet;

#[test]
fn point_counts_follow_the_mean_free_path() {
    assert_eq!(point_count(100.0, 1.0, 1.0), 32); // 100/π = 31.8
    assert_eq!(point_count(100.0, 1.0, 4.0), 128);
    assert_eq!(point_count(0.0, 1.0, 1.0), 1);
    assert_eq!(point_count(100.0, 0.0, 1.0), 1_000_000_000);
}

#[test]
fn placement_follows_area() {
    // Half of a quad's area is each triangle's: about half the points each.
    let mesh = quad(10.0);
    let (points, _) = place_points(&mesh, 20_000, 3);
    let first = points.triangle.iter().filter(|&&t| t == 0).count() as f64 / 20_000.0;
    assert!((first - 0.5).abs() < 0.02, "{first}");
    assert!(
        points
            .area
            .iter()
            .all(|&a| (a - 100.0 / 20_000.0).abs() < 1e-7)
    );
}

#[test]
fn repulsion_evens_out_the_spacing() {
    for mesh in [sphere(10.0, 32, 64), cube(10.0)] {
        let (mut points, mut weights) = place_points(&mesh, 3000, 1);
        let report = relax(&mesh, &mut points, &mut weights, 20);
        assert!(
            report.spread_after < 0.3 * report.spread_before,
            "{}: spread {} → {}",
            mesh.name,
            report.spread_before,
            report.spread_after
        );
        assert!(
            report.moves.last().unwrap() < &report.moves[0],
            "{}: moves {:?}",
            mesh.name,
            report.moves
        );
        let radius = 2.0 * (mesh.area() / 3000.0).sqrt();
        assert!(
            (nearest_neighbour_spread(&points.position, radius) - report.spread_after).abs()
                < 1e-12
        );
        for (p, n) in points.position.iter().zip(&points.normal) {
            assert!((n.length() - 1.0).abs() < 1e-5);
            if mesh.name == "sphere" {
                assert!(
                    p.length() > 9.9 && p.length() < 10.0 + 1e-4,
                    "{p:?} left the sphere"
                );
            } else {
                assert!(
                    p.abs().max_element() > 5.0 - 1e-4 && p.abs().max_element() < 5.0 + 1e-4,
                    "{p:?} left the cube"
                );
            }
        }
    }
}

#[test]
fn points_slide_across_edges_onto_other_faces() {
    // Every point starts on the cube's first face (triangles 0 and 1); the
    // push must carry some over the edges onto the faces around it.
    let mesh = cube(10.0);
    let count = 400;
    let triangles: Vec<u32> = (0..count).map(|i| (i % 2) as u32).collect();
    let weights: Vec<[f64; 3]> = (0..count)
        .map(|i| {
            let (a, b) = (
                ((i * 37) % 100) as f64 / 100.0,
                ((i * 61) % 100) as f64 / 100.0,
            );
            let (a, b) = if a + b > 1.0 {
                (1.0 - a, 1.0 - b)
            } else {
                (a, b)
            };
            [1.0 - a - b, a, b]
        })
        .collect();
    let mut points = points_at(&mesh, &triangles, &weights, 600.0 / count as f32);
    let mut weights = weights;
    relax(&mesh, &mut points, &mut weights, 60);
    let faces: HashSet<u32> = points.triangle.iter().map(|t| t / 2).collect();
    assert!(faces.len() >= 5, "points reached only faces {faces:?}");
}
