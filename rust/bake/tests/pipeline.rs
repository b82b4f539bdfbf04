//! The bake of one object end to end: thin parts, colour maps, a user's
//! irradiance image, cancellation and the automatic choice.

mod lit_scenes;

use glam::{Vec2, Vec3};
use lit_scenes::*;
use sssbake::Mesh;
use sssbake::control::Control;
use sssbake::image::Image;
use sssbake::materials::MaterialAssignment;
use sssbake::request::DEFAULT_TOLERANCE;
use sssbake::transport::Method;
use sssbake::transport::brute::BruteIntegrator;
use sssbake::transport::integrator::{Integrator, IntegratorSettings};
use sssbake::transport::thin::{crossing_share, thin_share};
use sssbake::{BakeRequest, Error, Lighting, Output, bake, plan};
use sssbake_profile::material::{Layer, Material, Optics};
use sssbake_profile::model::Model;

/// A closed sheet: two 80 mm squares `gap` mm apart, back to back (top
/// faces +Z, bottom faces −Z), joined by a rim; the top in the left half
/// of the UVs.
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
    let mut triangles = vec![[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6]];
    let (mut positions, mut uvs) = (positions, uvs);
    // The rim: four walls `gap` high close the sheet, so one medium fills
    // it (faces of separate pieces would exchange no light). Their UVs are
    // thin strips in the upper half.
    for k in 0..4 {
        let (a, b) = (positions[k], positions[(k + 1) % 4]);
        let base = positions.len() as u32;
        positions.extend([a, b, b - Vec3::Z * gap, a - Vec3::Z * gap]);
        let (u0, u1) = (0.02 + 0.245 * k as f32, 0.245 * (k + 1) as f32);
        uvs.extend([
            Vec2::new(u0, 0.6),
            Vec2::new(u1, 0.6),
            Vec2::new(u1, 0.62),
            Vec2::new(u0, 0.62),
        ]);
        // Wound counter-clockwise seen from outside.
        let outward = (a + b).with_z(0.0);
        let facing = (b - a).cross(-Vec3::Z * gap).dot(outward) > 0.0;
        triangles.extend(if facing {
            [[base, base + 1, base + 2], [base, base + 2, base + 3]]
        } else {
            [[base, base + 2, base + 1], [base, base + 3, base + 2]]
        });
    }
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
        coat_ior: None,
        top_layer: sssbake_profile::material::TopLayer::Diffusion,
        roughness: 0.0,
    }
}

