//! `include/sssbake.h` is what cbindgen makes of the crate now.

use std::path::Path;

#[test]
fn the_header_is_current() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bindings = cbindgen::generate(crate_dir).expect("cbindgen reads the crate");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let path = crate_dir.join("include/sssbake.h");
    if std::env::var_os("SSSBAKE_UPDATE_HEADER").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "{} is stale: SSSBAKE_UPDATE_HEADER=1 cargo test -p sssbake-ffi --test header",
        path.display()
    );
}

#[test]
fn the_header_compiles_as_c_and_cpp() {
    let header = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/sssbake.h");
    for language in ["c", "c++"] {
        let status = std::process::Command::new("cc")
            .args(["-fsyntax-only", "-Wall", "-Werror", "-x", language])
            .arg(&header)
            .status()
            .expect("a C compiler (the build needs one for xatlas)");
        assert!(
            status.success(),
            "{} does not compile as {language}",
            header.display()
        );
    }
}
