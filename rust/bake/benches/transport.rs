//! The integrators at scale, as ratios against the exact sum measured in
//! the same run: a 100k-triangle bumpy head-sized sphere at 2048² in skin1.
//! The exact sum over every texel would take many minutes, so it runs on
//! an evenly spread subset of texels (the same per-texel work) and its
//! full time is that × the texel count; errors are measured on the same
//! subset. Run: `cargo bench -p sssbake --bench transport`
//! (`SSSBAKE_BENCH_RESOLUTION=1024` for a quicker look).

use glam::Vec3;
use sssbake::control::Control;
use sssbake::materials::MaterialAssignment;
use sssbake::pipeline::prepare;
use sssbake::prepared::Prepared;
use sssbake::rays::RayScene;
use sssbake::request::DEFAULT_TOLERANCE;
use sssbake::transport::accuracy::relative_errors;
use sssbake::transport::importance::{self, Surface};
use sssbake::transport::integrator::IntegratorSettings;
use sssbake::transport::sources::{OwnSource, Targets};
use sssbake::transport::{Method, brute};
use sssbake::{BakeRequest, Light, LightKind, Mesh, Scene, SceneObject, plan};
use sssbake_profile::model::Model;
use sssbake_profile::presets::preset;
use std::time::Instant;

#[path = "../tests/shapes.rs"]
mod shapes;

/// An 80 mm sphere of 99,856 triangles with 3 mm bumps: curved, with
/// concave dips, about a head's size.
fn bumpy_sphere() -> Mesh {
    let mut mesh = shapes::sphere(80.0, 158, 316);
    for (p, n) in mesh.positions.iter_mut().zip(mesh.normals.iter_mut()) {
        let dir = p.normalize();
        let bump = 3.0 * (6.0 * dir.z.acos()).sin() * (6.0 * dir.y.atan2(dir.x)).sin();
        *p = dir * (80.0 + bump);
        *n = dir;
    }
    Mesh::new("head", mesh.positions, None, mesh.uvs, mesh.triangles)
        .unwrap()
        .0
}

fn scene() -> Scene {
    let light = |name: &str, kind, intensity, position, direction: Vec3| Light {
        name: name.into(),
        kind,
        color: [1.0; 3],
        intensity,
        position,
        direction: direction.normalize(),
        tangent: Vec3::X,
        casts_shadow: true,
    };
    Scene {
        source: "benchmark".into(),
        millimetres_per_unit: 1.0,
        objects: vec![SceneObject {
            mesh: bumpy_sphere(),
            uv_sets: vec![],
            ..SceneObject::default()
        }],
        lights: vec![
            light(
                "key",
                LightKind::Directional { angle: 0.0 },
                1.0,
                Vec3::ZERO,
                Vec3::new(-1.0, -0.4, -0.6),
            ),
            light(
                "rim",
                LightKind::Point { radius_mm: 20.0 },
                0.2,
                Vec3::new(150.0, 150.0, 0.0),
                Vec3::NEG_Z,
            ),
        ],
        notes: vec![],
    }
}

fn main() {
    let resolution: u32 = std::env::var("SSSBAKE_BENCH_RESOLUTION")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2048);
    let scene = scene();
    let request = BakeRequest {
        resolution,
        materials: MaterialAssignment::everywhere(preset("skin1").unwrap(), "skin1"),
        model: Some(Model::Dipole),
        ..BakeRequest::default()
    };
    let control = Control::new();
    let start = Instant::now();
    let plan = plan(&scene, &request).unwrap();
    let planned = &plan.objects[0];
    let skin = planned.scattering_profile.as_ref();
    let (profile, kernel) = (&skin.profile, &skin.kernel);
    let prepared: Prepared = prepare(
        &scene,
        0,
        planned.layout.clone(),
        &plan.request,
        skin,
        true,
        &control,
    )
    .unwrap();
    let texels = prepared.surfels.len();
    println!(
        "{} triangles, {resolution}² → {texels} texels, d_max {:.1} mm, {} threads; prepared in {:.2} s",
        prepared.mesh.triangles.len(),
        kernel.d_max,
        rayon::current_num_threads(),
        start.elapsed().as_secs_f64()
    );
    // Every k-th texel: about 4000 targets for the exact sum.
    let stride = (texels / 4000).max(1);
    let subset: Vec<usize> = (0..texels).step_by(stride).collect();
    let position: Vec<Vec3> = subset
        .iter()
        .map(|&s| prepared.surfels.position[s])
        .collect();
    let normal: Vec<Vec3> = subset.iter().map(|&s| prepared.surfels.normal[s]).collect();
    let piece: Vec<u32> = subset.iter().map(|&s| prepared.surfels.piece[s]).collect();
    let targets = Targets {
        position: &position,
        normal: &normal,
        own: OwnSource::Listed(&subset),
        piece: &piece,
        part: &[],
    };
    let start = Instant::now();
    let reference = brute::integrate(kernel, &prepared.texel_sources(), targets, &control).unwrap();
    let brute_full = start.elapsed().as_secs_f64() * texels as f64 / subset.len() as f64;
    println!(
        "{:<34} {:>10} {:>9} {:>11} {:>9}",
        "method", "seconds", "speed-up", "rel. RMSE", "max"
    );
    println!(
        "{:<34} {:>10.1} {:>9} {:>11} {:>9}",
        "brute (timed on 1 texel in stride)", brute_full, "1×", "—", "—"
    );
    let report = |name: &str, seconds: f64, got: &[[f32; 3]]| {
        let (rmse, max) = relative_errors(got, &reference);
        println!(
            "{name:<34} {seconds:>10.2} {:>8.0}× {:>10.2}% {:>8.2}%",
            brute_full / seconds,
            100.0 * rmse,
            100.0 * max
        );
    };
    let settings = |change: &dyn Fn(&mut IntegratorSettings)| {
        let mut settings = IntegratorSettings::default();
        change(&mut settings);
        settings
    };
    let default_octree = format!(
        "octree ε {} (default)",
        IntegratorSettings::default().octree.epsilon
    );
    for (name, method, settings) in [
        (default_octree.as_str(), Method::Octree, settings(&|_| {})),
        (
            "octree ε 0.2",
            Method::Octree,
            settings(&|s| s.octree.epsilon = 0.2),
        ),
        ("texture 6 Gaussians", Method::Texture, settings(&|_| {})),
        (
            "texture 3 Gaussians",
            Method::Texture,
            settings(&|s| s.texture.gaussians = 3),
        ),
    ] {
        let result = prepared
            .integrate(skin, settings.get(method), DEFAULT_TOLERANCE, &control)
            .unwrap();
        let picked: Vec<[f32; 3]> = subset.iter().map(|&s| result.exitance[s]).collect();
        report(name, result.seconds, &picked);
    }
    // Monte Carlo is per texel too: timed on the subset and scaled.
    let probes = RayScene::new(&[&prepared.mesh]);
    let texture = prepared.entering_texture();
    let surface = Surface {
        mesh: &prepared.mesh,
        uvs: &prepared.uvs,
        probes: &probes,
        irradiance: &texture,
        resolution: prepared.surfels.resolution,
        oblique: None,
        pieces: None,
    };
    for samples in [64u32, 256] {
        let start = Instant::now();
        let got = importance::integrate(
            kernel,
            profile.as_ref(),
            &surface,
            &position,
            &normal,
            samples,
            1,
            &control,
        )
        .unwrap();
        let seconds = start.elapsed().as_secs_f64() * texels as f64 / subset.len() as f64;
        report(&format!("importance {samples} spp (scaled)"), seconds, &got);
    }
}
