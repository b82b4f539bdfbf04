//! Batch baking: a TOML manifest of assets baked into one folder each,
//! unchanged assets skipped by a content hash, several at once, with a
//! JSON report per asset and for the batch; and the same batch as an Open
//! Job Description job bundle for render farms.

pub mod fingerprint;
pub mod manifest;
pub mod openjd;
pub mod report;
pub mod run;

pub use fingerprint::{Fingerprint, fingerprint};
pub use manifest::{Asset, Manifest};
pub use report::{AssetReport, BatchReport, Failure, Status};
pub use run::{BatchOptions, collect_reports, run_batch};
