//! The whole bake on seeded extreme combinations: albedo near 0 and 1, σt
//! from 1e-6 to 1e6 per mm, η from 1.0001 to 3, layers from 1e-6 mm thick
//! to semi-infinite, g and roughness across their ranges (smooth to 1), meshes with
//! degenerate triangles and collapsed UVs, lights from zero to enormous,
//! every integrator. Every map is finite and non-negative and no bake makes
//! energy: the power leaving (exitance × area) never exceeds the power
//! entering (transmitted irradiance × area). `SSSBAKE_SWEEP_CASES` sets the
//! number of combinations (default a few for the test command; 10000 for
//! the long run) and `SSSBAKE_SWEEP_SEED` their seed (default 15). The
//! cases run in parallel; a bake the plan's work limits refuse up front
//! counts as refused (at most a quarter may be), any other refusal as a
//! failure. The output lists the refusals, the slowest case with its
//! combination and the time by integrator.

mod lit_scenes;

use glam::{Vec2, Vec3};
use lit_scenes::{scene, sphere, sun_from};
use rayon::prelude::*;
use sssbake::control::Control;
use sssbake::materials::MaterialAssignment;
use sssbake::transport::Method;
use sssbake::{BakeRequest, Mesh, bake, plan};
use sssbake_profile::material::{Layer, Material, Optics};
use std::time::Instant;

/// SplitMix64: a seeded stream of uniform numbers, repeatable everywhere.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn pick<T: Copy>(&mut self, from: &[T]) -> T {
        from[(self.next() % from.len() as u64) as usize]
    }
    /// Log-uniform in [lo, hi].
    fn log(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + self.unit() * (hi.ln() - lo.ln())).exp()
    }
}

/// One combination, described for the failure message.
#[derive(Debug)]
struct Combination {
    albedo: f64,
    sigma_t: f64,
    ior: f64,
    thickness_mm: Option<f64>,
    g: f64,
    roughness: Option<f64>,
    light: f32,
    degenerate: bool,
    method: Method,
}

fn draw(rng: &mut Rng) -> Combination {
    let (any_albedo, any_thickness) = (rng.unit(), rng.log(1e-6, 1e3));
    Combination {
        albedo: rng.pick(&[1e-6, 1e-3, 0.5, 0.99, 0.999_999, any_albedo]),
        sigma_t: rng.log(1e-6, 1e6),
        ior: 1.0001 + rng.unit() * 1.9999,
        thickness_mm: rng.pick(&[Some(1e-6), Some(any_thickness), Some(1e3), None]),
        g: rng.pick(&[0.0, -0.9, 0.9, 0.99]),
        roughness: rng.pick(&[None, Some(1e-3), Some(0.5), Some(1.0)]),
        light: rng.pick(&[0.0, 1e-20, 1.0, 1e6, 1e12]),
        degenerate: rng.unit() < 0.5,
        method: rng.pick(&Method::ALL),
    }
}

/// A 10 mm sphere, with a zero-area triangle and a triangle whose UVs
/// collapse to a point when `degenerate`.
fn ball(degenerate: bool) -> Mesh {
    let mut mesh = sphere(10.0, 8, 12);
    if degenerate {
        let n = mesh.positions.len() as u32;
        let p = mesh.positions[0];
        mesh.positions.extend([p, p, p + Vec3::X * 1e-3]);
        let uvs = mesh.uvs.as_mut().unwrap();
        uvs.extend([Vec2::splat(0.5); 3]);
        mesh.triangles.push([n, n + 1, n + 2]);
        mesh.triangles.push([0, 1, n + 2]);
    }
    Mesh::new(&mesh.name, mesh.positions, None, mesh.uvs, mesh.triangles)
        .unwrap()
        .0
}

fn material(c: &Combination) -> Material {
    let sigma_s = c.albedo * c.sigma_t;
    Material {
        name: "extreme".into(),
        optics: Optics::Layers(vec![Layer {
            sigma_a: [c.sigma_t - sigma_s; 3],
            sigma_s: [sigma_s; 3],
            g: c.g,
            ior: c.ior,
            thickness_mm: c.thickness_mm,
        }]),
        coat_ior: None,
        top_layer: sssbake_profile::material::TopLayer::Diffusion,
        roughness: c.roughness.unwrap_or(0.0),
    }
}

/// Bakes combination `c`: why it was refused, or what is wrong with its
/// maps, or nothing.
fn failure_of(c: &Combination) -> Result<Option<String>, String> {
    let mut light = sun_from(Vec3::new(0.3, -0.2, -1.0));
    light.intensity = c.light;
    let scene = scene(vec![ball(c.degenerate)], vec![light]);
    let request = BakeRequest {
        resolution: 24,
        method: c.method,
        roughness: c.roughness,
        materials: MaterialAssignment::everywhere(material(c), "sweep"),
        ..BakeRequest::default()
    };
    let (objects, _) = plan(&scene, &request)
        .and_then(|p| bake(&scene, &p, &Control::new()))
        .map_err(|e| e.to_string())?;
    for object in &objects {
        let area = &object.prepared.surfels.area;
        let (mut entering, mut leaving) = (0.0f64, 0.0f64);
        for (s, (m, e)) in object
            .exitance
            .iter()
            .zip(&object.prepared.irradiance)
            .enumerate()
        {
            if m.iter().chain(e).any(|v| !v.is_finite() || *v < 0.0) {
                return Ok(Some(format!("texel {s}: exitance {m:?}, irradiance {e:?}")));
            }
            entering += e.iter().map(|&v| f64::from(v)).sum::<f64>() * f64::from(area[s]);
            leaving += m.iter().map(|&v| f64::from(v)).sum::<f64>() * f64::from(area[s]);
        }
        if leaving > entering * 1.02 + 1e-30 {
            return Ok(Some(format!("{leaving:e} leaves, {entering:e} enters")));
        }
    }
    Ok(None)
}

