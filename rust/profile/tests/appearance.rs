//! Shader descriptions (colour + mean free path) become materials whose
//! dipole shows exactly that colour, on ordinary and extreme inputs.

use sssbake_profile::appearance::{MIN_MEAN_FREE_PATH_MM, channel_mean_free_paths};
use sssbake_profile::boundary::fresnel::boundary_a;
use sssbake_profile::models::dipole::dipole_total_reflectance;
use sssbake_profile::presets::preset;
use sssbake_profile::{Appearance, Dipole, Profile};

fn appearance(colour: [f64; 3], mfp: [f64; 3], ior: f64, g: f64) -> Appearance {
    Appearance {
        name: "test".into(),
        colour,
        mean_free_path_mm: mfp,
        ior,
        anisotropy: g,
    }
}

#[test]
fn the_material_shows_the_colour_and_keeps_the_distance() {
    let look = appearance([0.8, 0.55, 0.45], [1.0, 0.2, 0.1], 1.4, 0.0);
    let material = look.to_material().unwrap();
    let layer = &material.layers().unwrap()[0];
    for c in 0..3 {
        let medium = layer.medium(c);
        let total = dipole_total_reflectance(medium.albedo_reduced(), boundary_a(1.4));
        assert!(
            (total - look.colour[c]).abs() < 1e-9,
            "channel {c}: {total}"
        );
        assert!((medium.mean_free_path() - look.mean_free_path_mm[c]).abs() < 1e-9);
    }
    // The profile integrates to the colour too.
    let dipole = Dipole::new([0, 1, 2].map(|c| layer.medium(c)), layer.ior);
    let total = dipole.total_reflectance();
    for c in 0..3 {
        assert!((total[c] - look.colour[c]).abs() < 2e-3, "{total:?}");
    }
}

#[test]
fn anisotropy_keeps_the_reduced_coefficient() {
    let isotropic = appearance([0.6; 3], [2.0; 3], 1.3, 0.0)
        .to_material()
        .unwrap();
    let forward = appearance([0.6; 3], [2.0; 3], 1.3, 0.8)
        .to_material()
        .unwrap();
    let (a, b) = (
        &isotropic.layers().unwrap()[0],
        &forward.layers().unwrap()[0],
    );
    assert_eq!(b.g, 0.8);
    for c in 0..3 {
        assert!((a.medium(c).sigma_s_reduced - b.medium(c).sigma_s_reduced).abs() < 1e-12);
        assert!(b.sigma_s[c] > 4.9 * a.sigma_s[c]);
    }
}

#[test]
fn extremes_stay_physical() {
    for colour in [0.0, 1e-9, 0.5, 1.0 - 1e-9, 1.0, 1.5, -0.2] {
        for mfp in [0.0, 1e-9, 1.0, 1e6] {
            for ior in [1.0, 1.0 + 1e-9, 1.5, 2.5] {
                for g in [-1.0, 0.0, 0.99, 1.0] {
                    let look = appearance([colour; 3], [mfp; 3], ior, g);
                    let material = look.to_material().unwrap_or_else(|e| {
                        panic!("{colour} {mfp} {ior} {g}: {e}");
                    });
                    material.validate("test").unwrap();
                    let layer = &material.layers().unwrap()[0];
                    for c in 0..3 {
                        let medium = layer.medium(c);
                        assert!(medium.sigma_a >= 0.0 && medium.sigma_s_reduced >= 0.0);
                        assert!(medium.mean_free_path() >= MIN_MEAN_FREE_PATH_MM * 0.999);
                        let total =
                            dipole_total_reflectance(medium.albedo_reduced(), boundary_a(ior));
                        let wanted = colour.clamp(0.0, 1.0);
                        assert!((total - wanted).abs() < 1e-6, "{colour} {ior}: {total}");
                    }
                }
            }
        }
    }
}

#[test]
fn non_finite_inputs_are_errors_not_materials() {
    assert!(
        appearance([f64::NAN, 0.5, 0.5], [1.0; 3], 1.4, 0.0)
            .to_material()
            .is_err()
    );
    assert!(
        appearance([0.5; 3], [1.0, f64::INFINITY, 1.0], 1.4, 0.0)
            .to_material()
            .is_err()
    );
    assert!(
        appearance([0.5; 3], [1.0, -1.0, 1.0], 1.4, 0.0)
            .to_material()
            .is_err()
    );
    assert!(
        appearance([0.5; 3], [1.0; 3], 0.0, 0.0)
            .to_material()
            .is_err()
    );
}

#[test]
fn every_preset_has_a_positive_scattering_distance() {
    for name in ["skin1", "marble", "skin3layer", "deon-skin"] {
        let material = preset(name).unwrap();
        let mfp = channel_mean_free_paths(&material);
        assert!(
            mfp.iter().all(|l| l.is_finite() && *l > 0.0),
            "{name}: {mfp:?}"
        );
    }
    // Skin's red travels furthest.
    let skin = channel_mean_free_paths(&preset("skin1").unwrap());
    assert!(skin[0] > skin[2], "{skin:?}");
}
