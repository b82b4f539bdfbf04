//! The corrected model against light itself: the exact sum with thin parts
//! by the local slab, against a volumetric random walk at every texel, at
//! skin's reach, where a semi-infinite profile is wrong (a thin slab lit
//! from one side: the lit face loses what crosses, the far face receives
//! it); and the integrators held to that corrected sum.

mod lit_scenes;

use glam::Vec3;
use lit_scenes::*;
use sssbake::control::Control;
use sssbake::prepared::Prepared;
use sssbake::request::DEFAULT_TOLERANCE;
use sssbake::scattering::Scattering;
use sssbake::transport::accuracy::relative_errors;
use sssbake::transport::brute::BruteIntegrator;
use sssbake::transport::integrator::Integrator;
use sssbake::transport::octree::OctreeIntegrator;
use sssbake::transport::verify::estimate_error;
use sssbake::transport::walk::walk_surfels;
use sssbake::walk::{StartDirection, WalkMedium, WalkSettings};
use sssbake_profile::model::Model;

/// How a bake compares with the walk over some texels, per channel.
#[derive(Debug)]
struct Agreement {
    /// Median of baked / walked.
    median_ratio: [f64; 3],
    /// 90th percentile of |ln(baked / walked)|.
    p90_log: [f64; 3],
}

fn percentile(mut values: Vec<f64>, p: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    if values.is_empty() {
        return f64::NAN;
    }
    values[((values.len() - 1) as f64 * p).round() as usize]
}

/// Baked against walked over the texels `keep` picks, where the walk's
/// exitance is at least a tenth of its largest there and its noise under
/// a tenth of its value.
fn agreement(
    baked: &[[f32; 3]],
    walked: &[[f32; 3]],
    noise: &[[f32; 3]],
    keep: impl Fn(usize) -> bool,
) -> Agreement {
    let mut median_ratio = [0.0; 3];
    let mut p90_log = [0.0; 3];
    for c in 0..3 {
        let texels: Vec<usize> = (0..baked.len()).filter(|&i| keep(i)).collect();
        let top = texels.iter().map(|&i| walked[i][c]).fold(0.0f32, f32::max);
        let lit: Vec<usize> = texels
            .into_iter()
            .filter(|&i| walked[i][c] > 0.1 * top && noise[i][c] < 0.1 * walked[i][c])
            .collect();
        let ratios: Vec<f64> = lit
            .iter()
            .map(|&i| f64::from(baked[i][c]) / f64::from(walked[i][c]))
            .collect();
        median_ratio[c] = percentile(ratios.clone(), 0.5);
        p90_log[c] = percentile(ratios.iter().map(|r| r.ln().abs()).collect(), 0.9);
    }
    Agreement {
        median_ratio,
        p90_log,
    }
}

/// An object prepared, its bake, and the walk's exitance and noise at
/// every texel.
type BakedAndWalked = (Prepared, Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<[f32; 3]>);

/// The bake by brute and the walk at every texel of `object` in `scene`.
fn bake_and_walk(
    scene: &sssbake::Scene,
    object: &str,
    resolution: u32,
    scattering: &Scattering,
) -> BakedAndWalked {
    let prepared = prepared(scene, object, resolution);
    let baked = prepared
        .integrate(
            scattering,
            &BruteIntegrator,
            DEFAULT_TOLERANCE,
            &Control::new(),
        )
        .unwrap()
        .exitance;
    let every: Vec<usize> = (0..prepared.surfels.len()).collect();
    let (walked, noise) = walked_at(&prepared, scattering, &every, 4096);
    (prepared, baked, walked, noise)
}

/// The mean over `texels` of channel `c`.
fn mean(values: &[[f32; 3]], texels: &[usize], c: usize) -> f64 {
    texels.iter().map(|&i| f64::from(values[i][c])).sum::<f64>() / texels.len().max(1) as f64
}

