//! The map carried from a lattice of texels ([`sssbake::fitted_map`]):
//! within its share of the tolerance of the integrator's own sums at every
//! texel, across a shadow's edge and a chart's, and the sums themselves
//! where no lattice holds or the octree is the exact sum (ε = 0).

mod lit_scenes;

use glam::Vec3;
use lit_scenes::*;
use sssbake::control::Control;
use sssbake::fitted_map::{Carrier, FIT_SHARE, first_step, fitted_map};
use sssbake::image::Image;
use sssbake::pipeline::half_light_texels;
use sssbake::prepared::Prepared;
use sssbake::request::DEFAULT_TOLERANCE;
use sssbake::scattering::Scattering;
use sssbake::transport::accuracy::relative_errors;
use sssbake::transport::brute::BruteIntegrator;
use sssbake::transport::integrator::{Integrator, Summer};
use sssbake::transport::octree::OctreeIntegrator;
use sssbake::{BakeRequest, Lighting};
use sssbake_profile::model::Model;
use std::sync::Arc;

/// A 20 mm square in skin1 at 256², lit by an irradiance image bright on
/// its left half and dark on its right: a shadow's sharp edge across the
/// middle, which the profile spreads over several texels.
fn half_lit() -> Prepared {
    let scene = scene(vec![centred_square(20.0, "square")], vec![]);
    let n = 64;
    let pixels = (0..n * n)
        .map(|i| if i % n < n / 2 { [1.0; 3] } else { [0.0; 3] })
        .collect();
    let request = BakeRequest {
        lighting: Lighting::Irradiance(Arc::new(Image::new(n, n, pixels).unwrap())),
        ..request(256)
    };
    prepare_with(&scene, "square", &request, &Control::new()).unwrap()
}

/// Runs `check` with the octree's summer over `prepared` in skin1, the
/// profile, and the octree's gathers at every texel.
fn with_gathers(prepared: &Prepared, check: impl FnOnce(&dyn Summer, &Scattering, &[[f32; 3]])) {
    let skin = scattering_of("skin1", Model::Dipole);
    let octree = OctreeIntegrator::default();
    let summer = octree.summer(prepared, &skin).unwrap();
    let every: Vec<usize> = (0..prepared.surfels.len()).collect();
    let direct = summer.at(&every, &Control::new()).unwrap();
    check(&*summer, &skin, &direct);
}

/// The map of `prepared` carried from its first lattice at a 1%
/// tolerance, checked over every texel (not only the probed ones) against
/// `direct`, the summer's own sums: within its share of the tolerance,
/// and carried (a lattice wider than one texel).
fn carried_within_share(
    prepared: &Prepared,
    summer: &dyn Summer,
    skin: &Scattering,
    direct: &[[f32; 3]],
) -> Vec<[f32; 3]> {
    let step = first_step(half_light_texels(skin, &prepared.surfels));
    let tolerance = 0.01;
    let (map, fit) = fitted_map(
        prepared,
        summer,
        &skin.kernel,
        step,
        tolerance,
        &Control::new(),
    )
    .unwrap();
    assert!(fit.step > 1, "{fit:?}");
    assert!(fit.missed <= FIT_SHARE * tolerance, "{fit:?}");
    let (relative, worst) = relative_errors(&map, direct);
    assert!(relative <= FIT_SHARE * tolerance, "{relative} {fit:?}");
    assert!(worst < 0.05, "worst {worst}");
    map
}

#[test]
fn a_map_carried_across_a_shadows_edge_keeps_within_its_share_of_the_tolerance() {
    let prepared = half_lit();
    with_gathers(&prepared, |summer, skin, direct| {
        let step = first_step(half_light_texels(skin, &prepared.surfels));
        assert!(step > 2, "the profile spans a few texels: step {step}");
        let map = carried_within_share(&prepared, summer, skin, direct);
        // Carried, not summed: most texels differ from their own sums.
        let carried = map.iter().zip(direct).filter(|(m, d)| m != d).count();
        assert!(carried > direct.len() / 2, "{carried} of {}", direct.len());
        assert!(map.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
    });
}

/// The square lit by an irradiance image that brightens smoothly from
/// left to right, without an edge.
fn smoothly_lit() -> Prepared {
    let scene = scene(vec![centred_square(20.0, "square")], vec![]);
    let n = 64;
    let pixels = (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f32 / n as f32, (i / n) as f32 / n as f32);
            [1.0 + x, 1.0 + 0.5 * y, 2.0 - x]
        })
        .collect();
    let request = BakeRequest {
        lighting: Lighting::Irradiance(Arc::new(Image::new(n, n, pixels).unwrap())),
        ..request(256)
    };
    prepare_with(&scene, "square", &request, &Control::new()).unwrap()
}

#[test]
fn where_the_light_is_smooth_the_map_is_carried_whole_within_the_share() {
    let prepared = smoothly_lit();
    with_gathers(&prepared, |summer, skin, direct| {
        let step = first_step(half_light_texels(skin, &prepared.surfels));
        let every: Vec<usize> = (0..prepared.surfels.len()).collect();
        let mut carrier = Carrier::split(&prepared, summer, &skin.kernel, 0.01);
        let whole = carrier.smooth_share_at(&every, step);
        assert!(whole > 0.5, "carried whole at {whole} of the texels");
        carried_within_share(&prepared, summer, skin, direct);
    });
    // Across a shadow's edge, the texels beside it keep their own N.
    let prepared = half_lit();
    with_gathers(&prepared, |summer, skin, _| {
        let step = first_step(half_light_texels(skin, &prepared.surfels));
        let every: Vec<usize> = (0..prepared.surfels.len()).collect();
        let mut carrier = Carrier::split(&prepared, summer, &skin.kernel, 0.01);
        let whole = carrier.smooth_share_at(&every, step);
        assert!(whole < 0.9, "carried whole at {whole} of the texels");
    });
}

