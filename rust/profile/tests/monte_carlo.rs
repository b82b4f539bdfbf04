//! The Monte Carlo reference: its own invariants, and the diffusion models
//! measured against it.
//!
//! Diffusion is an approximation: it misses single scattering near the
//! entry point, overshoots between one and two mean free paths under an
//! index-mismatched boundary (by up to about 55% here, as d'Eon 2012 also
//! reports for the classical dipole), and converges to the simulation
//! farther out. The tolerances are those known errors: 60% beyond one mean
//! free path, 25% beyond two and a half, plus three standard errors. Below a
//! reduced albedo of 0.9 diffusion no longer holds (skin1's green and blue
//! are off by up to a factor 2.3 at 1.5 mean free paths); such channels are
//! compared by their totals only.

mod common;
use common::*;
use sssbake_profile::models::monte_carlo::{MonteCarlo, Settings, edges_around, simulate};
use sssbake_profile::presets::preset;
use sssbake_profile::{Dipole, Layer, Layered, Multipole, Profile};

fn run(layers: &[Layer], photons: u64, radii: &[f64]) -> MonteCarlo {
    simulate(layers, &Settings::new(photons, 7, edges_around(radii)))
}

/// Compares a model against the simulation in bins beyond `mean_free_paths`
/// times each channel's mean free path `ell` (mm), where the simulation is
/// precise to 10%. Channels with `ell` = ∞ are skipped.
fn compare_profile(
    model: &dyn Profile,
    mc: &MonteCarlo,
    ell: [f64; 3],
    mean_free_paths: f64,
    tolerance: f64,
    what: &str,
) {
    let mut compared = 0;
    for (i, &r) in mc.radii_mm.iter().enumerate() {
        // The bin average of the model, for a fair comparison with a bin.
        let (e0, e1) = (mc.edges_mm[i], mc.edges_mm[i + 1]);
        let area = std::f64::consts::PI * (e1 * e1 - e0 * e0);
        let enclosed = |x: f64| model.enclosed_reflectance(x);
        for c in (0..3).filter(|&c| e0 >= mean_free_paths * ell[c]) {
            let expected = (enclosed(e1)[c] - enclosed(e0)[c]) / area;
            let (value, error) = (mc.reflectance[i][c], mc.reflectance_stderr[i][c]);
            if value <= 0.0 || error > 0.1 * value {
                continue;
            }
            compared += 1;
            assert!(
                (expected - value).abs() <= tolerance * value + 3.0 * error,
                "{what}: r {r:.3} channel {c}: model {expected:.4e}, Monte Carlo {value:.4e} ± {error:.1e}"
            );
        }
    }
    assert!(
        compared >= 6,
        "{what}: only {compared} bins were precise enough to compare"
    );
}

fn compare_total(model: f64, mc: f64, stderr: f64, tolerance: f64, what: &str) {
    assert!(
        (model - mc).abs() <= tolerance * mc + 3.0 * stderr,
        "{what}: model {model:.4}, Monte Carlo {mc:.4} ± {stderr:.4}"
    );
}

#[test]
fn the_same_seed_gives_the_same_answer_on_any_thread_count() {
    let layers = preset("skin1").unwrap().layers().unwrap().to_vec();
    let settings = Settings::new(10_000, 42, edges_around(&[0.5, 1.0, 2.0]));
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| simulate(&layers, &settings));
    let many = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(|| simulate(&layers, &settings));
    assert_eq!(single.reflectance, many.reflectance);
    assert_eq!(single.total_reflectance, many.total_reflectance);
    let other_seed = simulate(
        &layers,
        &Settings {
            seed: 43,
            ..settings
        },
    );
    assert_ne!(single.total_reflectance, other_seed.total_reflectance);
}

#[test]
fn without_absorption_every_photon_is_accounted_for() {
    let layers = vec![
        grey_layer(0.0, 2.0, 0.7, 1.5, Some(0.4)),
        grey_layer(0.0, 0.5, -0.3, 1.2, Some(1.5)),
    ];
    let mc = run(&layers, 20_000, &[0.1, 1.0]);
    for c in 0..3 {
        let sum = mc.total_reflectance[c]
            + mc.total_transmittance[c]
            + mc.unscattered_reflectance[c]
            + mc.unscattered_transmittance[c]
            + mc.truncated[c];
        assert!((sum - 1.0).abs() < 1e-9, "channel {c}: {sum}");
    }
    let absorbing = run(&[grey_layer(0.5, 2.0, 0.0, 1.4, Some(1.0))], 20_000, &[1.0]);
    assert!(absorbing.total_reflectance[0] + absorbing.total_transmittance[0] < 0.9);
}

