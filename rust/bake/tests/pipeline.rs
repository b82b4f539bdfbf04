//! The bake of one object end to end: thin parts, colour maps, a user's
//! irradiance image, cancellation and the automatic choice.

mod lit_scenes;

use glam::{Vec2, Vec3};
use lit_scenes::*;
use sssbake::Mesh;
use sssbake::control::Control;
use sssbake::image::Image;
use sssbake::pipeline::{BakeError, BakeSettings, Lighting, prepare};
use sssbake::transport::kernel::Kernel;
use sssbake::transport::{Method, MethodSettings};
use sssbake_profile::material::{Layer, Material, Optics};
use sssbake_profile::model::{Model, build_profile};

/// Two 80 mm squares `gap` mm apart, back to back (top faces +Z, bottom
/// faces −Z), in one object; the top in the left half of the UVs.
fn sheet(gap: f32) -> Mesh {
    let h = 40.0;
    let z = gap / 2.0;
    let positions = vec![
        Vec3::new(-h, -h, z),
        Vec3::new(h, -h, z),
        Vec3::new(h, h, z),
        Vec3::new(-h, h, z),
        Vec3::new(-h, -h, -z),
        Vec3::new(h, -h, -z),
        Vec3::new(h, h, -z),
        Vec3::new(-h, h, -z),
    ];
    let uvs = vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(0.49, 0.0),
        Vec2::new(0.49, 0.49),
        Vec2::new(0.0, 0.49),
        Vec2::new(0.51, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(1.0, 0.49),
        Vec2::new(0.51, 0.49),
    ];
    let triangles = vec![[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6]];
    Mesh::new("sheet", positions, None, Some(uvs), triangles)
        .unwrap()
        .0
}

fn slab(thickness_mm: f64) -> Material {
    Material {
        name: "slab".into(),
        optics: Optics::Layers(vec![Layer {
            sigma_a: [0.01, 0.05, 0.2],
            sigma_s: [2.0; 3],
            g: 0.0,
            ior: 1.3,
            thickness_mm: Some(thickness_mm),
        }]),
    }
}

#[test]
fn light_crosses_a_thin_sheet_in_the_3d_integrators_only() {
    let scene = scene(vec![sheet(1.0)], vec![sun_from(Vec3::NEG_Z)]);
    let material = slab(1.0);
    let profile = build_profile(&material, Model::default_for(&material), 6).unwrap();
    assert!(profile.total_transmittance()[0] > 0.1);
    let kernel = Kernel::new(profile.as_ref(), 1e-3);
    let prepared = prepared(&scene, "sheet", 192, 1.0);
    let centre_below: Vec<usize> = (0..prepared.surfels.len())
        .filter(|&s| {
            let p = prepared.surfels.position[s];
            p.z < 0.0 && p.x.abs() < 5.0 && p.y.abs() < 5.0
        })
        .collect();
    assert!(!centre_below.is_empty());
    assert!(
        centre_below
            .iter()
            .all(|&s| prepared.irradiance[s][0] == 0.0)
    );
    let lit = prepared.irradiance.iter().map(|e| e[0]).fold(0.0, f32::max) as f64;
    for method in Method::ALL {
        let settings = MethodSettings {
            samples: 256,
            ..MethodSettings::default()
        };
        let m = prepared
            .integrate(
                profile.as_ref(),
                &kernel,
                method,
                &settings,
                &Control::new(),
            )
            .unwrap()
            .exitance;
        let below: f64 =
            centre_below.iter().map(|&s| m[s][0] as f64).sum::<f64>() / centre_below.len() as f64;
        let expected = lit * profile.total_transmittance()[0];
        if method == Method::Texture {
            assert_eq!(below, 0.0, "texture space cannot carry light through");
        } else {
            // Normals are opposite, so P = T: the far face shows T_total·E.
            assert!(
                (below / expected - 1.0).abs() < 0.05,
                "{method}: {below} vs {expected}"
            );
        }
    }
}

