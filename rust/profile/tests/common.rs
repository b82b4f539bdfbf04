//! Helpers shared by the integration tests.
#![allow(dead_code)]

use sssbake_profile::models::stam::StamLayer;
use sssbake_profile::{Layer, Profile, Rgb};
use std::f64::consts::PI;

/// ∫ 2πr f(r) dr by the trapezoid rule in ln r over [lo, hi] with `n` steps,
/// plus the disk below `lo` at f(lo).
pub fn radial_integral(f: impl Fn(f64) -> f64, lo: f64, hi: f64, n: usize) -> f64 {
    let h = (hi / lo).ln() / n as f64;
    let mut sum = PI * lo * lo * f(lo);
    for i in 0..=n {
        let r = lo * (i as f64 * h).exp();
        let w = if i == 0 || i == n { 0.5 } else { 1.0 };
        sum += w * h * 2.0 * PI * r * r * f(r);
    }
    sum
}

/// A single layer with the same coefficients in every channel.
pub fn grey_layer(
    sigma_a: f64,
    sigma_s: f64,
    g: f64,
    ior: f64,
    thickness_mm: Option<f64>,
) -> Layer {
    Layer {
        sigma_a: [sigma_a; 3],
        sigma_s: [sigma_s; 3],
        g,
        ior,
        thickness_mm,
    }
}

/// Relative difference |a − b| / |b|.
pub fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// Asserts every channel of `a` is within `tolerance` (relative) of `b`.
pub fn assert_rgb_close(a: Rgb, b: Rgb, tolerance: f64, what: &str) {
    for c in 0..3 {
        assert!(
            relative(a[c], b[c]) <= tolerance,
            "{what}, channel {c}: {} vs {} (tolerance {tolerance})",
            a[c],
            b[c]
        );
    }
}

/// Checks the invariants every profile must keep at radius `r`.
pub fn assert_physical(profile: &dyn Profile, r: f64, what: &str) {
    let (rr, tt) = (profile.reflectance(r), profile.transmittance(r));
    for c in 0..3 {
        assert!(
            rr[c].is_finite() && rr[c] >= 0.0,
            "{what}: R({r})[{c}] = {}",
            rr[c]
        );
        assert!(
            tt[c].is_finite() && tt[c] >= 0.0,
            "{what}: T({r})[{c}] = {}",
            tt[c]
        );
    }
}

/// The Stam layer `l` as the Monte Carlo's slab (σt = 1/mm, so its
/// thickness in mm is τ) in three channels of single-scattering albedos
/// `albedos`.
pub fn stam_slab(l: StamLayer, albedos: [f64; 3]) -> Layer {
    Layer {
        sigma_a: albedos.map(|a| 1.0 - a),
        sigma_s: albedos,
        g: l.g,
        ior: l.eta,
        thickness_mm: Some(l.optical_depth),
    }
}
