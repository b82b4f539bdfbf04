//! `sssbake report`: every integrator on a scene across a ladder of
//! settings, each against the exact sum ([`sssbake_analysis::report`]),
//! written as report.json, report.csv, report.svg/.png and error maps.

use crate::request_args::RequestArgs;
use sssbake::Error;
use sssbake_analysis::report::{check_folder, error_against_time};
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
    check_folder(&args.out, args.force)?;
    let name = args.request.input.display().to_string();
    let files = error_against_time(&name, &scene, &request, &mut |line| eprintln!("{line}"))?;
    files.write(&args.out)?;
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
