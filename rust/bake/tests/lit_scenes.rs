//! Scenes built by hand for the transport tests: lit squares and spheres.
#![allow(dead_code)]

#[path = "shapes.rs"]
mod shapes;

use glam::Vec3;
use sssbake::control::Control;
use sssbake::materials::MaterialAssignment;
use sssbake::pipeline::prepare;
use sssbake::prepared::Prepared;
use sssbake::scattering::{D_MAX_EPSILON, Scattering};
use sssbake::transport::Method;
use sssbake::transport::brute;
use sssbake::transport::integrator::IntegratorSettings;
use sssbake::transport::kernel::Kernel;
use sssbake::transport::sources::{OwnSource, Sources, Targets};
use sssbake::transport::walk::walk_surfels;
use sssbake::walk::{StartDirection, WalkMedium, WalkSettings};
use sssbake::{BakeRequest, Error, Light, LightKind, Mesh, Scene, SceneObject, plan};
use sssbake_profile::material::Material;
use sssbake_profile::model::Model;
use sssbake_profile::presets::preset;

#[allow(unused_imports)]
pub use shapes::{boxes, cube, quad, sphere, stretched};

/// A light from straight above (−Z), 1 W/m², no angular size.
pub fn sun_from(direction: Vec3) -> Light {
    Light {
        name: "sun".into(),
        kind: LightKind::Directional { angle: 0.0 },
        color: [1.0; 3],
        intensity: 1.0,
        position: Vec3::ZERO,
        direction: direction.normalize(),
        tangent: Vec3::X,
        casts_shadow: true,
    }
}

/// A point light of 1 W/sr at `position`, no size.
pub fn point_light_at(position: Vec3) -> Light {
    Light {
        name: "bulb".into(),
        kind: LightKind::Point { radius_mm: 0.0 },
        position,
        direction: Vec3::Z,
        ..sun_from(Vec3::NEG_Z)
    }
}

/// A square of `size` mm centred on the origin in the xy plane, facing +Z.
pub fn centred_square(size: f32, name: &str) -> Mesh {
    let mut mesh = quad(size);
    for p in &mut mesh.positions {
        *p -= Vec3::new(size / 2.0, size / 2.0, 0.0);
    }
    mesh.name = name.into();
    mesh
}

/// A scene of `meshes` (objects in order) and `lights`.
pub fn scene(meshes: Vec<Mesh>, lights: Vec<Light>) -> Scene {
    Scene {
        source: "test scene".into(),
        millimetres_per_unit: 1.0,
        objects: meshes
            .into_iter()
            .map(|mesh| SceneObject {
                uv_sets: mesh.uvs.clone().into_iter().collect(),
                mesh,
                ..SceneObject::default()
            })
            .collect(),
        lights,
        notes: vec![],
    }
}

/// The profile of preset `name` by `model`, with its kernel.
pub fn scattering_of(name: &str, model: Model) -> Scattering {
    scattering_for(&preset(name).unwrap(), model)
}

/// The profile of `material` by `model`, with its kernel.
pub fn scattering_for(material: &Material, model: Model) -> Scattering {
    Scattering::new(material.clone(), Some(model), 6, D_MAX_EPSILON).unwrap()
}

/// Skin as Blender's Principled BSDF gives it and Cycles reads it:
/// Random Walk, Base Color (0.8, 0.55, 0.45), Radius (1, 0.35, 0.2), IOR
/// 1.4, at Subsurface Scale `scale_mm` (Blender's default 50 mm).
pub fn principled_skin(scale_mm: f64) -> Material {
    sssbake::materials::Principled {
        name: "skin".into(),
        base_colour: [0.8, 0.55, 0.45],
        subsurface_weight: 1.0,
        radius: [1.0, 0.35, 0.2],
        scale_mm,
        method: sssbake::materials::SubsurfaceMethod::RandomWalk,
        ior: 1.4,
        specular_ior_level: 0.5,
        subsurface_ior: 1.4,
        anisotropy: 0.0,
        roughness: 0.0,
        albedo: sssbake::materials::AlbedoMapping::Cycles,
    }
    .to_material()
    .unwrap()
}

