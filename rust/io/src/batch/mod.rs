//! Batch baking: a TOML manifest of assets baked into one folder each,
//! unchanged assets skipped by a content hash, several at once, with a
//! JSON report per asset and for the batch; and the same batch as an Open
//! Job Description job bundle for render farms. A large asset can be
//! baked one object per task and assembled after.

pub mod assemble;
pub mod fingerprint;
pub mod manifest;
pub mod openjd;
pub mod parts;
pub mod report;
pub mod run;
pub mod split;

pub use fingerprint::{Fingerprint, fingerprint};
pub use manifest::{Asset, Manifest, Split};
pub use parts::{PartReport, bake_part};
pub use report::{AssetReport, BatchReport, Failure, Status};
pub use run::{BatchOptions, collect_reports, run_batch};
pub use split::{AssetTasks, SPLIT_ABOVE, farm_tasks};
