//! Profile tabulation and Monte Carlo throughput.
//!
//! Goals: the three-layer skin tabulated (3 channels, full grid) in under
//! 20 ms; the Monte Carlo reference above 2 million photon interactions per
//! second on one core. Run: `cargo bench -p sssbake-profile`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use sssbake_profile::models::monte_carlo::{Settings, edges_around, simulate};
use sssbake_profile::presets::preset;
use sssbake_profile::{Layered, Model, Profile, build_profile};
use std::hint::black_box;

fn tabulation(c: &mut Criterion) {
    let skin = preset("skin3layer").unwrap();
    let layers = skin.layers().unwrap().to_vec();
    c.bench_function("layered three-layer skin, tabulated", |b| {
        b.iter(|| Layered::new(black_box(&layers)).total_reflectance())
    });
    let skin1 = preset("skin1").unwrap();
    c.bench_function("dipole skin1, d_max by eq. 40", |b| {
        b.iter(|| {
            build_profile(black_box(&skin1), Model::Dipole, 6)
                .unwrap()
                .d_max(1e-3)
        })
    });
}

fn monte_carlo(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut group = c.benchmark_group("Monte Carlo, one core");
    group.sample_size(10);
    for name in ["skin1", "skin3layer"] {
        let layers = preset(name).unwrap().layers().unwrap().to_vec();
        let settings = Settings::new(4096, 1, edges_around(&[0.1, 1.0, 10.0]));
        let interactions = simulate(&layers, &settings).interactions;
        group.throughput(Throughput::Elements(interactions));
        group.bench_function(format!("{name} interactions"), |b| {
            b.iter(|| pool.install(|| simulate(black_box(&layers), &settings).interactions))
        });
    }
    group.finish();
}

criterion_group!(benches, tabulation, monte_carlo);
criterion_main!(benches);
