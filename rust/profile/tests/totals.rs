//! Closed-form and k = 0 totals equal the numerical ∫ 2πr R(r) dr.

mod common;
use common::*;
use sssbake_profile::presets::preset;
use sssbake_profile::{Burley, Layered, Model, Multipole, Profile, SumOfGaussians, build_profile};

fn check(profile: &dyn Profile, tolerance: f64, what: &str) {
    let total_r = profile.total_reflectance();
    let total_t = profile.total_transmittance();
    let reach = profile.d_max(1e-8);
    let scale = profile.length_scale();
    for c in 0..3 {
        let hi = reach[c].max(1e-6) * 3.0;
        let lo = scale[c] * 1e-6;
        let numeric_r = radial_integral(|r| profile.reflectance(r)[c], lo, hi, 40_000);
        assert!(
            (numeric_r - total_r[c]).abs() <= tolerance * total_r[c].max(1e-12),
            "{what} channel {c}: ∫2πrR = {numeric_r}, closed form {}",
            total_r[c]
        );
        if total_t[c] > 1e-6 {
            let numeric_t = radial_integral(|r| profile.transmittance(r)[c], lo, hi * 10.0, 40_000);
            assert!(
                (numeric_t - total_t[c]).abs() <= tolerance * total_t[c],
                "{what} channel {c}: ∫2πrT = {numeric_t}, closed form {}",
                total_t[c]
            );
        }
    }
}

#[test]
fn dipole_total_matches_its_integral() {
    for name in ["skin1", "marble", "ketchup", "cream", "spectralon"] {
        let material = preset(name).unwrap();
        check(
            build_profile(&material, Model::Dipole, 6).unwrap().as_ref(),
            1e-5,
            name,
        );
    }
}

#[test]
fn multipole_totals_match_their_integrals() {
    for (thickness, g) in [(0.1, 0.0), (1.0, 0.5), (4.0, 0.0), (30.0, 0.9)] {
        let layer = grey_layer(0.05, 2.0, g, 1.4, Some(thickness));
        let profile = Multipole::new(&layer, 1e-8);
        check(&profile, 1e-4, &format!("slab {thickness} mm"));
    }
}

#[test]
fn layered_totals_at_zero_frequency_match_the_tabulated_integral() {
    let two_slab = vec![
        grey_layer(0.005, 1.3, 0.0, 1.4, Some(6.0)),
        grey_layer(0.01, 1.0, 0.0, 1.4, None),
    ];
    check(&Layered::new(&two_slab), 2e-3, "Mikkelsen table 3");
    let skin = preset("skin3layer").unwrap();
    check(
        &Layered::new(skin.layers().unwrap()),
        2e-3,
        "three-layer skin",
    );
    let finite = vec![
        grey_layer(0.1, 5.0, 0.2, 1.5, Some(0.3)),
        grey_layer(0.02, 1.0, 0.0, 1.33, Some(2.0)),
    ];
    check(&Layered::new(&finite), 2e-3, "finite two-layer stack");
}

#[test]
fn gaussian_and_burley_totals_match_their_integrals() {
    check(&SumOfGaussians::deon_skin(), 1e-6, "d'Eon skin");
    check(
        &Burley::from_cycles([0.8, 0.5, 0.3], [1.0, 0.2, 0.1]),
        1e-5,
        "Burley",
    );
}