#[test]
fn a_thin_slab_lit_from_above_sends_its_light_through_to_its_far_face() {
    // 3 mm of skin1: red reaches about 3.7 mm, green 1.5 mm, blue 0.8 mm.
    let skin = scattering_of("skin1", Model::Dipole);
    let slab = stretched(cube(1.0), Vec3::new(60.0, 60.0, 3.0), "slab");
    let scene = scene(vec![slab], vec![sun_from(Vec3::new(-0.3, 0.2, -1.0))]);
    let (prepared, baked, walked, noise) = bake_and_walk(&scene, "slab", 48, &skin);
    // Away from the rim, where the slab is a slab.
    let inside = |i: usize| {
        let p = prepared.surfels.position[i];
        p.x.abs() < 22.0 && p.y.abs() < 22.0
    };
    let face = |up: bool| -> Vec<usize> {
        (0..baked.len())
            .filter(|&i| inside(i) && (prepared.surfels.normal[i].z > 0.5) == up)
            .filter(|&i| prepared.surfels.normal[i].z.abs() > 0.5)
            .collect()
    };
    let (near, far) = (face(true), face(false));
    assert!(near.len() > 50 && far.len() > 50);
    let near_agrees = agreement(&baked, &walked, &noise, |i| near.contains(&i));
    let far_agrees = agreement(&baked, &walked, &noise, |i| far.contains(&i));
    eprintln!("near face: {near_agrees:?}\nfar face: {far_agrees:?}");
    for c in 0..3 {
        let crossing = mean(&walked, &far, c) / mean(&walked, &near, c);
        eprintln!("channel {c}: the far face has {crossing:.4} of the near face's light");
        assert!(
            (near_agrees.median_ratio[c] - 1.0).abs() < 0.08 && near_agrees.p90_log[c] < 0.2,
            "near face, channel {c}: {near_agrees:?}"
        );
        // Where light crosses at all (red and green), the far face gets
        // what the walk sends; blue's crossing is a few thousandths.
        if crossing > 0.02 {
            assert!(
                (far_agrees.median_ratio[c] - 1.0).abs() < 0.1 && far_agrees.p90_log[c] < 0.2,
                "far face, channel {c}: {far_agrees:?}"
            );
        }
    }
}

/// The exact sum of the corrected model checks the integrators: brute's
/// own estimate is nil, and the octree's estimate is its error against
/// the corrected brute at every texel.
#[test]
fn the_error_estimate_holds_an_integrator_to_the_corrected_exact_sum() {
    let skin = scattering_of("skin1", Model::Dipole);
    let slab = stretched(cube(1.0), Vec3::new(60.0, 60.0, 3.0), "slab");
    let scene = scene(vec![slab], vec![sun_from(Vec3::new(-0.3, 0.2, -1.0))]);
    let prepared = prepared(&scene, "slab", 64);
    assert!(prepared.has_thin_parts(skin.kernel.d_max));
    let control = Control::new();
    let exact = prepared
        .integrate(&skin, &BruteIntegrator, DEFAULT_TOLERANCE, &control)
        .unwrap();
    let own = estimate_error(
        &prepared,
        &skin,
        &exact.exitance,
        exact.raised.as_deref(),
        exact.kept,
        1.0,
        BruteIntegrator.thin_epsilon(),
        3,
        &control,
    )
    .unwrap();
    assert!(own.relative_rmse < 1e-5, "{own:?}");
    let octree = OctreeIntegrator { epsilon: 2.0 };
    let coarse = prepared
        .integrate(&skin, &octree, DEFAULT_TOLERANCE, &control)
        .unwrap();
    let (measured, _) = relative_errors(&coarse.exitance, &exact.exitance);
    let estimated = estimate_error(
        &prepared,
        &skin,
        &coarse.exitance,
        coarse.raised.as_deref(),
        coarse.kept,
        1.0,
        octree.thin_epsilon(),
        3,
        &control,
    )
    .unwrap()
    .relative_rmse;
    eprintln!("octree at ε 2: measured {measured:.5}, estimated {estimated:.5}");
    assert!(measured > 1e-4, "the test needs an octree with an error");
    assert!(
        (estimated / measured - 1.0).abs() < 0.2,
        "estimated {estimated} against measured {measured}"
    );
}

