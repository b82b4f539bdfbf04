//! `sssbake profile`: a material's reflectance profile as a table, JSON or plot.

use crate::plot::{Curve, render_png, render_svg};
use serde_json::{Value, json};
use sssbake::Error;
use sssbake_io::atomic_write::write_atomically;
use sssbake_profile::material::TopLayer;
use sssbake_profile::models::empirical::{EmpiricalProfile, EmpiricalSettings, FitError};
use sssbake_profile::models::monte_carlo::{self, MonteCarlo};
use sssbake_profile::profile::default_radii;
use sssbake_profile::{Material, Model, Profile, Rgb, Tabulated, build_profile};
use std::path::{Path, PathBuf};

/// Options of `sssbake profile`.
#[derive(clap::Args)]
pub struct ProfileArgs {
    /// A named material (see `sssbake presets`).
    #[arg(
        long,
        required_unless_present = "material",
        conflicts_with = "material"
    )]
    preset: Option<String>,
    /// A TOML material file with [[layers]].
    #[arg(long)]
    material: Option<PathBuf>,
    /// The profile model [default: the one the material needs].
    #[arg(long, value_parser = crate::request_args::named::<Model>(<Model as strum::VariantNames>::VARIANTS))]
    model: Option<Model>,
    /// Radii in mm, comma-separated [default: 60 from the peak to d_max].
    #[arg(long, value_delimiter = ',')]
    radii: Option<Vec<f64>>,
    /// Photons per channel for the Monte Carlo reference.
    #[arg(long, default_value_t = 100_000)]
    photons: u64,
    /// Seed of the Monte Carlo reference.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Number of Gaussians when fitting.
    #[arg(long, default_value_t = 6)]
    gaussians: usize,
    /// Fraction of the reflectance allowed outside d_max.
    #[arg(long, default_value_t = 1e-3)]
    epsilon: f64,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Draw R(r) and r·R(r) to FILE.svg or FILE.png.
    #[arg(long, value_name = "FILE")]
    plot: Option<PathBuf>,
    /// Overlay (and report) the Monte Carlo reference.
    #[arg(long)]
    compare_montecarlo: bool,
}

/// Runs the command.
pub fn run(args: &ProfileArgs) -> Result<(), Error> {
    check_arguments(args)?;
    let material = load_material(args)?;
    let model = args.model.unwrap_or_else(|| Model::default_for(&material));
    if model == Model::Stam {
        return run_stam(args, &material);
    }
    let needs_simulation = model == Model::MonteCarlo || args.compare_montecarlo;
    if needs_simulation && material.layers().is_none() {
        return Err(Error::input(format!(
            "material `{}` is a measured sum of Gaussians; it has no layers to simulate",
            material.name
        )));
    }

    let reference_model = if model == Model::MonteCarlo {
        Model::default_for(&material)
    } else {
        model
    };
    // The empirical model's fit error is reported with its profile.
    let empirical = if model == Model::Empirical {
        let fitted = EmpiricalProfile::simulate(&material, &EmpiricalSettings::default()).map_err(
            |reason| {
                Error::input(format!(
                    "material `{}`: model empirical: {reason}",
                    material.name
                ))
            },
        )?;
        Some(fitted)
    } else {
        None
    };
    let profile: Box<dyn Profile> = match &empirical {
        Some(fitted) => Box::new(fitted.clone()),
        None => build_profile(&material, reference_model, args.gaussians).map_err(Error::from)?,
    };
    let radii = match &args.radii {
        Some(r) => r.clone(),
        None => default_radii(profile.as_ref(), args.epsilon),
    };
    let simulation = needs_simulation.then(|| {
        let settings =
            monte_carlo::Settings::new(args.photons, args.seed, monte_carlo::edges_around(&radii));
        monte_carlo::simulate(material.layers().unwrap_or_default(), &settings)
    });

    let shown: Box<dyn Profile> = match (&simulation, model) {
        (Some(mc), Model::MonteCarlo) => Box::new(tabulate_simulation(mc, &radii)),
        _ => profile,
    };
    let report = Report {
        material: &material,
        model,
        profile: shown.as_ref(),
        radii: &radii,
        epsilon: args.epsilon,
    };

    if let Some(path) = &args.plot {
        let overlay = simulation.as_ref().filter(|_| model != Model::MonteCarlo);
        write_plot(
            path,
            &report,
            overlay,
            simulation.as_ref().filter(|_| model == Model::MonteCarlo),
        )?;
    }
    if args.json {
        let mut value = report.json();
        if let (Some(fitted), Value::Object(fields)) = (&empirical, &mut value) {
            fields.insert("fit_error".into(), fit_error_json(fitted));
        }
        if let Some(mc) = &simulation {
            let key = if model == Model::MonteCarlo {
                None
            } else {
                Some("montecarlo")
            };
            add_simulation(&mut value, mc, key);
        }
        emit(&format!(
            "{}\n",
            serde_json::to_string_pretty(&value).unwrap_or_default()
        ));
    } else {
        let mut text = report.table();
        if let Some(fitted) = &empirical {
            text += &fit_error_summary(fitted);
        }
        if let Some(mc) = &simulation {
            text += &simulation_summary(mc);
        }
        emit(&text);
    }
    Ok(())
}

