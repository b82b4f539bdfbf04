//! `sssbake profile`: a material's reflectance profile as a table, JSON or plot.

use sssbake::Error;
use sssbake_analysis::plot::{file_bytes, is_plot_file};
use sssbake_analysis::profile_report::{ProfileRequest, analyse, material};
use sssbake_io::atomic_write::write_atomically;
use sssbake_profile::material::TopLayer;
use sssbake_profile::{Material, Model};
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
    if let Some(path) = args.plot.as_ref().filter(|p| !is_plot_file(p)) {
        let message = format!(
            "--plot {}: the file must end in .svg or .png",
            path.display()
        );
        return Err(Error::input(message));
    }
    let material = material(args.preset.as_deref(), args.material.as_deref())?;
    let model = args.model.unwrap_or_else(|| Model::default_for(&material));
    if model == Model::Stam {
        return run_stam(args, &material);
    }
    let request = ProfileRequest {
        model,
        radii: args.radii.clone(),
        epsilon: args.epsilon,
        gaussians: args.gaussians,
        compare_montecarlo: args.compare_montecarlo,
        photons: args.photons,
        seed: args.seed,
    };
    let analysis = analyse(&material, &request).map_err(as_flag)?;
    if let Some(path) = &args.plot {
        write_svg(path, analysis.svg())?;
    }
    let json = || serde_json::to_string_pretty(&analysis.json()).unwrap_or_default() + "\n";
    emit(&if args.json { json() } else { analysis.text() });
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
        let epidermis = sssbake_analysis::stam_contact_report::solve(material)?;
        if let Some(path) = &args.plot {
            let title = format!(
                "{} — stam top layer in contact, roughness {}",
                material.name, material.roughness
            );
            write_svg(
                path,
                sssbake_analysis::angle_plot::render_contact_svg(&title, &epidermis),
            )?;
        }
        emit(&sssbake_analysis::stam_contact_report::report(
            material, &epidermis, args.json,
        ));
        return Ok(());
    }
    let responses = sssbake_analysis::stam_report::solve(material)?;
    if let Some(path) = &args.plot {
        let title = format!("{} — stam, roughness {}", material.name, material.roughness);
        write_svg(
            path,
            sssbake_analysis::angle_plot::render_svg(&title, &responses),
        )?;
    }
    emit(&sssbake_analysis::stam_report::report(
        material, &responses, args.json,
    ));
    Ok(())
}

/// Writes to standard output; a reader that went away (`| head`) is not an error.
fn emit(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

/// A setting's error said of its flag (`radii` is `--radii`).
fn as_flag(error: Error) -> Error {
    match error {
        Error::Setting { field, message } => Error::Setting {
            field: format!("--{}", field.replace('_', "-")),
            message,
        },
        other => other,
    }
}

/// Writes `svg` to `path` as it is, or rasterised for a `.png`.
fn write_svg(path: &Path, svg: String) -> Result<(), Error> {
    let bytes = file_bytes(path, svg).map_err(|e| Error::output(path.display(), e))?;
    write_atomically(path, &bytes)
        .map_err(|e| Error::output(path.display(), format!("cannot write: {e}")))
}