#[test]
fn where_no_lattice_holds_the_map_is_the_integrators_own_sums() {
    let prepared = half_lit();
    with_gathers(&prepared, |summer, skin, direct| {
        // A tolerance no fit meets.
        let (map, fit) =
            fitted_map(&prepared, summer, &skin.kernel, 8, 1e-9, &Control::new()).unwrap();
        assert_eq!(fit.step, 1);
        assert_eq!(map, direct);
        // A step of 1 sums every texel without a check.
        let (map, fit) =
            fitted_map(&prepared, summer, &skin.kernel, 1, 0.01, &Control::new()).unwrap();
        assert_eq!((fit.step, fit.probed), (1, 0));
        assert_eq!(map, direct);
    });
}

#[test]
fn a_part_smaller_than_the_lattice_is_summed_texel_by_texel() {
    // A 1 mm square at 16²: a profile of skin spans the whole part, and no
    // texel but the lattice's own has four corners within reach.
    let scene = scene(
        vec![centred_square(1.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let prepared = prepared(&scene, "square", 16);
    with_gathers(&prepared, |summer, skin, direct| {
        let (map, _) =
            fitted_map(&prepared, summer, &skin.kernel, 8, 0.01, &Control::new()).unwrap();
        let (relative, _) = relative_errors(&map, direct);
        assert!(relative <= FIT_SHARE * 0.01, "{relative}");
    });
}

#[test]
fn the_octree_at_epsilon_zero_stays_the_exact_sum_at_every_texel() {
    let scene = scene(
        vec![centred_square(20.0, "square")],
        vec![sun_from(Vec3::new(0.3, 0.0, -1.0))],
    );
    let prepared = prepared(&scene, "square", 64);
    let skin = scattering_of("skin1", Model::Dipole);
    let exact = OctreeIntegrator { epsilon: 0.0 };
    assert!(exact.summer(&prepared, &skin).is_none());
    let control = Control::new();
    let octree = prepared
        .integrate(&skin, &exact, DEFAULT_TOLERANCE, &control)
        .unwrap();
    let brute = prepared
        .integrate(&skin, &BruteIntegrator, DEFAULT_TOLERANCE, &control)
        .unwrap();
    assert!(octree.fit.is_none());
    let (relative, _) = relative_errors(&octree.exitance, &brute.exitance);
    assert!(relative < 1e-5, "{relative}");
}

/// Sums that are `high` left of x = `edge` (mm) and half that right of
/// it, at whatever texels are asked for, counting how many were.
struct StepSums<'a> {
    prepared: &'a Prepared,
    edge: f32,
    asked: std::sync::atomic::AtomicUsize,
}

impl Summer for StepSums<'_> {
    fn at(&self, listed: &[usize], _: &Control) -> Result<Vec<[f32; 3]>, sssbake::Error> {
        self.asked
            .fetch_add(listed.len(), std::sync::atomic::Ordering::Relaxed);
        let position = &self.prepared.surfels.position;
        Ok(listed
            .iter()
            .map(|&i| {
                let p = position[i];
                let high = 1.0 + 0.01 * p.y;
                if p.x < self.edge {
                    [high; 3]
                } else {
                    [0.5 * high; 3]
                }
            })
            .collect())
    }
}

#[test]
fn a_whole_map_is_carried_from_finer_lattices_where_its_sums_change_abruptly() {
    let scene = scene(vec![centred_square(20.0, "square")], vec![]);
    let prepared = prepared(&scene, "square", 64);
    let every: Vec<usize> = (0..prepared.surfels.len()).collect();
    let step = 8;
    // Without an edge the lattices' own sums carry the map: the coarse
    // lattice's, and finer ones' only by the square's border.
    let smooth = StepSums {
        prepared: &prepared,
        edge: f32::INFINITY,
        asked: Default::default(),
    };
    let map = Carrier::whole(&prepared, &smooth)
        .with_steep_cells()
        .at(&every, step, &Control::new())
        .unwrap();
    let lattice_sums = smooth.asked.load(std::sync::atomic::Ordering::Relaxed);
    assert!(lattice_sums < every.len() / 8, "{lattice_sums}");
    let direct = smooth.at(&every, &Control::new()).unwrap();
    let (relative, _) = relative_errors(&map, &direct);
    assert!(relative < 1e-4, "{relative}");
    // An abrupt edge between lattice columns: bilinear means across it
    // would miss by up to a third; the cells it crosses go down to every
    // texel, and the map is its sums everywhere.
    let edge = StepSums {
        prepared: &prepared,
        edge: 1.1,
        asked: Default::default(),
    };
    let map = Carrier::whole(&prepared, &edge)
        .with_steep_cells()
        .at(&every, step, &Control::new())
        .unwrap();
    let direct = edge.at(&every, &Control::new()).unwrap();
    let (relative, worst) = relative_errors(&map, &direct);
    assert!(relative < 1e-4 && worst < 1e-3, "{relative} {worst}");
    // Only the cells along the edge were summed finer.
    let asked = edge.asked.load(std::sync::atomic::Ordering::Relaxed) - every.len();
    assert!(asked < 2 * lattice_sums, "{asked} against {lattice_sums}");
}
