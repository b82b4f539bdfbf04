//! What a bake of an asset depends on, summed up in one content hash: the
//! bytes of the scene and of every file it references (glTF buffers and
//! images; USD layers and the assets they name), of its material, sidecar
//! and image files, its resolved options and sssbake's version. Equal
//! hashes mean the bake would be the same, so a batch can skip it.
//!
//! The hash is SipHash-1-3 with 128 bits: change detection among files a
//! studio writes, not a defence against someone forging a collision.

use crate::options::BakeOptions;
use serde::{Deserialize, Serialize};
use siphasher::sip128::{Hasher128, SipHasher13};
use std::hash::Hasher;
use std::path::{Path, PathBuf};

const LIST_DEPENDENCIES: &str = include_str!("../../../../usd/dependencies.py");

/// The content hash of an asset's bake and the files it covers.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Fingerprint {
    /// 32 hexadecimal digits.
    pub hash: String,
    /// sssbake's version the hash includes.
    pub version: String,
    /// Every file read, in the order hashed.
    pub files: Vec<String>,
}

/// The fingerprint of baking `scene` with `options` (paths resolved).
/// A file that cannot be read is hashed as missing, so the bake, which
/// will say why, is never skipped for it.
pub fn fingerprint(scene: &Path, options: &BakeOptions) -> Fingerprint {
    let mut files = vec![scene.to_path_buf()];
    files.extend(referenced_files(scene));
    files.extend(options.files());
    let mut hasher = SipHasher13::new();
    let mut field = |bytes: &[u8]| {
        hasher.write_u64(bytes.len() as u64);
        hasher.write(bytes);
    };
    field(crate::VERSION.as_bytes());
    field(&serde_json::to_vec(options).unwrap_or_default());
    for file in &files {
        field(file.to_string_lossy().as_bytes());
        match std::fs::read(file) {
            Ok(bytes) => field(&bytes),
            Err(_) => field(b"\0missing"),
        }
    }
    let hash = hasher.finish128();
    Fingerprint {
        hash: format!("{:016x}{:016x}", hash.h1, hash.h2),
        version: crate::VERSION.to_string(),
        files: files.iter().map(|f| f.display().to_string()).collect(),
    }
}

/// The files a scene file references: a glTF's buffers and images by
/// relative URI; a USD stage's layers and assets, as usd-core resolves
/// them (without the scene itself). None when it cannot be read.
pub fn referenced_files(scene: &Path) -> Vec<PathBuf> {
    let extension = scene
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("gltf" | "glb") => gltf_files(scene),
        Some("usd" | "usda" | "usdc" | "usdz") => usd_files(scene),
        _ => Vec::new(),
    }
}

fn gltf_files(scene: &Path) -> Vec<PathBuf> {
    let Ok(gltf) = gltf::Gltf::open(scene) else {
        return Vec::new();
    };
    let folder = scene.parent().unwrap_or(Path::new("."));
    let buffers = gltf.buffers().filter_map(|b| match b.source() {
        gltf::buffer::Source::Uri(uri) => Some(uri),
        gltf::buffer::Source::Bin => None,
    });
    let images = gltf.images().filter_map(|i| match i.source() {
        gltf::image::Source::Uri { uri, .. } => Some(uri),
        gltf::image::Source::View { .. } => None,
    });
    buffers
        .chain(images)
        .filter(|uri| !uri.starts_with("data:"))
        .map(|uri| crate::gltf_uri::local_path(folder, uri))
        .collect()
}

fn usd_files(scene: &Path) -> Vec<PathBuf> {
    let Ok(out) =
        crate::python::run_script(LIST_DEPENDENCIES, [scene.as_os_str()], "list its files")
    else {
        return Vec::new();
    };
    let own = scene.canonicalize().ok();
    String::from_utf8_lossy(&out)
        .lines()
        .filter(|l| !l.is_empty())
        .map(|l| PathBuf::from(l.strip_prefix('?').unwrap_or(l)))
        .filter(|p| p.canonicalize().ok() != own || own.is_none())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gltf_depends_on_its_buffers_and_a_changed_byte_changes_the_hash() {
        let folder = tempfile::tempdir().unwrap();
        let scene = folder.path().join("a.gltf");
        std::fs::write(
            &scene,
            r#"{"asset":{"version":"2.0"},"buffers":[{"uri":"a%20b.bin","byteLength":4}]}"#,
        )
        .unwrap();
        let bin = folder.path().join("a b.bin");
        std::fs::write(&bin, [0u8, 1, 2, 3]).unwrap();
        assert_eq!(referenced_files(&scene), vec![bin.clone()]);
        let options = BakeOptions::default();
        let before = fingerprint(&scene, &options);
        assert_eq!(
            before,
            fingerprint(&scene, &options),
            "the same bytes, the same hash"
        );
        std::fs::write(&bin, [0u8, 1, 2, 4]).unwrap();
        let after = fingerprint(&scene, &options);
        assert_ne!(before.hash, after.hash);
        let other = BakeOptions {
            resolution: Some(64),
            ..BakeOptions::default()
        };
        assert_ne!(
            after.hash,
            fingerprint(&scene, &other).hash,
            "settings count"
        );
    }
}
