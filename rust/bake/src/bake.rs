//! The bake: every planned object lit, scattered and ready to render any
//! of its maps, and a summary of what was done (the plan's decisions and
//! the seconds each stage took).

use crate::control::Control;
use crate::error::Error;
use crate::fitted_map::MapFit;
use crate::image::Image;
use crate::maps::{Output, margin_fill, render};
use crate::pipeline::prepare;
use crate::plan::{ObjectPlan, Plan};
use crate::prepared::Prepared;
use crate::request::BakeRequest;
use crate::scattering::Scattering;
use crate::scene::Scene;
use crate::transport::ExitanceKernel;
use crate::transport::Method;
use crate::transport::choice;
use crate::transport::integrator::IntegratorSettings;
use crate::transport::light_check::{LightCheck, NoCheck, check_against_light, event_budget};
use crate::transport::verify::{ErrorEstimate, estimate_error, predict_error};
use crate::transport::walk::WalkNoise;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::time::Instant;

/// One baked object: its layout, light and exitance, rendering its maps.
pub struct BakedObject {
    /// The plan it was baked by (decisions and reasons).
    pub plan: ObjectPlan,
    /// The layout and the light entering it.
    pub prepared: Prepared,
    /// Radiant exitance per surfel, W/m²; empty when no output needs it.
    pub exitance: Vec<[f32; 3]>,
    /// The outputs the plan made ready.
    pub outputs: Vec<Output>,
    fill: Vec<(u32, u32)>,
    /// What the bake did and how long each stage took.
    pub summary: ObjectSummary,
}

/// Seconds per stage of one object.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Seconds {
    /// UV analysis, unwrap and texels (while planning).
    pub layout: f64,
    /// The irradiance entering.
    pub lighting: f64,
    /// The integration.
    pub scattering: f64,
}

/// What a bake did for one object: the plan's decisions, then the numbers.
#[derive(Clone, Debug, Serialize)]
pub struct ObjectSummary {
    /// The decisions, exactly as the plan states them.
    #[serde(flatten)]
    pub plan: ObjectPlan,
    /// Sources the 3-D integrators gathered from (texels or points).
    pub sources: usize,
    /// How far the exitance is from the exact sum; `None` when the bake
    /// did not scatter.
    pub accuracy: Option<Accuracy>,
    /// Seconds per stage.
    pub seconds: Seconds,
}

/// How far an object's exitance is from the exact sum, and what `auto`
/// set aside to get there.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Accuracy {
    /// The method whose exitance the maps hold.
    pub method: Method,
    /// Relative RMSE against the exact sum at `texels_checked` random
    /// texels; 0 for `brute`, which is the exact sum.
    pub estimated_error: f64,
    /// How many texels the estimate checked.
    pub texels_checked: usize,
    /// The tolerance `auto` held the object to; `None` when a method was
    /// asked for.
    pub tolerance: Option<f64>,
    /// The octree's solid-angle threshold (sr) when `method` is the octree.
    pub octree_epsilon: Option<f32>,
    /// Methods `auto` ran and set aside for missing the tolerance.
    pub set_aside: Vec<SetAside>,
    /// `auto`'s pilot of the first method, when it had one: the error its
    /// first settings were predicted to make, from its sums at a few
    /// texels, and whether that refined them before the whole map ran.
    #[serde(default)]
    pub pilot: Option<Pilot>,
    /// The kernel the maps' exitance was integrated with.
    #[serde(default)]
    pub kernel: ExitanceKernel,
    /// The kernel of the exact sum the estimate compares against: the
    /// oblique one wherever the model has it and the light has directions,
    /// so an azimuthal-mean method's estimate counts what it misses.
    #[serde(default)]
    pub reference_kernel: ExitanceKernel,
    /// The walk's own noise and dropped weight when `method` is `walk`
    /// (its `estimated_error` is then the profile's distance from the
    /// walk, as measured by the exact sum: the model's error plus the
    /// walk's noise).
    #[serde(default)]
    pub walk: Option<WalkNoise>,
    /// How far the exitance is from light itself: the volumetric walk at
    /// random texels ([`crate::transport::light_check`]); `None` when the
    /// check was off or the walk cannot follow the material
    /// (`light_unchecked` says why).
    #[serde(default)]
    pub light: Option<LightCheck>,
    /// Why there is no check against light, when there is none.
    #[serde(default)]
    pub light_unchecked: Option<String>,
    /// What the corrected model changed of the profile's sums
    /// ([`crate::transport::local_slab`]); `None` for the walk and for
    /// materials it does not apply to (layered, measured, Stam).
    #[serde(default)]
    pub corrected: Option<Corrected>,
    /// How the map was carried from a lattice of texels
    /// ([`crate::fitted_map`]); `None` for a method that integrates the
    /// whole map at once.
    #[serde(default)]
    pub fit: Option<MapFit>,
}

