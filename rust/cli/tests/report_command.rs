//! `sssbake report` on the bundled marble example at a small size.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn sssbake(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sssbake"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/marble/marble.gltf")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sssbake-report-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn a_report_times_every_integrator_against_the_exact_sum() {
    let out = scratch("marble");
    let scene = example();
    let args = [
        "report",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--resolution",
        "48",
        "--preset",
        "marble",
    ];
    let result = sssbake(&args);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let report: Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    let runs = report["runs"].as_array().unwrap();
    for method in ["brute", "octree", "texture", "importance"] {
        assert!(runs.iter().any(|r| r["method"] == method), "{method}");
    }
    for run in runs {
        let error = run["relative_rmse"].as_f64().unwrap();
        assert!(error.is_finite() && error >= 0.0);
        assert!(run["seconds"].as_f64().unwrap() >= 0.0);
        if run["method"] == "brute" {
            assert_eq!(error, 0.0);
        }
    }
    // More Monte Carlo samples leave less error.
    let importance = |spp: &str| {
        runs.iter()
            .find(|r| r["method"] == "importance" && r["setting"] == spp)
            .unwrap()["relative_rmse"]
            .as_f64()
            .unwrap()
    };
    assert!(importance("512 spp") < importance("16 spp"));
    let csv = std::fs::read_to_string(out.join("report.csv")).unwrap();
    assert_eq!(csv.lines().count(), runs.len() + 1);
    let svg = std::fs::read_to_string(out.join("report.svg")).unwrap();
    assert!(svg.contains("octree") && svg.contains("relative RMSE"));
    assert!(
        std::fs::read(out.join("report.png"))
            .unwrap()
            .starts_with(b"\x89PNG")
    );
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(stdout.contains("Pareto front") && stdout.contains("brute"));
    // Each approximate method's default run maps where it departs from brute:
    // the layout's texels coloured (never black).
    let mut maps = Vec::new();
    for method in ["octree", "texture", "importance"] {
        let path = out.join(format!("error_Ball_{method}.png"));
        let map = sssbake_io::read_image(&path).unwrap();
        assert_eq!((map.width, map.height), (48, 48));
        let coloured = map
            .texels
            .iter()
            .filter(|t| t.iter().any(|&v| v > 0.0))
            .count();
        assert!(coloured > 48 * 48 / 4, "{method}: {coloured}");
        maps.push(map.texels);
    }
    assert_ne!(
        maps[0], maps[1],
        "octree and texture err in different places"
    );
    assert!(!out.join("error_Ball_brute.png").exists());

    // A second run refuses to replace the report, and leaves it as it was.
    let before = std::fs::read(out.join("report.json")).unwrap();
    let again = sssbake(&args);
    assert_eq!(again.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&again.stderr).contains("--force"));
    assert_eq!(std::fs::read(out.join("report.json")).unwrap(), before);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_report_of_an_unknown_object_names_it() {
    let out = scratch("unknown");
    let scene = example();
    let result = sssbake(&[
        "report",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--object",
        "Nobody",
    ]);
    assert_eq!(result.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(
        stderr.contains("Nobody") && stderr.contains("Ball"),
        "{stderr}"
    );
    assert!(!out.exists(), "no output folder for a failed report");
}
