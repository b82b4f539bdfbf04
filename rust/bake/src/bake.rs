//! The bake: every planned object lit, scattered and ready to render any
//! of its maps, and a summary of what was done (the plan's decisions and
//! the seconds each stage took).

use crate::control::Control;
use crate::error::Error;
use crate::image::Image;
use crate::maps::{Output, margin_fill, render};
use crate::pipeline::{Prepared, prepare};
use crate::plan::{ObjectPlan, Plan};
use crate::scene::Scene;
use serde::Serialize;
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
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
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
    /// Seconds per stage.
    pub seconds: Seconds,
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
    let prepared = prepare(
        scene,
        object.index,
        object.layout.clone(),
        request,
        scattering.entry_index(),
        object.lighting.run,
        control,
    )?;
    stage(1, "scattering");
    let (exitance, seconds, sources) = match &object.integrator {
        Some(integrator) => {
            let integrator = request.integrators.get(integrator.method);
            let integration = prepared.integrate(scattering, integrator, control)?;
            (
                integration.exitance,
                integration.seconds,
                integration.sources,
            )
        }
        None => (Vec::new(), 0.0, 0),
    };
    let start = Instant::now();
    let fill = margin_fill(&prepared, request.margin);
    let summary = ObjectSummary {
        plan: object.clone(),
        sources,
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
            self.plan.material.ior,
            output,
            &self.fill,
        ))
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