/// What the corrected model did to one object's profile sums.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Corrected {
    /// R_∞/R per channel: the Monte Carlo's half-space total over the
    /// profile's, by which every sum was scaled (1 where the profile is at
    /// light's level already).
    pub level: [f64; 3],
    /// Texels with a face behind them nearer than the profile's reach,
    /// whose light was re-shared by the slab of that thickness.
    pub thin_texels: usize,
    /// Texels on parts thinner than about a diffusion length of some
    /// channel, which gathered with their own slab's profile in that
    /// channel ([`crate::transport::slab_profiles`]).
    #[serde(default)]
    pub slab_profile_texels: usize,
    /// How those texels' map was carried from a lattice of them
    /// ([`crate::fitted_map`]); `None` where it was summed at each.
    #[serde(default)]
    pub slab_profile_fit: Option<MapFit>,
    /// Texels raised by more than 1% towards a plane's or a slab's light
    /// where the surface the profile reaches ends (a rim, a small part),
    /// or towards a ball's where the surface bulges.
    pub raised_texels: usize,
    /// Texels apart, along u and along v, at which the integrator summed
    /// its weights under a unit light to find where the surface ends (1:
    /// every texel; more where the fit between them met its check).
    pub uniform_stride: u32,
    /// Per channel, the share of the map kept where the raised light would
    /// have left more power than entered; `None` where all of it was.
    pub kept: Option<[f32; 3]>,
    /// Per channel, the most the level (or the gain of small convex parts)
    /// may be off by, as a share: the light of the Monte Carlo's photons
    /// and the balls' walks stopped unfinished where the bound on their
    /// work binds (a nearly lossless medium scattering nearly straight
    /// ahead); 0 where every one finished.
    #[serde(default)]
    pub unfinished: [f64; 3],
}

/// A method `auto` ran and set aside.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SetAside {
    /// The method.
    pub method: Method,
    /// The octree's solid-angle threshold (sr) when the method is the
    /// octree.
    pub octree_epsilon: Option<f32>,
    /// Its estimated relative RMSE.
    pub estimated_error: f64,
    /// Seconds it took, integration and check.
    pub seconds: f64,
}

/// `auto`'s prediction of a method's error before it runs
/// ([`crate::transport::verify::predict_error`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pilot {
    /// The method piloted.
    pub method: Method,
    /// The octree's solid-angle threshold (sr) piloted, for the octree.
    pub octree_epsilon: Option<f32>,
    /// The predicted relative RMSE against the exact sum.
    pub predicted_error: f64,
    /// Texels the pilot summed.
    pub texels: usize,
    /// The prediction above which the settings are refined: a share
    /// ([`PILOT_SHARE`]) of the tolerance.
    pub refine_above: f64,
    /// Whether the prediction, above [`Self::refine_above`], refined the
    /// settings before the whole map ran.
    pub refined: bool,
    /// Seconds it took.
    pub seconds: f64,
}

