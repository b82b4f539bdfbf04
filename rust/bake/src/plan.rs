//! What a bake of a scene will do, per object, and what it leaves out and
//! why. The plan is not a description beside the bake: it holds the
//! layouts and profiles the bake runs, so `sssbake plan` prints exactly
//! the decisions `sssbake bake` follows.

use crate::colour::{ColourMap, ColourPlan, area_mean, relative_to, texture_per_texel};
use crate::error::{Error, InputError};
use crate::irradiance::bounce::{gathering_bytes, gathering_rays};
use crate::layout::Layout;
use crate::limits::{Cost, ObjectCost, bytes_text, estimated_texels};
use crate::maps::Output;
use crate::materials::Sourced;
use crate::request::BakeRequest;
use crate::request::Lighting;
use crate::scattering::Scattering;
use crate::scene::Scene;
use crate::surface::medium::planned_rays;
use crate::surface::topology::{TopologyReport, topology_report};
use crate::transport::Method;
use crate::transport::ball_gain::BallGain;
use crate::transport::choice::{Choice, avoid_thin_parts, choose, neighbours};
use crate::transport::integrator::Work;
use crate::transport::light_check;
use crate::transport::local_slab::LocalSlab;
use crate::transport::thin::{crossing_share, thin_share};
use crate::walk::WalkMedium;
use serde::Serialize;
use std::fmt;
use std::sync::Arc;
use std::time::Instant;

/// The plan for a scene.
#[derive(Clone, Debug, Serialize)]
pub struct Plan {
    /// Input file.
    pub source: String,
    /// Millimetres per scene unit.
    pub millimetres_per_unit: f64,
    /// Texels per side.
    pub resolution: u32,
    /// Texels filled beyond each chart.
    pub margin: u32,
    /// The maps asked for.
    pub outputs: Vec<Output>,
    /// Objects to bake.
    pub objects: Vec<ObjectPlan>,
    /// Lights that light the bake, described.
    pub lights: Vec<String>,
    /// What is left out, each with its reason.
    pub left_out: Vec<String>,
    /// What the scene reader noticed.
    pub notes: Vec<String>,
    /// The memory and work the bake is estimated to take.
    pub cost: Cost,
    /// The request the plan was made for.
    #[serde(skip)]
    pub request: BakeRequest,
}

/// A stage of a bake: whether it runs, and why.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stage {
    /// Whether the stage runs.
    pub run: bool,
    /// Why it runs or is left out.
    pub reason: String,
}

impl Stage {
    fn new(run: bool, reason: impl Into<String>) -> Self {
        Stage {
            run,
            reason: reason.into(),
        }
    }
}

/// The plan for one object.
#[derive(Clone, Debug, Serialize)]
pub struct ObjectPlan {
    /// Object name.
    pub name: String,
    /// The object's index among the scene's objects.
    #[serde(skip)]
    pub index: usize,
    /// A file-name-safe form of the name, unique among the scene's objects.
    pub file_stem: String,
    /// Triangles with area.
    pub triangles: usize,
    /// Surface area, mm².
    pub area_mm2: f64,
    /// The surface's shape in words: parts, open edges, non-manifold edges.
    pub topology: String,
    /// What the bake does with the object's UVs.
    pub uvs: UvPlan,
    /// Texels the layout covers.
    pub texels: usize,
    /// The memory and work this object's bake is estimated to take.
    pub cost: ObjectCost,
    /// Surface area those texels stand for, mm².
    pub texel_area_mm2: f64,
    /// The material and its profile.
    pub material: MaterialPlan,
    /// Where the base colour came from, the nominal colour the profile is
    /// built for and the split (docs/materials.md, "Colour maps").
    pub colour: ColourPlan,
    /// Lighting: the irradiance entering every texel.
    pub lighting: Stage,
    /// Scattering: the exitance by the integrator.
    pub scattering: Stage,
    /// The integrator, when the bake scatters.
    pub integrator: Option<IntegratorPlan>,
    /// Seconds the layout took (UV analysis, unwrap, texels).
    #[serde(skip)]
    pub layout_seconds: f64,
    /// The layout the bake uses.
    #[serde(skip)]
    pub layout: Arc<Layout>,
    /// The profile the bake integrates.
    #[serde(skip)]
    pub scattering_profile: Arc<Scattering>,
}