#[test]
fn a_base_colour_splits_before_and_after_scattering() {
    let scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let profile = profile_of("skin1", Model::Dipole);
    let kernel = Kernel::new(profile.as_ref(), 1e-3);
    // Left half red-ish, right half white.
    let (w, h) = (64, 64);
    let texels = (0..w * h)
        .map(|i| {
            if i % w < w / 2 {
                [0.8, 0.2, 0.1]
            } else {
                [1.0; 3]
            }
        })
        .collect();
    let colour = Image::new(w, h, texels).unwrap();
    let run = |alpha: f32, colour: Option<Image>| {
        let settings = BakeSettings {
            resolution: 128,
            base_colour: colour,
            colour_split: alpha,
            ..BakeSettings::default()
        };
        let prepared = prepare(
            &scene,
            "square",
            Lighting::SceneLights,
            &settings,
            &Control::new(),
        )
        .unwrap();
        let m = prepared
            .integrate(
                profile.as_ref(),
                &kernel,
                Method::Brute,
                &MethodSettings::default(),
                &Control::new(),
            )
            .unwrap()
            .exitance;
        (prepared, m)
    };
    let (plain_prep, plain) = run(0.5, None);
    // α = 0: colour applied after scattering only, texel by texel.
    let (prepared, after) = run(0.0, Some(colour.clone()));
    for s in (0..plain.len()).step_by(97) {
        for c in 0..3 {
            let expected = plain[s][c] * prepared.colour[s][c];
            assert!(
                (after[s][c] - expected).abs() <= 1e-5 * plain[s][c].max(1e-6),
                "{s} {c}"
            );
        }
    }
    // α = 1: colour before scattering bleeds across the boundary: the white
    // side next to the red half is darker in blue than far from it.
    let (prepared, before) = run(1.0, Some(colour));
    let near = (0..before.len())
        .filter(|&s| {
            (prepared.surfels.position[s].x - 0.5).abs() < 0.3
                && prepared.surfels.position[s].y.abs() < 5.0
        })
        .collect::<Vec<_>>();
    let far = (0..before.len())
        .filter(|&s| {
            (prepared.surfels.position[s].x - 20.0).abs() < 0.3
                && prepared.surfels.position[s].y.abs() < 5.0
        })
        .collect::<Vec<_>>();
    let mean = |set: &[usize], m: &[[f32; 3]]| {
        set.iter().map(|&s| m[s][2] as f64).sum::<f64>() / set.len() as f64
    };
    assert!(mean(&near, &before) < 0.9 * mean(&near, &plain));
    assert!((mean(&far, &before) / mean(&far, &plain) - 1.0).abs() < 0.01);
    let _ = plain_prep;
}

#[test]
fn an_irradiance_image_replaces_the_lights() {
    let scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let image = Image::new(4, 4, vec![[2.0, 1.0, 0.5]; 16]).unwrap();
    let settings = BakeSettings {
        resolution: 64,
        ..BakeSettings::default()
    };
    let prepared = prepare(
        &scene,
        "square",
        Lighting::Irradiance(image),
        &settings,
        &Control::new(),
    )
    .unwrap();
    assert!(prepared.irradiance.iter().all(|e| *e == [2.0, 1.0, 0.5]));
}

#[test]
fn a_cancelled_bake_stops_with_cancelled() {
    let scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let control = Control::new();
    control.cancel();
    let settings = BakeSettings {
        resolution: 64,
        ..BakeSettings::default()
    };
    let result = prepare(&scene, "square", Lighting::SceneLights, &settings, &control);
    assert!(matches!(result, Err(BakeError::Cancelled(_))));
    let prepared = prepared(&scene, "square", 64, 1.0);
    let profile = profile_of("skin1", Model::Dipole);
    let kernel = Kernel::new(profile.as_ref(), 1e-3);
    for method in Method::ALL {
        let result = prepared.integrate(
            profile.as_ref(),
            &kernel,
            method,
            &MethodSettings::default(),
            &control,
        );
        assert!(matches!(result, Err(BakeError::Cancelled(_))), "{method}");
    }
    // Progress reaches one when nothing stops it.
    let fresh = Control::new();
    prepared
        .integrate(
            profile.as_ref(),
            &kernel,
            Method::Brute,
            &MethodSettings::default(),
            &fresh,
        )
        .unwrap();
    assert!((fresh.fraction() - 1.0).abs() < 1e-9);
}

#[test]
fn auto_says_what_it_chose_and_why() {
    let scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let profile = profile_of("skin1", Model::Dipole);
    let kernel = Kernel::new(profile.as_ref(), 1e-3);
    let small = prepared(&scene, "square", 32, 1.0);
    let choice = small.choose(Method::Auto, &kernel);
    assert_eq!(choice.method, Method::Brute, "{}", choice.reason);
    let large = prepared(&scene, "square", 1024, 1.0);
    let choice = large.choose(Method::Auto, &kernel);
    assert_eq!(choice.method, Method::Texture, "{}", choice.reason);
    assert!(choice.reason.contains("texels"));
    let thin = build_profile(&slab(1.0), Model::Multipole, 6).unwrap();
    let choice = large.choose(Method::Auto, &Kernel::new(thin.as_ref(), 1e-3));
    assert_eq!(choice.method, Method::Octree, "{}", choice.reason);
    assert_eq!(
        large.choose(Method::Importance, &kernel).method,
        Method::Importance
    );
}
