//! The error-against-time report: every integrator run across a ladder of
//! settings on a scene, each against the exact sum, with the Pareto front of
//! time and error, a CSV, a plot (SVG and PNG) and, for the request's own
//! settings, a map of where each errs.

use crate::error_map::error_map;
use crate::plot::render_png;
use crate::report_plot::{Series, render};
use serde::Serialize;
use sssbake::control::Control;
use sssbake::pipeline::prepare;
use sssbake::transport::accuracy::relative_errors;
use sssbake::transport::brute::BruteIntegrator;
use sssbake::{BakeRequest, Error, Method, Scene, plan};
use sssbake_io::atomic_write::write_atomically;
use sssbake_io::image_writer::png_bytes;
use std::path::{Path, PathBuf};

/// One run of the ladder.
#[derive(Clone, Debug, Serialize)]
pub struct Run {
    /// The object's name.
    pub object: String,
    /// The integrator.
    pub method: Method,
    /// Its setting, in words (`ε 0.5`, `6 G`, `512 spp`).
    pub setting: String,
    /// Seconds it integrated.
    pub seconds: f64,
    /// Its relative RMSE against the exact sum.
    pub relative_rmse: f64,
    /// Its largest error relative to the brightest texel.
    pub max_error: f64,
    /// Sources it gathered from.
    pub sources: usize,
    /// True when no run of the object is both faster and more accurate.
    pub pareto: bool,
}

/// One object of the report.
#[derive(Clone, Debug, Serialize)]
pub struct ReportObject {
    /// The object's name.
    pub name: String,
    /// Its material.
    pub material: String,
    /// The material's model.
    pub model: String,
    /// The profile's reach, mm.
    pub d_max_mm: f32,
    /// Its texels.
    pub texels: usize,
    /// Whether it was unwrapped.
    pub unwrapped: bool,
    /// Seconds spent lighting it.
    pub prepare_seconds: f64,
}

/// The whole report, as report.json holds it.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// The scene as named.
    pub scene: String,
    /// Texels per side.
    pub resolution: u32,
    /// Worker threads.
    pub threads: usize,
    /// Each object.
    pub objects: Vec<ReportObject>,
    /// Every run, the exact sum first per object.
    pub runs: Vec<Run>,
}

/// The files a report writes into a folder, its error maps aside.
pub const FILES: [&str; 4] = ["report.json", "report.csv", "report.svg", "report.png"];

/// Refuses a folder that holds a report already, unless `force`: checked
/// before the runs, which take minutes.
pub fn check_folder(out: &Path, force: bool) -> Result<(), Error> {
    match FILES.map(|f| out.join(f)).into_iter().find(|p| p.exists()) {
        Some(existing) if !force => Err(Error::output(
            existing.display(),
            "exists (use --force to replace it)",
        )),
        _ => Ok(()),
    }
}

/// A report and the files that show it.
pub struct ReportFiles {
    /// The report (report.json).
    pub report: Report,
    /// Its runs as CSV (report.csv).
    pub csv: Vec<u8>,
    /// Error against run time, as SVG (report.svg).
    pub svg: String,
    /// The same plot as PNG (report.png).
    pub png: Vec<u8>,
    /// Per object and method, where the run with the request's own
    /// settings errs: the file name (`error_<object>_<method>.png`) and
    /// its PNG bytes.
    pub error_maps: Vec<(String, Vec<u8>)>,
    /// The indices of the runs on the Pareto front, fastest first.
    pub front: Vec<usize>,
}

impl ReportFiles {
    /// Writes every file into `out` (made if missing), each whole; returns
    /// their paths, the error maps first.
    pub fn write(&self, out: &Path) -> Result<Vec<PathBuf>, Error> {
        std::fs::create_dir_all(out)
            .map_err(|e| Error::output(out.display(), format!("cannot create: {e}")))?;
        let json = serde_json::to_string_pretty(&self.report).unwrap_or_default() + "\n";
        let whole: [&[u8]; 4] = [json.as_bytes(), &self.csv, self.svg.as_bytes(), &self.png];
        let maps = self
            .error_maps
            .iter()
            .map(|(f, b)| (f.as_str(), b.as_slice()));
        let mut written = Vec::new();
        for (file, bytes) in maps.chain(FILES.into_iter().zip(whole)) {
            let path = out.join(file);
            write_atomically(&path, bytes)
                .map_err(|e| Error::output(path.display(), format!("cannot write: {e}")))?;
            written.push(path);
        }
        Ok(written)
    }
}

/// Runs every integrator of the ladder on `scene` (named `name`) as
/// `request` asks, each against the exact sum, which the plan checks
/// against the limits; `log` gets a line per run.
pub fn error_against_time(
    name: &str,
    scene: &Scene,
    request: &BakeRequest,
    log: &mut dyn FnMut(String),
) -> Result<ReportFiles, Error> {
    let mut request = request.clone();
    request.method = Method::Brute;
    let plan = plan(scene, &request)?;
    let mut error_maps = Vec::new();
    let control = Control::new();
    let mut runs = Vec::new();
    let mut objects = Vec::new();
    for object in &plan.objects {
        let scattering = &object.scattering_profile;
        let prepared = prepare(
            scene,
            object.index,
            object.layout.clone(),
            &plan.request,
            scattering,
            true,
            &control,
        )?;
        let reference =
            prepared.integrate(scattering, &BruteIntegrator, request.tolerance, &control)?;
        log(format!(
            "{}: brute over {} texels in {:.2} s (lit in {:.2} s)",
            object.name,
            prepared.surfels.len(),
            reference.seconds,
            prepared.seconds()
        ));
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
        // Each integrator of the profile across its own ladder of settings.
        let rungs = Method::ALL.iter().flat_map(|&method| {
            let own = plan.request.integrators.get(method);
            let own_name = format!("{own:?}");
            own.ladder()
                .into_iter()
                .map(move |(setting, rung)| (method, setting, rung, own_name.clone()))
        });
        for (method, setting, integrator, own) in rungs {
            let result =
                prepared.integrate(scattering, integrator.as_ref(), request.tolerance, &control)?;
            let (rmse, max_error) = relative_errors(&result.exitance, &reference.exitance);
            // The run with the request's own settings gets a map of where it
            // errs (an integrator's `Debug` form names it with its settings).
            if format!("{integrator:?}") == own {
                let map = error_map(&prepared.surfels, &result.exitance, &reference.exitance);
                let file = format!("error_{}_{}.png", object.file_stem, method.name());
                let bytes = png_bytes(&map).map_err(|e| Error::output(&file, e))?;
                error_maps.push((file, bytes));
            }
            log(format!(
                "{}: {method} {setting}: {:.3} s, RMSE {rmse:.2e}",
                object.name, result.seconds
            ));
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
            .map_err(|e| Error::output("report.csv", e.to_string()))?;
    }
    let csv = csv
        .into_inner()
        .map_err(|e| Error::output("report.csv", e.to_string()))?;
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
        std::path::Path::new(name)
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default(),
        first.name,
        first.model,
        plan.resolution
    );
    let svg = render(&title, &series, brute_seconds);
    let png = render_png(&svg).map_err(|e| Error::output("report.png", e))?;
    let report = Report {
        scene: name.to_string(),
        resolution: plan.resolution,
        threads: rayon::current_num_threads(),
        objects,
        runs,
    };
    Ok(ReportFiles {
        report,
        csv,
        svg,
        png,
        error_maps,
        front,
    })
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
