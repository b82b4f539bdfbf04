//! A batch's reports, as JSON: one per asset (`reports/<asset>.json`) and
//! one for the batch (`batch.json`), in the output folder.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What became of an asset.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Baked in this run.
    Baked,
    /// Its inputs, settings and sssbake's version were unchanged since its
    /// last bake, whose outputs stay.
    Skipped,
    /// Its bake failed; `error` says why.
    Failed,
    /// No report of it was found (collected, never run).
    Missing,
}

/// Why an asset failed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Failure {
    /// `input`, `setting`, `output`, `cancelled` (the library's error
    /// kinds) or `internal` (a bug).
    pub kind: String,
    /// The message, naming the file, object or option.
    pub message: String,
}

impl From<&sssbake::Error> for Failure {
    fn from(error: &sssbake::Error) -> Self {
        let kind = match error {
            sssbake::Error::Input(_) => "input",
            sssbake::Error::Setting { .. } => "setting",
            sssbake::Error::Output { .. } => "output",
            sssbake::Error::Cancelled => "cancelled",
        };
        Failure {
            kind: kind.into(),
            message: error.to_string(),
        }
    }
}

impl Failure {
    /// A panic caught: a bug, with what it said.
    pub fn internal(panic: Box<dyn std::any::Any + Send>) -> Self {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Failure {
            kind: "internal".into(),
            message: format!("internal error (please report it): {what}"),
        }
    }
}

/// One asset's report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AssetReport {
    /// The asset's name in the manifest.
    pub name: String,
    /// Its scene file.
    pub scene: String,
    /// What became of it.
    pub status: Status,
    /// Its output folder.
    pub folder: String,
    /// The files in its folder (for a failed asset, none).
    pub files: Vec<String>,
    /// Seconds this run spent on it (hashing, and baking if it did).
    pub seconds: f64,
    /// The content hash of its inputs ([`super::Fingerprint`]).
    pub hash: Option<String>,
    /// Why it failed.
    pub error: Option<Failure>,
    /// The bake's summary (as `sssbake bake --json` prints it), for an
    /// asset baked in this run.
    pub summary: Option<serde_json::Value>,
}

/// How many assets ended each way.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counts {
    /// Baked in this run.
    pub baked: usize,
    /// Skipped as unchanged.
    pub skipped: usize,
    /// Failed.
    pub failed: usize,
    /// Without a report.
    pub missing: usize,
}

/// A batch's report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BatchReport {
    /// The manifest.
    pub manifest: String,
    /// The output folder.
    pub out: String,
    /// sssbake's version.
    pub version: String,
    /// Assets baked at once.
    pub jobs: usize,
    /// Threads each of them had.
    pub threads_per_job: usize,
    /// Seconds from start to end of the batch.
    pub seconds: f64,
    /// How many assets ended each way.
    pub counts: Counts,
    /// Every asset's report, in the manifest's order.
    pub assets: Vec<AssetReport>,
}

impl BatchReport {
    /// True when every asset was baked or skipped.
    pub fn all_done(&self) -> bool {
        self.counts.failed == 0 && self.counts.missing == 0
    }

    /// Counts `assets` by status.
    pub fn count(assets: &[AssetReport]) -> Counts {
        let of = |s| assets.iter().filter(|a| a.status == s).count();
        Counts {
            baked: of(Status::Baked),
            skipped: of(Status::Skipped),
            failed: of(Status::Failed),
            missing: of(Status::Missing),
        }
    }
}

/// The batch report's path in `out`.
pub fn batch_report_path(out: &Path) -> PathBuf {
    out.join("batch.json")
}

/// Asset `name`'s report's path in `out`.
pub fn asset_report_path(out: &Path, name: &str) -> PathBuf {
    out.join("reports").join(format!("{name}.json"))
}
