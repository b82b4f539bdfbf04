//! The multipole and the layer combination: limits, symmetries and trends.

mod common;
use common::*;
use sssbake_profile::diffusion::medium::Medium;
use sssbake_profile::diffusion::slab::{Incidence, SlabChannel};
use sssbake_profile::models::layered::{Stack, tabulate};
use sssbake_profile::{Dipole, Layered, Multipole, Profile};

#[test]
fn a_thick_slab_tends_to_the_dipole() {
    let layer = grey_layer(0.05, 1.5, 0.0, 1.3, Some(1000.0));
    let slab = Multipole::new(&layer, 1e-8);
    let dipole = Dipole::new([0, 1, 2].map(|c| layer.medium(c)), layer.ior);
    assert_rgb_close(
        slab.total_reflectance(),
        dipole.total_reflectance(),
        1e-9,
        "totals",
    );
    for r in [1e-3, 0.1, 1.0, 5.0, 20.0] {
        assert_rgb_close(
            slab.reflectance(r),
            dipole.reflectance(r),
            1e-9,
            &format!("R({r})"),
        );
    }
}

#[test]
fn matched_boundaries_at_two_mean_free_paths_give_equal_r_and_t() {
    let medium = Medium {
        sigma_a: 0.02,
        sigma_s_reduced: 1.0,
    };
    let layer = grey_layer(0.02, 1.0, 0.0, 1.4, Some(2.0 * medium.mean_free_path()));
    let slab = Multipole::new(&layer, 1e-10);
    let table = Layered::new(std::slice::from_ref(&layer));
    assert_rgb_close(
        slab.total_reflectance(),
        slab.total_transmittance(),
        1e-12,
        "totals",
    );
    for r in [1e-3, 0.3, 1.0, 3.0, 10.0] {
        assert_rgb_close(
            slab.reflectance(r),
            slab.transmittance(r),
            1e-7,
            &format!("pole sum at {r}"),
        );
        assert_rgb_close(
            table.reflectance(r),
            table.transmittance(r),
            1e-6,
            &format!("table at {r}"),
        );
    }
}

#[test]
fn reflectance_plus_transmittance_tends_to_one_without_absorption() {
    for thickness in [0.5, 3.0, 50.0] {
        let mut previous = 0.0;
        for sigma_a in [1e-2, 1e-4, 1e-6, 1e-9, 0.0] {
            let layer = grey_layer(sigma_a, 1.0, 0.0, 1.3, Some(thickness));
            let slab = Multipole::new(&layer, 1e-6);
            let sum = slab.total_reflectance()[0]
                + slab.total_transmittance()[0]
                + slab.ballistic_reflectance()[0]
                + slab.ballistic_transmittance()[0];
            assert!(
                sum >= previous - 1e-12 && sum <= 1.0 + 1e-12,
                "{thickness} mm, σa {sigma_a}: {sum}"
            );
            previous = sum;
        }
        assert!(
            (previous - 1.0).abs() < 1e-9,
            "{thickness} mm without absorption: R + T = {previous}"
        );
    }
    let base = grey_layer(0.0, 1.0, 0.0, 1.3, None);
    let dipole = Dipole::new([0, 1, 2].map(|c| base.medium(c)), base.ior);
    assert!((dipole.total_reflectance()[0] - 1.0).abs() < 1e-12);
}

