//! `sssbake batch`: the assets of a manifest, each into its own folder,
//! unchanged ones skipped; or the manifest as an Open Job Description job
//! bundle for a render farm.

use sssbake::Error;
use sssbake_io::batch::openjd::write_bundle;
use sssbake_io::batch::{
    BatchOptions, Manifest, SPLIT_ABOVE, Status, bake_part, collect_reports, farm_tasks, run_batch,
};
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
    #[arg(long, required_unless_present_any = ["openjd", "tasks"])]
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
    /// Bake only this object (its file stem, as --tasks lists it, or its
    /// name) of the one --asset into its part
    /// (OUT/.parts/ASSET/), for --assemble to put together.
    #[arg(long, value_name = "NAME", requires = "assets", conflicts_with_all = ["collect", "openjd"])]
    object: Option<String>,
    /// Build each --asset's folder from its objects' parts instead of
    /// baking it.
    #[arg(long, requires = "assets", conflicts_with_all = ["collect", "openjd", "object"])]
    assemble: bool,
    /// Bake nothing: print each asset's farm tasks as JSON: one per object
    /// for an asset of several objects whose manifest says
    /// `split = "objects"` or, saying nothing, planned above --split-above.
    #[arg(long, conflicts_with_all = ["assets", "collect", "openjd"])]
    tasks: bool,
    /// Planned work (rays, kernel evaluations and probes) above which
    /// --tasks splits an asset of several objects.
    #[arg(long, value_name = "WORK", default_value_t = SPLIT_ABOVE, requires = "tasks")]
    split_above: f64,
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
    if args.tasks {
        crate::print_json(&farm_tasks(&manifest, args.split_above));
        return Ok(true);
    }
    let out = args.out.clone().unwrap_or_default();
    let options = BatchOptions {
        out: out.clone(),
        force: args.force,
        jobs: args.jobs,
        only: args.assets.clone(),
        assemble: args.assemble,
    };
    if let Some(object) = &args.object {
        let [asset] = &args.assets[..] else {
            return Err(Error::field("object", "give one --asset with --object"));
        };
        let part = bake_part(&manifest, asset, object, &options)?;
        if args.json {
            crate::print_json(&part);
        } else {
            let how = part
                .error
                .as_ref()
                .map_or(String::new(), |e| format!(" ({})", e.message));
            println!("{asset}, object {object}: {:?}{how}", part.status);
        }
        return Ok(part.status != Status::Failed);
    }
    let report = if args.collect {
        collect_reports(&manifest, &out, 0.0)?
    } else {
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
