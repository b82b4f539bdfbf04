//! Donner & Jensen 2005, table 1: the total reflectance and transmittance
//! of slabs 2, 10 and 20 mean free paths thick (ℓ = 1/σt' = 1 mm), by their
//! Monte Carlo, their multipole and the dipole.
//!
//! The paper states neither the albedo nor the boundary. Its dipole column,
//! 90.2% for every slab, is the semi-infinite dipole's total, which in
//! closed form, (α'/2)(1 + e^{−(4/3)A√(3(1−α'))})e^{−√(3(1−α'))}, fixes
//! α' = [`ALBEDO`] for an index-matched boundary (A = 1, the setting of the
//! paper's eq. 11); g = 0, so σt = σt' = 1/mm. Every row uses that albedo.
//!
//! One entry cannot be met: the multipole's transmittance of the 2-mfp
//! slab, 48.1% against 49.8% reflected. There the source sits at
//! mid-depth (ℓ = d/2) between two matched faces, so any diffusion solution
//! reflects and transmits alike; the converged image series gives 49.7%
//! both ways. That row is held to the mean of the paper's two numbers
//! (its R and T each lie within one point of it) and to R = T.
//!
//! The Monte Carlo column's 2-mfp row adds to 101.4% (51.6% + 49.8%), more
//! light than enters; no simulation that conserves energy meets both. Its
//! R is held to the paper's and its T to the 48.4% the paper's R leaves.
//!
//! `SSSBAKE_LONG_TABLES=1` runs the Monte Carlo with 25 times the photons.

mod common;
use common::grey_layer;
use sssbake_profile::models::dipole::dipole_total_reflectance;
use sssbake_profile::models::monte_carlo::{Settings, simulate};
use sssbake_profile::{Layer, Multipole, Profile};

/// The reduced albedo for which the dipole reflects 90.2% under a matched
/// boundary (solved below, and checked against the table's dipole column).
const ALBEDO: f64 = 0.99873;

/// (thickness in mean free paths, Monte Carlo R, T, multipole R, T), in %.
const TABLE_1: [(f64, f64, f64, f64, f64); 3] = [
    (2.0, 51.6, 49.8, 49.8, 48.1),
    (10.0, 83.4, 13.8, 83.8, 13.8),
    (20.0, 89.0, 6.0, 89.0, 5.9),
];

fn slab(thickness_mm: f64) -> Layer {
    grey_layer(1.0 - ALBEDO, ALBEDO, 0.0, 1.0, Some(thickness_mm))
}

#[test]
fn the_albedo_is_the_one_the_dipole_column_states() {
    let dipole = 100.0 * dipole_total_reflectance(ALBEDO, 1.0);
    assert!((dipole - 90.2).abs() < 0.05, "dipole {dipole:.3}%");
}

#[test]
fn the_multipole_reproduces_table_1() {
    for (mfp, _, _, paper_r, paper_t) in TABLE_1 {
        let multipole = Multipole::new(&slab(mfp), 1e-9);
        let r = 100.0 * multipole.total_reflectance()[0];
        let t = 100.0 * multipole.total_transmittance()[0];
        if mfp == 2.0 {
            assert!((r - t).abs() < 1e-9, "{mfp} mfp: symmetric, R {r} T {t}");
            let mean = 0.5 * (paper_r + paper_t);
            assert!((r - mean).abs() <= 1.0, "{mfp} mfp: R {r:.2}% vs {mean}%");
        } else {
            assert!(
                (r - paper_r).abs() <= 1.0,
                "{mfp} mfp: R {r:.2}%, paper {paper_r}%"
            );
            assert!(
                (t - paper_t).abs() <= 1.0,
                "{mfp} mfp: T {t:.2}%, paper {paper_t}%"
            );
        }
    }
}