/// `--model stam`: angles, not radii; the radial options do not apply.
fn run_stam(args: &ProfileArgs, material: &Material) -> Result<(), Error> {
    let radial = [
        ("--radii", args.radii.is_some()),
        ("--compare-montecarlo", args.compare_montecarlo),
    ];
    if let Some((flag, _)) = radial.iter().find(|(_, given)| *given) {
        return Err(Error::input(format!(
            "{flag}: stam gives R and T per incidence angle and BRDF slices (--json, --plot), not a radial profile"
        )));
    }
    // A stack's declared Stam top layer is shown as a bake uses it, in
    // contact with the layer beneath, not alone between air.
    if material.top_layer == TopLayer::Stam {
        let epidermis = crate::stam_contact_report::solve(material)?;
        if let Some(path) = &args.plot {
            let title = format!(
                "{} — stam top layer in contact, roughness {}",
                material.name, material.roughness
            );
            write_svg(
                path,
                crate::angle_plot::render_contact_svg(&title, &epidermis),
            )?;
        }
        emit(&crate::stam_contact_report::report(
            material, &epidermis, args.json,
        ));
        return Ok(());
    }
    let responses = crate::stam_report::solve(material)?;
    if let Some(path) = &args.plot {
        let title = format!("{} — stam, roughness {}", material.name, material.roughness);
        write_svg(path, crate::angle_plot::render_svg(&title, &responses))?;
    }
    emit(&crate::stam_report::report(material, &responses, args.json));
    Ok(())
}

/// Writes to standard output; a reader that went away (`| head`) is not an error.
fn emit(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

fn check_arguments(args: &ProfileArgs) -> Result<(), Error> {
    let bad = |m: String| Err(Error::input(m));
    if let Some(radii) = &args.radii {
        if radii.is_empty() {
            return bad("--radii: give at least one radius in mm".into());
        }
        if let Some(r) = radii.iter().find(|r| !(r.is_finite() && **r >= 0.0)) {
            return bad(format!(
                "--radii: {r} is not a finite, non-negative radius in mm"
            ));
        }
        if radii.windows(2).any(|w| w[1] <= w[0]) {
            return bad("--radii: radii must increase".into());
        }
    }
    if !(args.epsilon > 0.0 && args.epsilon < 1.0) {
        return bad(format!(
            "--epsilon: {} must lie strictly between 0 and 1",
            args.epsilon
        ));
    }
    if !(1..=16).contains(&args.gaussians) {
        return bad(format!(
            "--gaussians: {} must be between 1 and 16",
            args.gaussians
        ));
    }
    if args.photons == 0 && (args.compare_montecarlo || args.model == Some(Model::MonteCarlo)) {
        return bad("--photons: the Monte Carlo reference needs at least one photon".into());
    }
    if let Some(path) = &args.plot {
        plot_format(path)?;
    }
    Ok(())
}

fn load_material(args: &ProfileArgs) -> Result<Material, Error> {
    match (&args.preset, &args.material) {
        (Some(name), _) => sssbake_profile::presets::named(name).map_err(Error::input),
        (None, Some(path)) => Material::from_file(path).map_err(Error::from),
        (None, None) => Err(Error::input("give --preset NAME or --material FILE")),
    }
}

/// The simulation's bins as a profile (for d_max and plotting).
fn tabulate_simulation(mc: &MonteCarlo, radii: &[f64]) -> Tabulated {
    let positive: Vec<usize> = (0..radii.len()).filter(|&i| radii[i] > 0.0).collect();
    Tabulated::new(
        "montecarlo",
        positive.iter().map(|&i| radii[i]).collect(),
        positive.iter().map(|&i| mc.reflectance[i]).collect(),
        positive.iter().map(|&i| mc.transmittance[i]).collect(),
        mc.total_reflectance,
        mc.total_transmittance,
    )
}

struct Report<'a> {
    material: &'a Material,
    model: Model,
    profile: &'a dyn Profile,
    radii: &'a [f64],
    epsilon: f64,
}

