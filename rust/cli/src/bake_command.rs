//! `sssbake bake`: the maps of every selected object and the input's
//! assets showing them, written whole or not at all.

use crate::progress::watch;
use crate::request_args::{RequestArgs, Settings};
use sssbake::control::Control;
use sssbake::{Error, plan};
use sssbake_io::bake_to_folder;
use std::path::PathBuf;

/// Options of `sssbake bake`.
#[derive(clap::Args)]
pub struct BakeArgs {
    #[command(flatten)]
    pub(crate) request: RequestArgs,
    /// The folder for the maps (created if missing; not the input's own).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// How the maps are written.
    #[command(flatten)]
    writing: Settings<true>,
    /// Replace maps already in the folder.
    #[arg(long)]
    force: bool,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
}

/// Runs the command.
pub fn run(args: &BakeArgs) -> Result<(), Error> {
    let (scene, request) = args.request.load()?;
    let plan = plan(&scene, &request)?;
    let options = args
        .request
        .settings
        .options
        .or(&args.writing.options)
        .folder(&args.out, args.force);
    let control = Control::new();
    let summary = watch(&control, args.json, || {
        bake_to_folder(&args.request.input, &scene, &plan, &options, &control)
    })?;
    if args.json {
        crate::print_json(&summary);
    } else {
        print!("{summary}");
        println!("in {}", args.out.display());
    }
    Ok(())
}
