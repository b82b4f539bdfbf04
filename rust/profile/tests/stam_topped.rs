//! A Stam top layer (an epidermis in contact with the layer beneath) and
//! the stack under it, against independent answers: exact energy
//! conservation from both sides, the closed form of a vanishing layer (one
//! Fresnel face), the Monte Carlo photon transport of the same slab on an
//! absorbing base, and the Monte Carlo of the whole skin.

mod common;
use common::stam_slab;
use sssbake_profile::boundary::fresnel::{dielectric_reflectance, diffuse_reflectance_exact};
use sssbake_profile::boundary::surface::Surface;
use sssbake_profile::material::{Layer, Material, Optics, TopLayer};
use sssbake_profile::model::{Model, build_profile};
use sssbake_profile::models::monte_carlo::{Settings, simulate_oblique};
use sssbake_profile::models::stam::StamLayer;
use sssbake_profile::models::stam::contact::ContactTotals;
use sssbake_profile::presets::preset;

fn layer(albedo: f64, optical_depth: f64, g: f64, eta: f64, roughness: f64) -> StamLayer {
    StamLayer {
        albedo,
        optical_depth,
        g,
        eta,
        roughness,
    }
}

fn contact(l: StamLayer) -> ContactTotals {
    l.solve_in_contact(32)
        .unwrap_or_else(|e| panic!("{l:?}: {e}"))
}

#[test]
fn a_lossless_epidermis_returns_or_passes_all_light_from_either_side() {
    for (tau, g, eta, m) in [
        (0.01, 0.0, 1.0, 0.0),
        (1.0, 0.8, 1.4, 0.0),
        (2.0, 0.5, 1.4, 0.4),
        (20.0, -0.3, 1.3, 1.0),
    ] {
        let t = contact(layer(1.0, tau, g, eta, m));
        for e in 0..t.cosines.len() {
            let sum = t.reflectance[e] + t.transmittance[e];
            assert!(
                (sum - 1.0).abs() < 1e-6,
                "τ {tau} m {m} μ {}: R + T = {sum}",
                t.cosines[e]
            );
        }
        let below = t.reflectance_from_below + t.transmittance_from_below;
        assert!(
            (below - 1.0).abs() < 1e-6,
            "τ {tau} m {m}: from below R + T = {below}"
        );
        // The escaping light's angular shares add up to its exitance.
        let shares: f64 = (0..t.cosines.len())
            .map(|e| 2.0 * t.weights[e] * t.cosines[e] * t.exit_distribution[e])
            .sum();
        assert!((shares - 1.0).abs() < 1e-9, "{shares}");
    }
}

#[test]
fn a_vanishing_smooth_epidermis_is_the_fresnel_boundary_the_bake_used_before() {
    // τ → 0 with smooth faces: what is left is the top face alone (the
    // bottom is in contact). Light enters with 1 − F(θ), the entry term of a
    // smooth boundary; light from below returns F_dr, and what leaves at
    // the normal, per unit of the exitance into air, is
    // (1 − F(0))/(η²(1 − F_dr)): Fresnel's 1 − F(0) over the share of a
    // Lambertian flux inside that gets out, with the radiance's 1/η².
    let eta = 1.4;
    let material = Material {
        name: "vanishing".into(),
        optics: Optics::Layers(vec![
            Layer {
                sigma_a: [0.5; 3],
                sigma_s: [0.5; 3],
                g: 0.3,
                ior: eta,
                thickness_mm: Some(1e-9),
            },
            Layer::semi_infinite([0.01; 3], [1.0; 3], eta),
        ]),
        coat_ior: None,
        roughness: 0.0,
        top_layer: TopLayer::Stam,
    };
    let stam = Surface::of(&material, Model::Stam).unwrap();
    let fresnel = Surface::of(&material, Model::Layered).unwrap();
    assert!(matches!(fresnel, Surface::Boundary { .. }));
    let mut worst: f64 = 0.0;
    for i in 0..=400 {
        let cos = i as f64 / 400.0;
        let (a, b) = (stam.entry(cos)[0], fresnel.entry(cos)[0]);
        worst = worst.max((a - b).abs() * cos);
        // Between ordinates T is a parabola in the cosine; near grazing
        // the ordinates thin out, where cos θ makes the light small.
        assert!(
            (a - b).abs() * cos < 1e-3,
            "cos {cos}: stam {a}, Fresnel {b}"
        );
        if cos >= 0.3 {
            assert!((a - b).abs() < 2e-3, "cos {cos}: stam {a}, Fresnel {b}");
        }
    }
    println!("largest difference in cos θ·T: {worst:.2e}");
    let Surface::Stam(epidermis) = &stam else {
        panic!("{stam:?}")
    };
    let t = epidermis.channel(0);
    for e in 0..t.cosines.len() {
        let f = dielectric_reflectance(t.cosines[e], 1.0, eta);
        assert!(
            (t.transmittance[e] - (1.0 - f)).abs() < 1e-6,
            "μ {}",
            t.cosines[e]
        );
    }
    let f_dr = diffuse_reflectance_exact(eta);
    assert!(
        (t.reflectance_from_below - f_dr).abs() < 1e-3,
        "{} vs F_dr {f_dr}",
        t.reflectance_from_below
    );
    let exit = (1.0 - dielectric_reflectance(1.0, 1.0, eta)) / (eta * eta * (1.0 - f_dr));
    let got = stam.exit_at_normal()[0];
    assert!((got - exit).abs() < 2e-3, "exit {got} vs {exit}");
}

