//! The exact sum as the reference walks it (lit sources only, a grid
//! walked by chords of the ball, blocks of distances, vectorised near
//! fields) against the same sum written plainly: every target against
//! every source, one pair at a time, through the kernel's one weight.

use super::brute;
use super::disk_kernel::DiskKernel;
use super::kernel::{Kernel, Separation};
use super::source_table::{SUBDIVISIONS, disk_area, subdivision_radius, texel_disks};
use super::sources::{OwnSource, Sources, Targets};
use crate::control::Control;
use crate::scattering::{D_MAX_EPSILON, Scattering};
use glam::Vec3;
use sssbake_profile::material::{Layer, Material, Optics};
use sssbake_profile::model::Model;
use sssbake_profile::numerics::rng::Rng;
use sssbake_profile::presets::preset;

/// The exitance at `p` (normal `n`, being source `own`) summed over every
/// source in turn.
fn plain_sum(
    disks: &DiskKernel,
    sources: &Sources,
    p: Vec3,
    n: Vec3,
    own: Option<usize>,
) -> [f64; 3] {
    let kernel = disks.kernel();
    let transmits = kernel.transmits();
    let mut sum = [0.0f64; 3];
    for j in 0..sources.len() {
        let x = sources.position[j];
        let d2 = (x - p).length_squared();
        if d2 > kernel.d_max * kernel.d_max {
            continue;
        }
        let area = sources.area[j];
        let shape = sources.footprint.get(j).copied();
        let w = if own == Some(j) {
            match shape {
                Some([u, v]) if u.cross(v).length() > 0.0 => kernel.parallelogram_mean(u, v),
                _ => kernel.disk_mean(0.0, (area / std::f32::consts::PI).sqrt())[0],
            }
        } else if let Some([u, v]) = shape
            && d2 < subdivision_radius(u, v).powi(2)
        {
            // The parallelogram in SUBDIVISIONS² equal parts.
            let slot = disks.slot(area / (SUBDIVISIONS * SUBDIVISIONS) as f32);
            let mut w = [0.0f32; 3];
            for a in 0..SUBDIVISIONS {
                for b in 0..SUBDIVISIONS {
                    let along = |i: usize| (i as f32 + 0.5) / SUBDIVISIONS as f32 - 0.5;
                    let q = x + (u * along(a) + v * along(b));
                    let separation = Separation::new(
                        q,
                        sources.normal[j],
                        p,
                        n,
                        (q - p).length_squared(),
                        transmits,
                    );
                    let part = disks.weight(separation, slot);
                    for c in 0..3 {
                        w[c] += part[c] / (SUBDIVISIONS * SUBDIVISIONS) as f32;
                    }
                }
            }
            w
        } else {
            let separation = Separation::new(x, sources.normal[j], p, n, d2, transmits);
            disks.weight(separation, disks.slot(disk_area(sources, j)))
        };
        for c in 0..3 {
            sum[c] += w[c] as f64 * sources.irradiance[j][c] as f64 * area as f64;
        }
    }
    sum
}

/// A sheet folded into a V with a second sheet 1.5 mm under it facing the
/// other way (light crosses to it when the kernel transmits), of texels
/// 0.4 mm by 0.5 mm, some stretched 3:1 and some without area, a third
/// of them unlit; `shaped` gives each its parallelogram.
fn folded_sheets(shaped: bool) -> Sources<'static> {
    let mut rng = Rng::new(14, 5);
    let mut s = Sources::default();
    for sheet in 0..2 {
        for i in 0..40 {
            for k in 0..30 {
                let (du, dv) = (0.4f32, if i % 7 == 3 { 1.5 } else { 0.5 });
                let fold = if i < 20 { 0.0 } else { (i - 20) as f32 * 0.3 };
                let (position, normal) = if sheet == 0 {
                    (Vec3::new(i as f32 * du, k as f32 * 0.5, fold), Vec3::Z)
                } else {
                    (Vec3::new(i as f32 * du, k as f32 * 0.5, -1.5), Vec3::NEG_Z)
                };
                let area = if (i + k) % 17 == 0 { 0.0 } else { du * dv };
                let lit = rng.uniform() > 0.33;
                let e = [0, 1, 2].map(|_| {
                    if lit {
                        1.0 + 99.0 * rng.uniform() as f32
                    } else {
                        0.0
                    }
                });
                s.position.to_mut().push(position);
                s.normal.to_mut().push(normal);
                s.area.to_mut().push(area);
                s.irradiance.push(e);
                if shaped {
                    let u = Vec3::X * du;
                    let v = if area > 0.0 { Vec3::Y * dv } else { Vec3::ZERO };
                    s.footprint.to_mut().push([u, v]);
                }
            }
        }
    }
    s
}

