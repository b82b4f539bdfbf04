//! Faults while writing: a bake that cannot put one of its outputs in
//! place fails with exit 3 and leaves the previous outputs byte for byte as
//! they were, with no temporary file behind.

#[path = "malformed/quad.rs"]
#[allow(dead_code)]
mod quad;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output};

fn bake(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sssbake"))
        .arg("bake")
        .arg(scene)
        .args([
            "--out",
            out.to_str().unwrap(),
            "--resolution",
            "16",
            "--force",
        ])
        .args(extra)
        .output()
        .expect("the binary runs")
}

/// Every file in `dir` (not directories) with its bytes.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect()
}

#[test]
fn an_output_that_cannot_be_replaced_leaves_the_previous_bake_as_it_was() {
    let root = std::env::temp_dir().join(format!("sssbake-faults-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let scene = root.join("quad.gltf");
    std::fs::write(
        &scene,
        serde_json::to_vec(&quad::document(Some("quad.bin"))).unwrap(),
    )
    .unwrap();
    std::fs::write(root.join("quad.bin"), quad::bin()).unwrap();
    let out = root.join("out");
    let first = bake(&scene, &out, &[]);
    assert_eq!(
        first.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let mut before = files(&out);
    assert!(before.contains_key("Tile_subsurface.exr") && before.contains_key("Tile_diffuse.png"));
    // One target becomes a folder with a file in it: renaming over it fails
    // once every output is staged, and what was placed is put back.
    let blocked = out.join("Tile_diffuse.png");
    std::fs::remove_file(&blocked).unwrap();
    before.remove("Tile_diffuse.png");
    std::fs::create_dir(&blocked).unwrap();
    std::fs::write(blocked.join("keep"), "not an image").unwrap();
    // A different exposure changes the previews, so a file left replaced
    // would show.
    let second = bake(&scene, &out, &["--exposure", "2"]);
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert_eq!(second.status.code(), Some(3), "{stderr}");
    assert!(stderr.contains("Tile_diffuse.png"), "{stderr}");
    assert_eq!(files(&out), before, "the previous outputs changed");
    assert_eq!(
        std::fs::read(blocked.join("keep")).unwrap(),
        b"not an image"
    );
    let _ = std::fs::remove_dir_all(&root);
}