impl Report<'_> {
    fn reflectance(&self) -> Vec<Rgb> {
        self.radii
            .iter()
            .map(|&r| self.profile.reflectance(r))
            .collect()
    }

    fn json(&self) -> Value {
        json!({
            "material": self.material.name,
            "model": self.model.name(),
            "radii_mm": self.radii,
            "reflectance": self.reflectance(),
            "transmittance": self.radii.iter().map(|&r| self.profile.transmittance(r)).collect::<Vec<_>>(),
            "total_reflectance": self.profile.total_reflectance(),
            "total_transmittance": self.profile.total_transmittance(),
            "ballistic_reflectance": self.profile.ballistic_reflectance(),
            "ballistic_transmittance": self.profile.ballistic_transmittance(),
            "d_max_mm": self.profile.d_max(self.epsilon),
            "epsilon": self.epsilon,
        })
    }

    fn table(&self) -> String {
        let rgb = |v: Rgb| format!("{:>12.6} {:>12.6} {:>12.6}", v[0], v[1], v[2]);
        let mut text = format!(
            "material {}, model {}\n",
            self.material.name,
            self.model.name()
        );
        text += &format!(
            "total reflectance    {}\n",
            rgb(self.profile.total_reflectance())
        );
        text += &format!(
            "total transmittance  {}\n",
            rgb(self.profile.total_transmittance())
        );
        text += &format!(
            "d_max (eps {:.0e}) mm {}\n",
            self.epsilon,
            rgb(self.profile.d_max(self.epsilon))
        );
        text += &format!(
            "{:>12} {:>12} {:>12} {:>12}   (R in 1/mm²)\n",
            "r [mm]", "R red", "R green", "R blue"
        );
        for (r, v) in self.radii.iter().zip(self.reflectance()) {
            text += &format!(
                "{r:>12.5} {:>12.5e} {:>12.5e} {:>12.5e}\n",
                v[0], v[1], v[2]
            );
        }
        text
    }
}

fn add_simulation(value: &mut Value, mc: &MonteCarlo, key: Option<&str>) {
    let fields = json!({
        "reflectance": mc.reflectance,
        "reflectance_stderr": mc.reflectance_stderr,
        "transmittance": mc.transmittance,
        "transmittance_stderr": mc.transmittance_stderr,
        "bin_edges_mm": mc.edges_mm,
        "total_reflectance": mc.total_reflectance,
        "total_reflectance_stderr": mc.total_reflectance_stderr,
        "total_transmittance": mc.total_transmittance,
        "total_transmittance_stderr": mc.total_transmittance_stderr,
        "unscattered_reflectance": mc.unscattered_reflectance,
        "unscattered_transmittance": mc.unscattered_transmittance,
        "specular_reflectance": mc.specular_reflectance,
        "truncated_weight": mc.truncated,
        "photons": mc.photons,
        "interactions": mc.interactions,
    });
    let (Value::Object(target), Value::Object(fields)) = (value, fields) else {
        return;
    };
    match key {
        Some(key) => {
            target.insert(key.to_string(), Value::Object(fields));
        }
        None => target.extend(fields),
    }
}

