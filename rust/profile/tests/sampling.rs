//! Radii drawn from a profile follow its enclosed reflectance.

use sssbake_profile::model::{Model, build_profile};
use sssbake_profile::numerics::rng::Rng;
use sssbake_profile::presets::preset;

#[test]
fn dipole_radii_follow_the_enclosed_reflectance() {
    let material = preset("skin1").unwrap();
    let profile = build_profile(&material, Model::Dipole, 6).unwrap();
    for r_max in [0.5, 5.0, 50.0] {
        for channel in 0..3 {
            let mut rng = Rng::new(7, channel as u64);
            let count = 20_000;
            let mut radii: Vec<f64> = (0..count)
                .map(|_| {
                    profile
                        .sample_radius(channel, rng.uniform(), r_max)
                        .unwrap()
                })
                .collect();
            radii.sort_by(f64::total_cmp);
            assert!(radii.iter().all(|&r| (0.0..=r_max).contains(&r)));
            // Kolmogorov–Smirnov distance to the truncated CDF.
            let whole = profile.enclosed_reflectance(r_max)[channel];
            let distance = radii
                .iter()
                .enumerate()
                .map(|(i, &r)| {
                    let cdf = profile.enclosed_reflectance(r)[channel] / whole;
                    (cdf - i as f64 / count as f64)
                        .abs()
                        .max((cdf - (i + 1) as f64 / count as f64).abs())
                })
                .fold(0.0, f64::max);
            // 1.63/√n is the 1% critical value.
            assert!(
                distance < 1.63 / (count as f64).sqrt(),
                "r_max {r_max}, channel {channel}: {distance}"
            );
        }
    }
}

#[test]
fn models_without_a_closed_form_leave_sampling_to_tables() {
    let material = preset("skin3layer").unwrap();
    let profile = build_profile(&material, Model::Layered, 6).unwrap();
    assert!(profile.sample_radius(0, 0.5, 10.0).is_none());
}

/// One number both picks the dipole's source and places the radius, so
/// evenly spaced numbers give radii that follow the CDF as closely as the
/// spacing allows: a Kolmogorov–Smirnov distance of one step, far below
/// what independent draws reach (about 0.87/√n on average).
#[test]
fn stratified_numbers_give_stratified_dipole_radii() {
    let material = preset("skin1").unwrap();
    let profile = build_profile(&material, Model::Dipole, 6).unwrap();
    let (count, r_max) = (256, 20.0);
    for channel in 0..3 {
        let mut radii: Vec<f64> = (0..count)
            .map(|i| {
                let xi = (i as f64 + 0.5) / count as f64;
                profile.sample_radius(channel, xi, r_max).unwrap()
            })
            .collect();
        radii.sort_by(f64::total_cmp);
        let whole = profile.enclosed_reflectance(r_max)[channel];
        let distance = radii
            .iter()
            .enumerate()
            .map(|(i, &r)| {
                let cdf = profile.enclosed_reflectance(r)[channel] / whole;
                (cdf - (i as f64 + 0.5) / count as f64).abs()
            })
            .fold(0.0, f64::max);
        assert!(
            distance < 1.0 / count as f64,
            "channel {channel}: {distance}"
        );
    }
}
