//! `sssbake report`: every integrator across a ladder of settings, each
//! run's time and its error against the exact sum, as JSON, CSV and a
//! log–log plot, and the runs no other run beats on both.

use crate::Failure;
use crate::plot::render_png;
use crate::report_plot::{Series, render};
use crate::scene_options::SceneOptions;
use serde_json::json;
use sssbake::control::Control;
use sssbake::pipeline::{BakeError, Prepared, prepare};
use sssbake::transport::accuracy::relative_errors;
use sssbake::transport::kernel::Kernel;
use sssbake::transport::{Method, MethodSettings};
use sssbake_io::atomic_write::write_atomically;
use sssbake_profile::profile::Profile;
use std::path::PathBuf;

/// Options of `sssbake report`.
#[derive(clap::Args)]
pub struct ReportArgs {
    #[command(flatten)]
    scene: SceneOptions,
    /// The folder for report.json, report.csv and report.svg/.png.
    #[arg(long)]
    out: PathBuf,
    /// Replace a report already in the folder.
    #[arg(long)]
    force: bool,
}

/// One run of the ladder.
struct Run {
    object: String,
    method: Method,
    setting: String,
    seconds: f64,
    rmse: f64,
    max_error: f64,
    sources: usize,
}

/// The settings each integrator is run with, cheapest first.
fn ladder() -> Vec<(Method, String, MethodSettings)> {
    let base = MethodSettings::default();
    let mut runs = Vec::new();
    for epsilon in [0.5f32, 0.2, 0.05, 0.01] {
        let settings = MethodSettings {
            octree_epsilon: epsilon,
            ..base.clone()
        };
        runs.push((Method::Octree, format!("ε {epsilon}"), settings));
    }
    for multiplier in [1.0, 16.0] {
        let settings = MethodSettings {
            point_multiplier: multiplier,
            ..base.clone()
        };
        runs.push((Method::Octree, format!("{multiplier} pts/disk"), settings));
    }
    for gaussians in [1, 2, 3, 4, 6, 8] {
        let settings = MethodSettings {
            gaussians,
            ..base.clone()
        };
        runs.push((Method::Texture, format!("{gaussians} G"), settings));
    }
    for samples in [4, 16, 64, 256] {
        let settings = MethodSettings {
            samples,
            ..base.clone()
        };
        runs.push((Method::Importance, format!("{samples} spp"), settings));
    }
    runs
}

fn failure(error: BakeError) -> Failure {
    Failure::Input(error.to_string())
}

