//! Which assets a farm bakes one object per task: an asset of more than
//! one object whose manifest says `split = "objects"`, or, when it says
//! nothing, whose planned work (the plan's shadow rays, kernel evaluations
//! and probes) is above a threshold. The others are one task each, as is
//! an asset whose plan fails (its bake says why).

use super::manifest::{Asset, Manifest, Split};
use serde::{Deserialize, Serialize};
use sssbake::plan;

/// The planned work (shadow rays, kernel evaluations and probes) above
/// which an asset of several objects is split into one task per object
/// (each task reads and plans the whole scene again, and the assembly
/// once more, so a split pays only for assets whose bake is long).
pub const SPLIT_ABOVE: f64 = 1e7;

/// An asset's farm tasks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AssetTasks {
    /// The asset's name in the manifest.
    pub asset: String,
    /// One task per object (by its file stem, unique among the objects
    /// where names may not be), then an assembly; empty for one task for
    /// the whole asset.
    pub objects: Vec<String>,
    /// The plan's work estimate (rays, evaluations and probes); `None`
    /// when the asset could not be planned.
    pub work: Option<f64>,
}

/// The tasks of every asset of `manifest` (in its order), splitting the
/// assets of several objects that ask for it or, asking nothing, are
/// planned above `split_above`.
pub fn farm_tasks(manifest: &Manifest, split_above: f64) -> Vec<AssetTasks> {
    manifest
        .assets
        .iter()
        .map(|asset| asset_tasks(asset, split_above))
        .collect()
}

fn asset_tasks(asset: &Asset, split_above: f64) -> AssetTasks {
    let planned = std::panic::catch_unwind(|| {
        let (scene, request) = asset.options.load(&asset.scene).ok()?;
        plan(&scene, &request).ok()
    })
    .ok()
    .flatten();
    let mut tasks = AssetTasks {
        asset: asset.name.clone(),
        objects: Vec::new(),
        work: planned.as_ref().map(|p| p.cost.evaluations),
    };
    let large = |work: f64| match asset.split {
        Some(Split::Objects) => true,
        Some(Split::Whole) => false,
        None => work > split_above,
    };
    if let Some(plan) = planned
        && plan.objects.len() > 1
        && large(plan.cost.evaluations)
    {
        tasks.objects = plan.objects.iter().map(|o| o.file_stem.clone()).collect();
    }
    tasks
}
