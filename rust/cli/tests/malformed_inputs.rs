//! The malformed-input corpus (`malformed/`), each case baked by the
//! binary: refused with exit 1 and a message naming the file and what is
//! wrong, no panic, no output folder, and the input folder byte for byte
//! as it was.

mod malformed;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sssbake-malformed-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Every file under `dir` with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&path).unwrap())
        })
        .collect()
}

/// Bakes the case's files at a small size (so that a case the binary
/// wrongly accepts still finishes quickly); (exit code, stderr).
fn bake(case: &malformed::Case, input: &Path, out: &Path) -> (Option<i32>, String) {
    let args = case.args.iter().map(|a| match a.strip_prefix('@') {
        Some(file) => input.join(file).display().to_string(),
        None => a.clone(),
    });
    let output = Command::new(env!("CARGO_BIN_EXE_sssbake"))
        .arg("bake")
        .args(args)
        .args(["--out", out.to_str().unwrap(), "--resolution", "16"])
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    (output.status.code(), stderr)
}

#[test]
fn every_malformed_input_is_refused_by_name_and_leaves_everything_as_it_was() {
    let cases = malformed::all();
    eprintln!("{} malformed inputs", cases.len());
    assert!(cases.len() >= 50, "the corpus has {} cases", cases.len());
    let mut names: Vec<&str> = cases.iter().map(|c| c.name.as_str()).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), cases.len(), "case names repeat");
    let mut failures = Vec::new();
    for case in &cases {
        let root = scratch(&case.name);
        let (input, out) = (root.join("input"), root.join("out"));
        std::fs::create_dir_all(&input).unwrap();
        for (name, bytes) in &case.files {
            std::fs::write(input.join(name), bytes).unwrap();
        }
        let before = snapshot(&input);
        let (code, stderr) = bake(case, &input, &out);
        let blamed = input.join(&case.blame).display().to_string();
        let mut wrong = Vec::new();
        if code != Some(1) {
            wrong.push(format!("exit {code:?}"));
        }
        if !stderr.contains(&blamed) {
            wrong.push(format!("does not name {}", case.blame));
        }
        for word in case.words.iter().filter(|w| !stderr.contains(w.as_str())) {
            wrong.push(format!("does not say `{word}`"));
        }
        if stderr.contains("internal error") || stderr.contains("panicked") {
            wrong.push("panicked".into());
        }
        if out.exists() {
            wrong.push("left an output folder".into());
        }
        if snapshot(&input) != before {
            wrong.push("changed its input folder".into());
        }
        if !wrong.is_empty() {
            failures.push(format!(
                "{}: {}\n    {}",
                case.name,
                wrong.join("; "),
                stderr.trim()
            ));
        }
        let _ = std::fs::remove_dir_all(&root);
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

#[test]
fn the_corpus_base_bakes_so_each_case_fails_by_what_it_breaks() {
    let root = scratch("base");
    let (input, out) = (root.join("input"), root.join("out"));
    std::fs::create_dir_all(&input).unwrap();
    let document = malformed::quad::document(Some("quad.bin"));
    std::fs::write(
        input.join("quad.gltf"),
        serde_json::to_vec(&document).unwrap(),
    )
    .unwrap();
    std::fs::write(input.join("quad.bin"), malformed::quad::bin()).unwrap();
    std::fs::write(
        input.join("quad.glb"),
        malformed::quad::glb(&malformed::quad::document(None), &malformed::quad::bin()),
    )
    .unwrap();
    // The files the cases break, whole.
    let grey = sssbake::image::Image::new(4, 4, vec![[0.5; 3]; 16]).unwrap();
    let exr =
        sssbake_io::image_writer::exr_bytes(&grey, sssbake_io::image_writer::Precision::Float);
    std::fs::write(input.join("grey.exr"), exr.unwrap()).unwrap();
    let png = sssbake_io::image_writer::png_bytes(&grey).unwrap();
    std::fs::write(input.join("grey.png"), png).unwrap();
    let layer = "[[layers]]\nsigma_a = [0.03, 0.15, 0.45]\nsigma_s = 4.0\n";
    std::fs::write(input.join("good.toml"), layer).unwrap();
    std::fs::write(
        input.join("sidecar.toml"),
        "[objects]\nTile = \"good.toml\"\n",
    )
    .unwrap();
    let runs: [(&str, &[&str]); 8] = [
        ("quad.gltf", &[]),
        ("quad.glb", &[]),
        ("quad.gltf", &["--material", "@good.toml"]),
        ("quad.gltf", &["--materials", "@sidecar.toml"]),
        ("quad.gltf", &["--irradiance", "@grey.exr"]),
        ("quad.gltf", &["--irradiance", "@grey.png"]),
        ("quad.gltf", &["--environment", "@grey.exr"]),
        ("quad.gltf", &["--base-color", "@grey.png"]),
    ];
    for (scene, extra) in runs {
        let case = malformed::Case::new("base", vec![], scene, extra, scene, &[]);
        let (code, stderr) = bake(&case, &input, &out);
        assert_eq!(code, Some(0), "{scene} {extra:?}: {stderr}");
        assert!(
            out.join("Tile_subsurface.exr").is_file(),
            "{scene} {extra:?}"
        );
        std::fs::remove_dir_all(&out).unwrap();
    }
    let _ = std::fs::remove_dir_all(&root);
}