/// The project's Monte Carlo (specular reflection at entry excluded, as
/// the diffusion models exclude it; light leaving unscattered counted, as
/// a photon tracer counts every photon leaving) within one percentage
/// point of the paper's, plus three standard errors.
#[test]
fn the_monte_carlo_reproduces_table_1() {
    let long = std::env::var_os("SSSBAKE_LONG_TABLES").is_some();
    let photons = if long { 500_000 } else { 20_000 };
    let mut rows = Vec::new();
    for (mfp, paper_r, paper_t, _, _) in TABLE_1 {
        let mc = simulate(&[slab(mfp)], &Settings::new(photons, 11, vec![0.0, 1.0]));
        // The three channels are identical and independent: pool them.
        let pool = |v: [f64; 3]| 100.0 * v.iter().sum::<f64>() / 3.0;
        let error = |e: [f64; 3]| 100.0 * (e.iter().map(|x| x * x).sum::<f64>()).sqrt() / 3.0;
        let r = pool(mc.total_reflectance) + pool(mc.unscattered_reflectance);
        let t = pool(mc.total_transmittance) + pool(mc.unscattered_transmittance);
        let binomial = mc
            .unscattered_transmittance
            .map(|u| (u * (1.0 - u) / photons as f64).sqrt());
        let (r_err, t_err) = (
            error(mc.total_reflectance_stderr),
            error(mc.total_transmittance_stderr).hypot(error(binomial)),
        );
        println!("{mfp} mfp: R {r:.2} ± {r_err:.2}%, T {t:.2} ± {t_err:.2}%");
        rows.push((mfp, paper_r, paper_t, r, t, r_err, t_err));
    }
    for (mfp, paper_r, paper_t, r, t, r_err, t_err) in rows {
        let paper_t = if paper_r + paper_t > 100.0 {
            100.0 - paper_r
        } else {
            paper_t
        };
        assert!(
            (r - paper_r).abs() <= 1.0 + 3.0 * r_err,
            "{mfp} mfp: R {r:.2} ± {r_err:.2}%, paper {paper_r}%"
        );
        assert!(
            (t - paper_t).abs() <= 1.0 + 3.0 * t_err,
            "{mfp} mfp: T {t:.2} ± {t_err:.2}%, paper {paper_t}%"
        );
    }
}

/// van de Hulst's (1980) adding-doubling solution for a slab of optical
/// thickness 2, albedo 0.9 and Henyey–Greenstein g = 0.75 between matched
/// boundaries, as MCML (Wang, Jacques & Zheng 1995, table 3) checks itself
/// against: total diffuse reflectance 0.09739 and total transmittance
/// (unscattered included) 0.66096. The Monte Carlo must agree within three
/// standard errors and a rounding of the published fifth digit.
#[test]
fn the_monte_carlo_matches_van_de_hulsts_slab() {
    let long = std::env::var_os("SSSBAKE_LONG_TABLES").is_some();
    let photons = if long { 2_000_000 } else { 100_000 };
    // σt = 10/mm over 0.2 mm: τ = 2.
    let slab = grey_layer(1.0, 9.0, 0.75, 1.0, Some(0.2));
    let mc = simulate(&[slab], &Settings::new(photons, 5, vec![0.0, 1.0]));
    let pool = |v: [f64; 3]| v.iter().sum::<f64>() / 3.0;
    let error = |e: [f64; 3]| (e.iter().map(|x| x * x).sum::<f64>()).sqrt() / 3.0;
    let r = pool(mc.total_reflectance) + pool(mc.unscattered_reflectance);
    let t = pool(mc.total_transmittance) + pool(mc.unscattered_transmittance);
    // Unscattered light leaves with weight 1 or not at all: a binomial
    // count, whose error adds to the diffuse tally's.
    let binomial = mc
        .unscattered_transmittance
        .map(|u| (u * (1.0 - u) / photons as f64).sqrt());
    let (r_err, t_err) = (
        error(mc.total_reflectance_stderr),
        error(mc.total_transmittance_stderr).hypot(error(binomial)),
    );
    println!("R {r:.5} ± {r_err:.5}, T {t:.5} ± {t_err:.5}");
    assert!(
        (r - 0.09739).abs() <= 3.0 * r_err + 5e-6,
        "R {r:.5} ± {r_err:.5}, van de Hulst 0.09739"
    );
    assert!(
        (t - 0.66096).abs() <= 3.0 * t_err + 5e-6,
        "T {t:.5} ± {t_err:.5}, van de Hulst 0.66096"
    );
}