#[test]
fn the_dipole_matches_monte_carlo_for_skin1_and_marble() {
    let radii: Vec<f64> = (1..=30).map(|i| 0.25 * i as f64).collect();
    for (name, photons) in [("skin1", 40_000), ("marble", 10_000)] {
        let material = preset(name).unwrap();
        let layers = material.layers().unwrap();
        let dipole = Dipole::new([0, 1, 2].map(|c| layers[0].medium(c)), layers[0].ior);
        let mc = run(layers, photons, &radii);
        let diffusive = |c: usize| layers[0].medium(c).albedo_reduced() >= 0.9;
        for c in 0..3 {
            // The totals are diffusion's error alone: the Monte Carlo's own
            // is under 0.1% (`skin1_totals_match_discrete_ordinates`). It is
            // about 1% where diffusion holds, and grows as the albedo falls
            // (skin1's green 7% and blue 14% too bright).
            let tolerance = if diffusive(c) { 0.02 } else { 0.15 };
            compare_total(
                dipole.total_reflectance()[c],
                mc.total_reflectance[c],
                mc.total_reflectance_stderr[c],
                tolerance,
                &format!("{name} total, channel {c}"),
            );
        }
        let ell = [0, 1, 2].map(|c| {
            if diffusive(c) {
                layers[0].medium(c).mean_free_path()
            } else {
                f64::INFINITY
            }
        });
        compare_profile(&dipole, &mc, ell, 1.0, 0.6, name);
        compare_profile(&dipole, &mc, ell, 2.5, 0.25, name);
    }
}

#[test]
fn the_layered_model_matches_monte_carlo_for_mikkelsen_table_3() {
    let layers = vec![
        grey_layer(0.005, 1.3, 0.0, 1.4, Some(6.0)),
        grey_layer(0.01, 1.0, 0.0, 1.4, None),
    ];
    let model = Layered::new(&layers);
    let radii: Vec<f64> = (1..=30).map(|i| 0.5 * i as f64).collect();
    let mc = run(&layers, 10_000, &radii);
    compare_total(
        model.total_reflectance()[0],
        mc.total_reflectance[0],
        mc.total_reflectance_stderr[0],
        0.04,
        "table 3 total",
    );
    let ell = [1.0 / 1.305; 3];
    compare_profile(&model, &mc, ell, 1.0, 0.6, "table 3");
    compare_profile(&model, &mc, ell, 2.5, 0.25, "table 3");
}

#[test]
fn the_multipole_matches_monte_carlo_for_thin_and_thick_slabs() {
    // Donner & Jensen 2005 table 1: a 1 mm mean free path, 2 to 20 of them
    // thick. The Monte Carlo agrees with van de Hulst's slab to 0.1%
    // (published_tables.rs), so what remains is diffusion's own error:
    // about 3.5% at 2 mfp, where the source sits at mid-depth and diffusion
    // splits R and T evenly while transport favours R, and under 1% from
    // 10 mfp (tolerances: those plus half a point of margin, and three
    // standard errors).
    for (thickness, r_tolerance, t_tolerance) in [
        (2.0, 0.04, 0.04),
        (10.0, 0.015, 0.015),
        (20.0, 0.015, 0.015),
    ] {
        let layer = grey_layer(0.001, 0.999, 0.0, 1.0, Some(thickness));
        let model = Multipole::new(&layer, 1e-8);
        let mc = run(std::slice::from_ref(&layer), 10_000, &[1.0]);
        let what = format!("{thickness} mfp");
        compare_total(
            model.total_reflectance()[0],
            mc.total_reflectance[0],
            mc.total_reflectance_stderr[0],
            r_tolerance,
            &what,
        );
        compare_total(
            model.total_transmittance()[0],
            mc.total_transmittance[0] + mc.unscattered_transmittance[0],
            mc.total_transmittance_stderr[0],
            t_tolerance,
            &what,
        );
    }
}

#[test]
fn the_two_slab_example_matches_monte_carlo() {
    // Mikkelsen's table 3 (Donner & Jensen 2006, fig. 4a): 6 mm of a medium
    // of reduced albedo 0.996 over a semi-infinite one; the paper's multipole
    // and MCML agree on it, and so must ours.
    let layers = preset("two-slab").unwrap().layers().unwrap().to_vec();
    let model = Layered::new(&layers);
    let radii: Vec<f64> = (1..=40).map(|i| 1.0 * i as f64).collect();
    let mc = run(&layers, 40_000, &radii);
    compare_total(
        model.total_reflectance()[0],
        mc.total_reflectance[0],
        mc.total_reflectance_stderr[0],
        0.02,
        "two-slab total",
    );
    let ell = [layers[0].medium(0).mean_free_path(); 3];
    compare_profile(&model, &mc, ell, 2.5, 0.3, "two-slab");
}

