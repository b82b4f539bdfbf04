//! A batch as an Open Job Description job bundle (specification
//! `jobtemplate-2023-09`), for any render farm that runs OpenJD jobs
//! (Deadline Cloud among them): `template.json` and
//! `parameter_values.json` in a folder.
//!
//! The job has three parameters: `Manifest` (the manifest file), `OutDir`
//! (the batch's output folder, on storage every worker shares) and
//! `SssbakeCommand` (the `sssbake` executable on the workers). Step `Bake`
//! has one task per asset (task parameter `Asset`), each running
//! `sssbake batch Manifest --out OutDir --asset Asset`: the asset's own
//! folder, written whole, and its report. Step `Report`, after every
//! task, runs `sssbake batch … --collect` for the batch's report.

use super::manifest::Manifest;
use crate::atomic_write::write_atomically;
use serde_json::{Value, json};
use sssbake::Error;
use std::path::{Path, PathBuf};

/// The template's file name in a bundle.
pub const TEMPLATE: &str = "template.json";
/// The parameter values' file name in a bundle.
pub const PARAMETER_VALUES: &str = "parameter_values.json";

/// The job template of `manifest`: one `Bake` task per asset, then the
/// report.
pub fn job_template(manifest: &Manifest) -> Value {
    let stem = manifest
        .path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "batch".into());
    let assets: Vec<&str> = manifest.assets.iter().map(|a| a.name.as_str()).collect();
    let batch = |extra: &[&str]| {
        let mut args = vec!["batch", "{{Param.Manifest}}", "--out", "{{Param.OutDir}}"];
        args.extend_from_slice(extra);
        json!({ "actions": { "onRun": { "command": "{{Param.SssbakeCommand}}", "args": args } } })
    };
    json!({
        "specificationVersion": "jobtemplate-2023-09",
        "name": format!("sssbake batch {}", safe_name(&stem)),
        "description": "Bakes subsurface scattering maps for each asset of an sssbake manifest, one task per asset.",
        "parameterDefinitions": [
            {
                "name": "Manifest",
                "type": "PATH",
                "objectType": "FILE",
                "dataFlow": "IN",
                "description": "The batch manifest (TOML); its assets' paths are relative to it."
            },
            {
                "name": "OutDir",
                "type": "PATH",
                "objectType": "DIRECTORY",
                "dataFlow": "OUT",
                "description": "The batch's output folder, on storage every worker shares."
            },
            {
                "name": "SssbakeCommand",
                "type": "STRING",
                "default": "sssbake",
                "description": "The sssbake executable on the workers."
            }
        ],
        "steps": [
            {
                "name": "Bake",
                "parameterSpace": {
                    "taskParameterDefinitions": [
                        { "name": "Asset", "type": "STRING", "range": assets }
                    ]
                },
                "script": batch(&["--asset", "{{Task.Param.Asset}}"])
            },
            {
                "name": "Report",
                "dependencies": [{ "dependsOn": "Bake" }],
                "script": batch(&["--collect"])
            }
        ]
    })
}

/// The bundle's parameter values: the manifest and the output folder, as
/// absolute paths where they exist.
pub fn parameter_values(manifest: &Manifest, out: &Path) -> Value {
    let absolute = |p: &Path| {
        std::path::absolute(p)
            .unwrap_or_else(|_| p.to_path_buf())
            .display()
            .to_string()
    };
    json!({
        "parameterValues": [
            { "name": "Manifest", "value": absolute(&manifest.path) },
            { "name": "OutDir", "value": absolute(out) }
        ]
    })
}

/// Writes the bundle of `manifest` into `bundle` (made if missing), with
/// `out` as the output folder [default: `out` beside the manifest];
/// returns the files written.
pub fn write_bundle(
    manifest: &Manifest,
    bundle: &Path,
    out: Option<&Path>,
) -> Result<Vec<PathBuf>, Error> {
    std::fs::create_dir_all(bundle)
        .map_err(|e| Error::output(bundle.display(), format!("cannot create the folder: {e}")))?;
    let default_out = manifest.path.parent().unwrap_or(Path::new(".")).join("out");
    let files = [
        (bundle.join(TEMPLATE), job_template(manifest)),
        (
            bundle.join(PARAMETER_VALUES),
            parameter_values(manifest, out.unwrap_or(&default_out)),
        ),
    ];
    for (path, value) in &files {
        let text = serde_json::to_vec_pretty(value).unwrap_or_default();
        write_atomically(path, &text)
            .map_err(|e| Error::output(path.display(), format!("cannot write: {e}")))?;
    }
    Ok(files.into_iter().map(|(path, _)| path).collect())
}

/// `name` with only the characters a job name may hold.
fn safe_name(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_alphanumeric() || "-_ .".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect()
}