/// The empirical fit's error per channel, as JSON (see [`FitError`]).
fn fit_error_json(fitted: &EmpiricalProfile) -> Value {
    let errors = fitted.fit_error();
    let per_channel = |f: fn(&FitError) -> f64| errors.iter().map(f).collect::<Vec<f64>>();
    json!({
        "mean_rms": per_channel(|e| e.mean_rms),
        "mean_relative_rms": per_channel(|e| e.mean_relative_rms),
        "mean_noise_rms": per_channel(|e| e.mean_noise_rms),
    })
}

fn fit_error_summary(fitted: &EmpiricalProfile) -> String {
    let errors = fitted.fit_error();
    let row = |f: fn(&FitError) -> f64| {
        errors
            .iter()
            .map(|e| format!("{:.3e}", f(e)))
            .collect::<Vec<_>>()
            .join(" ")
    };
    format!(
        "Empirical fit within 10 mean free paths, per channel: RMS {} /(mfp² sr) \
         (simulation noise {}), RMS over peak {}\n",
        row(|e| e.mean_rms),
        row(|e| e.mean_noise_rms),
        row(|e| e.mean_relative_rms),
    )
}

fn simulation_summary(mc: &MonteCarlo) -> String {
    let rgb = |v: Rgb, e: Rgb| {
        format!(
            "{:.5}±{:.5} {:.5}±{:.5} {:.5}±{:.5}",
            v[0], e[0], v[1], e[1], v[2], e[2]
        )
    };
    format!(
        "Monte Carlo ({} photons per channel): total reflectance {}, total transmittance {}\n",
        mc.photons,
        rgb(mc.total_reflectance, mc.total_reflectance_stderr),
        rgb(mc.total_transmittance, mc.total_transmittance_stderr),
    )
}

enum PlotFormat {
    Svg,
    Png,
}

fn plot_format(path: &Path) -> Result<PlotFormat, Error> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("svg") => Ok(PlotFormat::Svg),
        Some("png") => Ok(PlotFormat::Png),
        _ => Err(Error::input(format!(
            "--plot {}: the file must end in .svg or .png",
            path.display()
        ))),
    }
}

fn write_plot(
    path: &Path,
    report: &Report,
    overlay: Option<&MonteCarlo>,
    simulated: Option<&MonteCarlo>,
) -> Result<(), Error> {
    let mut curves: Vec<Curve> = (0..3)
        .map(|c| Curve {
            channel: c,
            label: report.model.name().to_string(),
            points: report
                .radii
                .iter()
                .map(|&r| (r, report.profile.reflectance(r)[c]))
                .collect(),
            errors: simulated.map(|mc| mc.reflectance_stderr.iter().map(|e| e[c]).collect()),
            markers: simulated.is_some(),
        })
        .collect();
    if let Some(mc) = overlay {
        curves.extend((0..3).map(|c| {
            Curve {
                channel: c,
                label: "Monte Carlo".into(),
                points: report
                    .radii
                    .iter()
                    .zip(&mc.reflectance)
                    .map(|(&r, v)| (r, v[c]))
                    .collect(),
                errors: Some(mc.reflectance_stderr.iter().map(|e| e[c]).collect()),
                markers: true,
            }
        }));
    }
    let title = format!("{} — {}", report.material.name, report.model.name());
    let svg = render_svg(&title, &curves);
    write_svg(path, svg)
}

/// Writes `svg` to `path` as it is, or rasterised for a `.png`.
fn write_svg(path: &Path, svg: String) -> Result<(), Error> {
    let bytes = match plot_format(path)? {
        PlotFormat::Svg => svg.into_bytes(),
        PlotFormat::Png => render_png(&svg).map_err(|e| Error::output(path.display(), e))?,
    };
    write_atomically(path, &bytes)
        .map_err(|e| Error::output(path.display(), format!("cannot write: {e}")))
}