/// Where a thin part takes its own slab's profile, the octree carries that
/// map from a lattice of its texels, as it carries the whole map, and
/// still holds the exact sum's tolerance there: a 3 mm slab of skin1 under
/// a point light 30 mm above it (the light falling off over the lit face,
/// and sent through to the other), at 256².
#[test]
fn a_thin_parts_map_carried_from_a_lattice_holds_the_exact_sum() {
    let skin = scattering_of("skin1", Model::Dipole);
    let slab = stretched(cube(1.0), Vec3::new(60.0, 60.0, 3.0), "slab");
    let light = point_light_at(Vec3::new(5.0, -3.0, 1.5 + 30.0));
    let scene = scene(vec![slab], vec![light]);
    let prepared = prepared(&scene, "slab", 256);
    let control = Control::new();
    let octree = prepared
        .integrate(
            &skin,
            &OctreeIntegrator::default(),
            DEFAULT_TOLERANCE,
            &control,
        )
        .unwrap();
    let fit = octree
        .thin_fit
        .expect("the thin texels are many enough to carry");
    assert!(fit.step > 1, "{fit:?}");
    let exact = prepared
        .integrate(&skin, &BruteIntegrator, DEFAULT_TOLERANCE, &control)
        .unwrap();
    let profiles = skin.slab_profiles().unwrap();
    let thin: Vec<usize> = profiles
        .thin_texels(&prepared, None)
        .texels()
        .iter()
        .map(|t| t.texel)
        .collect();
    let at = |map: &[[f32; 3]]| -> Vec<[f32; 3]> { thin.iter().map(|&i| map[i]).collect() };
    let (whole, _) = relative_errors(&octree.exitance, &exact.exitance);
    let (on_thin, _) = relative_errors(&at(&octree.exitance), &at(&exact.exitance));
    eprintln!(
        "{} thin texels carried at {fit:?}; against the exact sum {whole:.4} whole, {on_thin:.4} on them",
        thin.len()
    );
    assert!(thin.len() > 4 * fit.probed, "{} thin texels", thin.len());
    assert!(whole < DEFAULT_TOLERANCE, "{whole}");
    assert!(on_thin < DEFAULT_TOLERANCE, "{on_thin}");
}

/// Where the object is thicker than the profile reaches, the local slab
/// changes only the level: on a 100 mm block, farther from its edges than
/// the reach, the bake is the plain exact sum times R_∞/R, the Monte
/// Carlo's total over the dipole's (skin1's blue: about 0.115/0.131),
/// within the discrete sum's own error. Nearer an edge, where the surface
/// the profile reaches ends, the light entering may be raised, never
/// lowered.
#[test]
fn a_thick_body_keeps_the_half_space_at_the_level_of_light() {
    let skin = scattering_of("skin1", Model::Dipole);
    let reach = skin.kernel.d_max;
    const SIDE: f32 = 100.0;
    let block = stretched(cube(1.0), Vec3::splat(SIDE), "block");
    assert!(SIDE > 2.5 * reach, "reach {reach} mm");
    let scene = scene(vec![block], vec![sun_from(Vec3::new(-0.3, 0.2, -1.0))]);
    let prepared = prepared(&scene, "block", 64);
    assert!(!prepared.has_thin_parts(reach));
    let control = Control::new();
    let baked = prepared
        .integrate(&skin, &BruteIntegrator, DEFAULT_TOLERANCE, &control)
        .unwrap()
        .exitance;
    let plain = BruteIntegrator
        .integrate(&prepared, &skin, &control)
        .unwrap();
    let level = skin.local_slab().unwrap().level();
    eprintln!("skin1's level against the dipole's: {level:?}");
    assert!((0.8..0.95).contains(&level[2]), "{level:?}");
    let (mut inside, mut worst_inside) = (0, 0.0f32);
    for (i, m) in baked.iter().enumerate() {
        let sum = plain.exitance[i];
        let levelled = [0, 1, 2].map(|c| (f64::from(sum[c]) * level[c]) as f32);
        let expected = prepared.after_scattering(i, levelled);
        let (p, n) = (
            prepared.surfels.position[i],
            prepared.surfels.normal[i].abs(),
        );
        let axis = if n.x >= n.y && n.x >= n.z {
            0
        } else if n.y >= n.z {
            1
        } else {
            2
        };
        let from_edge = (0..3)
            .filter(|&k| k != axis)
            .map(|k| SIDE / 2.0 - p[k].abs())
            .fold(f32::INFINITY, f32::min);
        for c in 0..3 {
            let ratio = m[c] / expected[c];
            if expected[c] <= 1e-12 {
                continue;
            }
            assert!(
                ratio >= 1.0 - 1e-6,
                "texel {i} channel {c}: lowered to {ratio}"
            );
            if from_edge > reach {
                inside += 1;
                worst_inside = worst_inside.max((ratio - 1.0).abs());
            }
        }
    }
    eprintln!("{inside} values away from the edges within {worst_inside:.5}");
    assert!(
        inside > 100 && worst_inside < 0.01,
        "{inside} {worst_inside}"
    );
}

