//! Stam 2001's discrete-ordinates layer against independent solutions:
//! exact energy conservation, Helmholtz reciprocity, and the Monte Carlo
//! photon transport of `monte_carlo` for the same slab at the same angles.
//!
//! `SSSBAKE_LONG_STAM=1` runs the Monte Carlo comparison with 20× the
//! photons and more slabs (about a minute).

mod common;
use common::stam_slab;
use sssbake_profile::boundary::fresnel::dielectric_reflectance;
use sssbake_profile::models::monte_carlo::{Settings, simulate_from_air, simulate_oblique};
use sssbake_profile::models::stam::{StamLayer, StamResponse, StamSettings};

fn layer(albedo: f64, optical_depth: f64, g: f64, eta: f64, roughness: f64) -> StamLayer {
    StamLayer {
        albedo,
        optical_depth,
        g,
        eta,
        roughness,
    }
}

fn solve(l: StamLayer) -> StamResponse {
    l.solve(&StamSettings::default())
        .unwrap_or_else(|e| panic!("{l:?}: {e}"))
}

/// Totals only: mode 0 carries all of R and T.
fn totals(l: StamLayer) -> StamResponse {
    let settings = StamSettings {
        modes: Some(1),
        ..StamSettings::default()
    };
    l.solve(&settings).unwrap_or_else(|e| panic!("{l:?}: {e}"))
}

#[test]
fn a_lossless_index_matched_layer_returns_all_light() {
    for (tau, g) in [
        (0.01, 0.0),
        (1.0, 0.0),
        (1.0, 0.9),
        (5.0, 0.5),
        (20.0, -0.3),
    ] {
        let r = solve(layer(1.0, tau, g, 1.0, 0.0));
        for e in 0..r.cosines.len() {
            let sum = r.reflectance[e] + r.transmittance[e];
            assert!(
                (sum - 1.0).abs() < 1e-6,
                "τ {tau} g {g} μ {}: R + T = {sum}",
                r.cosines[e]
            );
        }
    }
    // Smooth faces of another index conserve energy too, and rough ones
    // (normalised to, see `stam::boundary`).
    for m in [0.0, 0.1, 0.3, 1.0] {
        let r = totals(layer(1.0, 2.0, 0.8, 1.4, m));
        for e in 0..r.cosines.len() {
            let sum = r.reflectance[e] + r.transmittance[e];
            assert!((sum - 1.0).abs() < 1e-6, "m {m}: R + T = {sum}");
        }
    }
}

#[test]
fn the_brdf_and_btdf_are_reciprocal() {
    // Both faces against air: f(o, e) = f(e, o) in every mode, for the
    // reflected and the transmitted light alike; exactly (to rounding) for
    // smooth faces. Rough faces are normalised per incidence to conserve
    // energy (`stam::boundary`), which costs reciprocity up to 1.1% of the
    // largest value at m = 0.3.
    for (l, tolerance) in [
        (layer(0.9, 2.0, 0.7, 1.4, 0.0), 1e-9),
        (layer(0.5, 0.3, -0.2, 1.0, 0.0), 1e-9),
        (layer(0.99, 1.0, 0.5, 1.4, 0.3), 0.015),
    ] {
        let r = solve(l);
        for (name, modes) in [("BRDF", &r.brdf), ("BTDF", &r.btdf)] {
            let scale = modes.iter().map(|m| m.amax()).fold(0.0, f64::max);
            for (k, m) in modes.iter().enumerate() {
                let asymmetry = (m - m.transpose()).amax();
                assert!(
                    asymmetry <= tolerance * scale,
                    "{l:?} {name} mode {k}: asymmetry {asymmetry} of {scale}"
                );
            }
        }
    }
}

