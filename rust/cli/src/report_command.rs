//! `sssbake report`: every integrator across a ladder of settings, each
//! run's time and its error against the exact sum, as JSON, CSV and a
//! log–log plot, and the runs no other run beats on both.

use crate::error_map::error_map;
use crate::plot::render_png;
use crate::report_plot::{Series, render};
use crate::request_args::RequestArgs;
use serde::Serialize;
use sssbake::control::Control;
use sssbake::pipeline::prepare;
use sssbake::transport::accuracy::relative_errors;
use sssbake::transport::brute::BruteIntegrator;
use sssbake::transport::integrator::{Integrator, IntegratorSettings};
use sssbake::{Error, Method, plan};
use sssbake_io::atomic_write::write_atomically;
use sssbake_io::image_writer::png_bytes;
use std::path::PathBuf;

/// Options of `sssbake report`.
#[derive(clap::Args)]
pub struct ReportArgs {
    #[command(flatten)]
    request: RequestArgs,
    /// The folder for report.json, report.csv and report.svg/.png.
    #[arg(long)]
    out: PathBuf,
    /// Replace a report already in the folder.
    #[arg(long)]
    force: bool,
}

/// One run of the ladder.
#[derive(Serialize)]
struct Run {
    object: String,
    method: Method,
    setting: String,
    seconds: f64,
    relative_rmse: f64,
    max_error: f64,
    sources: usize,
    pareto: bool,
}

/// One object of the report.
#[derive(Serialize)]
struct ReportObject {
    name: String,
    material: String,
    model: String,
    d_max_mm: f32,
    texels: usize,
    unwrapped: bool,
    prepare_seconds: f64,
}

/// The whole report, as report.json holds it.
#[derive(Serialize)]
struct Report {
    scene: String,
    resolution: u32,
    threads: usize,
    objects: Vec<ReportObject>,
    runs: Vec<Run>,
}

/// The settings each integrator is run with, cheapest first, starting from
/// the request's own.
fn ladder(base: &IntegratorSettings) -> Vec<(Method, String, IntegratorSettings)> {
    let mut runs = Vec::new();
    let mut with = |method: Method, setting: String, change: &dyn Fn(&mut IntegratorSettings)| {
        let mut settings = base.clone();
        change(&mut settings);
        runs.push((method, setting, settings));
    };
    for epsilon in [2.0f32, 1.0, 0.5, 0.2, 0.05] {
        with(Method::Octree, format!("ε {epsilon}"), &|s| {
            s.octree.epsilon = epsilon
        });
    }
    for gaussians in [1, 2, 3, 4, 6, 8] {
        with(Method::Texture, format!("{gaussians} G"), &|s| {
            s.texture.gaussians = gaussians
        });
    }
    for samples in [16, 64, 256, 512] {
        with(Method::Importance, format!("{samples} spp"), &|s| {
            s.importance.samples = samples
        });
    }
    runs
}