#[test]
fn reflectance_rises_toward_the_dipole_as_the_slab_thickens() {
    // Donner & Jensen 2005 table 1: slabs of 2, 10 and 20 mean free paths.
    let (sigma_a, sigma_s) = (0.01, 0.99);
    let dipole = Dipole::new(
        [Medium {
            sigma_a,
            sigma_s_reduced: sigma_s,
        }; 3],
        1.3,
    )
    .total_reflectance()[0];
    let mut previous = (0.0, 1.0);
    for mean_free_paths in [2.0, 5.0, 10.0, 20.0, 40.0] {
        let slab = Multipole::new(
            &grey_layer(sigma_a, sigma_s, 0.0, 1.3, Some(mean_free_paths)),
            1e-8,
        );
        let (r, t) = (slab.total_reflectance()[0], slab.total_transmittance()[0]);
        assert!(
            r > previous.0 && r < dipole,
            "{mean_free_paths} mfp: R {r}, dipole {dipole}"
        );
        assert!(t < previous.1, "{mean_free_paths} mfp: T {t} should fall");
        previous = (r, t);
    }
    assert!(relative(previous.0, dipole) < 0.02);
}

#[test]
fn real_space_poles_agree_with_the_transformed_closed_form() {
    for (thickness, ior) in [(0.3, 1.4), (2.0, 1.3), (8.0, 1.0)] {
        let layer = grey_layer(0.03, 1.2, 0.3, ior, Some(thickness));
        let poles = Multipole::new(&layer, 1e-10);
        let stack = Stack::new(std::slice::from_ref(&layer));
        let table = tabulate("images", stack.length_scales(), |c, k| {
            stack.channel(c)[0].image_diffuse(k)
        });
        let peak = poles.reflectance(0.0)[0];
        for r in [1e-3, 0.05, 0.2, 0.7, 2.0, 6.0] {
            let (a, b) = (poles.reflectance(r)[0], table.reflectance(r)[0]);
            assert!(
                (a - b).abs() < 1e-4 * peak + 1e-3 * a,
                "slab {thickness}: R({r}) {a} vs {b}"
            );
            let (a, b) = (poles.transmittance(r)[0], table.transmittance(r)[0]);
            assert!(
                (a - b).abs() < 1e-4 * peak + 1e-3 * a,
                "slab {thickness}: T({r}) {a} vs {b}"
            );
        }
    }
}

#[test]
fn the_exact_slab_agrees_with_the_images_where_they_are_valid() {
    // Both solve the same boundary condition; the image series linearises
    // it over the extrapolation distance, which is exact to first order in
    // q·h. A thick, highly scattering slab under matched indices shows it.
    let medium = Medium {
        sigma_a: 0.002,
        sigma_s_reduced: 2.0,
    };
    let slab = SlabChannel::new(medium, 40.0, 1.0, 1.0, Incidence::Collimated);
    for k in [0.0, 0.01, 0.1] {
        let (exact, images) = (slab.frequency_response(k).down, slab.image_diffuse(k));
        assert!(
            relative(exact.reflectance, images.reflectance) < 2e-3,
            "k {k}: {exact:?} {images:?}"
        );
    }
    let dipole = Dipole::new([medium; 3], 1.0).total_reflectance()[0];
    let semi = SlabChannel::new(medium, f64::INFINITY, 1.0, 1.0, Incidence::Collimated);
    assert!(relative(semi.frequency_response(0.0).down.reflectance, dipole) < 2e-3);
}

#[test]
fn thin_mismatched_layers_stay_positive() {
    // A thin layer whose top face reflects far more than its bottom face
    // (|h_top − h_bottom| > d): the image series goes negative here, the
    // exact slab does not.
    let layers = vec![
        grey_layer(0.6, 35.0, 0.8, 1.4, Some(0.1)),
        grey_layer(0.03, 3.7, 0.8, 1.4, None),
    ];
    let medium = layers[0].medium(0);
    let slab = SlabChannel::new(medium, 0.1, 1.4, 1.0, Incidence::Collimated);
    let images = tabulate("images", slab.length_scales(), |_, k| slab.image_diffuse(k));
    let dip = (1..400)
        .map(|i| images.reflectance(0.005 * i as f64)[0])
        .fold(f64::INFINITY, f64::min);
    assert!(
        dip < 0.0,
        "the image series should dip below zero here ({dip})"
    );
    let stack = Layered::new(&layers);
    let exact_slab = Layered::new(&layers[..1]);
    for i in 0..2000 {
        let r = 1e-4 * 1.01f64.powi(i);
        assert_physical(&stack, r, "two-layer stack");
        assert_physical(&exact_slab, r, "thin slab");
    }
}