/// The exitance of one object and how it was reached.
struct Scattered {
    exitance: Vec<[f32; 3]>,
    seconds: f64,
    sources: usize,
    accuracy: Accuracy,
}

/// Integrates by `method` and estimates the error against the exact sum;
/// under `auto`, moves to a more exact method while the estimate exceeds
/// the request's tolerance: the octree once more at a finer threshold
/// before the exact sum.
fn scatter(
    prepared: &Prepared,
    object: &ObjectPlan,
    mut method: Method,
    request: &BakeRequest,
    control: &Control,
) -> Result<Scattered, Error> {
    let scattering = &object.scattering_profile;
    let chosen = request.method == Method::Auto;
    let texels = prepared.surfels.len();
    let neighbours = choice::neighbours(
        object.texel_area_mm2 / texels.max(1) as f64,
        f64::from(scattering.kernel.d_max),
    );
    let mut set_aside = Vec::new();
    let mut seconds = 0.0;
    let (oblique, directions) = (scattering.oblique.is_some(), prepared.splits_by_incidence());
    let mut integrators = request.integrators.clone();
    let mut refined = false;
    // Under `auto`, a pilot at a few texels predicts the first method's
    // error; settings that would miss the tolerance are refined before the
    // whole map is integrated, not after.
    let pilot = if chosen {
        control.part(0.0, PILOT_END, "pilot", || {
            run_pilot(
                prepared,
                scattering,
                &mut integrators,
                method,
                neighbours,
                request,
                control,
            )
        })?
    } else {
        None
    };
    seconds += pilot.map_or(0.0, |p| p.seconds);
    loop {
        let start = Instant::now();
        let integration = control.part(PILOT_END, INTEGRATION_END, "", || {
            prepared.integrate(
                scattering,
                integrators.get(method),
                request.tolerance,
                control,
            )
        })?;
        let estimate = if method == Method::Brute {
            ErrorEstimate {
                relative_rmse: 0.0,
                texels,
            }
        } else {
            control.part(INTEGRATION_END, ESTIMATE_END, "error estimate", || {
                estimate_error(
                    prepared,
                    scattering,
                    &integration.exitance,
                    integration.raised.as_deref(),
                    integration.kept,
                    neighbours,
                    integrators.get(method).thin_epsilon(),
                    request.integrators.importance.seed,
                    control,
                )
            })?
        };
        let elapsed = start.elapsed().as_secs_f64();
        seconds += elapsed;
        let epsilon = integrators.octree_epsilon(method);
        let missed = chosen && estimate.relative_rmse > request.tolerance;
        // A method that missed refines its own settings once, then hands
        // over to the next more exact one.
        let mut next = None;
        if missed {
            let runs = integrators.get_mut(method);
            next = if !refined && runs.refine(estimate.relative_rmse, request.tolerance) {
                refined = true;
                Some(method)
            } else {
                choice::more_exact(&*runs, texels, neighbours)
            };
        }
        match next {
            Some(next) => {
                set_aside.push(SetAside {
                    method,
                    octree_epsilon: epsilon,
                    estimated_error: estimate.relative_rmse,
                    seconds: elapsed,
                });
                method = next;
            }
            None => {
                let checked = control.part(ESTIMATE_END, 1.0, "check against light", || {
                    check_against_light(
                        prepared,
                        scattering,
                        &integration.exitance,
                        request.light_check,
                        event_budget(texels),
                        request.integrators.walk.seed,
                        control,
                    )
                })?;
                let (light, light_unchecked) = match checked {
                    Ok(check) => (Some(check), None),
                    Err(NoCheck::Off) => (None, Some("turned off".to_string())),
                    Err(NoCheck::Material(reason)) => (None, Some(reason)),
                };
                seconds += light.map_or(0.0, |l| l.seconds);
                let corrected = scattering
                    .local_slab()
                    .filter(|_| method.carries().profile)
                    .map(|slab| Corrected {
                        level: slab.level(),
                        thin_texels: prepared
                            .opposites(slab.reach())
                            .iter()
                            .flatten()
                            .filter(|o| slab.at(o.thickness).is_some())
                            .count(),
                        slab_profile_texels: integration
                            .raised
                            .as_ref()
                            .map_or(0, |r| r.by_slab_profile),
                        slab_profile_fit: integration.thin_fit.filter(|fit| fit.step > 1),
                        raised_texels: integration.raised.as_ref().map_or(0, |r| r.count),
                        uniform_stride: integration.raised.as_ref().map_or(1, |r| r.stride),
                        kept: integration.kept,
                        unfinished: slab.unfinished(),
                    });
                return Ok(Scattered {
                    exitance: integration.exitance,
                    seconds,
                    sources: integration.sources,
                    accuracy: Accuracy {
                        kernel: ExitanceKernel::of(method.carries(), oblique, directions),
                        reference_kernel: ExitanceKernel::of(
                            Method::Brute.carries(),
                            oblique,
                            directions,
                        ),
                        method,
                        octree_epsilon: epsilon,
                        estimated_error: estimate.relative_rmse,
                        texels_checked: estimate.texels,
                        tolerance: chosen.then_some(request.tolerance),
                        set_aside,
                        pilot,
                        walk: integration.walk,
                        light,
                        light_unchecked,
                        corrected,
                        fit: integration.fit,
                    },
                });
            }
        }
    }
}

