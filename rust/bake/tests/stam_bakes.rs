//! A material whose top layer is declared stam, baked: light enters through
//! the epidermis's T(θi) per channel, the `diffuse` map leaves through its
//! exit at the normal, the power leaving never exceeds the power entering,
//! and a vanishing smooth epidermis is the Fresnel boundary a bake without
//! one applies.

mod lit_scenes;

use glam::{Vec2, Vec3};
use lit_scenes::*;
use sssbake::image::Image;
use sssbake::materials::MaterialAssignment;
use sssbake::transport::Method;
use sssbake::{BakeRequest, BakedObject, Output, bake, plan};
use sssbake_profile::boundary::fresnel::{dielectric_reflectance, diffuse_reflectance_exact};
use sssbake_profile::boundary::surface::Surface;
use sssbake_profile::material::{Layer, Material, Optics, TopLayer};
use sssbake_profile::presets::preset;

/// Bakes a 60 mm square lit by a sun at incidence cosine `cos` with
/// `material`, by the exact sum, at 48².
fn bake_square(material: &Material, cos: f32) -> BakedObject {
    let sin = (1.0 - cos * cos).sqrt();
    let scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::new(sin, 0.0, -cos))],
    );
    let request = BakeRequest {
        materials: MaterialAssignment::everywhere(material.clone(), "test"),
        outputs: vec![Output::Irradiance, Output::Subsurface, Output::Diffuse],
        method: Method::Brute,
        ..request(48)
    };
    let plan = plan(&scene, &request).unwrap();
    let (mut objects, _) = bake(&scene, &plan, &sssbake::control::Control::new()).unwrap();
    objects.remove(0)
}

fn centre(image: &Image) -> [f64; 3] {
    image.sample(Vec2::new(0.5, 0.5)).map(f64::from)
}

#[test]
fn light_enters_through_the_epidermis_per_channel_and_leaves_through_it() {
    let skin = preset("stam-skin").unwrap();
    let cos = 0.6;
    let object = bake_square(&skin, cos);
    assert_eq!(object.plan.material.model, "stam");
    let surface = &object.plan.scattering_profile.surface;
    let Surface::Stam(epidermis) = surface else {
        panic!("{surface:?}")
    };
    let entered = centre(&object.render(Output::Irradiance).unwrap());
    let expected = epidermis.transmittance(cos as f64);
    for c in 0..3 {
        let got = entered[c] / cos as f64;
        assert!(
            (got / expected[c] - 1.0).abs() < 1e-3,
            "channel {c}: E_t/E {got} vs T(θi) {}",
            expected[c]
        );
    }
    // The channels differ (the epidermis absorbs blue most), so the entry
    // really is per channel.
    assert!(expected[2] < expected[0] - 0.01, "{expected:?}");
    let subsurface = centre(&object.render(Output::Subsurface).unwrap());
    let diffuse = centre(&object.render(Output::Diffuse).unwrap());
    let exit = epidermis.exit_at_normal();
    for c in 0..3 {
        let got = diffuse[c] / subsurface[c] * std::f64::consts::PI;
        assert!(
            (got / exit[c] - 1.0).abs() < 1e-4,
            "channel {c}: exit {got} vs {}",
            exit[c]
        );
    }
}

#[test]
fn a_stam_topped_bake_sends_out_no_more_power_than_enters() {
    for roughness in [0.0, 0.4, 1.0] {
        let skin = Material {
            roughness,
            ..preset("stam-skin").unwrap()
        };
        let object = bake_square(&skin, 0.8);
        let area = &object.prepared.surfels.area;
        for c in 0..3 {
            let power = |values: &[[f32; 3]]| -> f64 {
                values
                    .iter()
                    .zip(area)
                    .map(|(v, &a)| v[c] as f64 * a as f64)
                    .sum()
            };
            let (out, entering) = (power(&object.exitance), power(&object.prepared.irradiance));
            assert!(
                out > 0.0 && out <= entering,
                "m {roughness} channel {c}: {out} > {entering}"
            );
        }
    }
}

/// An epidermis 10⁻⁹ mm thick with smooth faces over a dermis of its own
/// index: light enters as through the smooth boundary (1 − F(θ)), the same
/// irradiance map as the same stack without a stam top; and what leaves at
/// the normal per unit exitance is (1 − F(0))/(η²(1 − F_dr)) under both,
/// one exit for every model.
#[test]
fn a_vanishing_smooth_epidermis_enters_as_the_fresnel_boundary() {
    let eta = 1.4;
    let stam = Material {
        name: "vanishing epidermis".into(),
        optics: Optics::Layers(vec![
            Layer {
                sigma_a: [0.5, 1.0, 2.0],
                sigma_s: [1.0; 3],
                g: 0.3,
                ior: eta,
                thickness_mm: Some(1e-9),
            },
            Layer::semi_infinite([0.01, 0.05, 0.2], [1.0; 3], eta),
        ]),
        coat_ior: None,
        roughness: 0.0,
        top_layer: TopLayer::Stam,
    };
    let plain = Material {
        top_layer: TopLayer::Diffusion,
        ..stam.clone()
    };
    for cos in [1.0, 0.7, 0.3] {
        let (a, b) = (bake_square(&stam, cos), bake_square(&plain, cos));
        let (ea, eb) = (
            centre(&a.render(Output::Irradiance).unwrap()),
            centre(&b.render(Output::Irradiance).unwrap()),
        );
        for c in 0..3 {
            assert!(
                (ea[c] / eb[c] - 1.0).abs() < 2e-3,
                "cos {cos} channel {c}: {} vs {}",
                ea[c],
                eb[c]
            );
        }
        if cos == 1.0 {
            let exit = |o: &BakedObject| {
                centre(&o.render(Output::Diffuse).unwrap())[0]
                    / centre(&o.render(Output::Subsurface).unwrap())[0]
                    * std::f64::consts::PI
            };
            let f0 = dielectric_reflectance(1.0, 1.0, eta);
            let f_dr = diffuse_reflectance_exact(eta);
            let expected = (1.0 - f0) / (eta * eta * (1.0 - f_dr));
            for (name, object) in [("stam", &a), ("boundary", &b)] {
                assert!(
                    (exit(object) - expected).abs() < 2e-3,
                    "{name}: {} vs {expected}",
                    exit(object)
                );
            }
        }
    }
}