/// Checks the walked sum against the plain one at every source as its own
/// target and at points that are no source, within 1e-5 relative, and at
/// a few of them alone (which walk only the sources near them); and the
/// same of the walk that sums a unit light beside the light.
fn assert_walk_is_the_plain_sum(kernel: &Kernel, sources: &Sources) {
    let mut position = sources.position.to_vec();
    let mut normal = sources.normal.to_vec();
    let mut own: Vec<Option<usize>> = (0..sources.len()).map(Some).collect();
    for k in 0..50 {
        position.push(Vec3::new(0.31 * k as f32, 0.17 * k as f32, 0.05));
        normal.push(Vec3::Z);
        own.push(None);
    }
    let listed: Vec<usize> = own.iter().map(|o| o.unwrap_or(usize::MAX)).collect();
    let targets = Targets {
        position: &position,
        normal: &normal,
        own: OwnSource::Listed(&listed),
        piece: &[],
        part: &[],
    };
    let walked = brute::integrate(kernel, sources, targets, &Control::new()).unwrap();
    let [lit, unit] =
        brute::integrate_with_unit(kernel, sources, targets, &Control::new()).unwrap();
    let disks = texel_disks(kernel, sources);
    let plain_of = |sources: &Sources| -> Vec<[f64; 3]> {
        (0..position.len())
            .map(|i| plain_sum(&disks, sources, position[i], normal[i], own[i]))
            .collect()
    };
    let mut unlit = sources.clone();
    unlit.irradiance.fill([1.0; 3]);
    let plain = plain_of(sources);
    assert_within(&walked, &plain, "walked sum");
    // A few targets alone: only the sources within their reach are walked.
    let few: Vec<usize> = (0..position.len()).step_by(97).collect();
    let pick = |v: &[Vec3]| -> Vec<Vec3> { few.iter().map(|&i| v[i]).collect() };
    let (few_position, few_normal) = (pick(&position), pick(&normal));
    let few_listed: Vec<usize> = few.iter().map(|&i| listed[i]).collect();
    let few_targets = Targets {
        position: &few_position,
        normal: &few_normal,
        own: OwnSource::Listed(&few_listed),
        piece: &[],
        part: &[],
    };
    let alone = brute::integrate(kernel, sources, few_targets, &Control::new()).unwrap();
    let few_plain: Vec<[f64; 3]> = few.iter().map(|&i| plain[i]).collect();
    assert_within(&alone, &few_plain, "walked sum at a few targets");
    assert_within(&lit, &plain, "walked sum beside a unit light");
    assert_within(&unit, &plain_of(&unlit), "unit light's walked sum");
}

/// `got` within 1e-5 relative of `want`, where `want` is above a
/// millionth of its largest.
fn assert_within(got: &[[f32; 3]], want: &[[f64; 3]], what: &str) {
    let peak = want.iter().flatten().cloned().fold(0.0f64, f64::max);
    assert!(peak > 0.0);
    let mut worst = 0.0f64;
    for (got, want) in got.iter().zip(want) {
        for c in 0..3 {
            let scale = want[c].abs().max(1e-6 * peak);
            worst = worst.max((got[c] as f64 - want[c]).abs() / scale);
        }
    }
    assert!(worst <= 1e-5, "{what} off the plain sum by {worst:e}");
}

fn scattering(material: Material) -> Scattering {
    Scattering::new(material, None, 6, D_MAX_EPSILON).unwrap()
}

/// skin1 by the dipole: a kernel that reflects and does not transmit.
fn skin_by_dipole() -> Scattering {
    Scattering::new(
        preset("skin1").unwrap(),
        Some(Model::Dipole),
        6,
        D_MAX_EPSILON,
    )
    .unwrap()
}

#[test]
fn the_walked_sum_is_the_plain_sum_for_a_reflecting_kernel() {
    let skin = skin_by_dipole();
    assert!(!skin.kernel.transmits());
    assert_walk_is_the_plain_sum(&skin.kernel, &folded_sheets(true));
    assert_walk_is_the_plain_sum(&skin.kernel, &folded_sheets(false));
}

#[test]
fn the_walked_sum_is_the_plain_sum_for_a_transmitting_kernel() {
    let slab = scattering(Material {
        name: "slab".into(),
        optics: Optics::Layers(vec![Layer {
            sigma_a: [0.01, 0.05, 0.2],
            sigma_s: [2.0; 3],
            g: 0.0,
            ior: 1.3,
            thickness_mm: Some(2.0),
        }]),
        coat_ior: None,
        top_layer: sssbake_profile::material::TopLayer::Diffusion,
        roughness: 0.0,
    });
    assert!(slab.kernel.transmits());
    assert_walk_is_the_plain_sum(&slab.kernel, &folded_sheets(true));
}

/// A few targets in one corner of a sheet several reaches wide: the walk
/// leaves the far sources out before it sorts them, and the sums are the
/// plain sums over every source.
#[test]
fn a_few_targets_on_a_wide_sheet_sum_as_every_source_does() {
    let skin = skin_by_dipole();
    let kernel = &skin.kernel;
    let mut rng = Rng::new(3, 9);
    let mut sources = Sources::default();
    let (step, side) = (0.5f32, 240);
    assert!(step * side as f32 > 4.0 * kernel.d_max, "{}", kernel.d_max);
    for i in 0..side * side {
        let (x, y) = ((i % side) as f32 * step, (i / side) as f32 * step);
        sources.position.to_mut().push(Vec3::new(x, y, 0.0));
        sources.normal.to_mut().push(Vec3::Z);
        sources.area.to_mut().push(step * step);
        let lit = rng.uniform() > 0.5;
        sources
            .irradiance
            .push([f32::from(u8::from(lit)) * 10.0; 3]);
        sources
            .footprint
            .to_mut()
            .push([Vec3::X * step, Vec3::Y * step]);
    }
    let listed: Vec<usize> = (0..5).map(|k| k * (side + 3)).collect();
    let position: Vec<Vec3> = listed.iter().map(|&i| sources.position[i]).collect();
    let normal = vec![Vec3::Z; listed.len()];
    let targets = Targets {
        position: &position,
        normal: &normal,
        own: OwnSource::Listed(&listed),
        piece: &[],
        part: &[],
    };
    let walked = brute::integrate(kernel, &sources, targets, &Control::new()).unwrap();
    let disks = texel_disks(kernel, &sources);
    let plain: Vec<[f64; 3]> = (0..listed.len())
        .map(|k| plain_sum(&disks, &sources, position[k], normal[k], Some(listed[k])))
        .collect();
    assert_within(
        &walked,
        &plain,
        "walked sum at a few targets of a wide sheet",
    );
}
