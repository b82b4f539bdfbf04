//! `sssbake report`: every integrator on a scene across a ladder of
//! settings, each against the exact sum ([`sssbake_analysis::report`]),
//! written as report.json, report.csv, report.svg/.png and error maps.

use crate::request_args::RequestArgs;
use sssbake::Error;
use sssbake_analysis::report::error_against_time;
use sssbake_io::atomic_write::write_atomically;
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

/// Runs the command.
pub fn run(args: &ReportArgs) -> Result<(), Error> {
    let (scene, request) = args.request.load()?;
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
    let name = args.request.input.display().to_string();
    let files = error_against_time(&name, &scene, &request, &mut |line| eprintln!("{line}"))?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| Error::output(args.out.display(), format!("cannot create: {e}")))?;
    let json_text = serde_json::to_string_pretty(&files.report).unwrap_or_default() + "\n";
    let maps = files
        .error_maps
        .iter()
        .map(|(file, bytes)| (args.out.join(file), bytes.as_slice()));
    let whole = outputs.iter().cloned().zip([
        json_text.as_bytes(),
        &files.csv,
        files.svg.as_bytes(),
        &files.png,
    ]);
    for (path, bytes) in maps.chain(whole) {
        write_atomically(&path, bytes)
            .map_err(|e| Error::output(path.display(), format!("cannot write: {e}")))?;
    }
    println!("Pareto front (no run is both faster and more accurate):");
    for &i in &files.front {
        let r = &files.report.runs[i];
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
