//! `sssbake`: bakes subsurface scattering into textures.
//!
//! Exit codes: 0 success; 1 bad input (a scene or image that cannot be
//! read, an unknown object or preset, an invalid material file, a model
//! that does not fit the material, a value out of range); 2 bad command
//! line; 3 an output could not be written.

mod asset_outputs;
mod bake_command;
mod material_choice;
mod material_map;
mod plan_command;
mod plot;
mod profile_command;
mod progress;
mod report_command;
mod report_plot;
mod scene_options;
mod staging;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "sssbake",
    version,
    about = "Bake subsurface scattering into textures"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Bake subsurface scattering maps for the objects of a scene.
    Bake(bake_command::BakeArgs),
    /// Print and plot a material's diffusion reflectance profile.
    Profile(profile_command::ProfileArgs),
    /// Show what a bake of a scene would do, and what it would leave out.
    Plan(plan_command::PlanArgs),
    /// List the material presets.
    Presets,
    /// Run every integrator on a scene across a ladder of settings and
    /// report each one's error against the exact sum and its run time.
    Report(report_command::ReportArgs),
}

/// A failure with the exit code it maps to.
pub enum Failure {
    /// Bad input: exit code 1.
    Input(String),
    /// An output could not be written: exit code 3.
    Output(String),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Bake(args) => bake_command::run(&args),
        Command::Profile(args) => profile_command::run(&args),
        Command::Plan(args) => plan_command::run(&args),
        Command::Report(args) => report_command::run(&args),
        Command::Presets => {
            for (name, description) in sssbake_profile::presets::list() {
                println!("{name:<12} {description}");
            }
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Input(message)) => {
            eprintln!("error: {message}");
            ExitCode::from(1)
        }
        Err(Failure::Output(message)) => {
            eprintln!("error: {message}");
            ExitCode::from(3)
        }
    }
}
