//! Every bake's estimate of its distance from light (a volumetric walk at
//! a few hundred random texels) against that distance measured at every
//! texel by many more walks, on three shapes where the profile's model is
//! wrong by different amounts at skin's reach: a block, a thin slab lit
//! from above and a small ball.

mod lit_scenes;

use glam::Vec3;
use lit_scenes::*;
use sssbake::control::Control;
use sssbake::prepared::Prepared;
use sssbake::scattering::Scattering;
use sssbake::transport::brute::BruteIntegrator;
use sssbake::transport::light_check::{EVENT_BUDGET, check_against_light};
use sssbake::transport::walk::walk_surfels;
use sssbake::walk::{StartDirection, WalkMedium, WalkSettings};
use sssbake_profile::model::Model;

/// The relative RMSE of `baked` against walks at every texel of
/// `prepared`, with the walks' own noise taken out, as the check does.
fn measured_distance(prepared: &Prepared, scattering: &Scattering, baked: &[[f32; 3]]) -> f64 {
    let medium = WalkMedium::of_material(&scattering.material).unwrap();
    let settings = WalkSettings {
        walks: 2048,
        max_events: 1024,
        seed: 99,
        start: StartDirection::Pencil,
    };
    let estimate = walk_surfels(prepared, &medium, None, &settings, &Control::new()).unwrap();
    let (mut diff2, mut ref2, mut noise2) = (0.0f64, 0.0f64, 0.0f64);
    for (i, baked) in baked.iter().enumerate() {
        let walked = prepared.after_scattering(i, estimate.exitance[i]);
        let error = prepared.after_scattering(i, estimate.standard_error[i]);
        for c in 0..3 {
            diff2 += f64::from(baked[c] - walked[c]).powi(2);
            ref2 += f64::from(walked[c]).powi(2);
            noise2 += f64::from(error[c]).powi(2);
        }
    }
    ((diff2 - noise2).max(0.0) / ref2).sqrt()
}

#[test]
fn the_estimate_against_light_is_within_one_and_a_half_times_the_measured_distance() {
    let sun = sun_from(Vec3::new(-0.3, 0.2, -1.0));
    let scenes = [
        ("block", stretched(cube(1.0), Vec3::splat(40.0), "block")),
        (
            "slab",
            stretched(cube(1.0), Vec3::new(60.0, 60.0, 3.0), "slab"),
        ),
        (
            "ball",
            stretched(sphere(1.0, 24, 48), Vec3::splat(15.0), "ball"),
        ),
    ];
    let skin = scattering_of("skin1", Model::Dipole);
    let mut distances = Vec::new();
    for (name, mesh) in scenes {
        let scene = scene(vec![mesh], vec![sun.clone()]);
        let prepared = prepared(&scene, name, 40);
        let baked = prepared
            .integrate(
                &skin,
                &BruteIntegrator,
                sssbake::request::DEFAULT_TOLERANCE,
                &Control::new(),
            )
            .unwrap()
            .exitance;
        let check = check_against_light(
            &prepared,
            &skin,
            &baked,
            256,
            EVENT_BUDGET,
            1,
            &Control::new(),
        )
        .unwrap()
        .expect("skin1 is one medium the walk follows");
        let measured = measured_distance(&prepared, &skin, &baked);
        eprintln!(
            "{name}: estimated {:.4} (rmse {:.4}, walk noise {:.4}, {} walks), measured {measured:.4}",
            check.estimated_error, check.relative_rmse, check.walk_noise, check.walks
        );
        assert!(check.estimated_error.is_finite() && check.walk_noise > 0.0);
        let ratio = check.estimated_error / measured;
        assert!(
            (1.0 / 1.5..=1.5).contains(&ratio),
            "{name}: the estimate {:.4} is {ratio:.2}× the measured {measured:.4}",
            check.estimated_error
        );
        distances.push(measured);
    }
    // The shapes differ in how far the planar profile is from light: the
    // check must tell them apart, not report one figure everywhere.
    let (low, high) = distances
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &d| (l.min(d), h.max(d)));
    assert!(high > 1.5 * low, "{distances:?}");
}

#[test]
fn a_check_turned_off_or_on_a_layered_material_says_why() {
    let scene = scene(
        vec![centred_square(40.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let skin = scattering_of("skin1", Model::Dipole);
    let prepared = prepared(&scene, "square", 16);
    let baked = vec![[0.0f32; 3]; prepared.surfels.len()];
    let off = check_against_light(
        &prepared,
        &skin,
        &baked,
        0,
        EVENT_BUDGET,
        1,
        &Control::new(),
    )
    .unwrap();
    assert_eq!(off, Err(sssbake::transport::light_check::NoCheck::Off));
    let layered = scattering_of("skin3layer", Model::Layered);
    let refused = check_against_light(
        &prepared,
        &layered,
        &baked,
        16,
        EVENT_BUDGET,
        1,
        &Control::new(),
    )
    .unwrap();
    assert!(
        matches!(&refused, Err(sssbake::transport::light_check::NoCheck::Material(why)) if !why.is_empty()),
        "{refused:?}"
    );
}