/// Runs the command.
pub fn run(args: &ReportArgs) -> Result<(), Error> {
    let (scene, mut request) = args.request.load()?;
    // The exact sum is every run's reference, so its cost is the one the
    // plan checks against the limits.
    request.method = Method::Brute;
    let plan = plan(&scene, &request)?;
    let outputs =
        ["report.json", "report.csv", "report.svg", "report.png"].map(|f| args.out.join(f));
    if !args.force
        && let Some(existing) = outputs.iter().find(|p| p.exists())
    {
        return Err(Error::output(
            existing.display(),
            "exists (use --force to replace it)",
        ));
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| Error::output(args.out.display(), format!("cannot create: {e}")))?;
    let control = Control::new();
    let mut runs = Vec::new();
    let mut objects = Vec::new();
    for object in &plan.objects {
        let scattering = &object.scattering_profile;
        let prepared = prepare(
            &scene,
            object.index,
            object.layout.clone(),
            &plan.request,
            scattering,
            true,
            &control,
        )?;
        let reference = prepared.integrate(scattering, &BruteIntegrator, &control)?;
        eprintln!(
            "{}: brute over {} texels in {:.2} s (lit in {:.2} s)",
            object.name,
            prepared.surfels.len(),
            reference.seconds,
            prepared.seconds()
        );
        runs.push(Run {
            object: object.name.clone(),
            method: Method::Brute,
            setting: "exact".into(),
            seconds: reference.seconds,
            relative_rmse: 0.0,
            max_error: 0.0,
            sources: reference.sources,
            pareto: false,
        });
        for (method, setting, settings) in ladder(&plan.request.integrators) {
            let integrator: &dyn Integrator = settings.get(method);
            let result = prepared.integrate(scattering, integrator, &control)?;
            let (rmse, max_error) = relative_errors(&result.exitance, &reference.exitance);
            // The run with the request's own settings gets a map of where it errs.
            if settings == plan.request.integrators {
                let map = error_map(&prepared.surfels, &result.exitance, &reference.exitance);
                let path =
                    args.out
                        .join(format!("error_{}_{}.png", object.file_stem, method.name()));
                let bytes = png_bytes(&map).map_err(|e| Error::output(path.display(), e))?;
                write_atomically(&path, &bytes)
                    .map_err(|e| Error::output(path.display(), format!("cannot write: {e}")))?;
            }
            eprintln!(
                "{}: {method} {setting}: {:.3} s, RMSE {rmse:.2e}",
                object.name, result.seconds
            );
            runs.push(Run {
                object: object.name.clone(),
                method,
                setting,
                seconds: result.seconds,
                relative_rmse: rmse,
                max_error,
                sources: result.sources,
                pareto: false,
            });
        }
        objects.push(ReportObject {
            name: object.name.clone(),
            material: object.material.name.clone(),
            model: object.material.model.clone(),
            d_max_mm: object.material.d_max_mm,
            texels: object.texels,
            unwrapped: object.uvs.unwrap,
            prepare_seconds: prepared.seconds(),
        });
    }
    let front = pareto_front(&runs);
    for &i in &front {
        runs[i].pareto = true;
    }
    let mut csv = csv::Writer::from_writer(Vec::new());
    for run in &runs {
        csv.serialize(run)
            .map_err(|e| Error::output(outputs[1].display(), e.to_string()))?;
    }
    let csv = csv
        .into_inner()
        .map_err(|e| Error::output(outputs[1].display(), e.to_string()))?;
    let series: Vec<Series> = [Method::Octree, Method::Texture, Method::Importance]
        .into_iter()
        .map(|m| Series {
            name: m.name().to_string(),
            points: runs
                .iter()
                .filter(|r| r.method == m)
                .map(|r| (r.seconds, r.relative_rmse, r.setting.clone()))
                .collect(),
        })
        .collect();
    let brute_seconds = runs
        .iter()
        .filter(|r| r.method == Method::Brute)
        .map(|r| r.seconds)
        .sum::<f64>();
    let first = &plan.objects[0].material;
    let title = format!(
        "{} · {} ({}) · {}² · error against run time",
        args.request
            .input
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default(),
        first.name,
        first.model,
        plan.resolution
    );
    let svg = render(&title, &series, brute_seconds);
    let png = render_png(&svg).map_err(|e| Error::output(outputs[3].display(), e))?;
    let report = Report {
        scene: args.request.input.display().to_string(),
        resolution: plan.resolution,
        threads: rayon::current_num_threads(),
        objects,
        runs,
    };
    let json_text = serde_json::to_string_pretty(&report).unwrap_or_default() + "\n";
    for (path, bytes) in outputs
        .iter()
        .zip([json_text.as_bytes(), &csv, svg.as_bytes(), &png])
    {
        write_atomically(path, bytes)
            .map_err(|e| Error::output(path.display(), format!("cannot write: {e}")))?;
    }
    println!("Pareto front (no run is both faster and more accurate):");
    for &i in &front {
        let r = &report.runs[i];
        println!(
            "  {:<12} {:<11} {:<14} {:>9.3} s   RMSE {:.2e}   max {:.2e}",
            r.object,
            r.method.name(),
            r.setting,
            r.seconds,
            r.relative_rmse,
            r.max_error
        );
    }
    println!("wrote {}", args.out.display());
    Ok(())
}

/// Indices of the runs that no other run of the same object beats on both
/// time and error, fastest first.
fn pareto_front(runs: &[Run]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..runs.len()).collect();
    order.sort_by(|&a, &b| {
        runs[a]
            .object
            .cmp(&runs[b].object)
            .then(runs[a].seconds.total_cmp(&runs[b].seconds))
    });
    let mut front = Vec::new();
    let mut best: Option<(&str, f64)> = None;
    for i in order {
        let r = &runs[i];
        let better = match best {
            Some((object, error)) if object == r.object => r.relative_rmse < error,
            _ => true,
        };
        if better {
            front.push(i);
            best = Some((&r.object, r.relative_rmse));
        }
    }
    front
}