#[test]
fn the_pole_count_follows_the_requested_accuracy() {
    let layer = grey_layer(0.01, 1.0, 0.0, 1.4, Some(1.0));
    let coarse = Multipole::new(&layer, 1e-2).pole_pairs()[0].unwrap();
    let fine = Multipole::new(&layer, 1e-8).pole_pairs()[0].unwrap();
    assert!(
        fine > coarse,
        "1e-8 needs more pairs ({fine}) than 1e-2 ({coarse})"
    );
    let thick = Multipole::new(&grey_layer(0.01, 1.0, 0.0, 1.4, Some(100.0)), 1e-8).pole_pairs()[0]
        .unwrap();
    assert!(
        thick < fine,
        "a thick slab converges faster ({thick} vs {fine})"
    );
}

#[test]
fn a_non_scattering_base_leaves_the_slab_reflectance_alone() {
    // Over a base that reflects nothing, the stack reflects what the slab
    // alone reflects with the base's index below it, and transmits nothing.
    let slab = grey_layer(0.02, 3.0, 0.0, 1.4, Some(0.8));
    let black_base = grey_layer(5.0, 0.0, 0.0, 1.5, None);
    let stack = Stack::new(&[slab.clone(), black_base]);
    let alone = SlabChannel::new(slab.medium(0), 0.8, 1.4, 1.4 / 1.5, Incidence::Collimated);
    for k in [0.0, 0.5, 3.0, 40.0] {
        let combined = stack.frequency_response(0, k).down;
        let single = alone.frequency_response(k).down;
        assert!(
            relative(combined.reflectance, single.reflectance) < 1e-12,
            "k {k}"
        );
        assert_eq!(combined.transmittance, 0.0);
    }
}

#[test]
fn boundaries_make_the_two_sides_differ() {
    let medium = Medium {
        sigma_a: 0.05,
        sigma_s_reduced: 2.0,
    };
    let slab = SlabChannel::new(medium, 1.0, 1.4, 1.0, Incidence::Collimated);
    let response = slab.frequency_response(0.0);
    assert!(relative(response.down.reflectance, response.up.reflectance) > 1e-3);
    assert!(relative(response.down.transmittance, response.up.transmittance) > 1e-3);
    let symmetric =
        SlabChannel::new(medium, 1.0, 1.4, 1.4, Incidence::Diffuse).frequency_response(0.7);
    assert!(relative(symmetric.down.reflectance, symmetric.up.reflectance) < 1e-14);
}

#[test]
fn thin_slabs_become_transparent_continuously() {
    let medium = Medium {
        sigma_a: 0.1,
        sigma_s_reduced: 10.0,
    };
    let ell = medium.mean_free_path();
    let total = |d: f64| {
        let s = SlabChannel::new(medium, d, 1.3, 1.3, Incidence::Collimated);
        let r = s.image_totals();
        (
            r.reflectance,
            r.transmittance,
            s.ballistic().down.transmittance,
        )
    };
    let (below, above) = (total(2.0 * ell * (1.0 - 1e-9)), total(2.0 * ell));
    assert!(
        relative(below.0, above.0) < 1e-6 && relative(below.1, above.1) < 1e-6,
        "{below:?} {above:?}"
    );
    // A vanishing slab is a pair of faces: the beam passes with the normal
    // incidence Fresnel transmittance, bouncing between them.
    let (r, t, ballistic) = total(1e-7);
    let face = ((1.3f64 - 1.0) / 2.3).powi(2);
    assert!(r < 1e-5 && t < 1e-5, "{r} {t}");
    assert!(
        relative(ballistic, 1.0 / (1.0 + face)) < 1e-5,
        "{ballistic}"
    );
}
