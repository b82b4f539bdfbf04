//! `sssbake bake`: the maps of every selected object and the input's
//! assets showing them, written whole or not at all.

use crate::progress::watch;
use crate::request_args::RequestArgs;
use sssbake::control::Control;
use sssbake::{Error, plan};
use sssbake_io::image_writer::Precision;
use sssbake_io::{FolderOptions, bake_to_folder};
use std::path::PathBuf;

/// Options of `sssbake bake`.
#[derive(clap::Args)]
pub struct BakeArgs {
    #[command(flatten)]
    pub(crate) request: RequestArgs,
    /// The folder for the maps (created if missing; not the input's own).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Write EXRs as 16-bit half floats instead of 32-bit.
    #[arg(long)]
    half: bool,
    /// Exposure of the PNG previews, in stops (the EXRs stay as baked).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    exposure: f32,
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
    let options = FolderOptions {
        out: args.out.clone(),
        force: args.force,
        precision: if args.half {
            Precision::Half
        } else {
            Precision::Float
        },
        exposure: args.exposure,
        uv_set: args.request.uv_set,
        layer_writer: None,
    };
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