/// A small thin part, a 12 mm square 3 mm thick in skin1: red reaches
/// past its rim, and a profile hands each texel the light of surface
/// beyond the rim that is not there. Red takes the slab's own profile
/// here, right in the middle of the square; past the rim the light meets
/// the square's side, and the share F_dr the boundary reflects comes
/// back; the rest passes the side, and light entering through the side,
/// which the sun lights at a fifth of the top's irradiance, comes in
/// (`rim_light`). So the bake returns what the walk returns: red within
/// 3% on both faces, p90 of |ln ratio| under 0.08 (without the side's
/// light 1.3% over, p90 0.09 and 0.08), held to 3% and 0.12 (the
/// half-space's profile was 7% dark, p90 0.29 and 0.35; raised by the
/// whole shortfall, 1.03 and 1.03, p90 0.12 and 0.16; the slab's raised
/// by the whole, 7% bright). Green and blue are nearly half-spaces here;
/// their spread is at the square's edges, where the medium beyond the
/// edge is missing and light that a half-space absorbs comes out (not
/// modelled: their medians are 2–3% low).
#[test]
fn a_small_thin_part_returns_the_light_of_the_walk() {
    let skin = scattering_of("skin1", Model::Dipole);
    let tile = stretched(cube(1.0), Vec3::new(12.0, 12.0, 3.0), "tile");
    let scene = scene(vec![tile], vec![sun_from(Vec3::new(-0.3, 0.2, -1.0))]);
    let (prepared, baked, walked, noise) = bake_and_walk(&scene, "tile", 64, &skin);
    let face = |up: bool| -> Vec<usize> {
        (0..baked.len())
            .filter(|&i| prepared.surfels.normal[i].z.abs() > 0.5)
            .filter(|&i| (prepared.surfels.normal[i].z > 0.5) == up)
            .collect()
    };
    for (name, texels) in [("near", face(true)), ("far", face(false))] {
        let agrees = agreement(&baked, &walked, &noise, |i| texels.contains(&i));
        eprintln!("{name} face: {agrees:?}");
        assert!(
            (agrees.median_ratio[0] - 1.0).abs() < 0.03 && agrees.p90_log[0] < 0.12,
            "{name} face, red: {agrees:?}"
        );
        for c in 1..3 {
            assert!(
                (agrees.median_ratio[c] - 1.0).abs() < 0.07,
                "{name} face, channel {c}: {agrees:?}"
            );
        }
    }
}

/// Light a thin part's slab would carry past its rim meets the rim's
/// surface; followed the other way, light entering through the rim
/// reaches the faces near it, with the rim's irradiance. A 12 mm tile of
/// Blender's default skin 3 mm thick (index-matched: the rim reflects
/// nothing back) under a sun at 45° that lights one side as brightly as
/// the top: along that side, red on the top face was 0.84 of the walk and
/// on the bottom 0.94, green 0.83 on both, while the texels' sums missed
/// the light beyond the rim and nothing brought the rim's own.
#[test]
fn a_thin_tile_lit_across_its_rim_takes_the_light_entering_there() {
    let ratios = along_the_lit_side(&blender_default_skin());
    for (top, ratio) in [true, false].iter().zip(ratios) {
        assert!(
            (ratio[0] - 1.0).abs() < 0.06,
            "top face {top}, red: {ratio:?}"
        );
        assert!(
            (ratio[1] - 1.0).abs() < 0.12,
            "top face {top}, green: {ratio:?}"
        );
    }
    // Behind skin1's dielectric the rim returns F_dr itself and passes the
    // rest (printed: docs/accuracy.md).
    along_the_lit_side(&scattering_of("skin1", Model::Dipole));
}

