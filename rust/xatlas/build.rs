//! Compiles the C++ side of the bridge to xatlas against the xatlas.h that the
//! xatlas-rs crate ships beside the source it builds the library from, so the
//! declarations we compile against are the ones the library was built with.

use std::path::PathBuf;
use std::process::Command;

fn main() {
    for file in ["src/lib.rs", "cpp/shim.h", "cpp/shim.cc"] {
        println!("cargo:rerun-if-changed={file}");
    }
    let xatlas = xatlas_header_dir();
    println!(
        "cargo:rerun-if-changed={}",
        xatlas.join("xatlas.h").display()
    );
    cxx_build::bridge("src/lib.rs")
        .file("cpp/shim.cc")
        .include(&xatlas)
        .std("c++14")
        .warnings(true)
        .compile("sssbake_xatlas_shim");
}

/// The folder holding xatlas.h: `vendor/` beside the manifest of the resolved
/// xatlas-rs package. That crate declares no `links` key, so Cargo hands its
/// dependents nothing about it; `cargo metadata` finds it wherever it was
/// unpacked (registry, vendored sources or a patch).
fn xatlas_header_dir() -> PathBuf {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let manifest =
        PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap()).join("Cargo.toml");
    let target = std::env::var("TARGET").expect("Cargo sets TARGET for build scripts");
    // Offline and locked: the outer build has already resolved and unpacked
    // every package it needs, and a build script must neither download nor
    // rewrite Cargo.lock. Filtered to the target, because the packages of
    // other platforms' dependencies need not be on this machine.
    let output = Command::new(cargo)
        .args(["metadata", "--format-version", "1", "--offline", "--locked"])
        .args(["--filter-platform", &target])
        .arg("--manifest-path")
        .arg(&manifest)
        .output()
        .expect("cannot run `cargo metadata` to locate xatlas-rs");
    assert!(
        output.status.success(),
        "`cargo metadata` failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let metadata: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("`cargo metadata` printed invalid JSON");
    let found: Vec<&str> = metadata["packages"]
        .as_array()
        .expect("`cargo metadata` lists no packages")
        .iter()
        .filter(|package| package["name"] == "xatlas-rs")
        .filter_map(|package| package["manifest_path"].as_str())
        .collect();
    let [manifest_path] = found[..] else {
        panic!("expected exactly one xatlas-rs package in the build, found {found:?}");
    };
    let dir = PathBuf::from(manifest_path)
        .parent()
        .expect("a manifest path has a parent")
        .join("vendor");
    assert!(
        dir.join("xatlas.h").is_file(),
        "xatlas-rs at {} ships no vendor/xatlas.h",
        dir.display()
    );
    dir
}
