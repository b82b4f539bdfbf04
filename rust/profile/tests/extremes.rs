//! Every model stays finite, non-negative and energy-conserving on extreme
//! inputs: albedo near 0 and 1, coefficients from 1e-4 to 1e4 /mm, η from 1
//! to 2.5, layers from 1e-5 mm to 1e4 mm thick and semi-infinite, g from
//! −0.9 to 0.99.

mod common;
use common::*;
use sssbake_profile::models::gaussians::fit_gaussians;
use sssbake_profile::{Burley, Dipole, Layer, Layered, Multipole, Profile};
use std::time::{Duration, Instant};

const ALBEDOS: [f64; 3] = [1.0 - 1e-9, 0.5, 1e-6];
const EXTINCTIONS: [f64; 3] = [1e-4, 1.0, 1e4];
const INDICES: [f64; 4] = [1.0, 1.0 + 1e-9, 1.33, 2.5];
const THICKNESSES: [Option<f64>; 4] = [Some(1e-5), Some(1.0), Some(1e4), None];
const ANISOTROPIES: [f64; 3] = [-0.9, 0.0, 0.99];

fn layer(albedo: f64, sigma_t: f64, g: f64, ior: f64, thickness: Option<f64>) -> Layer {
    grey_layer(
        (1.0 - albedo) * sigma_t,
        albedo * sigma_t,
        g,
        ior,
        thickness,
    )
}

fn every_layer() -> Vec<Layer> {
    let mut layers = Vec::new();
    for albedo in ALBEDOS {
        for sigma_t in EXTINCTIONS {
            for ior in INDICES {
                for thickness in THICKNESSES {
                    for g in ANISOTROPIES {
                        layers.push(layer(albedo, sigma_t, g, ior, thickness));
                    }
                }
            }
        }
    }
    layers
}

fn check(profile: &dyn Profile, what: &str) {
    let (r, t) = (profile.total_reflectance(), profile.total_transmittance());
    let (br, bt) = (
        profile.ballistic_reflectance(),
        profile.ballistic_transmittance(),
    );
    for c in 0..3 {
        let parts = [
            ("R", r[c]),
            ("T", t[c]),
            ("ballistic R", br[c]),
            ("ballistic T", bt[c]),
        ];
        for (name, v) in parts {
            assert!(v.is_finite() && v >= 0.0, "{what}: total {name} = {v}");
        }
        let sum: f64 = parts.iter().map(|p| p.1).sum();
        assert!(sum <= 1.0 + 1e-9, "{what}: R + T = {sum}");
    }
    let reach = profile.d_max(1e-3);
    assert!(
        reach.iter().all(|d| d.is_finite() && *d >= 0.0),
        "{what}: d_max {reach:?}"
    );
    let scale = profile.length_scale();
    assert!(
        scale.iter().all(|s| s.is_finite() && *s > 0.0),
        "{what}: length scale {scale:?}"
    );
    let mut radii = vec![0.0];
    radii.extend((-8..=8).map(|e| 10f64.powi(e)));
    radii.extend(scale.iter().flat_map(|s| [0.1 * s, *s, 10.0 * s]));
    for radius in radii {
        assert_physical(profile, radius, what);
        let enclosed = profile.enclosed_reflectance(radius);
        assert!(
            enclosed.iter().all(|e| e.is_finite()),
            "{what}: enclosed({radius}) {enclosed:?}"
        );
        // What a disc holds never exceeds the whole (a table's far tail
        // once carried the transform's round-off as many times the total).
        for c in 0..3 {
            assert!(
                enclosed[c] <= r[c] * (1.0 + 1e-3) + 1e-12,
                "{what}: enclosed({radius}) {} above the total {}",
                enclosed[c],
                r[c]
            );
        }
    }
}

fn timed<T>(slowest: &mut (Duration, String), what: &str, build: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let value = build();
    if start.elapsed() > slowest.0 {
        *slowest = (start.elapsed(), what.to_string());
    }
    value
}