/// The bake over the walk per channel on a 12 × 12 × 3 mm tile of
/// `skin` under a sun at 45° that lights its +x side as brightly as its
/// top, over the strip of each face (top, then bottom) within 3 mm of
/// that side, its corners left out.
fn along_the_lit_side(skin: &Scattering) -> [[f64; 3]; 2] {
    let (side, thickness) = (12.0f32, 3.0f32);
    let tile = stretched(cube(1.0), Vec3::new(side, side, thickness), "tile");
    let scene = scene(vec![tile], vec![sun_from(Vec3::new(-1.0, 0.0, -1.0))]);
    let (prepared, baked, walked, _) = bake_and_walk(&scene, "tile", 64, skin);
    let half = side / 2.0;
    [true, false].map(|top| {
        let strip: Vec<usize> = (0..baked.len())
            .filter(|&i| {
                let (p, n) = (prepared.surfels.position[i], prepared.surfels.normal[i]);
                (n.z > 0.5) == top && n.z.abs() > 0.5 && p.x > half - 3.0 && p.y.abs() < half - 3.0
            })
            .collect();
        assert!(strip.len() > 40, "{} texels", strip.len());
        let ratio = [0, 1, 2].map(|c| mean(&baked, &strip, c) / mean(&walked, &strip, c));
        eprintln!(
            "{}: top face {top}, along the lit side: bake / walk {ratio:.3?}",
            skin.material.name
        );
        ratio
    })
}

/// The raised light belongs to the scattering it was found for: one
/// object baked in two materials raises each by its own reach.
#[test]
fn each_material_raises_its_own_light() {
    let skin = scattering_of("skin1", Model::Dipole);
    let marble = scattering_of("marble", Model::Dipole);
    let tile = stretched(cube(1.0), Vec3::new(12.0, 12.0, 3.0), "tile");
    let scene = scene(vec![tile], vec![sun_from(Vec3::new(-0.3, 0.2, -1.0))]);
    let prepared = prepared(&scene, "tile", 24);
    let control = Control::new();
    let in_skin = prepared
        .integrate(&skin, &BruteIntegrator, DEFAULT_TOLERANCE, &control)
        .unwrap();
    let raised_skin = in_skin.raised.clone().expect("raised under skin1");
    let in_marble = prepared
        .integrate(&marble, &BruteIntegrator, DEFAULT_TOLERANCE, &control)
        .unwrap();
    let raised_marble = in_marble.raised.clone().expect("raised under marble");
    assert!(raised_skin.count > 0 && raised_marble.count > 0);
    assert_ne!(raised_skin.halves, raised_marble.halves);
    // Asked again under skin1, the bake is what it was.
    let again = prepared
        .integrate(&skin, &BruteIntegrator, DEFAULT_TOLERANCE, &control)
        .unwrap();
    assert_eq!(again.exitance, in_skin.exitance);
}

/// A small ball returns more light than a half-space: light that goes
/// deep meets its surface soon and comes out. An 11 mm ball of skin1 under
/// a sun: on its lit half the bake was 18% darker than the walk in red,
/// 13% in green, 7% in blue; raised by what a ball as curved returns
/// beyond the slab of its diameter, each channel's median is within 4%.
#[test]
fn a_small_ball_returns_the_light_of_the_walk() {
    let skin = scattering_of("skin1", Model::Dipole);
    let ball = sphere(11.0, 48, 96);
    let down = Vec3::new(-0.3, 0.2, -1.0);
    let scene = scene(vec![ball], vec![sun_from(down)]);
    let prepared = prepared(&scene, "sphere", 64);
    let baked = prepared
        .integrate(&skin, &BruteIntegrator, DEFAULT_TOLERANCE, &Control::new())
        .unwrap()
        .exitance;
    // The lit half, away from the terminator (where the map's texels,
    // 1–3 mm here, blur light and shadow), walked texel by texel; the
    // rest, read only as sums over bands, by a quarter of the walks.
    let facing = -down.normalize();
    let (lit, rest): (Vec<usize>, Vec<usize>) =
        (0..baked.len()).partition(|&i| prepared.surfels.normal[i].dot(facing) > 0.3);
    let (mut walked, mut noise) = (vec![[0.0; 3]; baked.len()], vec![[0.0; 3]; baked.len()]);
    for (texels, walks) in [(&lit, 4096), (&rest, 1024)] {
        let (light, error) = walked_at(&prepared, &skin, texels, walks);
        for (k, &i) in texels.iter().enumerate() {
            (walked[i], noise[i]) = (light[k], error[k]);
        }
    }
    let agrees = agreement(&baked, &walked, &noise, |i| lit.contains(&i));
    eprintln!("lit half: {agrees:?}");
    // The dark half, by how far each texel faces from the sun: the bake's
    // light over the walk's, summed over the band, and what it misses of
    // the ball's light (not asserted: the model's far field is short of
    // light's there; docs/accuracy.md).
    let sum = |m: &[[f32; 3]], band: &[usize], c: usize| -> f64 {
        band.iter().map(|&i| f64::from(m[i][c])).sum()
    };
    let everywhere: Vec<usize> = (0..baked.len()).collect();
    let dark: Vec<usize> = (0..baked.len())
        .filter(|&i| prepared.surfels.normal[i].dot(facing) < 0.0)
        .collect();
    for (lo, hi) in [(-1.0, -0.9), (-0.9, -0.6), (-0.6, -0.3), (-0.3, 0.0)] {
        let band: Vec<usize> = (0..baked.len())
            .filter(|&i| (lo..hi).contains(&prepared.surfels.normal[i].dot(facing)))
            .collect();
        let ratio = [0, 1, 2].map(|c| sum(&baked, &band, c) / sum(&walked, &band, c));
        eprintln!("dark half, facing the sun {lo}..{hi}: bake/walk {ratio:.2?}");
    }
    let missing = [0, 1, 2]
        .map(|c| (sum(&walked, &dark, c) - sum(&baked, &dark, c)) / sum(&walked, &everywhere, c));
    eprintln!("dark half: the bake misses {missing:.3?} of the ball's light");
    for c in 0..3 {
        assert!(
            (agrees.median_ratio[c] - 1.0).abs() < 0.04 && agrees.p90_log[c] < 0.12,
            "channel {c}: {agrees:?}"
        );
    }
}