#[test]
fn the_three_layer_skin_matches_monte_carlo() {
    // Donner & Jensen 2005's epidermis and upper dermis are thinner than two
    // reduced mean free paths; their unscattered light and faces matter.
    let layers = preset("skin3layer").unwrap().layers().unwrap().to_vec();
    let model = Layered::new(&layers);
    let radii: Vec<f64> = (1..=40).map(|i| 0.2 * i as f64).collect();
    let mc = run(&layers, 40_000, &radii);
    for c in 0..3 {
        compare_total(
            model.total_reflectance()[c],
            mc.total_reflectance[c],
            mc.total_reflectance_stderr[c],
            0.08,
            &format!("three-layer skin total, channel {c}"),
        );
    }
    // Far out only the red light of the bloody dermis (reduced albedo 0.91,
    // ℓ ≈ 1 mm) is left, and it is diffusive.
    let dermis = layers[2].medium(0);
    let ell = [dermis.mean_free_path(), f64::INFINITY, f64::INFINITY];
    compare_profile(&model, &mc, ell, 2.5, 0.3, "three-layer skin, red");
}

/// The Monte Carlo's totals for skin1 (semi-infinite, η = 1.3 under a
/// smooth face) against an independent transport solution of the same
/// medium: Stam's discrete ordinates (checked against van de Hulst's
/// adding-doubling slab in `stam.rs`), at the ordinate nearest the normal,
/// whose refracted cosine the photons enter along. The two methods share
/// no code but the Fresnel formula; they agree to within the photons' own
/// noise, so the Monte Carlo's totals are held to half a percent. What the
/// dipole comparison above allows beyond that (up to 15% in skin1's blue)
/// is diffusion's error, and the dipole misses the discrete ordinates by
/// the same amount.
#[test]
fn skin1_totals_match_discrete_ordinates() {
    use sssbake_profile::boundary::fresnel::dielectric_reflectance;
    use sssbake_profile::models::monte_carlo::simulate_oblique;
    use sssbake_profile::models::stam::StamSettings;
    use sssbake_profile::models::stam::material::layers_for;
    let material = preset("skin1").unwrap();
    let layers = material.layers().unwrap().to_vec();
    let settings = StamSettings {
        ordinates: 64,
        modes: Some(1),
    };
    let ordinates = layers_for(&material)
        .unwrap()
        .map(|layer| layer.solve(&settings).unwrap());
    let e = ordinates[0].cosines.len() - 1;
    let mu = ordinates[0].cosines[e];
    let eta = layers[0].ior;
    let cos_inside = (1.0 - (1.0 - mu * mu) / (eta * eta)).sqrt();
    let mc = simulate_oblique(
        &layers,
        &Settings::new(photons(), 5, vec![0.0, 1e9]),
        cos_inside,
    );
    let entering = 1.0 - dielectric_reflectance(mu, 1.0, eta);
    let dipole = Dipole::new([0, 1, 2].map(|c| layers[0].medium(c)), eta);
    for (c, solved) in ordinates.iter().enumerate() {
        // Per unit of light entering: the discrete ordinates' R without the
        // face's own reflection.
        let transport = (solved.reflectance[e] - solved.surface_reflectance[e]) / entering;
        let (ours, error) = (mc.total_reflectance[c], mc.total_reflectance_stderr[c]);
        println!(
            "channel {c}: Monte Carlo {ours:.5} ± {error:.5}, discrete ordinates {transport:.5}, dipole {:.5}",
            dipole.total_reflectance()[c]
        );
        compare_total(transport, ours, error, 0.005, &format!("skin1 channel {c}"));
        // The dipole's error is the same against either.
        let against_mc = dipole.total_reflectance()[c] - ours;
        let against_do = dipole.total_reflectance()[c] - transport;
        assert!(
            (against_mc - against_do).abs() <= 0.005 * transport + 3.0 * error,
            "channel {c}: dipole off by {against_mc:.5} from the Monte Carlo, {against_do:.5} from the ordinates"
        );
    }
}

/// Photons for the comparison with the discrete ordinates:
/// `SSSBAKE_LONG_MONTE_CARLO=1` takes 40 times CI's.
fn photons() -> u64 {
    if std::env::var_os("SSSBAKE_LONG_MONTE_CARLO").is_some() {
        4_000_000
    } else {
        100_000
    }
}