/// A request for `resolution`² maps of skin1.
pub fn request(resolution: u32) -> BakeRequest {
    BakeRequest {
        resolution,
        materials: MaterialAssignment::everywhere(preset("skin1").unwrap(), "test"),
        ..BakeRequest::default()
    }
}

/// Plans `request` for object `object` alone and lights it under `control`.
pub fn prepare_with(
    scene: &Scene,
    object: &str,
    request: &BakeRequest,
    control: &Control,
) -> Result<Prepared, Error> {
    let request = BakeRequest {
        objects: vec![object.to_string()],
        ..request.clone()
    };
    let plan = plan(scene, &request)?;
    let planned = &plan.objects[0];
    prepare(
        scene,
        planned.index,
        planned.layout.clone(),
        &plan.request,
        &planned.scattering_profile,
        true,
        control,
    )
}

/// Prepares object `object` of `scene` at `resolution`² lit by its lights.
pub fn prepared(scene: &Scene, object: &str, resolution: u32) -> Prepared {
    prepare_with(scene, object, &request(resolution), &Control::new()).unwrap()
}

/// The exitance of `prepared` by `method` with `settings`: the
/// integrator's sums of the profile, with the colour after scattering but
/// without the corrected model's level and thin parts
/// (`Prepared::integrate` adds those), so an integrator is tested against
/// the profile's own mathematics.
pub fn exitance(
    prepared: &Prepared,
    scattering: &Scattering,
    method: Method,
    settings: &IntegratorSettings,
) -> Vec<[f32; 3]> {
    let sums = settings
        .get(method)
        .integrate(prepared, scattering, &Control::new())
        .unwrap()
        .exitance;
    sums.iter()
        .enumerate()
        .map(|(i, &m)| prepared.after_scattering(i, m))
        .collect()
}

/// Integrator settings with `samples` importance probes, `gaussians` and
/// `seed`.
pub fn with(samples: u32, gaussians: usize, seed: u64) -> IntegratorSettings {
    let mut settings = IntegratorSettings::default();
    settings.importance.samples = samples;
    settings.texture.gaussians = gaussians;
    settings.seed(seed);
    settings
}

/// Indices of surfels at least `margin` mm inside a centred square of
/// half-width `half` mm.
pub fn interior(prepared: &Prepared, half: f32, margin: f32) -> Vec<usize> {
    (0..prepared.surfels.len())
        .filter(|&s| {
            let p = prepared.surfels.position[s];
            p.x.abs() < half - margin && p.y.abs() < half - margin
        })
        .collect()
}

/// The exact sum of `kernel` over `sources` at the surfels `texels` of
/// `prepared` (each its own source), gathering from every piece.
pub fn exact_sum_at(
    prepared: &Prepared,
    kernel: &Kernel,
    sources: &Sources,
    texels: &[usize],
) -> Vec<[f32; 3]> {
    let surfels = &prepared.surfels;
    let position: Vec<Vec3> = texels.iter().map(|&i| surfels.position[i]).collect();
    let normal: Vec<Vec3> = texels.iter().map(|&i| surfels.normal[i]).collect();
    let targets = Targets {
        position: &position,
        normal: &normal,
        own: OwnSource::Listed(texels),
        piece: &[],
        part: &[],
    };
    brute::integrate(kernel, sources, targets, &Control::new()).unwrap()
}

/// The walk's exitance and its standard error after the colour after
/// scattering, by `walks` pencils at the texels `picked`, in their order.
pub fn walked_at(
    prepared: &Prepared,
    scattering: &Scattering,
    picked: &[usize],
    walks: u32,
) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let medium = WalkMedium::of_material(&scattering.material).unwrap();
    let settings = WalkSettings {
        walks,
        max_events: 1024,
        seed: 7,
        start: StartDirection::Pencil,
    };
    let estimate =
        walk_surfels(prepared, &medium, Some(picked), &settings, &Control::new()).unwrap();
    let after = |values: &[[f32; 3]]| -> Vec<[f32; 3]> {
        picked
            .iter()
            .zip(values)
            .map(|(&i, &v)| prepared.after_scattering(i, v))
            .collect()
    };
    (after(&estimate.exitance), after(&estimate.standard_error))
}