/// Where the scattering's progress ([`Control::part`]) stands as the pilot,
/// the integration and the error estimate end; the check against light
/// fills the rest. From where the time went on the head in skin1 at 4096²
/// (the pilot about 10 s, the integration 70 s, the estimate 9 s, the
/// check 4 s).
const PILOT_END: f64 = 0.11;
const INTEGRATION_END: f64 = 0.86;
const ESTIMATE_END: f64 = 0.96;

/// The share of the tolerance above which a pilot's prediction refines the
/// settings. The pilot sums the light as it enters; the map sums it raised
/// where the surface ends or bulges, whose gains carry an error of their
/// own, and misses by about a tenth more (skin1 on the head at 1024²:
/// 0.76% predicted, 0.86% measured; at 4096² 0.92% and 1.04%, which ran
/// the whole map twice).
pub const PILOT_SHARE: f64 = 0.9;

/// The share of light's level the Monte Carlo may have left unfinished
/// below which the summary does not mention it (one in ten thousand).
const UNFINISHED_SAID: f64 = 1e-4;

/// Pilots `method` under `integrators` and refines its settings there when
/// the prediction is above [`PILOT_SHARE`] of the request's tolerance.
fn run_pilot(
    prepared: &Prepared,
    scattering: &Scattering,
    integrators: &mut IntegratorSettings,
    method: Method,
    neighbours: f64,
    request: &BakeRequest,
    control: &Control,
) -> Result<Option<Pilot>, Error> {
    let start = Instant::now();
    let seed = request.integrators.importance.seed;
    let piloted = integrators.get(method);
    let Some(predicted) = predict_error(prepared, scattering, piloted, neighbours, seed, control)?
    else {
        return Ok(None);
    };
    let octree_epsilon = integrators.octree_epsilon(method);
    let refine_above = PILOT_SHARE * request.tolerance;
    let refined = integrators
        .get_mut(method)
        .refine(predicted.relative_rmse, refine_above);
    Ok(Some(Pilot {
        method,
        octree_epsilon,
        predicted_error: predicted.relative_rmse,
        texels: predicted.texels,
        refine_above,
        refined,
        seconds: start.elapsed().as_secs_f64(),
    }))
}