#[test]
fn single_layers_at_the_extremes() {
    let mut slowest = (Duration::ZERO, String::new());
    for layer in every_layer() {
        let what = format!("{layer:?}");
        let media = [0, 1, 2].map(|c| layer.medium(c));
        check(
            &timed(&mut slowest, &what, || Dipole::new(media, layer.ior)),
            &format!("dipole {what}"),
        );
        check(
            &timed(&mut slowest, &what, || Multipole::new(&layer, 1e-6)),
            &format!("multipole {what}"),
        );
        check(
            &timed(&mut slowest, &what, || {
                Layered::new(std::slice::from_ref(&layer))
            }),
            &format!("layered {what}"),
        );
    }
    eprintln!(
        "slowest single-layer profile: {:?} for {}",
        slowest.0, slowest.1
    );
}

#[test]
fn stacks_at_the_extremes() {
    let skin = grey_layer(0.03, 0.8, 0.0, 1.3, None);
    let mut slowest = (Duration::ZERO, String::new());
    for layer in every_layer() {
        let mut stack = vec![layer.clone()];
        if layer.thickness_mm.is_some() {
            stack.push(layer.clone());
            stack.push(skin.clone());
        } else {
            stack.insert(0, grey_layer(0.5, 20.0, 0.5, 1.4, Some(0.05)));
        }
        let what = format!("{stack:?}");
        check(
            &timed(&mut slowest, &what, || Layered::new(&stack)),
            &format!("stack {what}"),
        );
    }
    eprintln!("slowest stack: {:?} for {}", slowest.0, slowest.1);
}

#[test]
fn fits_at_the_extremes() {
    for albedo in ALBEDOS {
        for sigma_t in EXTINCTIONS {
            for thickness in [Some(1e-5), None] {
                let layer = layer(albedo, sigma_t, 0.0, 1.33, thickness);
                let reference = Layered::new(std::slice::from_ref(&layer));
                let what = format!("{layer:?}");
                let fit = fit_gaussians(&reference, 4);
                assert!(
                    fit.error.iter().all(|e| e.is_finite() && *e >= 0.0),
                    "{what}: fit error {:?}",
                    fit.error
                );
                check(&fit.gaussians, &format!("gaussians {what}"));
                check(&Burley::matching(&reference), &format!("burley {what}"));
            }
        }
    }
}

#[test]
fn monte_carlo_at_the_extremes() {
    use sssbake_profile::models::monte_carlo::{Settings, edges_around, simulate};
    for albedo in [1.0 - 1e-9, 1e-6] {
        for sigma_t in [1e-4, 1e4] {
            for (ior, g) in [(1.0, -0.9), (2.5, 0.99)] {
                for thickness in [Some(1e-5), Some(1.0), None] {
                    let layer = layer(albedo, sigma_t, g, ior, thickness);
                    let settings = Settings {
                        max_interactions: 10_000,
                        ..Settings::new(100, 3, edges_around(&[0.01, 1.0]))
                    };
                    let mut stack = vec![layer.clone()];
                    if thickness.is_some() {
                        stack.push(grey_layer(0.1, 1.0, 0.0, 1.4, Some(0.5)));
                    }
                    let mc = simulate(&stack, &settings);
                    for c in 0..3 {
                        let parts = [
                            mc.total_reflectance[c],
                            mc.total_transmittance[c],
                            mc.unscattered_reflectance[c],
                            mc.unscattered_transmittance[c],
                            mc.truncated[c],
                        ];
                        assert!(
                            parts.iter().all(|p| p.is_finite() && *p >= 0.0),
                            "{layer:?}: {parts:?}"
                        );
                        // Roulette is unbiased, not bounded per photon: allow its spread.
                        assert!(
                            parts.iter().sum::<f64>() <= 1.0 + 0.2,
                            "{layer:?}: {parts:?}"
                        );
                        let bins = mc
                            .reflectance
                            .iter()
                            .chain(&mc.transmittance)
                            .chain(&mc.reflectance_stderr);
                        assert!(
                            bins.map(|b| b[c]).all(|v| v.is_finite() && v >= 0.0),
                            "{layer:?}"
                        );
                    }
                }
            }
        }
    }
}
