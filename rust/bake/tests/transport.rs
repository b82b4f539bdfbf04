//! The four integrators against closed-form and independent answers.

mod lit_scenes;

use glam::Vec3;
use lit_scenes::*;
use sssbake::control::Control;
use sssbake::prepared::Prepared;
use sssbake::transport::integrator::IntegratorSettings;
use sssbake::transport::sources::{OwnSource, Targets};
use sssbake::transport::{Method, brute, octree};
use sssbake_profile::material::{Layer, Material, Optics};
use sssbake_profile::model::Model;
use sssbake_profile::profile::Profile;

/// Mean of exitance over transmitted irradiance on `texels`, per channel.
fn mean_ratio(prepared: &Prepared, exitance: &[[f32; 3]], texels: &[usize]) -> [f64; 3] {
    [0, 1, 2].map(|c| {
        texels
            .iter()
            .map(|&s| exitance[s][c] as f64 / prepared.irradiance[s][c] as f64)
            .sum::<f64>()
            / texels.len() as f64
    })
}

#[test]
fn a_flat_lit_square_returns_the_total_reflectance() {
    let scene = scene(
        vec![centred_square(120.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let skin = scattering_of("skin1", Model::Dipole);
    let (profile, kernel) = (&skin.profile, &skin.kernel);
    let prepared = prepared(&scene, "square", 256);
    let inside = interior(&prepared, 60.0, kernel.d_max);
    assert!(
        inside.len() > 1000,
        "d_max {} leaves {}",
        kernel.d_max,
        inside.len()
    );
    let total = profile.total_reflectance();
    for (method, tolerance) in [
        (Method::Brute, 0.01),
        (Method::Octree, 0.01),
        (Method::Texture, 0.03),
        (Method::Importance, 0.03),
    ] {
        let exitance = exitance(&prepared, &skin, method, &IntegratorSettings::default());
        assert!(
            exitance
                .iter()
                .flatten()
                .all(|v| v.is_finite() && *v >= 0.0)
        );
        let ratio = mean_ratio(&prepared, &exitance, &inside);
        for c in 0..3 {
            let error = (ratio[c] / total[c] - 1.0).abs();
            assert!(
                error < tolerance,
                "{method} channel {c}: M/E = {:.5}, R_total = {:.5}",
                ratio[c],
                total[c]
            );
        }
    }
}

#[test]
fn a_profile_narrower_than_a_texel_still_returns_the_total_reflectance() {
    // The bundled head's skin as Cycles reads it: mean free paths of 0.16,
    // 0.06 and 0.03 mm under texels of 0.47 mm. A texel's own disk then
    // holds nearly all of the light it sends out.
    let scene = scene(
        vec![centred_square(120.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let skin = scattering_for(&head_skin(), Model::Dipole);
    let prepared = prepared(&scene, "square", 256);
    let inside = interior(&prepared, 60.0, skin.kernel.d_max);
    let total = skin.profile.total_reflectance();
    let mut wrong = Vec::new();
    for (method, tolerance) in [
        (Method::Brute, 0.01),
        (Method::Octree, 0.01),
        (Method::Texture, 0.03),
        (Method::Importance, 0.03),
    ] {
        let exitance = exitance(&prepared, &skin, method, &IntegratorSettings::default());
        let ratio = mean_ratio(&prepared, &exitance, &inside);
        for c in 0..3 {
            if (ratio[c] / total[c] - 1.0).abs() > tolerance {
                wrong.push(format!(
                    "{method} channel {c}: M/E = {:.5}, R_total = {:.5}",
                    ratio[c], total[c]
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn texels_of_two_sizes_and_shapes_return_the_total_reflectance() {
    // Two 60 × 120 mm halves of one square, mapped onto 80% and 20% of the
    // image: texels of 0.29 × 0.47 mm and 1.17 × 0.47 mm under the head's
    // skin, whose red light travels about as far as the larger texel.
    let at = |x: f32, y: f32| Vec3::new(x - 60.0, y - 60.0, 0.0);
    let positions = vec![
        at(0.0, 0.0),
        at(60.0, 0.0),
        at(60.0, 120.0),
        at(0.0, 120.0),
        at(120.0, 0.0),
        at(120.0, 120.0),
    ];
    let uvs = [
        (0.0, 0.0),
        (0.8, 0.0),
        (0.8, 1.0),
        (0.0, 1.0),
        (1.0, 0.0),
        (1.0, 1.0),
    ]
    .map(|(u, v)| glam::Vec2::new(u, v))
    .to_vec();
    let triangles = vec![[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]];
    let (square, _) = sssbake::Mesh::new("square", positions, None, Some(uvs), triangles).unwrap();
    let scene = scene(vec![square], vec![sun_from(Vec3::NEG_Z)]);
    let skin = scattering_for(&head_skin(), Model::Dipole);
    let prepared = prepared(&scene, "square", 256);
    let total = skin.profile.total_reflectance();
    let m = exitance(
        &prepared,
        &skin,
        Method::Brute,
        &IntegratorSettings::default(),
    );
    for (lo, hi) in [(-50.0f32, -10.0f32), (10.0, 50.0)] {
        let inside: Vec<usize> = (0..prepared.surfels.position.len())
            .filter(|&i| {
                let q = prepared.surfels.position[i];
                q.x > lo && q.x < hi && q.y.abs() < 40.0
            })
            .collect();
        let ratio = mean_ratio(&prepared, &m, &inside);
        for c in 0..3 {
            assert!(
                (ratio[c] / total[c] - 1.0).abs() < 0.01,
                "x in ({lo}, {hi}) mm, channel {c}: M/E = {:.5}, R_total = {:.5}",
                ratio[c],
                total[c]
            );
        }
    }
}

/// The bundled head's skin as Cycles reads it at Subsurface Scale 2 mm:
/// mean free paths of 0.16, 0.06 and 0.03 mm.
fn head_skin() -> Material {
    principled_skin(2.0)
}

/// ∫ over the half-plane x' > 0 of R(|p − x'|) for a point at signed
/// distance `s` from the edge (positive on the lit side): rings of radius
/// r contribute the share of their circumference in the lit half.
fn half_plane(profile: &dyn Profile, s: f64, channel: usize, reach: f64) -> f64 {
    let steps = 20000;
    let h = reach / steps as f64;
    (0..steps)
        .map(|i| {
            let r = (i as f64 + 0.5) * h;
            let inside = if r <= s.abs() {
                if s > 0.0 { std::f64::consts::TAU } else { 0.0 }
            } else {
                let half = (s.abs() / r).acos();
                if s > 0.0 {
                    std::f64::consts::TAU - 2.0 * half
                } else {
                    2.0 * half
                }
            };
            profile.reflectance(r)[channel] * r * inside * h
        })
        .sum()
}

/// A square 120 mm wide whose half x < 0 a blocker 10 mm above shadows
/// from a sun overhead, lit at `resolution`².
fn half_shadowed_square(resolution: u32) -> Prepared {
    shadowed_square(120.0, 10.0, resolution)
}

/// A square `width` mm wide whose half x < 0 a blocker `height` mm above
/// shadows from a sun overhead, lit at `resolution`².
fn shadowed_square(width: f32, height: f32, resolution: u32) -> Prepared {
    let mut blocker = centred_square(2.0 * width, "blocker");
    for p in &mut blocker.positions {
        p.x = p.x.min(0.0);
        p.z = height;
    }
    let scene = scene(
        vec![centred_square(width, "square"), blocker],
        vec![sun_from(Vec3::NEG_Z)],
    );
    prepared(&scene, "square", resolution)
}

/// Asserts that each method's exitance across the shadow edge of
/// `prepared` (columns of a band averaged to tame noise) is the lit
/// irradiance times the half-plane integral of `scattering`'s own profile,
/// within `tolerance` of the lit level.
fn assert_follows_the_half_plane(
    prepared: &Prepared,
    scattering: &sssbake::scattering::Scattering,
    methods: &[(Method, f64)],
) {
    let (profile, kernel) = (&scattering.profile, &scattering.kernel);
    let lit = prepared.irradiance.iter().map(|e| e[1]).fold(0.0, f32::max) as f64;
    let band: Vec<usize> = (0..prepared.surfels.len())
        .filter(|&s| {
            let p = prepared.surfels.position[s];
            p.x.abs() < 6.0 && p.y.abs() < 5.0
        })
        .collect();
    let total = profile.total_reflectance();
    for &(method, tolerance) in methods {
        // Enough probes that Monte Carlo noise sits well inside the bound.
        let exitance = exitance(prepared, scattering, method, &with(256, 6, 1));
        let mut columns: std::collections::BTreeMap<i32, (f64, [f64; 3], usize)> =
            Default::default();
        for &s in &band {
            let x = prepared.surfels.position[s].x;
            let entry = columns.entry((x * 100.0).round() as i32).or_default();
            entry.0 = x as f64;
            for (sum, &m) in entry.1.iter_mut().zip(&exitance[s]) {
                *sum += m as f64;
            }
            entry.2 += 1;
        }
        for (x, sum, count) in columns.values() {
            for c in 0..3 {
                let expected = lit * half_plane(profile.as_ref(), *x, c, kernel.d_max as f64);
                let got = sum[c] / *count as f64;
                assert!(
                    (got - expected).abs() < tolerance * lit * total[c],
                    "{method} channel {c} at x = {x:.2} mm: {got:.5} vs {expected:.5}"
                );
            }
        }
    }
}

#[test]
fn a_shadow_edge_blurs_as_the_half_plane_integral_of_the_profile() {
    let skin = scattering_of("skin1", Model::Dipole);
    assert_follows_the_half_plane(
        &half_shadowed_square(256),
        &skin,
        &[
            (Method::Brute, 0.01),
            // Turk points carry the irradiance of their centres, so the edge is
            // resolved only to their spacing.
            (Method::Octree, 0.03),
            (Method::Texture, 0.03),
            (Method::Importance, 0.04),
        ],
    );
}

/// A stack under a Stam epidermis (the `stam-skin` preset) is a radial
/// profile like any other: the shadow edge follows its half-plane integral.
#[test]
fn a_stam_topped_skin_blurs_a_shadow_edge_as_its_half_plane_integral() {
    let skin = scattering_of("stam-skin", Model::Stam);
    assert_follows_the_half_plane(
        &half_shadowed_square(256),
        &skin,
        &[(Method::Brute, 0.01), (Method::Octree, 0.03)],
    );
}

/// The Monte Carlo bakes: its tallies, smoothed, are a profile like any
/// other, simulated once and read back from the cache the second time.
#[test]
fn the_monte_carlo_profile_bakes_and_is_simulated_once() {
    use sssbake::monte_carlo_cache::{cache_file, monte_carlo_profile};
    use sssbake_profile::models::monte_carlo::profile::ProfileSettings;
    let dir = std::env::temp_dir().join(format!("sssbake-mc-cache-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let material = sssbake::materials::preset("skin1").unwrap();
    let settings = ProfileSettings {
        photons: 20_000,
        seed: 3,
    };
    let simulated = monte_carlo_profile(&material, &settings, Some(&dir)).unwrap();
    let file = cache_file(&material, &settings, &dir).unwrap();
    assert!(file.exists(), "{} was not written", file.display());
    let cached = monte_carlo_profile(&material, &settings, Some(&dir)).unwrap();
    assert_eq!(simulated.tallies(), cached.tallies());
    // Another seed is another simulation, in another file.
    let other = ProfileSettings {
        seed: 4,
        ..settings.clone()
    };
    assert_ne!(cache_file(&material, &other, &dir).unwrap(), file);
    // The fit smooths the tallies without moving their total.
    let fit = simulated.fit_error();
    let mc = simulated.tallies();
    let fitted = simulated.total_reflectance();
    for (c, ((total, tallied), error)) in fitted
        .iter()
        .zip(mc.total_reflectance)
        .zip(fit[0])
        .enumerate()
    {
        assert!(
            (total - tallied).abs() < 0.01 * tallied,
            "channel {c}: fitted total {total}, simulated {tallied}"
        );
        assert!(error < 0.2, "channel {c}: fit error {error}");
    }
    let scattering = sssbake::scattering::Scattering::from_profile(
        material,
        Model::MonteCarlo,
        Box::new(cached),
        sssbake::scattering::D_MAX_EPSILON,
    );
    assert_follows_the_half_plane(
        &half_shadowed_square(128),
        &scattering,
        &[(Method::Brute, 0.015)],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The empirical model bakes: its slices, fitted once per channel and read
/// back from the cache, give a profile the half-shadowed square follows.
#[test]
fn the_empirical_profile_bakes_and_is_fitted_once() {
    use sssbake::empirical_cache::{cache_file, empirical_profile};
    use sssbake_profile::models::empirical::EmpiricalSettings;
    let dir = std::env::temp_dir().join(format!("sssbake-empirical-cache-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let material = sssbake::materials::preset("skin1").unwrap();
    let settings = EmpiricalSettings {
        photons: 20_000,
        seed: 3,
        ..EmpiricalSettings::default()
    };
    let fitted = empirical_profile(&material, &settings, Some(&dir)).unwrap();
    for c in 0..3 {
        let file = cache_file(&material, &settings, c, &dir).unwrap();
        assert!(file.exists(), "{} was not written", file.display());
    }
    let cached = empirical_profile(&material, &settings, Some(&dir)).unwrap();
    assert_eq!(fitted.slices(), cached.slices());
    let scattering = sssbake::scattering::Scattering::from_profile(
        material,
        Model::Empirical,
        Box::new(cached),
        sssbake::scattering::D_MAX_EPSILON,
    );
    assert_follows_the_half_plane(
        &half_shadowed_square(128),
        &scattering,
        &[(Method::Brute, 0.015)],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_octree_converges_to_the_exact_sum_as_epsilon_shrinks() {
    let scene = scene(
        vec![sphere(20.0, 48, 96)],
        vec![sun_from(Vec3::new(-1.0, -0.3, -0.2))],
    );
    let skin = scattering_of("skin1", Model::Dipole);
    let kernel = &skin.kernel;
    let prepared = prepared(&scene, "sphere", 128);
    let sources = prepared.texel_sources();
    let targets = Targets {
        own: OwnSource::Same,
        ..prepared.targets()
    };
    let exact = brute::integrate(kernel, &sources, targets, &Control::new()).unwrap();
    let scale: f64 = exact.iter().map(|m| m[0] as f64).sum::<f64>() / exact.len() as f64;
    let mut previous = f64::INFINITY;
    for epsilon in [2.0f32, 0.5, 0.2, 0.05, 0.0] {
        let tree = octree::integrate(kernel, &sources, targets, epsilon, &Control::new()).unwrap();
        let squares: f64 = tree
            .iter()
            .zip(&exact)
            .flat_map(|(a, b)| (0..3).map(move |c| (a[c] as f64 - b[c] as f64).powi(2)))
            .sum();
        let rmse = (squares / (3 * exact.len()) as f64).sqrt() / scale;
        assert!(
            rmse <= previous * 1.05 + 1e-7,
            "ε = {epsilon}: {rmse} after {previous}"
        );
        previous = rmse;
        if epsilon == 0.0 {
            assert!(rmse < 1e-5, "at ε = 0 the octree is the exact sum: {rmse}");
        } else if epsilon == 2.0 {
            assert!(rmse > 1e-4, "a coarse ε must differ measurably: {rmse}");
        }
    }
}

#[test]
fn the_importance_estimator_is_unbiased() {
    let scene = scene(
        vec![centred_square(120.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let skin = scattering_of("skin1", Model::Dipole);
    let kernel = &skin.kernel;
    let prepared = prepared(&scene, "square", 64);
    let centre: Vec<usize> = interior(&prepared, 60.0, 54.0);
    assert!(!centre.is_empty());
    let expected = kernel.enclosed(kernel.d_max);
    let seeds = 48;
    let per_seed: Vec<[f64; 3]> = (0..seeds)
        .map(|seed| {
            let m = exitance(&prepared, &skin, Method::Importance, &with(4, 6, seed));
            mean_ratio(&prepared, &m, &centre)
        })
        .collect();
    for c in 0..3 {
        let mean = per_seed.iter().map(|v| v[c]).sum::<f64>() / seeds as f64;
        let var = per_seed.iter().map(|v| (v[c] - mean).powi(2)).sum::<f64>() / (seeds - 1) as f64;
        let standard_error = (var / seeds as f64).sqrt();
        let truth = expected[c] as f64;
        assert!(standard_error > 0.0 && standard_error < 0.02 * truth);
        assert!(
            (mean - truth).abs() < 3.0 * standard_error,
            "channel {c}: {mean:.5} ± {standard_error:.5} vs {truth:.5}"
        );
    }
}

fn grey(albedo: f64, sigma_t: f64, ior: f64, thickness_mm: Option<f64>) -> Material {
    Material {
        name: format!("albedo {albedo}, σt {sigma_t}, η {ior}, {thickness_mm:?} mm"),
        optics: Optics::Layers(vec![Layer {
            sigma_a: [(1.0 - albedo) * sigma_t; 3],
            sigma_s: [albedo * sigma_t; 3],
            g: 0.0,
            ior,
            thickness_mm,
        }]),
        coat_ior: None,
        top_layer: sssbake_profile::material::TopLayer::Diffusion,
        roughness: 0.0,
    }
}

/// How much more than the light that enters each method may send out: the
/// exact sum only the table's interpolation of the enclosed reflectance
/// (0.2%, where a profile sharper than a texel puts all of a texel's light
/// in its own weight); the others carry their own
/// discretisation or Monte Carlo error, which only shows where the profile
/// returns nearly all light (R_total → 1).
fn energy_allowance(method: Method) -> f64 {
    match method {
        Method::Brute | Method::Auto => 0.002,
        Method::Octree => 0.01,
        Method::Texture | Method::Importance | Method::Walk => 0.03,
    }
}

#[test]
fn no_integrator_creates_energy() {
    let scene = scene(
        vec![sphere(10.0, 24, 48)],
        vec![sun_from(Vec3::new(0.3, -1.0, -0.5))],
    );
    let prepared = prepared(&scene, "sphere", 64);
    let incoming: f64 = prepared
        .irradiance
        .iter()
        .zip(&prepared.surfels.area)
        .map(|(e, &a)| e[1] as f64 * a as f64)
        .sum();
    let mut materials: Vec<Material> = ["skin1", "marble", "ketchup", "skin3layer"]
        .iter()
        .map(|name| sssbake_profile::presets::preset(name).unwrap())
        .collect();
    for albedo in [1.0 - 1e-9, 1e-6] {
        for sigma_t in [1e-2, 1e3] {
            for ior in [1.0 + 1e-9, 1.33] {
                for thickness in [None, Some(1.0)] {
                    materials.push(grey(albedo, sigma_t, ior, thickness));
                }
            }
        }
    }
    for material in &materials {
        let scattering = scattering_for(material, Model::default_for(material));
        for method in Method::ALL {
            let m = exitance(&prepared, &scattering, method, &with(16, 3, 1));
            assert!(
                m.iter().flatten().all(|v| v.is_finite() && *v >= 0.0),
                "{method}, {}",
                material.name
            );
            let outgoing: f64 = m
                .iter()
                .zip(&prepared.surfels.area)
                .map(|(m, &a)| m[1] as f64 * a as f64)
                .sum();
            assert!(
                outgoing <= incoming * (1.0 + energy_allowance(method)),
                "{method}, {}: {outgoing} out of {incoming}",
                material.name
            );
        }
    }
}

/// Importance sampling at its default settings, texel by texel (no
/// averaging), follows the half-plane integral across a shadow edge: RMS
/// within 1% and every texel within 5% of the lit level, on a 60 mm skin1
/// square a blocker 5 mm above half shadows. Its probes are stratified per
/// axis and strategy; drawn independently (as before) the same 64 probes
/// per texel left 5% RMS and 27%.
#[test]
fn importance_at_its_defaults_follows_a_shadow_edge_texel_by_texel() {
    let skin = scattering_of("skin1", Model::Dipole);
    let (width, resolution) = (60.0, 256);
    let prepared = shadowed_square(width, 5.0, resolution);
    let (profile, kernel) = (&skin.profile, &skin.kernel);
    let lit = prepared.irradiance.iter().map(|e| e[1]).fold(0.0, f32::max) as f64;
    let total = profile.total_reflectance();
    // Texels whose whole reach lies on the square see the half-plane.
    let inside = width / 2.0 - kernel.d_max;
    let texels = interior(&prepared, width / 2.0, kernel.d_max);
    assert!(inside > 5.0 && texels.len() > 3000, "{}", texels.len());
    let exitance = exitance(
        &prepared,
        &skin,
        Method::Importance,
        &IntegratorSettings::default(),
    );
    for c in 0..3 {
        let errors: Vec<f64> = texels
            .iter()
            .map(|&s| {
                let x = prepared.surfels.position[s].x as f64;
                let expected = lit * half_plane(profile.as_ref(), x, c, kernel.d_max as f64);
                (exitance[s][c] as f64 - expected) / (lit * total[c])
            })
            .collect();
        let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
        let max = errors.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        println!("channel {c}: RMS {rms:.4}, max {max:.4}");
        assert!(
            rms < 0.01 && max < 0.05,
            "channel {c}: RMS {rms:.4}, max {max:.4}"
        );
    }
}