/// What a bake did: each object's decisions and timings, and the scene's
/// notes and leftovers. Writers add the files they wrote.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Input file.
    pub source: String,
    /// Texels per side.
    pub resolution: u32,
    /// The maps made.
    pub outputs: Vec<Output>,
    /// Each object's decisions and timings.
    pub objects: Vec<ObjectSummary>,
    /// Lights that lit the bake.
    pub lights: Vec<String>,
    /// What was left out, each with its reason.
    pub left_out: Vec<String>,
    /// What the scene reader noticed.
    pub notes: Vec<String>,
    /// Files written, when a writer wrote them.
    pub files: Vec<String>,
    /// Seconds a writer spent after the last object: the assets and moving
    /// every file into place (maps are encoded as each object is done).
    pub write_seconds: f64,
}

impl Summary {
    /// The summary of a bake by `plan` before any object is baked.
    pub fn new(plan: &Plan) -> Self {
        Summary {
            source: plan.source.clone(),
            resolution: plan.resolution,
            outputs: plan.outputs.clone(),
            objects: Vec::new(),
            lights: plan.lights.clone(),
            left_out: plan.left_out.clone(),
            notes: plan.notes.clone(),
            files: Vec::new(),
            write_seconds: 0.0,
        }
    }
}

/// Bakes every object of `plan`, handing each to `each` as it is done (so
/// a writer holds one object at a time); returns the summary.
pub fn bake_each(
    scene: &Scene,
    plan: &Plan,
    control: &Control,
    mut each: impl FnMut(BakedObject) -> Result<(), Error>,
) -> Result<Summary, Error> {
    let mut summary = Summary::new(plan);
    let stages_per_object = 2;
    let stages = plan.objects.len() * stages_per_object;
    for (i, object_plan) in plan.objects.iter().enumerate() {
        let object = bake_object(scene, plan, object_plan, control, |k, label| {
            control.begin_stage(
                i * stages_per_object + k,
                stages,
                &format!("{}: {label}", object_plan.name),
            )
        })?;
        summary.objects.push(object.summary.clone());
        each(object)?;
    }
    Ok(summary)
}

/// Bakes every object of `plan` and keeps them all.
pub fn bake(
    scene: &Scene,
    plan: &Plan,
    control: &Control,
) -> Result<(Vec<BakedObject>, Summary), Error> {
    let mut objects = Vec::new();
    let summary = bake_each(scene, plan, control, |object| {
        objects.push(object);
        Ok(())
    })?;
    Ok((objects, summary))
}

fn bake_object(
    scene: &Scene,
    plan: &Plan,
    object: &ObjectPlan,
    control: &Control,
    stage: impl Fn(usize, &str),
) -> Result<BakedObject, Error> {
    let request = &plan.request;
    let scattering = &object.scattering_profile;
    stage(0, "lighting");
    let mut prepared = prepare(
        scene,
        object.index,
        object.layout.clone(),
        request,
        scattering,
        object.lighting.run,
        control,
    )?;
    stage(1, "scattering");
    let (exitance, seconds, sources, accuracy) = match &object.integrator {
        Some(integrator) => {
            let scattered = scatter(&prepared, object, integrator.method, request, control)?;
            (
                scattered.exitance,
                scattered.seconds,
                scattered.sources,
                Some(scattered.accuracy),
            )
        }
        None => (Vec::new(), 0.0, 0, None),
    };
    // The scene's rays and the light split by incidence served the
    // scattering; a baked object kept for its maps does not hold them.
    prepared.release_lighting();
    let start = Instant::now();
    let fill = margin_fill(&prepared, request.margin);
    let summary = ObjectSummary {
        plan: object.clone(),
        sources,
        accuracy,
        seconds: Seconds {
            layout: object.layout_seconds + start.elapsed().as_secs_f64(),
            lighting: prepared.seconds(),
            scattering: seconds,
        },
    };
    Ok(BakedObject {
        plan: object.clone(),
        prepared,
        exitance,
        outputs: request.outputs.clone(),
        fill,
        summary,
    })
}

impl BakedObject {
    /// The object's name.
    pub fn name(&self) -> &str {
        &self.plan.name
    }

