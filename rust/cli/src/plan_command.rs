//! `sssbake plan`: the plan `sssbake bake` with the same options runs,
//! without running it.

use crate::request_args::RequestArgs;
use sssbake::{Error, plan};

/// Options of `sssbake plan`: those of `sssbake bake` that decide the bake.
#[derive(clap::Args)]
pub struct PlanArgs {
    #[command(flatten)]
    request: RequestArgs,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs the command.
pub fn run(args: &PlanArgs) -> Result<(), Error> {
    let (scene, request) = args.request.load()?;
    let plan = plan(&scene, &request)?;
    if args.json {
        crate::print_json(&plan);
    } else {
        print!("{plan}");
    }
    Ok(())
}