/// R(θi) of the slab `l` in contact with an index-matched, purely
/// absorbing base, by the Monte Carlo in three channels of `albedos`:
/// (value, standard error) per channel, the face's reflection included.
fn monte_carlo_on_absorber(l: StamLayer, albedos: [f64; 3], mu_out: f64) -> [[f64; 2]; 3] {
    let slab = stam_slab(l, albedos);
    let absorber = Layer::semi_infinite([1e3; 3], [0.0; 3], l.eta);
    let cos_inside = (1.0 - (1.0 - mu_out * mu_out) / (l.eta * l.eta)).sqrt();
    let mut settings = Settings::new(100_000, 5, vec![0.0, 1e9]);
    settings.max_interactions = 100_000;
    let mc = simulate_oblique(&[slab, absorber], &settings, cos_inside);
    let fresnel = dielectric_reflectance(mu_out, 1.0, l.eta);
    std::array::from_fn(|c| {
        let enter = 1.0 - fresnel;
        [
            fresnel + enter * (mc.total_reflectance[c] + mc.unscattered_reflectance[c]),
            enter * mc.total_reflectance_stderr[c],
        ]
    })
}

#[test]
fn an_epidermis_on_an_absorber_matches_the_monte_carlo_per_incidence_angle() {
    // Whatever crosses the contact is absorbed, so R(θi) is all that comes
    // back; with no absorption in the slab, T(θi) = 1 − R(θi) exactly
    // (checked above), so the absorbing albedos check T through R.
    let albedos = [0.5, 0.9, 1.0];
    let (tau, g, eta) = (1.5, 0.0, 1.4);
    let probe = contact(layer(albedos[0], tau, g, eta, 0.0));
    for e in [probe.cosines.len() / 3, probe.cosines.len() - 1] {
        let mc = monte_carlo_on_absorber(layer(0.0, tau, g, eta, 0.0), albedos, probe.cosines[e]);
        for (c, &albedo) in albedos.iter().enumerate() {
            let ours = contact(layer(albedo, tau, g, eta, 0.0)).reflectance[e];
            let (theirs, error) = (mc[c][0], mc[c][1]);
            assert!(
                (ours - theirs).abs() <= 0.02 * theirs + 3.0 * error,
                "Ω {albedo} μ {:.3}: R {ours:.5}, Monte Carlo {theirs:.5} ± {error:.5}",
                probe.cosines[e]
            );
        }
    }
}

#[test]
fn stam_skin_bakes_as_a_profile_that_makes_no_energy() {
    let material = preset("stam-skin").unwrap();
    assert_eq!(Model::default_for(&material), Model::Stam);
    let profile = build_profile(&material, Model::Stam, 6).unwrap();
    assert_eq!(profile.model(), "stam");
    let total = profile.total_reflectance();
    let surface = Surface::of(&material, Model::Stam).unwrap();
    let Surface::Stam(epidermis) = &surface else {
        panic!("{surface:?}")
    };
    let through = epidermis.transmittance_from_below();
    let ring = profile.enclosed_reflectance(1e3);
    for (c, total) in total.into_iter().enumerate() {
        // All that leaves into air came through the epidermis from below.
        assert!(
            total > 0.0 && total <= through[c],
            "{c}: {total} of {}",
            through[c]
        );
        assert!(
            (ring[c] - total).abs() < 0.01 * total,
            "{c}: {} vs {total}",
            ring[c]
        );
    }
    for r in [1e-4, 0.01, 0.1, 1.0, 10.0, 100.0] {
        assert!(
            profile
                .reflectance(r)
                .iter()
                .all(|v| v.is_finite() && *v >= 0.0)
        );
    }
}

/// The skin's diffuse reflectance at normal incidence by the Monte Carlo
/// of both layers (smooth faces, the layers in contact) against the
/// epidermis's own return plus what the stack under it sends back through
/// it: R_e(0°) + T_e(0°)·R_stack. The dermis is diffusion, whose own error
/// against transport is a few per cent here; the same stack wholly by
/// diffusion (`layered`) is printed beside it.
#[test]
fn smooth_stam_skin_matches_the_monte_carlo_of_both_layers() {
    let material = Material {
        roughness: 0.0,
        ..preset("stam-skin").unwrap()
    };
    let layers = material.layers().unwrap().to_vec();
    let profile = build_profile(&material, Model::Stam, 6).unwrap();
    let layered = build_profile(&material, Model::Layered, 6).unwrap();
    let Surface::Stam(epidermis) = Surface::of(&material, Model::Stam).unwrap() else {
        panic!("not a stam surface")
    };
    let mut settings = Settings::new(20_000, 9, vec![0.0, 1e9]);
    settings.max_interactions = 1_000_000;
    let mc = simulate_oblique(&layers, &settings, 1.0);
    let fresnel = dielectric_reflectance(1.0, 1.0, layers[0].ior);
    for c in 0..3 {
        let ours = epidermis.reflectance(1.0)[c]
            + epidermis.transmittance(1.0)[c] * profile.total_reflectance()[c];
        let diffusion = fresnel + (1.0 - fresnel) * layered.total_reflectance()[c];
        let theirs =
            fresnel + (1.0 - fresnel) * (mc.total_reflectance[c] + mc.unscattered_reflectance[c]);
        let error = (1.0 - fresnel) * mc.total_reflectance_stderr[c];
        println!(
            "channel {c}: stam-topped {ours:.4}, layered {diffusion:.4}, Monte Carlo {theirs:.4} ± {error:.4}"
        );
        assert!(
            (ours - theirs).abs() <= 0.06 * theirs + 3.0 * error,
            "channel {c}: {ours:.4} vs Monte Carlo {theirs:.4} ± {error:.4}"
        );
    }
}