/// What the bake does with an object's UVs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UvPlan {
    /// The UV analysis in words.
    pub verdict: String,
    /// Whether the object is unwrapped with xatlas.
    pub unwrap: bool,
    /// Why.
    pub reason: String,
    /// What is wrong with UVs baked into although they overlap or stretch.
    pub warning: Option<String>,
}

/// An object's material as the bake uses it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MaterialPlan {
    /// The material's name.
    pub name: String,
    /// Where it came from (sidecar, option, asset, default).
    pub source: String,
    /// The profile model.
    pub model: String,
    /// Index of refraction light enters through.
    pub ior: f64,
    /// RMS facet slope of the surface (0: smooth), the request's override
    /// or the material's own.
    pub roughness: f64,
    /// Radius holding all but the request's share of the reflectance, mm.
    pub d_max_mm: f32,
    /// The finest mean free path, mm.
    pub mean_free_path_mm: f64,
    /// Whether light crosses thin parts (the profile transmits).
    pub transmits: bool,
}

/// The integrator a bake runs for an object.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct IntegratorPlan {
    /// The method.
    pub method: Method,
    /// Why.
    pub reason: String,
}

/// Plans a bake of `scene` as `request` asks.
pub fn plan(scene: &Scene, request: &BakeRequest) -> Result<Plan, Error> {
    let mut request = request.clone();
    request.validate()?;
    let selected = scene.select(&request.objects)?;
    if selected.is_empty() {
        return Err(Error::Input(InputError {
            file: Some(scene.source.clone()),
            message: "has no object to bake".into(),
            ..InputError::default()
        }));
    }
    let names: Vec<&str> = scene.objects.iter().map(|o| o.mesh.name.as_str()).collect();
    if let Some(sidecar) = &request.materials.sidecar {
        sidecar.check_objects(&names)?;
    }
    let stems = file_stems(&names);
    let mut left_out: Vec<String> = (0..scene.objects.len())
        .filter(|i| !selected.contains(i))
        .map(|i| format!("object `{}`: not selected", names[i]))
        .collect();
    let lights = describe_lights(scene, &mut left_out);
    check_layouts_fit(scene, &selected, &request)?;
    let objects = selected
        .iter()
        .map(|&index| plan_object(scene, index, &stems[index], &request))
        .collect::<Result<Vec<_>, Error>>()?;
    let cost = Cost::of(&objects.iter().map(|o| o.cost).collect::<Vec<_>>());
    cost.check(&request.limits, &drivers(&objects, &request))
        .map_err(|e| e.in_file(scene.source.clone()))?;
    if !request.lights() {
        left_out.push(format!(
            "lighting and scattering: the outputs ({}) need neither",
            output_names(&request.outputs)
        ));
    } else if !request.scatters() {
        left_out.push(format!(
            "scattering: the outputs ({}) do not need it",
            output_names(&request.outputs)
        ));
    }
    Ok(Plan {
        source: scene.source.clone(),
        millimetres_per_unit: scene.millimetres_per_unit,
        resolution: request.resolution,
        margin: request.margin,
        outputs: request.outputs.clone(),
        objects,
        lights,
        left_out,
        notes: scene.notes.clone(),
        cost,
        request,
    })
}

/// Refuses, before any layout is made, a request whose layouts alone
/// could not fit: texels estimated from each object's UV area.
fn check_layouts_fit(
    scene: &Scene,
    selected: &[usize],
    request: &BakeRequest,
) -> Result<(), Error> {
    let costs: Vec<ObjectCost> = selected
        .iter()
        .map(|&i| {
            let texels = estimated_texels(&scene.objects[i].mesh, request.resolution, request.uvs);
            ObjectCost::memory(texels, request.resolution, &request.outputs)
        })
        .collect();
    let texels: f64 = costs.iter().map(|c| c.texels).sum();
    let what = format!(
        "{} object{} at {}², about {:.0} million texels",
        selected.len(),
        if selected.len() == 1 { "" } else { "s" },
        request.resolution,
        texels / 1e6
    );
    Cost::of(&costs).check(&request.limits, &what)
}