    /// Map `output` as an image, rows top to bottom, margins filled; only
    /// the outputs the plan made ready.
    pub fn render(&self, output: Output) -> Result<Image, Error> {
        if !self.outputs.contains(&output) {
            return Err(Error::field(
                "outputs",
                format!(
                    "object `{}`: the bake did not make the {output} map",
                    self.plan.name
                ),
            ));
        }
        Ok(render(
            &self.prepared,
            &self.exitance,
            &self.plan.scattering_profile.surface,
            output,
            &self.fill,
        ))
    }

    /// The margin's filled texels and the covered texels they copy
    /// (row-major, y growing with v).
    pub fn fill(&self) -> &[(u32, u32)] {
        &self.fill
    }

    /// Whether texel `t` (row-major, y growing with v) holds a value:
    /// covered by the layout or filled in its margin.
    pub fn covered(&self) -> Vec<bool> {
        let n = self.prepared.surfels.resolution as usize;
        let mut covered = vec![false; n * n];
        for &t in &self.prepared.surfels.texel {
            covered[t as usize] = true;
        }
        for &(to, _) in &self.fill {
            covered[to as usize] = true;
        }
        covered
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for o in &self.objects {
            let p = &o.plan;
            let method = p
                .integrator
                .as_ref()
                .map_or("not scattered".to_string(), |i| {
                    format!("{} ({})", i.method, i.reason)
                });
            writeln!(
                f,
                "{}: material `{}` ({}); {} texels, {method}; laid out in {:.2} s, lit in {:.2} s, scattered in {:.2} s",
                p.name,
                p.material.name,
                p.material.source,
                p.texels,
                o.seconds.layout,
                o.seconds.lighting,
                o.seconds.scattering,
            )?;
            if let Some(a) = &o.accuracy {
                if let Some(pilot) = &a.pilot {
                    let then = if pilot.refined {
                        "above the tolerance: refined before the whole map"
                    } else {
                        "kept"
                    };
                    writeln!(
                        f,
                        "{}: pilot: {}{} predicted {:.2}% at {} texels, {then} ({:.2} s)",
                        p.name,
                        pilot.method,
                        at_epsilon(pilot.octree_epsilon),
                        100.0 * pilot.predicted_error,
                        pilot.texels,
                        pilot.seconds
                    )?;
                }
                for aside in &a.set_aside {
                    writeln!(
                        f,
                        "{}: {}{} set aside: estimated error {:.2}% is above the tolerance ({:.2} s)",
                        p.name,
                        aside.method,
                        at_epsilon(aside.octree_epsilon),
                        100.0 * aside.estimated_error,
                        aside.seconds
                    )?;
                }
                if let Some(fit) = &a.fit.filter(|fit| fit.step > 1) {
                    writeln!(
                        f,
                        "{}: summed whole on a lattice {} texels apart along u and v and carried between, {:.2}% from its own sums at {} texels",
                        p.name,
                        fit.step,
                        100.0 * fit.missed,
                        fit.probed
                    )?;
                }
                if a.kernel != ExitanceKernel::Radial {
                    writeln!(f, "{}: exitance by {}", p.name, a.kernel.describe())?;
                }
                if let Some(walk) = &a.walk {
                    let [r, g, b] = walk.relative_standard_error.map(|e| 100.0 * e);
                    let dropped = (0..3)
                        .map(|c| walk.truncated[c] + walk.lost[c])
                        .fold(0.0, f64::max);
                    writeln!(
                        f,
                        "{}: walk: relative standard error {r:.2}% / {g:.2}% / {b:.2}% (R/G/B, {} walks per texel and channel, {:.0} events each on average); {:.3}% of the light dropped at the event bound or lost",
                        p.name,
                        walk.samples,
                        walk.events_per_walk,
                        100.0 * dropped
                    )?;
                }
                if a.method == Method::Brute {
                    writeln!(f, "{}: {}: the exact sum", p.name, a.method)?;
                } else {
                    let over = match a.tolerance {
                        Some(t) if a.estimated_error > t => {
                            "; above the tolerance, and nothing more exact is affordable at this size"
                        }
                        _ => "",
                    };
                    writeln!(
                        f,
                        "{}: {}{}: estimated error {:.2}% (relative RMSE against the {}exact sum at {} texels){over}",
                        p.name,
                        a.method,
                        at_epsilon(a.octree_epsilon),
                        100.0 * a.estimated_error,
                        if a.reference_kernel == ExitanceKernel::Oblique {
                            "oblique "
                        } else {
                            ""
                        },
                        a.texels_checked
                    )?;
                }
            }
            if let Some(corrected) = o.accuracy.as_ref().and_then(|a| a.corrected) {
                let [r, g, b] = corrected.level;
                writeln!(
                    f,
                    "{}: corrected model: light's level ×{r:.3} / {g:.3} / {b:.3} (R/G/B, the Monte Carlo's total over the profile's); {} texels through thin parts by the slab of their thickness, {} of them by their own slab's profile; {} raised where the surface within reach ends or bulges",
                    p.name,
                    corrected.thin_texels,
                    corrected.slab_profile_texels,
                    corrected.raised_texels
                )?;
                let unfinished = corrected.unfinished.iter().copied().fold(0.0, f64::max);
                if unfinished >= UNFINISHED_SAID {
                    writeln!(
                        f,
                        "{}: corrected model: the Monte Carlo stopped photons unfinished within its bound on the work: light's level may be off by up to {:.2}%",
                        p.name,
                        100.0 * unfinished
                    )?;
                }
                if let Some(fit) = corrected.slab_profile_fit {
                    writeln!(
                        f,
                        "{}: corrected model: thin parts' own profiles summed on a lattice {} texels apart and carried between, {:.2}% from their own sums at {} texels",
                        p.name,
                        fit.step,
                        100.0 * fit.missed,
                        fit.probed
                    )?;
                }
                if let Some([r, g, b]) = corrected.kept {
                    writeln!(
                        f,
                        "{}: corrected model: kept ×{r:.3} / {g:.3} / {b:.3} of the raised light, which would have left more power than entered",
                        p.name
                    )?;
                }
            }
            if let Some(light) = o.accuracy.as_ref().and_then(|a| a.light) {
                writeln!(
                    f,
                    "{}: against light: estimated error {:.1}% (relative RMSE {:.1}% against a volumetric random walk in the mesh at {} texels, {} walks each, whose own noise is {:.1}%; {:.2} s)",
                    p.name,
                    100.0 * light.estimated_error,
                    100.0 * light.relative_rmse,
                    light.texels,
                    light.walks,
                    100.0 * light.walk_noise,
                    light.seconds
                )?;
            } else if let Some(why) = o.accuracy.as_ref().and_then(|a| a.light_unchecked.as_ref()) {
                writeln!(f, "{}: against light: not checked ({why})", p.name)?;
            }
            if let Some(warning) = &p.uvs.warning {
                writeln!(f, "warning: {}: {warning}", p.name)?;
            }
        }
        for note in &self.notes {
            writeln!(f, "note: {note}")?;
        }
        for reason in &self.left_out {
            writeln!(f, "left out {reason}")?;
        }
        if !self.files.is_empty() {
            // The maps are encoded as each object finishes; write_seconds
            // covers the assets and the renames after the last one.
            writeln!(
                f,
                "wrote {} files (assets and renames {:.2} s)",
                self.files.len(),
                self.write_seconds
            )?;
        }
        Ok(())
    }
}

/// " at ε …" for an octree's threshold, else nothing.
fn at_epsilon(epsilon: Option<f32>) -> String {
    epsilon.map_or(String::new(), |e| format!(" at ε {e:.3} sr"))
}
