//! `sssbake batch`: the assets of a manifest, each into its own folder,
//! unchanged ones skipped; or the manifest as an Open Job Description job
//! bundle for a render farm.

use sssbake::Error;
use sssbake_io::batch::openjd::write_bundle;
use sssbake_io::batch::{BatchOptions, Manifest, Status, collect_reports, run_batch};
use std::path::PathBuf;

/// Exit code of a batch in which some assets failed (the others were
/// baked or skipped).
pub const SOME_FAILED: u8 = 5;

/// Options of `sssbake batch`.
#[derive(clap::Args)]
pub struct BatchArgs {
    /// The manifest: a TOML file of [defaults] and [assets.NAME] tables.
    manifest: PathBuf,
    /// The folder for every asset's folder and the reports.
    #[arg(long, required_unless_present = "openjd")]
    out: Option<PathBuf>,
    /// Bake every asset, even those unchanged since their last bake.
    #[arg(long)]
    force: bool,
    /// Assets baked at once; the threads are split between them.
    #[arg(long, default_value_t = 1)]
    jobs: usize,
    /// Only this asset (repeat for more); writes its report, not the batch's.
    #[arg(long = "asset", value_name = "NAME")]
    assets: Vec<String>,
    /// Bake nothing: write the batch report from the asset reports in --out
    /// (after a farm ran the assets one by one).
    #[arg(long, conflicts_with_all = ["assets", "force", "openjd"])]
    collect: bool,
    /// Write an Open Job Description job bundle (one task per asset) into
    /// this folder instead of baking.
    #[arg(long, value_name = "DIR")]
    openjd: Option<PathBuf>,
    /// Print the batch report as JSON.
    #[arg(long)]
    json: bool,
}

/// Runs the command; `Ok(false)` when some assets failed.
pub fn run(args: &BatchArgs) -> Result<bool, Error> {
    let manifest = Manifest::read(&args.manifest)?;
    if let Some(bundle) = &args.openjd {
        let written = write_bundle(&manifest, bundle, args.out.as_deref())?;
        for file in written {
            println!("{}", file.display());
        }
        return Ok(true);
    }
    let out = args.out.clone().unwrap_or_default();
    let report = if args.collect {
        collect_reports(&manifest, &out, 0.0)?
    } else {
        let options = BatchOptions {
            out,
            force: args.force,
            jobs: args.jobs,
            only: args.assets.clone(),
        };
        run_batch(&manifest, &options, |asset| {
            let what = match (&asset.status, &asset.error) {
                (Status::Failed, Some(e)) => format!("failed ({}): {}", e.kind, e.message),
                (status, _) => format!("{status:?}").to_lowercase(),
            };
            eprintln!("{}: {what} in {:.1} s", asset.name, asset.seconds);
        })?
    };
    if args.json {
        crate::print_json(&report);
    } else {
        let c = &report.counts;
        println!(
            "{} baked, {} skipped, {} failed{} in {:.1} s ({} at once, {} threads each); reports in {}",
            c.baked,
            c.skipped,
            c.failed,
            if c.missing > 0 {
                format!(", {} missing", c.missing)
            } else {
                String::new()
            },
            report.seconds,
            report.jobs,
            report.threads_per_job,
            report.out
        );
    }
    Ok(report.all_done())
}
