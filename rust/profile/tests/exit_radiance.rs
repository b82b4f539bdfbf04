//! The light leaving towards the normal per unit exitance, the factor the
//! `diffuse` map applies, against the slab Monte Carlo's radiance at
//! normal view.

use sssbake_profile::Layer;
use sssbake_profile::boundary::fresnel::{dielectric_reflectance, diffuse_reflectance_exact};
use sssbake_profile::boundary::rough::hemispherical_transmittance;
use sssbake_profile::boundary::surface::Surface;
use sssbake_profile::models::monte_carlo::{Settings, simulate};

/// A semi-infinite medium of index `eta` whose channels have
/// single-scattering albedos `albedo` (σt = 1/mm), simulated.
fn at_normal_view(eta: f64, albedo: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let layer = Layer {
        sigma_a: albedo.map(|a| 1.0 - a),
        sigma_s: albedo,
        g: 0.0,
        ior: eta,
        thickness_mm: None,
    };
    let mc = simulate(&[layer], &Settings::new(200_000, 11, vec![0.0, 1e9]));
    let ratio = |c: usize| mc.reflectance_at_normal[c] / mc.total_reflectance[c];
    let error = |c: usize| mc.reflectance_at_normal_stderr[c] / mc.total_reflectance[c];
    ([0, 1, 2].map(ratio), [0, 1, 2].map(error))
}

/// Where diffusion holds (albedo near 1) the light under a boundary is
/// nearly isotropic, and a boundary's π L(0)/M = ρdt(0)/ρ̄dt is the
/// simulation's within 1.5% and its noise; 1 − F(0) alone (the exitance
/// taken before its exit term) is 5–9% short at η 1.33–1.5.
#[test]
fn a_boundary_leaves_towards_the_normal_as_light_does() {
    for eta in [1.33, 1.5] {
        let (simulated, noise) = at_normal_view(eta, [0.999, 0.998, 0.995]);
        let exit = Surface::boundary(eta, 0.0).exit_at_normal();
        for c in 0..3 {
            assert!(
                (exit[c] - simulated[c]).abs() < 0.015 * simulated[c] + 3.0 * noise[c],
                "η {eta}, channel {c}: {:.4} against the simulation's {:.4} ± {:.4}",
                exit[c],
                simulated[c],
                noise[c]
            );
        }
        let before_exit = 1.0 - dielectric_reflectance(1.0, eta, 1.0);
        assert!(simulated[0] - before_exit > 0.03, "η {eta}");
    }
}

/// Index-matched, the exit is Lambertian (Cycles shades the walk's exit
/// so); the simulation's surface is 3% brighter at the normal at albedo
/// 0.999 and darker below (limb darkening fades as the light leaving
/// comes from fewer events), which one radiance per texel cannot carry.
#[test]
fn an_index_matched_surface_leaves_lambertian_within_what_one_radiance_can_hold() {
    assert_eq!(Surface::boundary(1.0, 0.0).exit_at_normal(), [1.0; 3]);
    let (simulated, _) = at_normal_view(1.0, [0.999, 0.99, 0.95]);
    for (c, s) in simulated.iter().enumerate() {
        assert!((s - 1.0).abs() < 0.06, "channel {c}: {s:.4}");
    }
}

/// Reciprocity: the hemispherical transmittance from outside is η² times
/// the internal one, so the smooth boundary's factor is also
/// (1 − F(0))/(η²(1 − F_dr(η))), the form the Stam layer's derivation
/// reaches; rough faces let more diffuse light through and stay finite.
#[test]
fn the_exit_factor_is_reciprocal_and_finite_on_extremes() {
    for eta in [1.0001, 1.1, 1.4, 2.0, 3.0] {
        let smooth = Surface::boundary(eta, 0.0).exit_at_normal()[0];
        let f0 = dielectric_reflectance(1.0, eta, 1.0);
        let internal = (1.0 - f0) / (eta * eta * (1.0 - diffuse_reflectance_exact(eta)));
        assert!(
            (smooth - internal).abs() < 1e-3 * internal,
            "η {eta}: {smooth} vs {internal}"
        );
        for roughness in [0.05, 0.3, 1.0] {
            let rough = Surface::boundary(eta, roughness).exit_at_normal()[0];
            assert!(
                rough.is_finite() && rough > 0.5 && rough < 2.0,
                "η {eta} m {roughness}: {rough}"
            );
            let through = hemispherical_transmittance(eta, roughness);
            assert!(through > 0.0 && through <= 1.0);
        }
    }
    for eta in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            Surface::boundary(eta, 0.0).exit_at_normal(),
            [1.0; 3],
            "η {eta}"
        );
    }
}