/// What drives a plan's cost, in words: the costliest object, its texels
/// and method.
fn drivers(objects: &[ObjectPlan], request: &BakeRequest) -> String {
    let Some(worst) = objects.iter().max_by(|a, b| {
        (a.cost.evaluations + a.cost.rays).total_cmp(&(b.cost.evaluations + b.cost.rays))
    }) else {
        return String::new();
    };
    let method = worst
        .integrator
        .as_ref()
        .map_or("no scattering".to_string(), |i| {
            format!("method {}", i.method)
        });
    format!(
        "{} object{} at {}²; the costliest, `{}`: {} texels, {:.1e} shadow rays, {method} with \
         {:.1e} kernel evaluations",
        objects.len(),
        if objects.len() == 1 { "" } else { "s" },
        request.resolution,
        worst.name,
        worst.texels,
        worst.cost.rays,
        worst.cost.evaluations
    )
}

fn output_names(outputs: &[Output]) -> String {
    outputs
        .iter()
        .map(|o| o.name())
        .collect::<Vec<_>>()
        .join(", ")
}

fn plan_object(
    scene: &Scene,
    index: usize,
    file_stem: &str,
    request: &BakeRequest,
) -> Result<ObjectPlan, Error> {
    let object = &scene.objects[index];
    let name = object.mesh.name.clone();
    let sourced = request.materials.resolve(object, &scene.source)?;
    let source = sourced.source.clone();
    let start = Instant::now();
    let (mut layout, uvs) = Layout::new(scene, index, request)?;
    let layout_seconds = start.elapsed().as_secs_f64();
    let (colour, ColourMap { relative, nominal }) =
        plan_colour(scene, index, &layout, request, &sourced)?;
    layout.relative_colour = relative;
    let mut profile_material = match (&sourced.recipe, nominal) {
        (Some(recipe), Some(m)) if m != recipe.colour() => recipe
            .with_colour(m)
            .map_err(|e| e.for_object(name.clone()).in_file(scene.source.clone()))?,
        _ => sourced.material,
    };
    if let Some(roughness) = request.roughness {
        profile_material.roughness = roughness;
    }
    let scattering = Scattering::new(
        profile_material,
        request.model,
        request.integrators.texture.gaussians,
        request.d_max_epsilon,
    )
    .map_err(|e| e.for_object(name.clone()))?;
    let texels = layout.surfels.len();
    let texel_area_mm2 = layout.surfels.total_area();
    let material = MaterialPlan {
        name: scattering.material.name.clone(),
        source,
        model: scattering.model.name().to_string(),
        ior: scattering.entry_index(),
        roughness: scattering.material.roughness,
        d_max_mm: scattering.kernel.d_max,
        mean_free_path_mm: scattering.material.finest_mean_free_path_mm(),
        transmits: scattering.kernel.transmits(),
    };
    let lighting = if !request.lights() {
        Stage::new(false, "no output needs light")
    } else {
        match &request.lighting {
            Lighting::Irradiance(_) => Stage::new(true, "read from the irradiance image"),
            _ if scene.lights.is_empty() => {
                Stage::new(true, "the scene has no lights: the maps are black")
            }
            _ => Stage::new(
                true,
                format!(
                    "{} lights, shadowed by every object of the scene",
                    scene.lights.len()
                ),
            ),
        }
    };
    let (scattering_stage, integrator) = if request.scatters() {
        let choice = choose_integrator(request, &layout, &scattering);
        let plan = IntegratorPlan {
            method: choice.method,
            reason: choice.reason,
        };
        (
            Stage::new(true, "the subsurface or diffuse map"),
            Some(plan),
        )
    } else {
        (Stage::new(false, "no output needs the exitance"), None)
    };
    let rays_per_texel = match &request.lighting {
        Lighting::Irradiance(_) => 0.0,
        _ if request.lights() => scene.lights.len() as f64 * f64::from(request.light_samples),
        _ => 0.0,
    };
    let method = integrator.as_ref().map(|i| i.method);
    let runs = method.map(|m| request.integrators.get(m));
    // An integrator that cannot bake the material says why before any work.
    if let Some(runs) = runs {
        runs.accepts(&scattering.material).map_err(|reason| {
            Error::Input(InputError {
                file: Some(scene.source.clone()),
                object: Some(name.clone()),
                field: Some("method".into()),
                message: format!("`{}` cannot bake it: {reason}", runs.method()),
            })
        })?;
    }
    // The check against light walks a few hundred texels, when the walk can
    // follow the material.
    let light_check = match (method, WalkMedium::of_material(&scattering.material)) {
        (Some(_), Ok(medium)) if request.light_check > 0 => {
            let checked = (request.light_check as usize).min(texels);
            light_check::planned_events(&medium, checked, light_check::event_budget(texels))
        }
        _ => 0.0,
    };
    // An oblique kernel splits the light of the scene's lights by incidence
    // (not an irradiance image's, which has no direction).
    let splits = scattering.oblique.is_some() && rays_per_texel > 0.0 && method.is_some();
    let work = Work {
        texels: texels as f64,
        neighbours: neighbours(
            texel_area_mm2 / texels.max(1) as f64,
            f64::from(scattering.kernel.d_max),
        ),
        material: &scattering.material,
    };
    let cost = ObjectCost::memory(texels as f64, request.resolution, &request.outputs)
        .with_work(runs, &work, rays_per_texel)
        .with_incidence_split(splits, runs, request.resolution)
        .with_uniform_pass(LocalSlab::applies(&scattering), runs);
    let bounces = if rays_per_texel > 0.0 {
        request.bounces
    } else {
        0
    };
    // The corrected model raises small convex parts by the curvature, for
    // an integrator of the profile whose kernel is not oblique.
    let raises = LocalSlab::applies(&scattering)
        && scattering.oblique.is_none()
        && runs.is_some_and(|i| i.carries().profile);
    let curvature = if raises {
        BallGain::planned_steps(&scattering.kernel, texels as f64, texel_area_mm2)
    } else {
        0.0
    };
    // Thin parts gather with their own slab's profile, twice (their gains
    // under a unit light, then the light), through the octree at the
    // integrator's ε for them (0: every pair): at most as many targets
    // as texels.
    let thin_parts = match runs.filter(|_| raises && scattering.slab_profiles().is_some()) {
        Some(integrator) if integrator.thin_epsilon() > 0.0 => 2.0 * work.n_log_n(),
        Some(_) => 2.0 * work.texels * work.neighbours,
        None => 0.0,
    };
    // What thin parts hold, by the share of texels a probe finds thin.
    let thin_bytes = match scattering.slab_profiles().filter(|_| thin_parts > 0.0) {
        Some(slabs) => {
            let thickest = slabs.thickest_thin() as f32;
            let thin = thin_share(&layout.mesh, &layout.surfels, thickest);
            slabs.planned_bytes(texels as f64, thin)
        }
        None => 0.0,
    };
    let topology = topology_report(&object.mesh);
    let cost = ObjectCost {
        light_check,
        curvature,
        thin_parts,
        rays: cost.rays
            + gathering_rays(texels, bounces)
            + planned_rays(topology.parts, object.mesh.triangles.len()),
        memory_bytes: cost.memory_bytes + gathering_bytes(texels, bounces) + thin_bytes,
        ..cost
    };
    Ok(ObjectPlan {
        name,
        index,
        file_stem: file_stem.to_string(),
        triangles: object.mesh.triangles.len(),
        area_mm2: object.mesh.area(),
        topology: describe(&topology),
        uvs: UvPlan {
            verdict: uvs.verdict,
            unwrap: uvs.unwrap,
            reason: uvs.reason,
            warning: uvs.warning,
        },
        texels,
        cost,
        texel_area_mm2,
        material,
        colour,
        lighting,
        scattering: scattering_stage,
        integrator,
        layout_seconds,
        layout: Arc::new(layout),
        scattering_profile: Arc::new(scattering),
    })
}

