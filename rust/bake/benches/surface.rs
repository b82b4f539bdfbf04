//! Surface sampling at scale: rasterising a million triangles at 4096²
//! (goal: under 2 s), relaxing a million Turk points for ten iterations
//! (goal: under 10 s on 2 cores), and unwrapping with xatlas (time
//! reported). Run: `cargo bench -p sssbake`.

use criterion::{Criterion, criterion_group, criterion_main};
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
    group.finish();
}

criterion_group!(benches, rasterisation);
criterion_main!(benches);
