//! A batch manifest: a TOML file naming assets to bake, each with its
//! scene and its own options over a `[defaults]` table for all.
//!
//! ```toml
//! [defaults]
//! resolution = 512
//!
//! [assets.head]
//! scene = "head/head.gltf"
//! material = "materials/skin_two_layer.toml"
//!
//! [assets.head_usd]
//! scene = "head/head.usda"
//! resolution = 1024
//!
//! [assets.crowd]
//! scene = "crowd/crowd.gltf"
//! split = "objects"
//! ```
//!
//! `split` says how a farm bakes the asset: `"objects"`, one task per
//! object and an assembly; `"whole"`, one task; left out, by the plan's
//! work ([`super::split`]).
//!
//! An asset's name is its output folder, so two assets never share one,
//! whatever their files or objects are called. Paths are relative to the
//! manifest's folder. Unknown keys are refused, naming the asset (or the
//! line, for the manifest's own layout).

use crate::options::BakeOptions;
use serde::Deserialize;
use sssbake::{Error, InputError};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A manifest as read, with its options resolved.
#[derive(Clone, Debug)]
pub struct Manifest {
    /// The manifest file.
    pub path: PathBuf,
    /// Its assets, in the order of their names.
    pub assets: Vec<Asset>,
}

/// One asset of a manifest.
#[derive(Clone, Debug, PartialEq)]
pub struct Asset {
    /// Its name: letters, digits, `_` and `-`; its output folder's name.
    pub name: String,
    /// The scene file.
    pub scene: PathBuf,
    /// Its options over the manifest's defaults, paths resolved.
    pub options: BakeOptions,
    /// How a farm bakes it; `None` decides by the plan's work.
    pub split: Option<Split>,
}

/// How a farm bakes an asset.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Split {
    /// One task per object, then an assembly (for an asset of several objects).
    Objects,
    /// One task for the whole asset.
    Whole,
}

/// A manifest's text as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ManifestFile {
    #[serde(default)]
    defaults: BakeOptions,
    assets: BTreeMap<String, toml::Table>,
}

impl Manifest {
    /// Reads the manifest at `path`.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::input(format!("cannot read the manifest: {e}"))
                .in_file(path.display().to_string())
        })?;
        Manifest::parse(&text, path)
    }

    /// Parses manifest `text`; `path` names it in messages and its folder
    /// anchors relative paths.
    pub fn parse(text: &str, path: &Path) -> Result<Self, Error> {
        let file = path.display().to_string();
        let bad = |asset: Option<&str>, message: String| {
            Error::Input(InputError {
                file: Some(file.clone()),
                field: asset.map(|a| format!("assets.{a}")),
                message,
                ..InputError::default()
            })
        };
        // toml's message names the line and column.
        let parsed: ManifestFile = toml::from_str(text).map_err(|e| {
            bad(
                None,
                format!("{e}(a manifest is a [defaults] table and [assets.NAME] tables, each with a scene)"),
            )
        })?;
        if parsed.assets.is_empty() {
            return Err(bad(
                None,
                "names no asset ([assets.NAME] with a scene)".into(),
            ));
        }
        let folder = path.parent().unwrap_or(Path::new("."));
        let mut assets = Vec::new();
        for (name, mut table) in parsed.assets {
            if name.is_empty()
                || !name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            {
                return Err(bad(
                    Some(&name),
                    "an asset's name is its folder: use letters, digits, `_` and `-`".into(),
                ));
            }
            let scene = match table.remove("scene") {
                Some(toml::Value::String(scene)) => folder.join(scene),
                Some(_) => return Err(bad(Some(&name), "scene: must be a file path".into())),
                None => return Err(bad(Some(&name), "has no scene (the file to bake)".into())),
            };
            let split = match table.remove("split") {
                None => None,
                Some(value) => Some(Split::deserialize(value).map_err(|_| {
                    bad(
                        Some(&name),
                        "split: must be \"objects\" or \"whole\"".into(),
                    )
                })?),
            };
            let own = BakeOptions::deserialize(toml::Value::Table(table))
                .map_err(|e| bad(Some(&name), e.message().trim().to_string()))?;
            assets.push(Asset {
                name,
                scene,
                options: own.or(&parsed.defaults).relative_to(folder),
                split,
            });
        }
        Ok(Manifest {
            path: path.to_path_buf(),
            assets,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Manifest, Error> {
        Manifest::parse(text, Path::new("jobs/batch.toml"))
    }

    #[test]
    fn an_asset_takes_the_defaults_it_does_not_override_and_paths_are_the_manifests() {
        let manifest = parse(
            "[defaults]\nresolution = 64\npreset = \"skin1\"\n\
             [assets.a]\nscene = \"a/x.gltf\"\nresolution = 128\n\
             [assets.b]\nscene = \"b/x.gltf\"\nmaterial = \"m.toml\"\npreset = \"marble\"\n",
        )
        .unwrap();
        let [a, b] = &manifest.assets[..] else {
            panic!("two assets")
        };
        assert_eq!(a.scene, Path::new("jobs/a/x.gltf"));
        assert_eq!(a.options.resolution, Some(128));
        assert_eq!(a.options.preset.as_deref(), Some("skin1"));
        assert_eq!(b.options.resolution, Some(64));
        assert_eq!(
            b.options.material.as_deref(),
            Some(Path::new("jobs/m.toml"))
        );
        assert_eq!(b.options.preset.as_deref(), Some("marble"));
    }

    #[test]
    fn an_unknown_key_is_refused_naming_its_asset() {
        let error = parse("[assets.head]\nscene = \"h.gltf\"\nresolutoin = 64\n").unwrap_err();
        let text = error.to_string();
        assert!(
            text.contains("jobs/batch.toml") && text.contains("assets.head"),
            "{text}"
        );
        assert!(text.contains("resolutoin"), "{text}");
    }

    #[test]
    fn a_misspelt_table_is_refused_naming_its_line() {
        let error = parse("[assets.head]\nscene = \"h.gltf\"\n\n[defualts]\nresolution = 1\n")
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("line 4") && error.contains("defualts"),
            "{error}"
        );
    }

    #[test]
    fn an_assets_split_is_read_and_a_wrong_one_refused_naming_the_asset() {
        let manifest = parse(
            "[assets.a]\nscene = \"a.gltf\"\nsplit = \"objects\"\n\
             [assets.b]\nscene = \"b.gltf\"\nsplit = \"whole\"\n\
             [assets.c]\nscene = \"c.gltf\"\n",
        )
        .unwrap();
        let splits: Vec<Option<Split>> = manifest.assets.iter().map(|a| a.split).collect();
        assert_eq!(splits, [Some(Split::Objects), Some(Split::Whole), None]);
        let error = parse("[assets.head]\nscene = \"h.gltf\"\nsplit = \"parts\"\n").unwrap_err();
        let text = error.to_string();
        assert!(
            text.contains("assets.head") && text.contains("split"),
            "{text}"
        );
    }

    #[test]
    fn an_asset_without_a_scene_or_with_an_unsafe_name_is_refused() {
        let error = parse("[assets.head]\nresolution = 64\n").unwrap_err();
        assert!(error.to_string().contains("no scene"), "{error}");
        let error = parse("[assets.\"../up\"]\nscene = \"h.gltf\"\n").unwrap_err();
        assert!(error.to_string().contains("folder"), "{error}");
        assert!(parse("[defaults]\nresolution = 64\n").is_err());
    }
}