/// The object's colour: its plan, and its map relative to the nominal
/// colour the profile is to be built for (crate::colour).
fn plan_colour(
    scene: &Scene,
    index: usize,
    layout: &Layout,
    request: &BakeRequest,
    sourced: &Sourced,
) -> Result<(ColourPlan, ColourMap), Error> {
    let object = &scene.objects[index];
    let stated = sourced.recipe.as_ref().map(|r| r.colour());
    let texture = object.colour_texture.as_ref();
    let mut plan = ColourPlan {
        source: if stated.is_some() { "material" } else { "none" }.to_string(),
        file: None,
        input: None,
        uv_set: None,
        colour_space: None,
        nominal: stated,
        split: request.colour_split,
        note: None,
    };
    let map = if let Some(image) = &request.base_colour {
        plan.source = "image".into();
        plan.note = Some(match texture {
            Some(t) => format!(
                "a base-colour image in the bake's layout replaces the texture {} on {}",
                t.file, t.input
            ),
            None => "a base-colour image in the bake's layout".to_string(),
        });
        (0..layout.surfels.len())
            .map(|s| image.sample(layout.texel_uv(s)))
            .collect()
    } else if let Some(texture) = texture {
        if stated.is_none() {
            plan.note = Some(format!(
                "the material ({}) is given by coefficients, not by a colour; the texture {} on \
                 {} is not used",
                sourced.source, texture.file, texture.input
            ));
            return Ok((
                plan,
                ColourMap {
                    relative: Vec::new(),
                    nominal: None,
                },
            ));
        }
        plan.source = "texture".into();
        plan.file = Some(texture.file.clone());
        plan.input = Some(texture.input.clone());
        plan.uv_set = Some(texture.uv_set_name.clone());
        plan.colour_space = Some(texture.colour_space.clone());
        texture_per_texel(layout, object, texture).map_err(|message| {
            Error::Input(InputError {
                file: Some(scene.source.clone()),
                object: Some(object.mesh.name.clone()),
                field: Some(format!(
                    "material `{}`: {} texture {}",
                    texture.material, texture.input, texture.file
                )),
                message,
            })
        })?
    } else {
        return Ok((
            plan,
            ColourMap {
                relative: Vec::new(),
                nominal: stated,
            },
        ));
    };
    if stated.is_none() {
        // A material given by coefficients: the map multiplies as it is.
        return Ok((
            plan,
            ColourMap {
                relative: map,
                nominal: None,
            },
        ));
    }
    let nominal = area_mean(layout, &map);
    plan.nominal = Some(nominal);
    Ok((
        plan,
        ColourMap {
            relative: relative_to(&map, nominal),
            nominal: Some(nominal),
        },
    ))
}

