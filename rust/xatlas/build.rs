//! Compiles xatlas, from the source the xatlas-rs crate ships, and the C++ side
//! of the bridge against the xatlas.h beside it.
//!
//! xatlas is compiled here, not linked as xatlas-rs builds it, to build it
//! without its thread pool (`XA_MULTITHREADED=0`). That pool loses a wake-up
//! when it stops: a worker that has just seen it running parks after the
//! atlas's `Destroy` has woken every worker, and `Destroy` then waits for it
//! forever. On two loaded cores about one unwrap in a thousand hung so. Built
//! single-threaded, xatlas charts and packs in the caller's thread.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The xatlas-rs release this crate pins in its manifest (`=0.1.3`).
const XATLAS_RS: &str = "xatlas-rs-0.1.3";

fn main() {
    for file in ["src/lib.rs", "cpp/shim.h", "cpp/shim.cc"] {
        println!("cargo:rerun-if-changed={file}");
    }
    println!("cargo:rerun-if-env-changed=CARGO_HOME");
    let xatlas = xatlas_source_dir();
    for file in ["xatlas.h", "xatlas.cpp"] {
        println!("cargo:rerun-if-changed={}", xatlas.join(file).display());
    }
    // As xatlas-rs compiles it, but for the thread pool.
    cc::Build::new()
        .cpp(true)
        .file(xatlas.join("xatlas.cpp"))
        .std("c++11")
        .define("NDEBUG", None)
        .define("XA_MULTITHREADED", "0")
        .warnings(false)
        .compile("sssbake_xatlas_lib");
    cxx_build::bridge("src/lib.rs")
        .file("cpp/shim.cc")
        .include(&xatlas)
        .std("c++14")
        .warnings(true)
        .compile("sssbake_xatlas_shim");
}

/// The folder holding xatlas.h and xatlas.cpp: `vendor/` beside the manifest of the xatlas-rs
/// package the build unpacked. That crate declares no `links` key, so Cargo
/// hands its dependents nothing about it. Where Cargo unpacks registry
/// packages (`$CARGO_HOME/registry/src/<registry>/`) is looked at first: it
/// needs nothing but the package this build already downloaded. Vendored
/// sources and patches are found by `cargo metadata`, which needs every
/// package of the workspace on disk (true where sources are vendored), so it
/// is only the fallback: on a fresh machine `cargo run -p sssbake-cli` has
/// downloaded only what the CLI needs.
fn xatlas_source_dir() -> PathBuf {
    if let Some(dir) = cargo_home().and_then(|home| in_registry(&home)) {
        return dir;
    }
    from_metadata()
}

/// Cargo's home: `$CARGO_HOME`, else `~/.cargo` (`%USERPROFILE%\.cargo`).
fn cargo_home() -> Option<PathBuf> {
    let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
    var("CARGO_HOME").map(PathBuf::from).or_else(|| {
        var("HOME")
            .or_else(|| var("USERPROFILE"))
            .map(|home| Path::new(&home).join(".cargo"))
    })
}

/// `vendor/` of the pinned xatlas-rs under any registry Cargo unpacked into
/// below `home`. Every registry serves the same checksummed package, so any
/// copy is the one the build compiles.
fn in_registry(home: &Path) -> Option<PathBuf> {
    let registries = std::fs::read_dir(home.join("registry").join("src")).ok()?;
    let mut found: Vec<PathBuf> = registries
        .filter_map(|entry| entry.ok())
        .map(|entry| entry.path().join(XATLAS_RS).join("vendor"))
        .filter(|dir| dir.join("xatlas.h").is_file() && dir.join("xatlas.cpp").is_file())
        .collect();
    found.sort();
    found.into_iter().next()
}

/// The source folder as `cargo metadata` resolves the package.
fn from_metadata() -> PathBuf {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let manifest =
        PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap()).join("Cargo.toml");
    let target = std::env::var("TARGET").expect("Cargo sets TARGET for build scripts");
    // Offline and locked: a build script must neither download nor rewrite
    // Cargo.lock. Filtered to the target, because the packages of other
    // platforms' dependencies need not be on this machine.
    let output = Command::new(cargo)
        .args(["metadata", "--format-version", "1", "--offline", "--locked"])
        .args(["--filter-platform", &target])
        .arg("--manifest-path")
        .arg(&manifest)
        .output()
        .expect("cannot run `cargo metadata` to locate xatlas-rs");
    assert!(
        output.status.success(),
        "xatlas.h is not under $CARGO_HOME/registry/src/*/{XATLAS_RS}/vendor, and \
         `cargo metadata` failed to locate xatlas-rs: {}",
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
    for file in ["xatlas.h", "xatlas.cpp"] {
        assert!(
            dir.join(file).is_file(),
            "xatlas-rs at {} ships no vendor/{file}",
            dir.display()
        );
    }
    dir
}