#[test]
fn between_matched_faces_contact_and_air_are_one_layer() {
    // At η = 1 the contact and a face against air are the same nothing,
    // so the contact solve must give what the layer solve gives (which
    // `tests/stam.rs` checks against the Monte Carlo).
    for (albedo, tau, g) in [(0.5, 1.0, 0.0), (0.9, 2.0, 0.8), (0.99, 0.3, -0.5)] {
        let l = layer(albedo, tau, g, 1.0, 0.0);
        let ours = contact(l);
        let settings = sssbake_profile::models::stam::StamSettings {
            modes: Some(1),
            ..Default::default()
        };
        let theirs = l.solve(&settings).unwrap();
        for e in 0..ours.cosines.len() {
            assert!((ours.reflectance[e] - theirs.reflectance[e]).abs() < 1e-9);
            assert!((ours.transmittance[e] - theirs.transmittance[e]).abs() < 1e-9);
        }
        let diffuse = |v: &[f64]| -> f64 {
            (0..v.len())
                .map(|e| 2.0 * theirs.weights[e] * theirs.cosines[e] * v[e])
                .sum()
        };
        // Lambertian light from below meets the same symmetric layer.
        assert!((ours.reflectance_from_below - diffuse(&theirs.reflectance)).abs() < 1e-9);
        assert!((ours.transmittance_from_below - diffuse(&theirs.transmittance)).abs() < 1e-9);
    }
}

#[test]
fn extreme_stam_topped_stacks_stay_physical_and_a_lone_top_is_refused() {
    let mut built = 0;
    for albedo in [0.0, 0.5, 1.0] {
        for tau in [1e-9, 1.0, 1e3] {
            for g in [-0.9, 0.9] {
                for (eta, m) in [(1.0, 0.0), (1.4, 0.0), (3.0, 0.0), (1.4, 1.0)] {
                    let thickness = 0.05;
                    let sigma_t = tau / thickness;
                    let material = Material {
                        name: "extreme".into(),
                        optics: Optics::Layers(vec![
                            Layer {
                                sigma_a: [(1.0 - albedo) * sigma_t; 3],
                                sigma_s: [albedo * sigma_t; 3],
                                g,
                                ior: eta,
                                thickness_mm: Some(thickness),
                            },
                            Layer::semi_infinite([0.02, 0.1, 0.5], [1.0; 3], 1.4),
                        ]),
                        coat_ior: None,
                        roughness: m,
                        top_layer: TopLayer::Stam,
                    };
                    let case = format!("Ω {albedo} τ {tau} g {g} η {eta} m {m}");
                    let profile = build_profile(&material, Model::Stam, 6)
                        .unwrap_or_else(|e| panic!("{case}: {e}"));
                    let surface = Surface::of(&material, Model::Stam).unwrap();
                    let total = profile.total_reflectance();
                    let exit = surface.exit_at_normal();
                    for c in 0..3 {
                        assert!((0.0..=1.0).contains(&total[c]), "{case}: R {}", total[c]);
                        assert!(
                            exit[c].is_finite() && exit[c] >= 0.0,
                            "{case}: exit {}",
                            exit[c]
                        );
                    }
                    for cos in [0.0, 1e-6, 0.5, 1.0] {
                        let t = surface.entry(cos);
                        assert!(
                            t.iter().all(|v| (0.0..=1.0 + 1e-9).contains(v)),
                            "{case}: {t:?}"
                        );
                    }
                    for r in [1e-3, 0.1, 10.0] {
                        let v = profile.reflectance(r);
                        assert!(
                            v.iter().all(|x| x.is_finite() && *x >= 0.0),
                            "{case}: {v:?}"
                        );
                    }
                    built += 1;
                }
            }
        }
    }
    assert_eq!(built, 3 * 3 * 2 * 4);
    let lone = Material {
        optics: Optics::Layers(vec![
            preset("stam-skin").unwrap().layers().unwrap()[0].clone(),
        ]),
        ..preset("stam-skin").unwrap()
    };
    let error = build_profile(&lone, Model::Stam, 6)
        .err()
        .unwrap()
        .to_string();
    assert!(error.contains("needs a layer under it"), "{error}");
}