/// The request's method itself, or for `auto` the method that suits the
/// texels, the profile and the object's thin parts, with the reason.
fn choose_integrator(request: &BakeRequest, layout: &Layout, scattering: &Scattering) -> Choice {
    if request.method != Method::Auto {
        return Choice {
            method: request.method,
            reason: "asked for".to_string(),
        };
    }
    let texels = layout.surfels.len();
    let mean_area = layout.surfels.total_area() / texels.max(1) as f64;
    let choice = choose(
        texels,
        mean_area,
        f64::from(scattering.kernel.d_max),
        scattering.kernel.transmits(),
    );
    if choice.method != Method::Texture {
        return choice;
    }
    let crossing = crossing_share(
        &layout.mesh,
        &layout.surfels,
        scattering.profile.as_ref(),
        scattering.kernel.d_max,
    );
    avoid_thin_parts(choice, crossing, request.tolerance)
}

/// The lights that give light, described; those that give none go to
/// `left_out`.
fn describe_lights(scene: &Scene, left_out: &mut Vec<String>) -> Vec<String> {
    let mut lights = Vec::new();
    for light in &scene.lights {
        let power = light.intensity * light.color.iter().sum::<f32>();
        if power.is_nan() || power <= 0.0 {
            left_out.push(format!("light `{}`: gives no light", light.name));
            continue;
        }
        lights.push(format!(
            "`{}`: {}, intensity {}",
            light.name,
            light.kind.name(),
            light.intensity
        ));
    }
    lights
}

/// A file-name-safe form of each name: characters outside letters, digits
/// and `-_.` become `_`, and names that then coincide (ignoring case, as
/// some file systems do) get `-2`, `-3`, … in order.
pub fn file_stems(names: &[&str]) -> Vec<String> {
    let mut taken = std::collections::HashSet::new();
    names
        .iter()
        .map(|name| {
            let safe: String = name
                .chars()
                .map(|c| {
                    if c.is_alphanumeric() || "-_.".contains(c) {
                        c
                    } else {
                        '_'
                    }
                })
                .collect();
            let mut stem = safe.clone();
            let mut n = 1;
            while !taken.insert(stem.to_lowercase()) {
                n += 1;
                stem = format!("{safe}-{n}");
            }
            stem
        })
        .collect()
}

/// "1 part, closed", or the parts and the edges that are open or shared by
/// more than two triangles.
fn describe(shape: &TopologyReport) -> String {
    let parts = if shape.parts == 1 {
        "1 part".to_string()
    } else {
        format!("{} parts", shape.parts)
    };
    let mut words = vec![parts];
    if shape.boundary_edges == 0 && shape.non_manifold_edges == 0 {
        words.push("closed".into());
    }
    if shape.boundary_edges > 0 {
        words.push(format!("{} open edges", shape.boundary_edges));
    }
    if shape.non_manifold_edges > 0 {
        words.push(format!(
            "{} non-manifold edges (treated as open)",
            shape.non_manifold_edges
        ));
    }
    words.join(", ")
}