/// Where a thin part's light goes sideways: a 2 mm slab of skin1 under a
/// point light 2 mm above its top face, the bake's light over the walk's
/// in rings about the point beneath the light. A half-space's profile
/// spread red wider than a slab, which light leaves through both faces as
/// it goes (rings 0.77–1.46 of the walk; docs/accuracy.md); the slab's own
/// profile (`SlabProfiles`), which the bake takes where a part is
/// thinner than about a diffusion length, spreads red as light does:
/// every ring of both faces within 7% of the walk, by the exact sum and
/// by the octree. Green and blue, whose diffusion lengths are shorter
/// than 2 mm, keep the half-space's profile; each face's whole within
/// 15 mm is the walk's.
#[test]
fn a_thin_slab_under_a_point_light_keeps_each_face_s_light() {
    let skin = scattering_of("skin1", Model::Dipole);
    let thickness = 2.0;
    let slab = stretched(cube(1.0), Vec3::new(40.0, 40.0, thickness), "slab");
    let light = point_light_at(Vec3::new(0.0, 0.0, thickness / 2.0 + 2.0));
    let scene = scene(vec![slab], vec![light]);
    let (prepared, baked, walked, _) = bake_and_walk(&scene, "slab", 64, &skin);
    let by_octree = prepared
        .integrate(
            &skin,
            &OctreeIntegrator::default(),
            DEFAULT_TOLERANCE,
            &Control::new(),
        )
        .unwrap()
        .exitance;
    let radius = |i: usize| prepared.surfels.position[i].truncate().length();
    let faces: Vec<usize> = (0..baked.len())
        .filter(|&i| prepared.surfels.normal[i].z.abs() > 0.5 && radius(i) < 15.0)
        .collect();
    let slabs = skin.slab_profiles().unwrap();
    // Thin in red only: 2 mm is 0.5 of red's diffusion length, 1.5 of
    // green's, 3 of blue's.
    let thin = [0, 1, 2].map(|c| slabs.is_thin(thickness.into(), c));
    assert_eq!(thin, [true, false, false], "{:?}", slabs.thin_below);
    let rings = [0.0, 2.0, 4.0, 6.0, 8.0, 11.0, 15.0];
    let mut wholes = Vec::new();
    let mut worst_ring = 0.0f64;
    for top in [true, false] {
        let face: Vec<usize> = faces
            .iter()
            .copied()
            .filter(|&i| (prepared.surfels.normal[i].z > 0.0) == top)
            .collect();
        let ratio = |map: &[[f32; 3]], texels: &[usize], c: usize| {
            mean(map, texels, c) / mean(&walked, texels, c)
        };
        for pair in rings.windows(2) {
            let ring: Vec<usize> = face
                .iter()
                .copied()
                .filter(|&i| (pair[0]..pair[1]).contains(&radius(i)))
                .collect();
            let ratios = [0, 1, 2].map(|c| format!("{:.2}", ratio(&baked, &ring, c)));
            let octree_red = ratio(&by_octree, &ring, 0);
            eprintln!(
                "top face {top}, {}–{} mm: {}; red by the octree {octree_red:.2}",
                pair[0],
                pair[1],
                ratios.join(" / "),
            );
            for red in [ratio(&baked, &ring, 0), octree_red] {
                worst_ring = worst_ring.max((red - 1.0).abs());
            }
        }
        for c in 0..3 {
            let whole = ratio(&baked, &face, c);
            eprintln!("top face {top}, channel {c}: within 15 mm {whole:.3} of the walk");
            wholes.push(whole);
        }
    }
    assert!(wholes.iter().all(|w| (w - 1.0).abs() < 0.15), "{wholes:?}");
    assert!(worst_ring < 0.07, "a ring of red {worst_ring:.3} off");
}