/// Runs the command.
pub fn run(args: &ReportArgs) -> Result<(), Failure> {
    let loaded = args.scene.load()?;
    let outputs =
        ["report.json", "report.csv", "report.svg", "report.png"].map(|f| args.out.join(f));
    if !args.force
        && let Some(existing) = outputs.iter().find(|p| p.exists())
    {
        return Err(Failure::Output(format!(
            "{}: exists (use --force to replace it)",
            existing.display()
        )));
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| Failure::Output(format!("{}: cannot create: {e}", args.out.display())))?;
    let control = Control::new();
    let mut runs = Vec::new();
    let mut objects = Vec::new();
    for (object, assigned) in &loaded.objects {
        let profile: &dyn Profile = assigned.profile.as_ref();
        let kernel = Kernel::new(profile, MethodSettings::default().d_max_epsilon);
        let prepared: Prepared = prepare(
            &loaded.scene,
            object,
            loaded.lighting.clone(),
            &assigned.settings,
            &control,
        )
        .map_err(failure)?;
        let seeded = |settings: &MethodSettings| MethodSettings {
            seed: args.scene.seed,
            ..settings.clone()
        };
        let reference = prepared
            .integrate(
                profile,
                &kernel,
                Method::Brute,
                &seeded(&MethodSettings::default()),
                &control,
            )
            .map_err(failure)?;
        eprintln!(
            "{object}: brute over {} texels in {:.2} s (prepared in {:.2} s)",
            prepared.surfels.len(),
            reference.seconds,
            prepared.seconds()
        );
        runs.push(Run {
            object: object.clone(),
            method: Method::Brute,
            setting: "exact".into(),
            seconds: reference.seconds,
            rmse: 0.0,
            max_error: 0.0,
            sources: reference.sources,
        });
        for (method, setting, settings) in ladder() {
            let result = prepared
                .integrate(profile, &kernel, method, &seeded(&settings), &control)
                .map_err(failure)?;
            let (rmse, max_error) = relative_errors(&result.exitance, &reference.exitance);
            eprintln!(
                "{object}: {method} {setting}: {:.3} s, RMSE {rmse:.2e}",
                result.seconds
            );
            runs.push(Run {
                object: object.clone(),
                method,
                setting,
                seconds: result.seconds,
                rmse,
                max_error,
                sources: result.sources,
            });
        }
        objects.push(json!({
            "name": object,
            "material": assigned.material.name,
            "model": profile.model(),
            "d_max_mm": kernel.d_max,
            "texels": prepared.surfels.len(),
            "unwrapped": prepared.unwrapped,
            "prepare_seconds": prepared.seconds(),
        }));
    }
    let front = pareto_front(&runs);
    let report = json!({
        "scene": args.scene.input.display().to_string(),
        "resolution": args.scene.resolution,
        "threads": rayon::current_num_threads(),
        "objects": objects,
        "runs": runs.iter().enumerate().map(|(i, r)| json!({
            "object": r.object,
            "method": r.method.name(),
            "setting": r.setting,
            "seconds": r.seconds,
            "relative_rmse": r.rmse,
            "max_error": r.max_error,
            "sources": r.sources,
            "pareto": front.contains(&i),
        })).collect::<Vec<_>>(),
    });
    let mut csv =
        String::from("object,method,setting,seconds,relative_rmse,max_error,sources,pareto\n");
    for (i, r) in runs.iter().enumerate() {
        csv.push_str(&format!(
            "{},{},{},{:.6},{:.6e},{:.6e},{},{}\n",
            r.object,
            r.method.name(),
            r.setting,
            r.seconds,
            r.rmse,
            r.max_error,
            r.sources,
            front.contains(&i)
        ));
    }
    let series: Vec<Series> = [Method::Octree, Method::Texture, Method::Importance]
        .into_iter()
        .map(|m| Series {
            name: m.name().to_string(),
            points: runs
                .iter()
                .filter(|r| r.method == m)
                .map(|r| (r.seconds, r.rmse, r.setting.clone()))
                .collect(),
        })
        .collect();
    let brute_seconds = runs
        .iter()
        .filter(|r| r.method == Method::Brute)
        .map(|r| r.seconds)
        .sum::<f64>();
    let (_, first) = &loaded.objects[0];
    let title = format!(
        "{} · {} ({}) · {}² · error against run time",
        args.scene
            .input
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default(),
        first.material.name,
        first.profile.model(),
        args.scene.resolution
    );
    let svg = render(&title, &series, brute_seconds);
    let png = render_png(&svg).map_err(Failure::Output)?;
    let json_text = serde_json::to_string_pretty(&report).unwrap_or_default() + "\n";
    for (path, bytes) in
        outputs
            .iter()
            .zip([json_text.as_bytes(), csv.as_bytes(), svg.as_bytes(), &png])
    {
        write_atomically(path, bytes).map_err(Failure::Output)?;
    }
    println!("Pareto front (no run is both faster and more accurate):");
    for &i in &front {
        let r = &runs[i];
        println!(
            "  {:<12} {:<11} {:<14} {:>9.3} s   RMSE {:.2e}   max {:.2e}",
            r.object,
            r.method.name(),
            r.setting,
            r.seconds,
            r.rmse,
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
            Some((object, error)) if object == r.object => r.rmse < error,
            _ => true,
        };
        if better {
            front.push(i);
            best = Some((&r.object, r.rmse));
        }
    }
    front
}
