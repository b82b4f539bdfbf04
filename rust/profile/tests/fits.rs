//! Gaussian fits, Burley profiles and albedo inversion.

mod common;
use common::*;
use sssbake_profile::appearance::inversion::{InversionError, InversionModel, invert_albedo};
use sssbake_profile::boundary::fresnel::boundary_a;
use sssbake_profile::models::burley::{ScalingFit, scaling_factor};
use sssbake_profile::models::dipole::dipole_total_reflectance;
use sssbake_profile::models::gaussians::fit_gaussians;
use sssbake_profile::presets::preset;
use sssbake_profile::{
    Burley, Dipole, Layered, Model, Multipole, Profile, SumOfGaussians, build_profile,
};

#[test]
fn deon_skin_is_normalised_and_ordered() {
    let skin = SumOfGaussians::deon_skin();
    assert_rgb_close(
        skin.total_reflectance(),
        [1.0; 3],
        1e-12,
        "weights sum to one",
    );
    let reach = skin.d_max(1e-3);
    assert!(
        reach[0] > reach[1] && reach[1] > reach[2],
        "red reaches farthest: {reach:?}"
    );
}

#[test]
fn more_gaussians_fit_better_and_keep_the_energy() {
    let skin1 = preset("skin1").unwrap();
    let dipole = build_profile(&skin1, Model::Dipole, 6).unwrap();
    let mut previous = [f64::INFINITY; 3];
    for count in [1, 2, 4, 6] {
        let fit = fit_gaussians(dipole.as_ref(), count);
        for c in 0..3 {
            assert!(
                fit.error[c] <= previous[c] * 1.0001,
                "{count} Gaussians: error {:?} after {previous:?}",
                fit.error
            );
        }
        assert_rgb_close(
            fit.gaussians.total_reflectance(),
            dipole.total_reflectance(),
            0.01,
            "fit total",
        );
        previous = fit.error;
    }
    assert!(
        previous.iter().all(|e| *e < 0.05),
        "six Gaussians fit the dipole to 5%: {previous:?}"
    );
    // The reported error is the r-weighted RMS, recomputed here independently.
    let fit = fit_gaussians(dipole.as_ref(), 3);
    let reach = dipole.d_max(1e-5)[0];
    let weighted = |f: &dyn Fn(f64) -> f64| radial_integral(f, reach * 1e-5, reach, 20_000);
    let residual =
        weighted(&|r| (dipole.reflectance(r)[0] - fit.gaussians.reflectance(r)[0]).powi(2));
    let norm = weighted(&|r| dipole.reflectance(r)[0].powi(2));
    assert!(
        relative((residual / norm).sqrt(), fit.error[0]) < 0.05,
        "{} vs {}",
        (residual / norm).sqrt(),
        fit.error[0]
    );
}

#[test]
fn burley_follows_cycles_conventions() {
    let colour = [0.8, 0.4, 0.25];
    let radius = [1.0, 0.5, 0.25];
    let burley = Burley::from_cycles(colour, radius);
    assert_rgb_close(
        burley.total_reflectance(),
        colour,
        1e-12,
        "albedo is the total",
    );
    for c in 0..3 {
        let expected_d = radius[c]
            / (4.0 * std::f64::consts::PI)
            / scaling_factor(ScalingFit::DiffuseDiffuseMfp, colour[c]);
        assert!(relative(burley.d[c], expected_d) < 1e-12);
    }
    assert!((scaling_factor(ScalingFit::SearchlightDiffuseMfp, 0.8) - 1.05).abs() < 1e-12);
    assert!((scaling_factor(ScalingFit::SearchlightMfp, 0.33) - 3.5).abs() < 1e-12);
    // Matching a profile keeps its total and its mean radius.
    let reference = Layered::new(preset("skin3layer").unwrap().layers().unwrap());
    let matched = Burley::matching(&reference);
    assert_rgb_close(
        matched.total_reflectance(),
        reference.total_reflectance(),
        1e-12,
        "matched total",
    );
    let mean_radius = |p: &dyn Profile, c: usize| {
        let reach = reference.d_max(1e-8)[c];
        radial_integral(|r| r * p.reflectance(r)[c], reach * 1e-8, reach, 40_000)
            / p.total_reflectance()[c]
    };
    for c in 0..3 {
        assert!(
            relative(mean_radius(&matched, c), mean_radius(&reference, c)) < 0.02,
            "channel {c}"
        );
    }
}

#[test]
fn inverted_albedos_reproduce_the_colour() {
    let colour = [0.63, 0.44, 0.34];
    let mfp = [1.2, 0.6, 0.3];
    let layer = invert_albedo(colour, mfp, 1.3, InversionModel::Dipole).unwrap();
    let dipole = Dipole::new([0, 1, 2].map(|c| layer.medium(c)), layer.ior);
    assert_rgb_close(dipole.total_reflectance(), colour, 1e-9, "dipole total");
    for (c, wanted) in mfp.iter().enumerate() {
        assert!(relative(layer.medium(c).mean_free_path(), *wanted) < 1e-12);
    }
    let slab = invert_albedo(
        colour,
        mfp,
        1.4,
        InversionModel::Slab { thickness_mm: 10.0 },
    )
    .unwrap();
    assert_rgb_close(
        Multipole::new(&slab, 1e-8).total_reflectance(),
        colour,
        1e-9,
        "slab total",
    );
    // The extremes of the colour range invert to the extremes of albedo.
    let white = invert_albedo([1.0, 0.0, 1e-9], [1.0; 3], 1.3, InversionModel::Dipole).unwrap();
    assert!(white.sigma_a[0] < 1e-12 && white.sigma_s[1] < 1e-12);
    assert!(
        (dipole_total_reflectance(white.medium(2).albedo_reduced(), boundary_a(1.3)) - 1e-9).abs()
            < 1e-15
    );
}

#[test]
fn impossible_colours_are_refused() {
    let err = invert_albedo([1.2, 0.5, 0.5], [1.0; 3], 1.3, InversionModel::Dipole).unwrap_err();
    assert_eq!(
        err,
        InversionError::Colour {
            channel: 0,
            value: 1.2
        }
    );
    let err = invert_albedo([0.5; 3], [1.0, 0.0, 1.0], 1.3, InversionModel::Dipole).unwrap_err();
    assert!(matches!(
        err,
        InversionError::MeanFreePath { channel: 1, .. }
    ));
    // A thin slab over air cannot look white.
    let err = invert_albedo(
        [0.99; 3],
        [1.0; 3],
        1.3,
        InversionModel::Slab { thickness_mm: 0.5 },
    )
    .unwrap_err();
    assert!(
        matches!(err, InversionError::Unreachable { channel: 0, .. }),
        "{err}"
    );
}