/// Blender's default skin: Principled, Random Walk, Base Color (0.8, 0.55,
/// 0.45), Radius (1, 0.35, 0.2), Subsurface Scale 0.05 m, as Cycles reads
/// it (red's diffusion length 25 mm, its mean free path 4 mm).
fn blender_default_skin() -> Scattering {
    scattering_for(&principled_skin(50.0), Model::Dipole)
}

/// The bake over the walk in rings (inner and outer radius, mm) about the
/// point under a point light 20 mm above the middle of the top face of a
/// `side` × `side` × `depth` block of Blender's default skin, per channel:
/// a mean over each ring of the face.
fn rings_under_a_bulb(side: f32, depth: f32, rings: &[(f32, f32)]) -> Vec<[f64; 3]> {
    let skin = blender_default_skin();
    let block = stretched(cube(1.0), Vec3::new(side, side, depth), "block");
    let light = point_light_at(Vec3::new(0.0, 0.0, depth / 2.0 + 20.0));
    let prepared = prepared(&scene(vec![block], vec![light]), "block", 192);
    let baked = prepared
        .integrate(&skin, &BruteIntegrator, DEFAULT_TOLERANCE, &Control::new())
        .unwrap()
        .exitance;
    let radius = |i: usize| prepared.surfels.position[i].truncate().length();
    let top: Vec<usize> = (0..baked.len())
        .filter(|&i| prepared.surfels.normal[i].z > 0.5)
        .filter(|&i| rings.iter().any(|&(_, outer)| radius(i) < outer))
        .collect();
    let settings = WalkSettings {
        walks: 256,
        max_events: 1 << 16,
        seed: 7,
        start: StartDirection::Pencil,
    };
    let medium = WalkMedium::of_material(&skin.material).unwrap();
    let estimate =
        walk_surfels(&prepared, &medium, Some(&top), &settings, &Control::new()).unwrap();
    let mut walked = vec![[0.0f32; 3]; baked.len()];
    for (k, &i) in top.iter().enumerate() {
        walked[i] = prepared.after_scattering(i, estimate.exitance[k]);
    }
    rings
        .iter()
        .map(|&(inner, outer)| {
            let ring: Vec<usize> = top
                .iter()
                .copied()
                .filter(|&i| (inner..outer).contains(&radius(i)))
                .collect();
            let ratio = [0, 1, 2].map(|c| mean(&baked, &ring, c) / mean(&walked, &ring, c));
            eprintln!(
                "{side} × {side} × {depth} mm, {}–{} mm ({} texels): {:.2} / {:.2} / {:.2}",
                inner,
                outer,
                ring.len(),
                ratio[0],
                ratio[1],
                ratio[2]
            );
            ratio
        })
        .collect()
}

/// A body wider and deeper than light's spread is a half-space, and the
/// corrected profile is light's there at the reach of Blender's default
/// skin: under a point light on a 400 × 400 × 200 mm block the bake is
/// within 7% of the walk in every ring out to 170 mm (red's diffusion
/// length is 25 mm; its light falls 500-fold over these rings).
#[test]
fn a_block_wider_than_light_spreads_matches_the_walk_ring_by_ring() {
    let edges = [0.0, 10.0, 20.0, 30.0, 45.0, 60.0, 80.0, 100.0, 130.0, 170.0];
    let rings: Vec<(f32, f32)> = edges.windows(2).map(|w| (w[0], w[1])).collect();
    for (ring, ratio) in rings_under_a_bulb(400.0, 200.0, &rings).iter().enumerate() {
        for (c, r) in ratio.iter().enumerate() {
            assert!((r - 1.0).abs() < 0.07, "ring {ring}, channel {c}: {r:.3}");
        }
    }
}

