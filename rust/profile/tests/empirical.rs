//! The empirical model (Donner et al. 2009 fitted to photon tracing)
//! against independent solutions: the project's Monte Carlo for the total,
//! a diffuse lobe for the fit, and physical bounds at the extremes. Set
//! `SSSBAKE_LONG_EMPIRICAL` for ten times the photons and more media.

use sssbake_profile::models::empirical::lobe::exit_transmittance;
use sssbake_profile::models::empirical::{EmpiricalProfile, EmpiricalSettings};
use sssbake_profile::models::monte_carlo::{Settings, simulate};
use sssbake_profile::{Layer, Material, Model, Optics, Profile, build_profile, presets};

fn long() -> bool {
    std::env::var_os("SSSBAKE_LONG_EMPIRICAL").is_some()
}

fn settings(photons: u64) -> EmpiricalSettings {
    EmpiricalSettings {
        photons: if long() { 10 * photons } else { photons },
        seed: 5,
        ..EmpiricalSettings::default()
    }
}

/// A preset's top layer as a semi-infinite material.
fn top_layer(name: &str) -> Material {
    let mut material = presets::named(name).expect("a preset");
    if let Optics::Layers(layers) = &mut material.optics {
        layers.truncate(1);
        layers[0].thickness_mm = None;
    }
    material
}

fn material(sigma_a: f64, sigma_s: f64, g: f64, ior: f64) -> Material {
    Material {
        name: format!("σa {sigma_a} σs {sigma_s} g {g} η {ior}"),
        optics: Optics::Layers(vec![Layer {
            sigma_a: [sigma_a; 3],
            sigma_s: [sigma_s; 3],
            g,
            ior,
            thickness_mm: None,
        }]),
        coat_ior: None,
        top_layer: sssbake_profile::material::TopLayer::Diffusion,
        roughness: 0.0,
    }
}

fn media() -> Vec<&'static str> {
    if long() {
        vec!["skin1", "ketchup", "marble", "wholemilk", "apple"]
    } else {
        vec!["skin1", "ketchup"]
    }
}

/// The total diffuse reflectance at normal incidence equals the project's
/// Monte Carlo (another code: layered, radial tallies only) within 3%,
/// beyond the two simulations' own noise (two combined standard errors).
#[test]
fn the_exitance_equals_the_monte_carlo_within_three_percent() {
    for name in media() {
        let material = top_layer(name);
        let photons = settings(300_000).photons;
        let model = EmpiricalProfile::simulate(&material, &settings(300_000)).unwrap();
        let mc = simulate(
            material.layers().unwrap(),
            &Settings::new(photons, 11, vec![0.0, f64::INFINITY]),
        );
        let total = model.total_reflectance();
        for (c, &m) in total.iter().enumerate() {
            let (t, e) = (mc.total_reflectance[c], mc.total_reflectance_stderr[c]);
            let noise = e.hypot(model.slices()[c].simulated_total_stderr);
            eprintln!("{name} channel {c}: empirical {m:.5}, Monte Carlo {t:.5} ± {e:.5}");
            assert!(
                (m - t).abs() < 0.03 * t + 2.0 * noise,
                "{name} channel {c}: empirical {m}, Monte Carlo {t} ± {e}"
            );
        }
    }
}

/// The fit error is reported per material and bounded: on average within
/// 10 mean free paths the lobe misses the simulated hemisphere by less
/// than a quarter of the peak radiance (RMS; measured 9–17% for skin1 and
/// ketchup on 156 direction bins, of which 2–5% is the tallies' noise: a
/// single lobe cannot follow the single-scattering ridge near the entry
/// point), and it follows the hemispheres better than a diffuse lobe
/// F_t·M/π of the same exitance does (what a diffusion model predicts,
/// §2.3), so the shape is fitted.
#[test]
fn the_fit_error_is_reported_and_beats_a_diffuse_lobe() {
    for name in media() {
        let material = top_layer(name);
        let model = EmpiricalProfile::simulate(&material, &settings(100_000)).unwrap();
        for (c, error) in model.fit_error().iter().enumerate() {
            eprintln!("{name} channel {c}: {error:?}");
            assert!(error.mean_rms.is_finite() && error.mean_rms >= 0.0);
            assert!(
                error.mean_relative_rms < 0.25,
                "{name} channel {c}: {error:?}"
            );
            let slice = &model.slices()[c];
            // The diffuse lobe's RMS, bin by bin, from the same hemispheres
            // is not kept; compare at the peak instead: a diffuse lobe of
            // the same exitance reaches F_t(1)·M/π, the fit the data's peak
            // within its RMS.
            let mut better = 0;
            let mut counted = 0;
            for ((fit, r), m) in slice
                .fits
                .iter()
                .zip(&slice.radii_mfp)
                .zip(&slice.simulated_exitance)
            {
                if *r > 10.0 || fit.peak <= 0.0 {
                    continue;
                }
                counted += 1;
                let diffuse = exit_transmittance(1.0, slice.optics.eta) * m / std::f64::consts::PI;
                if fit.rms < (fit.peak - diffuse).abs() {
                    better += 1;
                }
            }
            assert!(
                better * 4 >= counted * 3,
                "{name} channel {c}: the fit beats a diffuse lobe at {better} of {counted} radii"
            );
        }
    }
}

/// `build_profile` builds the model, and a rough material is refused with
/// a reason (the fit is for a smooth boundary).
#[test]
fn the_model_is_built_and_refuses_a_rough_surface() {
    let mut material = material(0.1, 1.0, 0.5, 1.3);
    let profile = build_profile(&material, Model::Empirical, 6).unwrap();
    assert_eq!(profile.model(), "empirical");
    material.roughness = 0.3;
    let Err(error) = build_profile(&material, Model::Empirical, 6) else {
        panic!("a rough material was accepted");
    };
    assert!(error.to_string().contains("rough"), "{error}");
    let measured = presets::named("deon-skin").unwrap();
    assert!(build_profile(&measured, Model::Empirical, 6).is_err());
}

/// Albedo near 0 and 1, tiny and huge coefficients, η near 1: finite,
/// non-negative, and never more light out than in.
#[test]
fn extremes_stay_finite_non_negative_and_create_no_energy() {
    let cases = [
        material(1.0, 1e-6, 0.0, 1.3),   // albedo near 0
        material(0.0, 1.0, 0.0, 1.3),    // albedo 1: every photon leaves
        material(1e-9, 1e-6, 0.9, 1.4),  // tiny coefficients
        material(1e3, 1e6, -0.5, 1.2),   // huge coefficients
        material(0.1, 1.0, 0.0, 1.0001), // η near 1
    ];
    for material in &cases {
        let model = EmpiricalProfile::simulate(material, &settings(3_000)).unwrap();
        let total = model.total_reflectance();
        let scale = model.length_scale();
        for c in 0..3 {
            assert!(
                total[c].is_finite() && (0.0..=1.0 + 1e-9).contains(&total[c]),
                "{}: total {total:?}",
                material.name
            );
            for r in [0.0, 1e-3 * scale[c], scale[c], 10.0 * scale[c], 1e30] {
                let value = model.reflectance(r)[c];
                assert!(
                    value.is_finite() && value >= 0.0,
                    "{}: R({r}) = {value}",
                    material.name
                );
            }
        }
        for error in model.fit_error() {
            assert!(error.mean_rms.is_finite() && error.mean_rms >= 0.0);
        }
    }
}