/// The simulation of the slab `l` (σt = 1/mm, so the thickness in mm is τ)
/// in three channels of albedos `albedos`, entered at outside cosine
/// `mu_out`; returns R and T per channel with their standard errors, faces
/// and unscattered light included as the discrete ordinates count them.
fn monte_carlo(l: StamLayer, albedos: [f64; 3], mu_out: f64, photons: u64) -> [[f64; 4]; 3] {
    let slab = stam_slab(l, albedos);
    let cos_inside = (1.0 - (1.0 - mu_out * mu_out) / (l.eta * l.eta)).sqrt();
    let mut settings = Settings::new(photons, 11, vec![0.0, 1e9]);
    settings.max_interactions = 100_000;
    let mc = simulate_oblique(&[slab], &settings, cos_inside);
    let fresnel = dielectric_reflectance(mu_out, 1.0, l.eta);
    std::array::from_fn(|c| {
        let enter = 1.0 - fresnel;
        [
            fresnel + enter * (mc.total_reflectance[c] + mc.unscattered_reflectance[c]),
            enter * mc.total_reflectance_stderr[c],
            enter * (mc.total_transmittance[c] + mc.unscattered_transmittance[c]),
            enter * mc.total_transmittance_stderr[c],
        ]
    })
}

#[test]
fn smooth_slabs_match_the_monte_carlo_per_incidence_angle() {
    let long = std::env::var_os("SSSBAKE_LONG_STAM").is_some();
    let photons = if long { 2_000_000 } else { 100_000 };
    let albedos = [0.5, 0.9, 0.99];
    let mut slabs = vec![(1.0, 0.0, 1.0), (2.0, 0.8, 1.4)];
    if long {
        slabs.extend([(0.5, 0.5, 1.4), (5.0, 0.9, 1.4), (1.0, -0.5, 1.0)]);
    }
    for (tau, g, eta) in slabs {
        for c in 0..3 {
            let l = layer(albedos[c], tau, g, eta, 0.0);
            let r = totals(l);
            let angles: Vec<usize> = if long {
                (0..r.cosines.len()).step_by(2).collect()
            } else {
                vec![r.cosines.len() / 3, r.cosines.len() - 1]
            };
            for &e in &angles {
                if c > 0 {
                    continue; // one simulation serves the three albedos
                }
                let mc = monte_carlo(l, albedos, r.cosines[e], photons);
                for (cc, &albedo) in albedos.iter().enumerate() {
                    let d = totals(layer(albedo, tau, g, eta, 0.0));
                    for (what, ours, theirs, error) in [
                        ("R", d.reflectance[e], mc[cc][0], mc[cc][1]),
                        ("T", d.transmittance[e], mc[cc][2], mc[cc][3]),
                    ] {
                        let allowed = 0.02 * theirs + 3.0 * error;
                        assert!(
                            (ours - theirs).abs() <= allowed,
                            "τ {tau} g {g} η {eta} Ω {albedo} μ {:.3}: {what} {ours:.5}, Monte Carlo {theirs:.5} ± {error:.5}",
                            d.cosines[e]
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn extreme_layers_stay_physical() {
    let mut checked = 0;
    for albedo in [0.0, 1e-6, 0.5, 1.0 - 1e-9, 1.0] {
        for tau in [1e-9, 1e-3, 1.0, 1e3, 1e9, f64::INFINITY] {
            for g in [-0.999, 0.0, 0.999] {
                for eta in [1.0, 1.0 + 1e-9, 1.4, 3.0] {
                    for m in [0.0, 0.5] {
                        // Rough faces cost more; a third of the cases.
                        if m > 0.0 && (albedo * (1.0 - albedo) > 0.0 || tau > 1.0 && tau < 1e9) {
                            continue;
                        }
                        let r = totals(layer(albedo, tau, g, eta, m));
                        for e in 0..r.cosines.len() {
                            let (rr, tt) = (r.reflectance[e], r.transmittance[e]);
                            assert!(
                                rr.is_finite() && tt.is_finite() && rr >= 0.0 && tt >= 0.0,
                                "Ω {albedo} τ {tau} g {g} η {eta} m {m}: R {rr} T {tt}"
                            );
                            assert!(
                                rr + tt <= 1.0 + 1e-6,
                                "Ω {albedo} τ {tau} g {g} η {eta} m {m}: R + T = {}",
                                rr + tt
                            );
                        }
                        checked += 1;
                    }
                }
            }
        }
    }
    assert_eq!(checked, 5 * 6 * 3 * 4 + 2 * 5 * 3 * 4);
}

#[test]
fn a_vanishing_layer_is_its_two_faces() {
    // τ → 0: what is left is two smooth faces, light bouncing between
    // them: R = F + (1 − F)²F/(1 − F²) = 2F/(1 + F), T = 1 − R.
    let r = solve(layer(0.7, 1e-9, 0.3, 1.4, 0.0));
    for e in 0..r.cosines.len() {
        let f = dielectric_reflectance(r.cosines[e], 1.0, 1.4);
        let expected = 2.0 * f / (1.0 + f);
        assert!((r.reflectance[e] - expected).abs() < 1e-6, "{e}");
        assert!((r.transmittance[e] - (1.0 - expected)).abs() < 1e-6, "{e}");
    }
    // τ → ∞ and no absorption: everything comes back.
    let r = solve(layer(1.0, f64::INFINITY, 0.5, 1.4, 0.0));
    for e in 0..r.cosines.len() {
        assert!(r.transmittance[e] < 1e-12);
        assert!(r.reflectance[e] > 0.99, "{}", r.reflectance[e]);
    }
}

#[test]
fn errors_name_the_parameter() {
    let e = layer(1.5, 1.0, 0.0, 1.4, 0.0)
        .solve(&StamSettings::default())
        .unwrap_err();
    assert!(e.to_string().contains("albedo"), "{e}");
    let e = layer(0.5, -1.0, 0.0, 1.4, 0.0)
        .solve(&StamSettings::default())
        .unwrap_err();
    assert!(e.to_string().contains("optical depth"), "{e}");
    let e = layer(0.5, 1.0, 1.0, 1.4, 0.0)
        .solve(&StamSettings::default())
        .unwrap_err();
    assert!(e.to_string().contains("g "), "{e}");
    let e = layer(0.5, 1.0, 0.0, f64::NAN, 0.0)
        .solve(&StamSettings::default())
        .unwrap_err();
    assert!(e.to_string().contains("eta"), "{e}");
}

#[test]
fn a_slab_matches_van_de_hulsts_adding_doubling_table() {
    // τ = 2, Ω = 0.9, g = 0.75, matched faces, normal incidence: van de
    // Hulst (1980) as MCML (Wang et al. 1995) quotes it: diffuse R 0.09739,
    // total T 0.66096 (the unscattered e⁻² included). The nearest ordinate
    // to the normal is at θ ≈ 1.5° with 64 ordinates, where R and T differ
    // from their normal-incidence values by under 10⁻⁴.
    let settings = StamSettings {
        ordinates: 64,
        modes: Some(1),
    };
    let r = layer(0.9, 2.0, 0.75, 1.0, 0.0).solve(&settings).unwrap();
    let e = r.cosines.len() - 1;
    assert!(
        (r.reflectance[e] - 0.09739).abs() < 2e-4,
        "R {}",
        r.reflectance[e]
    );
    assert!(
        (r.transmittance[e] - 0.66096).abs() < 2e-4,
        "T {}",
        r.transmittance[e]
    );
}

#[test]
fn nearly_smooth_rough_faces_approach_the_smooth_layer() {
    // Rough faces of m = 0.1 on 64 ordinates against exact Fresnel faces,
    // a thick layer of Ω 0.9, g 0.5, η 1.4: within 1.5% for θi ≤ 68°.
    // (Closer to grazing, and for m below about 0.05, the faces' lobes
    // are narrower than the ordinates' spacing: 6% apart at 78°.)
    let settings = StamSettings {
        ordinates: 64,
        modes: Some(1),
    };
    let smooth = layer(0.9, f64::INFINITY, 0.5, 1.4, 0.0)
        .solve(&settings)
        .unwrap();
    let rough = layer(0.9, f64::INFINITY, 0.5, 1.4, 0.1)
        .solve(&settings)
        .unwrap();
    let mut compared = 0;
    for e in (0..smooth.cosines.len()).filter(|&e| smooth.cosines[e] >= 0.37) {
        let (a, b) = (rough.reflectance[e], smooth.reflectance[e]);
        assert!(
            (a - b).abs() <= 0.015 * b,
            "μ {}: rough {a}, smooth {b}",
            smooth.cosines[e]
        );
        compared += 1;
    }
    assert!(compared >= 20, "{compared}");
}

/// The simulation of the slab `l` with rough faces of its own slope,
/// entered from air at cosine `mu_out`: R and T per channel (faces and
/// unscattered light included) with their standard errors.
fn rough_monte_carlo(l: StamLayer, albedos: [f64; 3], mu_out: f64, photons: u64) -> [[f64; 4]; 3] {
    let slab = stam_slab(l, albedos);
    let mut settings = Settings::new(photons, 13, vec![0.0, 1e9]);
    settings.max_interactions = 100_000;
    settings.roughness = l.roughness;
    let mc = simulate_from_air(&[slab], &settings, mu_out);
    // The face's own reflection is a weighted Bernoulli count; its noise
    // is bounded by √(F/n) with F the share it reflects.
    let face_noise = (mc.unscattered_reflectance[0].max(1e-3) / photons as f64).sqrt();
    std::array::from_fn(|c| {
        [
            mc.total_reflectance[c] + mc.unscattered_reflectance[c],
            mc.total_reflectance_stderr[c] + face_noise,
            mc.total_transmittance[c] + mc.unscattered_transmittance[c],
            mc.total_transmittance_stderr[c] + face_noise,
        ]
    })
}

/// Rough faces (Beckmann, RMS slope 0.3 and 0.6) against a Monte Carlo
/// whose faces draw the same single-scattering facets and return the
/// light their shadowing blocks along the lobes, as the solver's per-angle
/// renormalisation does: R and T within 2% and the noise, from normal
/// incidence to 66°.
#[test]
fn rough_slabs_match_a_monte_carlo_with_rough_faces() {
    let albedos = [0.5, 0.9, 0.99];
    for (tau, g, eta, m) in [(1.0, 0.5, 1.4, 0.3), (2.0, 0.0, 1.3, 0.6)] {
        let r = totals(layer(albedos[0], tau, g, eta, m));
        let angles: Vec<usize> = (0..r.cosines.len())
            .filter(|&e| r.cosines[e] >= 0.4)
            .step_by(6)
            .chain([r.cosines.len() - 1])
            .collect();
        for &e in &angles {
            let mc = rough_monte_carlo(
                layer(albedos[0], tau, g, eta, m),
                albedos,
                r.cosines[e],
                100_000,
            );
            for (c, &albedo) in albedos.iter().enumerate() {
                let d = totals(layer(albedo, tau, g, eta, m));
                for (what, ours, theirs, error) in [
                    ("R", d.reflectance[e], mc[c][0], mc[c][1]),
                    ("T", d.transmittance[e], mc[c][2], mc[c][3]),
                ] {
                    println!(
                        "τ {tau} m {m} Ω {albedo} μ {:.3}: {what} {ours:.5}, Monte Carlo {theirs:.5} ± {error:.5}",
                        d.cosines[e]
                    );
                    assert!(
                        (ours - theirs).abs() <= 0.02 * theirs + 3.0 * error,
                        "τ {tau} m {m} Ω {albedo} μ {:.3}: {what} {ours:.5}, Monte Carlo {theirs:.5} ± {error:.5}",
                        d.cosines[e]
                    );
                }
            }
        }
    }
}