#[test]
fn light_crosses_a_thin_sheet_in_the_3d_integrators_only() {
    let scene = scene(vec![sheet(1.0)], vec![sun_from(Vec3::NEG_Z)]);
    let material = slab(1.0);
    let thin = scattering_for(&material, Model::default_for(&material));
    let profile = &thin.profile;
    assert!(profile.total_transmittance()[0] > 0.1);
    let prepared = prepared(&scene, "sheet", 192);
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
        let m = exitance(&prepared, &thin, method, &with(256, 6, 1));
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
    let skin = scattering_of("skin1", Model::Dipole);
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
        let request = BakeRequest {
            base_colour: colour.map(std::sync::Arc::new),
            colour_split: alpha,
            ..request(128)
        };
        let prepared = prepare_with(&scene, "square", &request, &Control::new()).unwrap();
        let m = exitance(
            &prepared,
            &skin,
            Method::Brute,
            &IntegratorSettings::default(),
        );
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
    let request = BakeRequest {
        lighting: Lighting::Irradiance(std::sync::Arc::new(image)),
        ..request(64)
    };
    let prepared = prepare_with(&scene, "square", &request, &Control::new()).unwrap();
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
    let result = prepare_with(&scene, "square", &request(64), &control);
    assert!(matches!(result, Err(Error::Cancelled)));
    let prepared = prepared(&scene, "square", 64);
    let skin = scattering_of("skin1", Model::Dipole);
    let settings = IntegratorSettings::default();
    for method in Method::ALL {
        let result = prepared.integrate(&skin, settings.get(method), DEFAULT_TOLERANCE, &control);
        assert!(matches!(result, Err(Error::Cancelled)), "{method}");
    }
    // Progress reaches one when nothing stops it.
    let fresh = Control::new();
    prepared
        .integrate(
            &skin,
            settings.get(Method::Brute),
            DEFAULT_TOLERANCE,
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
    let chosen = |resolution: u32, material: Material, method: Method| {
        let request = BakeRequest {
            materials: MaterialAssignment::everywhere(material, "test"),
            method,
            ..request(resolution)
        };
        plan(&scene, &request).unwrap().objects[0]
            .integrator
            .clone()
            .unwrap()
    };
    let skin1 = sssbake_profile::presets::preset("skin1").unwrap();
    let small = chosen(32, skin1.clone(), Method::Auto);
    assert_eq!(small.method, Method::Brute, "{}", small.reason);
    let large = chosen(1024, skin1.clone(), Method::Auto);
    assert_eq!(large.method, Method::Texture, "{}", large.reason);
    assert!(large.reason.contains("texels"));
    let thin = chosen(1024, slab(1.0), Method::Auto);
    assert_eq!(thin.method, Method::Octree, "{}", thin.reason);
    assert_eq!(
        chosen(1024, skin1, Method::Importance).method,
        Method::Importance
    );
}

/// The plan's share of texels on thin parts holds the texels truly there
/// and not many more: on a 1 mm sheet, its two broad faces (all but the
/// rim); none for a part thinner than the sheet.
#[test]
fn the_planned_thin_share_holds_the_sheets_faces_and_no_more() {
    let scene = scene(vec![sheet(1.0)], vec![sun_from(Vec3::NEG_Z)]);
    let prepared = prepared(&scene, "sheet", 192);
    let surfels = &prepared.surfels;
    let faces = (0..surfels.len())
        .filter(|&s| surfels.normal[s].z.abs() > 0.9)
        .count() as f64
        / surfels.len() as f64;
    let share = thin_share(&prepared.mesh, surfels, 2.0);
    assert!(
        share >= faces && share <= faces + 0.05,
        "{share} for {faces}"
    );
    assert!(share <= 1.0);
    assert_eq!(thin_share(&prepared.mesh, surfels, 0.5), 0.0);
    assert_eq!(thin_share(&prepared.mesh, surfels, f32::NAN), 0.0);
    // The plan holds nothing where no texel is thin, and no more than every
    // texel's worth on any share.
    let skin = scattering_of("skin1", Model::Dipole);
    let slabs = skin.slab_profiles().expect("skin has thin parts");
    assert_eq!(slabs.planned_bytes(1e6, 0.0), 0.0);
    assert_eq!(slabs.planned_bytes(1e6, f64::NAN), 0.0);
    let (some, all) = (
        slabs.planned_bytes(1e6, share),
        slabs.planned_bytes(1e6, 1.0),
    );
    assert!(0.0 < some && some <= all && all.is_finite());
    assert_eq!(slabs.planned_bytes(1e6, f64::INFINITY), all);
}

/// The share of the light that crosses a thin part, as `auto` estimates
/// it, is what the exact sum carries across before the local slab corrects
/// it: on a sheet lit from above only, the far face at the centre shows
/// that share of the near face's exitance (the near face gathers the whole
/// profile R, the far face the part beyond the thickness, R − E(t)).
#[test]
fn the_share_crossing_a_thin_sheet_is_what_the_exact_sum_carries_across() {
    let scene = scene(vec![sheet(1.0)], vec![sun_from(Vec3::NEG_Z)]);
    let skin = scattering_of("skin1", Model::Dipole);
    let prepared = prepared(&scene, "sheet", 192);
    let share = crossing_share(
        &prepared.mesh,
        &prepared.surfels,
        skin.profile.as_ref(),
        skin.kernel.d_max,
    );
    let m = BruteIntegrator
        .integrate(&prepared, &skin, &Control::new())
        .unwrap()
        .exitance;
    let centre = |top: bool| {
        let texels: Vec<usize> = (0..prepared.surfels.len())
            .filter(|&s| {
                let p = prepared.surfels.position[s];
                (p.z > 0.0) == top && p.x.abs() < 5.0 && p.y.abs() < 5.0
            })
            .collect();
        let sum: [f64; 3] =
            std::array::from_fn(|c| texels.iter().map(|&s| f64::from(m[s][c])).sum());
        sum.map(|v| v / texels.len() as f64)
    };
    let (near, far) = (centre(true), centre(false));
    let carried = (0..3).map(|c| far[c] / near[c]).fold(0.0, f64::max);
    assert!(share > 0.05, "{share}");
    assert!((carried / share - 1.0).abs() < 0.05, "{carried} vs {share}");
}

#[test]
fn auto_turns_texture_space_away_where_thin_parts_carry_light() {
    let chosen = |gap: f32| {
        let scene = scene(vec![sheet(gap)], vec![sun_from(Vec3::NEG_Z)]);
        plan(&scene, &request(1024)).unwrap().objects[0]
            .integrator
            .clone()
            .unwrap()
    };
    let thin = chosen(1.0);
    assert_eq!(thin.method, Method::Octree, "{}", thin.reason);
    assert!(thin.reason.contains("thinner"), "{}", thin.reason);
    let thick = chosen(60.0);
    assert_eq!(thick.method, Method::Texture, "{}", thick.reason);
}

#[test]
fn a_bake_computes_only_what_its_outputs_need() {
    let scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let bake_of = |outputs: Vec<Output>| {
        let request = BakeRequest {
            outputs,
            ..request(64)
        };
        let plan = plan(&scene, &request).unwrap();
        let (mut objects, summary) = bake(&scene, &plan, &Control::new()).unwrap();
        (objects.remove(0), summary)
    };
    // The irradiance alone is lit but never scattered.
    let (lit, summary) = bake_of(vec![Output::Irradiance]);
    assert!(lit.exitance.is_empty());
    assert_eq!(lit.prepared.irradiance.len(), lit.prepared.surfels.len());
    assert!(summary.objects[0].plan.integrator.is_none());
    assert!(!summary.objects[0].plan.scattering.run);
    assert!(lit.render(Output::Irradiance).is_ok());
    assert!(lit.render(Output::Subsurface).is_err());
    // Area and stretch need neither light nor scattering.
    let (shape, summary) = bake_of(vec![Output::Area, Output::Stretch]);
    assert!(shape.prepared.irradiance.is_empty() && shape.exitance.is_empty());
    assert!(!summary.objects[0].plan.lighting.run);
    assert!(summary.left_out.iter().any(|r| r.contains("need neither")));
    let area = shape.render(Output::Area).unwrap();
    let total: f64 = area.texels.iter().map(|t| t[0] as f64).sum();
    assert!(total > 0.0);
    // The subsurface map runs everything.
    let (full, summary) = bake_of(vec![Output::Subsurface]);
    assert_eq!(full.exitance.len(), full.prepared.surfels.len());
    assert!(summary.objects[0].plan.integrator.is_some());
}

#[test]
fn the_plan_is_what_the_bake_runs() {
    let scene = scene(
        vec![centred_square(60.0, "square"), sheet(1.0)],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let request = BakeRequest {
        method: Method::Auto,
        ..request(96)
    };
    let plan = plan(&scene, &request).unwrap();
    let (_, summary) = bake(&scene, &plan, &Control::new()).unwrap();
    let decisions = |value: serde_json::Value| -> Vec<serde_json::Value> {
        value["objects"]
            .as_array()
            .unwrap()
            .iter()
            .map(|o| {
                let mut o = o.clone();
                let map = o.as_object_mut().unwrap();
                map.remove("seconds");
                map.remove("sources");
                map.remove("accuracy");
                o
            })
            .collect()
    };
    assert_eq!(
        decisions(serde_json::to_value(&plan).unwrap()),
        decisions(serde_json::to_value(&summary).unwrap())
    );
}

#[test]
fn a_request_out_of_range_names_its_setting() {
    let scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let mut gaussians = request(64);
    gaussians.integrators.texture.gaussians = 0;
    for (request, field) in [
        (request(0), "resolution"),
        (
            BakeRequest {
                outputs: vec![],
                ..request(64)
            },
            "outputs",
        ),
        (
            BakeRequest {
                colour_split: 2.0,
                ..request(64)
            },
            "colour_split",
        ),
        (gaussians, "texture.gaussians"),
    ] {
        match plan(&scene, &request) {
            Err(Error::Setting { field: named, .. }) => assert_eq!(named, field),
            other => panic!("{field}: {:?}", other.map(|p| p.objects.len())),
        }
    }
}

/// A material's roughness sets the light crossing in (ρdt of Donner &
/// Jensen 2005 eq. 26) and out (the `diffuse` map's ρdt(0)/(π ρ̄dt));
/// the request's roughness overrides every material's.
#[test]
fn a_rough_surface_sets_entry_and_exit_and_the_request_overrides_it() {
    use sssbake_profile::boundary::rough::{diffuse_transmittance, hemispherical_transmittance};
    let scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let rough = Material {
        roughness: 0.8,
        ..slab(5.0)
    };
    let bake_with = |override_roughness: Option<f64>| {
        let request = BakeRequest {
            materials: MaterialAssignment::everywhere(rough.clone(), "test"),
            outputs: vec![Output::Irradiance, Output::Subsurface, Output::Diffuse],
            roughness: override_roughness,
            ..request(32)
        };
        let plan = plan(&scene, &request).unwrap();
        let (mut objects, _) = bake(&scene, &plan, &Control::new()).unwrap();
        objects.remove(0)
    };
    let centre = |image: &Image| image.sample(Vec2::new(0.5, 0.5))[0] as f64;
    let (own, smooth) = (bake_with(None), bake_with(Some(0.0)));
    assert_eq!(own.plan.material.roughness, 0.8);
    assert_eq!(smooth.plan.material.roughness, 0.0);
    let entry = |object: &sssbake::BakedObject| centre(&object.render(Output::Irradiance).unwrap());
    let expected = diffuse_transmittance(1.0, 1.3, 0.8) / diffuse_transmittance(1.0, 1.3, 0.0);
    assert!(
        (entry(&own) / entry(&smooth) / expected - 1.0).abs() < 1e-3,
        "entry: {} / {} against ρdt ratio {expected}",
        entry(&own),
        entry(&smooth)
    );
    for (object, m) in [(&own, 0.8), (&smooth, 0.0)] {
        let exit = centre(&object.render(Output::Diffuse).unwrap())
            / centre(&object.render(Output::Subsurface).unwrap());
        let expected = diffuse_transmittance(1.0, 1.3, m)
            / hemispherical_transmittance(1.3, m)
            / std::f64::consts::PI;
        assert!(
            (exit / expected - 1.0).abs() < 1e-3,
            "{m}: exit {exit} vs {expected}"
        );
    }
    let out_of_range = BakeRequest {
        roughness: Some(1.5),
        ..request(32)
    };
    assert!(matches!(
        plan(&scene, &out_of_range),
        Err(Error::Setting { field, .. }) if field == "roughness"
    ));
}

/// The sums under a unit light (where the surface ends within reach) are
/// taken on a lattice of texels and carried between, from finer lattices
/// in cells whose corners' sums differ steeply; only where the carried
/// sums still miss direct sums at its check is the whole lattice taken
/// denser. A rod 20 mm long and 2 mm across in skin1, whose sums fall
/// steeply toward its rims from every side (its fit missed at its first
/// stride and was summed again at half of it before steep cells went
/// finer), and an 80 mm block 40 mm thick, whose sums are flat but for
/// its edges, both keep their first stride.
#[test]
fn the_sums_under_a_unit_light_keep_their_stride_where_steep_cells_go_finer() {
    let strides = |size: Vec3, resolution: u32| -> (u32, u32) {
        let one = cube(1.0);
        let positions = one.positions.iter().map(|p| *p * size).collect();
        let mesh = Mesh::new("part", positions, None, one.uvs, one.triangles)
            .unwrap()
            .0;
        let scene = scene(vec![mesh], vec![sun_from(Vec3::new(-0.3, 0.2, -1.0))]);
        let request = BakeRequest {
            method: Method::Octree,
            outputs: vec![Output::Subsurface],
            ..request(resolution)
        };
        let plan = plan(&scene, &request).unwrap();
        let (objects, summary) = bake(&scene, &plan, &Control::new()).unwrap();
        let first = sssbake::pipeline::uniform_stride(
            &plan.objects[0].scattering_profile,
            &objects[0].prepared.surfels,
        );
        let accuracy = summary.objects[0].accuracy.as_ref().unwrap();
        (first, accuracy.corrected.unwrap().uniform_stride)
    };
    let (first, used) = strides(Vec3::new(20.0, 2.0, 2.0), 256);
    assert!(first > 1 && used == first, "rod: from {first} to {used}");
    let (first, used) = strides(Vec3::new(80.0, 80.0, 40.0), 512);
    assert!(first > 1 && used == first, "block: from {first} to {used}");
}

/// The plan counts the corrected model's own work: the curvature's steps
/// where it raises convex parts (a profile's integrator, not the walk,
/// which is light), growing with the texels.
#[test]
fn the_plan_counts_the_curvature_where_convex_parts_are_raised() {
    let scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let skin1 = sssbake_profile::presets::preset("skin1").unwrap();
    let cost = |resolution: u32, method: Method| {
        let request = BakeRequest {
            materials: MaterialAssignment::everywhere(skin1.clone(), "test"),
            method,
            ..request(resolution)
        };
        plan(&scene, &request).unwrap().objects[0].cost
    };
    let (small, large) = (cost(64, Method::Brute), cost(256, Method::Brute));
    assert!(small.curvature > 0.0, "{small:?}");
    assert!(large.curvature > small.curvature, "{small:?} {large:?}");
    // Counted in the plan's work, which the limits bound.
    assert_eq!(cost(128, Method::Walk).curvature, 0.0);
}

/// The plan counts the thin parts' own gathers, at most two maps' worth
/// (under a unit light and under the light): pair by pair for the exact
/// sum, as the octree's for the others, none for the walk.
#[test]
fn the_plan_counts_the_thin_parts_gathers() {
    let scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let skin1 = sssbake_profile::presets::preset("skin1").unwrap();
    let cost = |method: Method| {
        let request = BakeRequest {
            materials: MaterialAssignment::everywhere(skin1.clone(), "test"),
            method,
            ..request(256)
        };
        plan(&scene, &request).unwrap().objects[0].cost
    };
    let (brute, octree) = (cost(Method::Brute), cost(Method::Octree));
    // The exact sum's own are two sums too: the light's and a unit
    // light's, to find where the surface ends.
    assert_eq!(brute.thin_parts, brute.evaluations, "{brute:?}");
    assert!(octree.thin_parts > 0.0 && octree.thin_parts < brute.thin_parts);
    assert_eq!(cost(Method::Texture).thin_parts, octree.thin_parts);
    assert_eq!(cost(Method::Walk).thin_parts, 0.0);
}