impl fmt::Display for Plan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "scene {}: {} mm per unit, maps of {}² texels ({}), margin {}",
            self.source,
            self.millimetres_per_unit,
            self.resolution,
            output_names(&self.outputs),
            self.margin
        )?;
        for o in &self.objects {
            o.fmt_decisions(f)?;
        }
        let lights = if self.lights.is_empty() {
            "none".to_string()
        } else {
            self.lights.join("; ")
        };
        writeln!(f, "lights: {lights}")?;
        writeln!(
            f,
            "cost: about {} of memory and {:.1e} rays, kernel evaluations and other steps \
             (limits {} and {:.0e})",
            bytes_text(self.cost.memory_bytes),
            self.cost.evaluations,
            bytes_text(self.request.limits.max_memory_bytes as f64),
            self.request.limits.max_evaluations
        )?;
        for note in &self.notes {
            writeln!(f, "note: {note}")?;
        }
        for reason in &self.left_out {
            writeln!(f, "leaves out {reason}")?;
        }
        Ok(())
    }
}

impl ObjectPlan {
    /// The decisions in words, a few lines.
    pub fn fmt_decisions(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "object `{}`: {} triangles, {:.1} mm², {}",
            self.name, self.triangles, self.area_mm2, self.topology
        )?;
        let unwrap = if self.uvs.unwrap { "unwrap" } else { "keep" };
        writeln!(
            f,
            "  UVs: {}; {unwrap}: {}",
            self.uvs.verdict, self.uvs.reason
        )?;
        if let Some(warning) = &self.uvs.warning {
            writeln!(f, "  warning: {warning}")?;
        }
        writeln!(
            f,
            "  texels: {} covering {:.1} mm²",
            self.texels, self.texel_area_mm2
        )?;
        let m = &self.material;
        writeln!(
            f,
            "  material `{}` ({}): {}, η {}, ℓ {:.3} mm, d_max {:.3} mm{}",
            m.name,
            m.source,
            m.model,
            m.ior,
            m.mean_free_path_mm,
            m.d_max_mm,
            if m.transmits { ", transmits" } else { "" }
        )?;
        let c = &self.colour;
        let mut colour = c.source.clone();
        if let Some(file) = &c.file {
            colour += &format!(
                " {file} on {} through {} ({})",
                c.input.as_deref().unwrap_or("?"),
                c.uv_set.as_deref().unwrap_or("?"),
                c.colour_space.as_deref().unwrap_or("?")
            );
        }
        if let Some(m) = c.nominal {
            colour += &format!(", nominal ({:.4}, {:.4}, {:.4})", m[0], m[1], m[2]);
        }
        writeln!(f, "  colour: {colour}, split α {}", c.split)?;
        if let Some(note) = &c.note {
            writeln!(f, "  note: {note}")?;
        }
        let stage = |s: &Stage| if s.run { "yes" } else { "no" };
        writeln!(
            f,
            "  lighting: {}, {}",
            stage(&self.lighting),
            self.lighting.reason
        )?;
        match &self.integrator {
            Some(i) => writeln!(f, "  scattering: {}: {}", i.method, i.reason)?,
            None => writeln!(f, "  scattering: no, {}", self.scattering.reason)?,
        }
        if self.cost.curvature > 0.0 {
            writeln!(
                f,
                "  corrected model: the curvature of convex parts, about {:.1e} steps",
                self.cost.curvature
            )?;
        }
        if let Some(profiles) = self
            .scattering_profile
            .slab_profiles()
            .filter(|_| self.cost.thin_parts > 0.0)
        {
            let [r, g, b] = profiles.thin_below;
            writeln!(
                f,
                "  corrected model: parts thinner than {r:.1} / {g:.1} / {b:.1} mm (R/G/B) by their own slab's profile, from up to {} slabs simulated by the Monte Carlo when first met (then kept in the cache folder); their gathers at most about {:.1e} kernel evaluations",
                profiles.thicknesses().len(),
                self.cost.thin_parts
            )?;
        }
        if self.cost.light_check > 0.0 {
            writeln!(
                f,
                "  check against light: a volumetric random walk at a few hundred texels, about {:.1e} events",
                self.cost.light_check
            )?;
        }
        Ok(())
    }
}
