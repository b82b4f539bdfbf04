//! Surface sampling at scale: rasterising a million triangles at 4096²
//! (goal: under 2 s), relaxing a million Turk points for ten iterations
//! (goal: under 10 s on 2 cores), unwrapping with xatlas, and the mean
//! curvature of 4 million texels at one scale (times reported). Run:
//! `cargo bench -p sssbake`.

use criterion::{Criterion, criterion_group, criterion_main};
use sssbake::surface::curvature::mean_curvature;
use sssbake::surface::turk::{place_points, relax};
use sssbake::surface::unwrap::unwrap;
use sssbake::{Mesh, rasterize};
use std::hint::black_box;
use std::time::Duration;

#[path = "../tests/shapes.rs"]
mod shapes;

/// A UV sphere of radius 50 mm with `2 · rings · segments` triangles.
fn sphere(rings: u32, segments: u32) -> Mesh {
    shapes::sphere(50.0, rings, segments)
}

fn rasterisation(c: &mut Criterion) {
    let mesh = sphere(500, 1000); // 1,000,000 triangles
    let uvs = mesh.uvs.clone().unwrap();
    let mut group = c.benchmark_group("surface");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(20));
    group.bench_function("rasterise 1M triangles at 4096²", |b| {
        b.iter(|| rasterize(black_box(&mesh), &uvs, 4096).len())
    });
    let (points, weights) = place_points(&mesh, 1_000_000, 1);
    group.bench_function("relax 1M Turk points, 10 iterations", |b| {
        b.iter(|| {
            let (mut p, mut w) = (points.clone(), weights.clone());
            relax(&mesh, &mut p, &mut w, 10).spread_after
        })
    });
    let small = sphere(50, 100); // 10,000 triangles
    group.bench_function("unwrap 10k triangles with xatlas", |b| {
        b.iter(|| unwrap(black_box(&small), 1024, 4).unwrap().triangles.len())
    });
    let ball = sphere(200, 400);
    let surfels = rasterize(&ball, ball.uvs.as_ref().unwrap(), 2048);
    group.bench_function("mean curvature of 4M texels at 3 mm", |b| {
        b.iter(|| mean_curvature(black_box(&surfels), 3.0).len())
    });
    group.finish();
}

criterion_group!(benches, rasterisation);
criterion_main!(benches);
