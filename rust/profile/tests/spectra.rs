//! Closed-form spectra R̂(k) equal the numerical 2-D Fourier transform of R(r).

mod common;
use common::*;
use sssbake_profile::presets::preset;
use sssbake_profile::{Burley, Layered, Model, Multipole, Profile, SumOfGaussians, build_profile};
use std::f64::consts::PI;

/// J₀(x) = (1/π) ∫_0^π cos(x sin θ) dθ, by the midpoint rule (spectrally
/// accurate for this periodic integrand).
fn bessel_j0(x: f64) -> f64 {
    let n = 200 + (x.abs() * 2.0) as usize;
    (0..n)
        .map(|i| (x * (PI * (i as f64 + 0.5) / n as f64).sin()).cos())
        .sum::<f64>()
        / n as f64
}

fn check(profile: &dyn Profile, what: &str) {
    let total = profile.total_reflectance();
    let spectrum = |k: f64| {
        profile
            .reflectance_spectrum(k)
            .expect("a closed-form spectrum")
    };
    assert_rgb_close(
        spectrum(0.0),
        total,
        1e-9,
        &format!("{what}: R̂(0) is the total"),
    );
    let reach = profile.d_max(1e-7);
    let scale = profile.length_scale();
    for c in 0..3 {
        for k in [0.3 / scale[c], 1.0 / scale[c], 3.0 / scale[c]] {
            let numeric = radial_integral(
                |r| profile.reflectance(r)[c] * bessel_j0(k * r),
                scale[c] * 1e-6,
                reach[c] * 2.0,
                4_000,
            );
            let closed = spectrum(k)[c];
            assert!(
                (numeric - closed).abs() <= 2e-3 * total[c],
                "{what}, channel {c}, k {k}: numeric {numeric}, closed form {closed}"
            );
        }
    }
}

#[test]
fn every_closed_form_spectrum_matches_its_profile() {
    let skin1 = preset("skin1").unwrap();
    check(
        build_profile(&skin1, Model::Dipole, 6).unwrap().as_ref(),
        "dipole",
    );
    check(
        &Multipole::new(&grey_layer(0.02, 1.5, 0.0, 1.4, Some(2.0)), 1e-8),
        "multipole",
    );
    check(
        &Layered::new(preset("skin3layer").unwrap().layers().unwrap()),
        "layered",
    );
    check(&SumOfGaussians::deon_skin(), "gaussians");
    check(
        &Burley::from_cycles([0.8, 0.5, 0.2], [1.0, 0.5, 0.2]),
        "burley",
    );
}
