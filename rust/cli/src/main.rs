//! `sssbake`: bakes subsurface scattering into textures.
//!
//! Exit codes: 0 success; 1 bad input (a scene or image that cannot be
//! read, an unknown object or preset, an invalid material file, a model
//! that does not fit the material, a value out of range); 2 bad command
//! line; 3 an output could not be written; 4 cancelled; 5 a batch in
//! which some assets failed (the others were baked); 70 an internal error
//! (a bug: please report it).

mod bake_command;
mod batch_command;
mod plan_command;
mod profile_command;
mod progress;
mod report_command;
mod request_args;

use clap::{Parser, Subcommand};
use sssbake::Error;
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

// A negative number is a value, so `--resolution -5` is refused as out of
// range for that option rather than as an unknown flag.
#[derive(Subcommand)]
enum Command {
    /// Bake subsurface scattering maps for the objects of a scene.
    #[command(allow_negative_numbers = true)]
    Bake(Box<bake_command::BakeArgs>),
    /// Bake the assets of a TOML manifest, each into its own folder,
    /// skipping those unchanged since their last bake; or write the batch
    /// as an Open Job Description job bundle.
    #[command(allow_negative_numbers = true)]
    Batch(batch_command::BatchArgs),
    /// Print and plot a material's diffusion reflectance profile.
    #[command(allow_negative_numbers = true)]
    Profile(profile_command::ProfileArgs),
    /// Show what a bake with the same options would do, and what it would
    /// leave out, without baking.
    #[command(allow_negative_numbers = true)]
    Plan(Box<plan_command::PlanArgs>),
    /// List the material presets.
    Presets,
    /// Run every integrator on a scene across a ladder of settings and
    /// report each one's error against the exact sum and its run time.
    #[command(allow_negative_numbers = true)]
    Report(Box<report_command::ReportArgs>),
    /// Print every command and option as Markdown: the reference in
    /// docs/cli.md.
    #[command(hide = true)]
    HelpMarkdown,
}

/// Every command and option as Markdown, from the definitions above: the
/// headings one level down, to sit under a page's own title, and one blank
/// line at most between blocks.
fn help_markdown() -> String {
    let options = clap_markdown::MarkdownOptions::new()
        .title("Every command and option".to_string())
        .show_footer(false);
    let text = clap_markdown::help_markdown_custom::<Cli>(&options);
    let mut markdown = String::with_capacity(text.len());
    let mut blank = true;
    for line in text.lines() {
        let line = line.trim_end();
        // The page says what the reference is; clap-markdown's own sentence
        // calls it a document of its own.
        if line.starts_with("This document contains") {
            continue;
        }
        if line.is_empty() && blank {
            continue;
        }
        blank = line.is_empty();
        if let Some(label) = line.strip_prefix("###### ") {
            markdown.push_str(label);
        } else if line.starts_with('#') {
            markdown.push('#');
            markdown.push_str(line);
        } else {
            markdown.push_str(line);
        }
        markdown.push('\n');
    }
    while markdown.ends_with("\n\n") {
        markdown.pop();
    }
    markdown
}

/// Prints `value` as pretty JSON on stdout.
pub fn print_json(value: &impl serde::Serialize) {
    match serde_json::to_string_pretty(value) {
        Ok(text) => println!("{text}"),
        Err(e) => eprintln!("error: cannot print JSON: {e}"),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Panics are caught where they can come from bad input (the readers)
    // and here, and reported as errors; the default hook would print a
    // backtrace first. RUST_BACKTRACE keeps it for debugging.
    if std::env::var_os("RUST_BACKTRACE").is_none() {
        std::panic::set_hook(Box::new(|_| {}));
    }
    let result = std::panic::catch_unwind(|| run(cli)).unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        eprintln!("error: internal error (please report it): {what}");
        Err(None)
    });
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(batch_command::SOME_FAILED),
        Err(None) => ExitCode::from(70),
        Err(Some(error)) => {
            let error = error.naming_limit(|field| format!("--{}", field.replace('_', "-")));
            eprintln!("error: {error}");
            ExitCode::from(match error {
                Error::Input(_) | Error::Setting { .. } => 1,
                Error::Output { .. } => 3,
                Error::Cancelled => 4,
            })
        }
    }
}

/// Runs the command; `Ok(false)` when a batch finished with some assets
/// failed, `Err(Some)` for a failure, as the exit codes say.
fn run(cli: Cli) -> Result<bool, Option<Error>> {
    if let Command::Batch(args) = &cli.command {
        return batch_command::run(args).map_err(Some);
    }
    let result = match cli.command {
        Command::Batch(_) => Ok(()),
        Command::Bake(args) => bake_command::run(&args),
        Command::Profile(args) => profile_command::run(&args),
        Command::Plan(args) => plan_command::run(&args),
        Command::Report(args) => report_command::run(&args),
        Command::HelpMarkdown => {
            print!("{}", help_markdown());
            Ok(())
        }
        Command::Presets => {
            for (name, description) in sssbake_profile::presets::list() {
                println!("{name:<12} {description}");
            }
            Ok(())
        }
    };
    result.map(|()| true).map_err(Some)
}