/// Found by the long sweep (seed 7, case 542, importance): on a slab
/// 5.7e-5 mm thick of σt 25215 /mm (optical depth 1.45, η 1.0074) the exact
/// sum returned about 35 times the power that entered. The profile's table
/// carried the Hankel transform's round-off, 10⁻⁹ of the peak, as a plateau
/// out to 10⁵ times the slab's scale, which over that area held many times
/// the total; the table now ends where it holds the total.
#[test]
fn a_thin_dense_slab_makes_no_energy() {
    let c = Combination {
        albedo: 0.5,
        sigma_t: 25215.060239435825,
        ior: 1.007407080467361,
        thickness_mm: Some(5.7497780913299136e-5),
        g: 0.0,
        roughness: Some(1.0),
        light: 1e12,
        degenerate: false,
        method: Method::Brute,
    };
    assert_eq!(failure_of(&c), Ok(None));
}

/// Found by the long sweep (seed 2026, case 9066, texture): albedo
/// 0.999999 at σt 0.18 /mm reaches metres, far past the 10 mm ball. The
/// texture-space blurs divide by the blurred mask of known surface, which
/// for a Gaussian wider than the whole layout fills in an endless surface
/// lit at the mean, and returned 1.02 times the power entering (the exact
/// sum returns 0.62 of it). Each Gaussian now keeps at most its weight of
/// the power entering.
#[test]
fn a_blur_wider_than_the_object_makes_no_energy() {
    let c = Combination {
        albedo: 0.999999,
        sigma_t: 0.17787585519982832,
        ior: 2.5531202957436103,
        thickness_mm: None,
        g: -0.9,
        roughness: Some(1.0),
        light: 1e12,
        degenerate: false,
        method: Method::Texture,
    };
    assert_eq!(failure_of(&c), Ok(None));
}

#[test]
fn extreme_bakes_stay_finite_non_negative_and_make_no_energy() {
    let cases = std::env::var("SSSBAKE_SWEEP_CASES")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(12);
    let seed = std::env::var("SSSBAKE_SWEEP_SEED")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(15);
    let mut rng = Rng(seed);
    // Drawn in order, so case n of a seed is the same however the cases
    // are then spread over threads.
    let combinations: Vec<Combination> = (0..cases).map(|_| draw(&mut rng)).collect();
    let outcomes: Vec<(Result<Option<String>, String>, f64)> = combinations
        .par_iter()
        .map(|c| {
            let start = Instant::now();
            let outcome = failure_of(c);
            (outcome, start.elapsed().as_secs_f64())
        })
        .collect();
    let (mut failures, mut refused) = (Vec::new(), Vec::new());
    for (case, (c, (outcome, _))) in combinations.iter().zip(&outcomes).enumerate() {
        match outcome {
            // Refused up front by the plan's work bound, in milliseconds,
            // rather than run for hours: the bound is what keeps each case
            // bounded in time. Any other refusal is a failure.
            Err(e) if e.starts_with("max_evaluations: ") || e.starts_with("max_memory: ") => {
                refused.push(format!("case {case} {c:?}: {e}"))
            }
            Err(e) => failures.push(format!("case {case} {c:?}: refused: {e}")),
            Ok(Some(failure)) => failures.push(format!("case {case} {c:?}: {failure}")),
            Ok(None) => {}
        }
    }
    eprintln!(
        "{cases} combinations (seed {seed}), {} refused:\n{}",
        refused.len(),
        refused.join("\n")
    );
    report_times(&combinations, &outcomes);
    assert!(refused.len() * 4 <= cases, "most combinations must bake");
    assert!(
        failures.is_empty(),
        "{} of {cases}:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Prints where the time went: the slowest case with its combination, and
/// the total by integrator (printed, never asserted: speed is for benchmarks).
fn report_times(combinations: &[Combination], outcomes: &[(Result<Option<String>, String>, f64)]) {
    let Some((slowest, (_, seconds))) = outcomes
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.1.total_cmp(&b.1.1))
    else {
        return;
    };
    eprintln!(
        "slowest: case {slowest} {:?}, {seconds:.2} s",
        combinations[slowest]
    );
    for method in Method::ALL {
        let times: Vec<f64> = combinations
            .iter()
            .zip(outcomes)
            .filter(|(c, _)| c.method == method)
            .map(|(_, (_, t))| *t)
            .collect();
        eprintln!(
            "{}: {} cases, {:.1} s in all",
            method.name(),
            times.len(),
            times.iter().sum::<f64>()
        );
    }
}