/// Where a block is about as wide as light spreads, the top face's light
/// stays within 10% of the walk's, but not its shape: near the rim, where
/// light leaks through the sides, the profile (whose far field hugs a
/// plane that does not end) puts more light than the walk
/// (docs/accuracy.md, "Where a body ends within light's spread").
#[test]
fn a_block_as_wide_as_light_spreads_keeps_its_top_face_s_light() {
    // The whole face (57 mm reaches its corners), then rings.
    let rings = [
        (0.0, 57.0),
        (0.0, 10.0),
        (10.0, 20.0),
        (20.0, 30.0),
        (30.0, 45.0),
        (45.0, 57.0),
    ];
    let ratios = rings_under_a_bulb(80.0, 40.0, &rings);
    for (c, (whole, middle)) in ratios[0].iter().zip(&ratios[1]).enumerate() {
        assert!((whole - 1.0).abs() < 0.1, "channel {c}: {whole:.3}");
        assert!((middle - 1.0).abs() < 0.1, "channel {c}: {middle:.3}");
    }
}

/// The map is what light gives along the normal (the walk turned round, as
/// Cycles' bake sees it), not the flux leaving: on a backlit 3 mm slab of
/// Blender's default skin (30 mm square, a sun straight up from below) the
/// walk's own map carries more power than entered, and the bake, held to
/// light rather than to that power, meets the walk in the middle of both
/// faces. When the bake scaled its map down to the power entering, red was
/// 0.944 of the walk on the far face and 0.954 on the lit one.
#[test]
fn a_backlit_slab_keeps_light_s_level_where_its_map_carries_more_power_than_entered() {
    let material = principled_skin(50.0);
    let skin = scattering_for(&material, Model::Dipole);
    let slab = stretched(cube(1.0), Vec3::new(30.0, 30.0, 3.0), "slab");
    let scene = scene(vec![slab], vec![sun_from(Vec3::Z)]);
    let request = sssbake::BakeRequest {
        resolution: 64,
        materials: sssbake::materials::MaterialAssignment::everywhere(material, "test"),
        ..sssbake::BakeRequest::default()
    };
    let prepared = prepare_with(&scene, "slab", &request, &Control::new()).unwrap();
    let baked = prepared
        .integrate(&skin, &BruteIntegrator, DEFAULT_TOLERANCE, &Control::new())
        .unwrap()
        .exitance;
    let medium = WalkMedium::of_material(&skin.material).unwrap();
    let settings = WalkSettings {
        walks: 1024,
        max_events: 1 << 14,
        seed: 7,
        start: StartDirection::Pencil,
    };
    let estimate = walk_surfels(&prepared, &medium, None, &settings, &Control::new()).unwrap();
    let walked: Vec<[f32; 3]> = (0..baked.len())
        .map(|i| prepared.after_scattering(i, estimate.exitance[i]))
        .collect();
    let (walk_red, entering_red) = (
        prepared.power(&walked)[0],
        prepared.power(&prepared.entering())[0],
    );
    eprintln!(
        "red: the walk's map carries {:.3} of the power entering",
        walk_red / entering_red
    );
    assert!(
        walk_red > 1.03 * entering_red,
        "{walk_red} against {entering_red}"
    );
    // The middle of each face, within 9 mm of its centre.
    let face = |up: bool| -> Vec<usize> {
        (0..baked.len())
            .filter(|&i| {
                let (p, n) = (prepared.surfels.position[i], prepared.surfels.normal[i]);
                p.x.abs() < 9.0 && p.y.abs() < 9.0 && n.z.abs() > 0.5 && (n.z > 0.0) == up
            })
            .collect()
    };
    for (name, texels) in [("far (top)", face(true)), ("lit (bottom)", face(false))] {
        assert!(texels.len() > 100, "{name}: {} texels", texels.len());
        let ratios = [0, 1, 2].map(|c| mean(&baked, &texels, c) / mean(&walked, &texels, c));
        eprintln!("{name} face: bake / walk {ratios:.3?}");
        for (c, r) in ratios.iter().enumerate() {
            assert!((r - 1.0).abs() < 0.03, "{name} face, channel {c}: {r:.3}");
        }
    }
}
