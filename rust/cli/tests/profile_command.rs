//! `sssbake profile` end to end: output formats, defaults and bad input.

use serde_json::Value;
use sssbake_profile::presets::preset;
use sssbake_profile::{Model, build_profile};
use std::path::PathBuf;
use std::process::{Command, Output};

fn sssbake(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sssbake"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn json(args: &[&str]) -> Value {
    let out = sssbake(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

fn numbers(value: &Value) -> Vec<f64> {
    value
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sssbake-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn json_reports_the_library_numbers() {
    let out = json(&[
        "profile", "--preset", "skin1", "--json", "--radii", "0.1,1,3",
    ]);
    assert_eq!(out["model"], "dipole");
    assert_eq!(numbers(&out["radii_mm"]), vec![0.1, 1.0, 3.0]);
    let material = preset("skin1").unwrap();
    let profile = build_profile(&material, Model::Dipole, 6).unwrap();
    let same = |json: &Value, library: [f64; 3]| {
        let printed = numbers(json);
        (0..3).all(|c| (printed[c] - library[c]).abs() <= 1e-14 * library[c].abs())
    };
    assert!(same(&out["total_reflectance"], profile.total_reflectance()));
    assert!(same(&out["reflectance"][1], profile.reflectance(1.0)));
    assert!(same(&out["d_max_mm"], profile.d_max(1e-3)));
    assert_eq!(numbers(&out["total_transmittance"]), vec![0.0; 3]);
}

#[test]
fn the_default_model_is_the_one_the_material_needs() {
    for (name, model) in [
        ("marble", "dipole"),
        ("skin3layer", "layered"),
        ("deon-skin", "gaussians"),
    ] {
        let out = json(&["profile", "--preset", name, "--json"]);
        assert_eq!(out["model"], model, "{name}");
        assert_eq!(out["radii_mm"].as_array().unwrap().len(), 60);
    }
}

#[test]
fn every_model_of_a_slab_runs_on_a_slab_file() {
    let dir = scratch("slab");
    let file = dir.join("wax.toml");
    std::fs::write(
        &file,
        "[[layers]]\nsigma_a = [0.01, 0.02, 0.05]\nsigma_s = 1.5\nthickness_mm = 3\n",
    )
    .unwrap();
    let file = file.to_str().unwrap();
    for model in ["multipole", "layered", "gaussians", "burley"] {
        let out = json(&["profile", "--material", file, "--model", model, "--json"]);
        assert_eq!(out["model"], model);
        assert!(
            numbers(&out["total_reflectance"])
                .iter()
                .all(|v| *v > 0.0 && *v < 1.0),
            "{model}"
        );
    }
    // The dipole's medium is semi-infinite: it says so and names the
    // models of a slab, rather than drawing the slab's top as a half-space.
    let refused = sssbake(&["profile", "--material", file, "--model", "dipole"]);
    let said = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success(), "{said}");
    assert!(
        said.contains("3 mm thick") && said.contains("use multipole or layered"),
        "{said}"
    );
    let slab = json(&["profile", "--material", file, "--json"]);
    assert_eq!(slab["model"], "layered");
    assert!(
        numbers(&slab["total_transmittance"])
            .iter()
            .all(|v| *v > 0.0)
    );
}

#[test]
fn monte_carlo_reports_standard_errors() {
    let args = [
        "profile",
        "--preset",
        "skin1",
        "--model",
        "montecarlo",
        "--photons",
        "3000",
        "--radii",
        "0.5,1,2",
        "--json",
    ];
    let out = json(&args);
    assert_eq!(out["model"], "montecarlo");
    let stderr = out["reflectance_stderr"].as_array().unwrap();
    assert_eq!(stderr.len(), 3);
    assert!(numbers(&stderr[0]).iter().all(|e| *e > 0.0));
    assert_eq!(
        out["reflectance"],
        json(&args)["reflectance"],
        "the same seed repeats"
    );
    let compared = json(&[
        "profile",
        "--preset",
        "skin1",
        "--compare-montecarlo",
        "--photons",
        "2000",
        "--json",
    ]);
    assert_eq!(compared["model"], "dipole");
    assert!(compared["montecarlo"]["total_reflectance"].is_array());
}

#[test]
fn plots_are_written_whole() {
    let dir = scratch("plots");
    let svg = dir.join("skin.svg");
    let png = dir.join("skin.png");
    let out = sssbake(&[
        "profile",
        "--preset",
        "skin3layer",
        "--plot",
        svg.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.starts_with("<svg")
            && text.ends_with("</svg>")
            && text.matches("<polyline").count() >= 12
    );
    let out = sssbake(&[
        "profile",
        "--preset",
        "skin1",
        "--compare-montecarlo",
        "--photons",
        "1000",
        "--plot",
        png.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(&std::fs::read(&png).unwrap()[..8], b"\x89PNG\r\n\x1a\n");
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("partial"))
        .collect();
    assert!(leftovers.is_empty());
}

fn assert_fails(args: &[&str], code: i32, words: &[&str]) {
    let out = sssbake(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
    for w in words {
        assert!(stderr.contains(w), "{args:?}: `{w}` not in {stderr}");
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn bad_input_gets_a_clear_error() {
    let dir = scratch("bad");
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "[[layers]]\nsigma_a = 0.1\nsigma_s = 1\nior = 0\n").unwrap();
    let bad = bad.to_str().unwrap();
    assert_fails(
        &["profile", "--preset", "jade"],
        1,
        &["unknown preset `jade`", "skin1"],
    );
    assert_fails(&["profile", "--material", bad], 1, &[bad, "layers[0].ior"]);
    assert_fails(
        &["profile", "--material", "/nonexistent/x.toml"],
        1,
        &["/nonexistent/x.toml", "cannot read"],
    );
    assert_fails(
        &["profile", "--preset", "skin1", "--radii", "1,-2"],
        1,
        &["--radii", "-2"],
    );
    assert_fails(
        &["profile", "--preset", "skin1", "--radii", "2,1"],
        1,
        &["increase"],
    );
    assert_fails(
        &["profile", "--preset", "skin1", "--epsilon", "1.5"],
        1,
        &["--epsilon"],
    );
    assert_fails(
        &["profile", "--preset", "skin3layer", "--model", "multipole"],
        1,
        &["skin3layer", "one slab"],
    );
    assert_fails(
        &["profile", "--preset", "deon-skin", "--model", "montecarlo"],
        1,
        &["deon-skin", "no layers"],
    );
    assert_fails(
        &["profile", "--preset", "skin1", "--plot", "out.jpg"],
        1,
        &[".svg or .png"],
    );
    assert_fails(
        &["profile", "--preset", "skin1", "--model", "cubic"],
        2,
        &["invalid value 'cubic'", "possible values", "montecarlo"],
    );
    assert_fails(&["profile"], 2, &["--preset"]);
    let unwritable = dir.join("missing-dir").join("plot.svg");
    assert_fails(
        &[
            "profile",
            "--preset",
            "skin1",
            "--plot",
            unwritable.to_str().unwrap(),
        ],
        3,
        &["plot.svg", "cannot write"],
    );
    assert!(!unwritable.exists());
}

#[test]
fn stam_reports_angles_and_the_library_numbers() {
    use sssbake_profile::models::stam::StamSettings;
    use sssbake_profile::models::stam::material::solve_material;
    let out = json(&[
        "profile",
        "--preset",
        "stam-dermis",
        "--model",
        "stam",
        "--json",
    ]);
    assert_eq!(out["model"], "stam");
    let material = preset("stam-dermis").unwrap();
    let library = solve_material(&material, &StamSettings::default()).unwrap();
    let cosines = numbers(&out["cosines"]);
    assert_eq!(cosines, library[0].cosines);
    for (e, row) in out["reflectance"].as_array().unwrap().iter().enumerate() {
        let printed = numbers(row);
        let transmitted = numbers(&out["transmittance"][e]);
        for c in 0..3 {
            assert!((printed[c] - library[c].reflectance[e]).abs() <= 1e-14);
            // An opaque (semi-infinite) dermis transmits nothing.
            assert_eq!(transmitted[c], 0.0);
        }
        // Its albedo falls from red to blue, and so does what it returns.
        assert!(
            printed[0] > printed[1] && printed[1] > printed[2],
            "{printed:?}"
        );
    }
    // In-plane slices: [channel][incidence][exit], non-negative.
    let slice = &out["brdf_forward"][0];
    assert_eq!(slice.as_array().unwrap().len(), cosines.len());
    assert!(
        numbers(&slice[3])
            .iter()
            .all(|v| *v >= 0.0 && v.is_finite())
    );
    // The plot: R and T per channel over every ordinate, and a BRDF slice per
    // channel over both sides of the plane of incidence.
    let plot = scratch("stam-plot").join("stam.svg");
    let out = sssbake(&[
        "profile",
        "--preset",
        "stam-dermis",
        "--model",
        "stam",
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let svg = std::fs::read_to_string(&plot).unwrap();
    let lines: Vec<usize> = svg
        .split("<polyline points=\"")
        .skip(1)
        .map(|l| l.split('"').next().unwrap().split(' ').count())
        .collect();
    let n = cosines.len();
    assert_eq!(lines, [[n; 6].as_slice(), &[2 * n; 3]].concat());
    // Several layers, radial options and a bake are refused, saying why.
    assert_fails(
        &["profile", "--preset", "skin3layer", "--model", "stam"],
        1,
        &["skin3layer", "one layer", "3 layers"],
    );
    assert_fails(
        &[
            "profile",
            "--preset",
            "stam-dermis",
            "--model",
            "stam",
            "--radii",
            "1,2",
        ],
        1,
        &["--radii", "incidence angle"],
    );
    assert_eq!(
        build_profile(&material, Model::Stam, 6)
            .err()
            .map(|e| e.to_string().contains("not a radial profile")),
        Some(true)
    );
}

/// On a stack whose top layer is declared stam, `--model stam` shows that
/// layer as a bake uses it: in contact with the layer beneath, which takes
/// the light a face against air would have sent back up.
#[test]
fn stam_shows_a_declared_top_layer_in_contact_with_the_layer_beneath() {
    use sssbake_profile::models::stam::StamSettings;
    use sssbake_profile::models::stam::epidermis::Epidermis;
    use sssbake_profile::models::stam::material::layers_for;
    let out = json(&[
        "profile",
        "--preset",
        "stam-skin",
        "--model",
        "stam",
        "--json",
    ]);
    assert_eq!(out["form"], "contact");
    let material = preset("stam-skin").unwrap();
    let library = Epidermis::solve(&material).unwrap();
    let between_air = layers_for(&material)
        .unwrap()
        .map(|layer| layer.solve(&StamSettings::default()).unwrap());
    let cosines = numbers(&out["cosines"]);
    assert_eq!(cosines, library.channel(0).cosines);
    let mut compared = 0;
    for (e, &mu) in cosines.iter().enumerate() {
        let reflected = numbers(&out["reflectance"][e]);
        let transmitted = numbers(&out["transmittance"][e]);
        for c in 0..3 {
            let contact = library.channel(c);
            assert!((reflected[c] - contact.reflectance[e]).abs() <= 1e-14);
            assert!((transmitted[c] - contact.transmittance[e]).abs() <= 1e-14);
            assert!(reflected[c] + transmitted[c] <= 1.0 + 1e-9);
            // The layer alone between air, at the same outside ordinate.
            let alone = &between_air[c];
            if let Some(a) = alone.cosines.iter().position(|&m| (m - mu).abs() < 1e-12) {
                assert!(
                    transmitted[c] > alone.transmittance[a],
                    "θ {mu}: contact {} against air {}",
                    transmitted[c],
                    alone.transmittance[a]
                );
                assert!(reflected[c] <= alone.reflectance[a] + 1e-12);
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 3 * cosines.len());
    let below = numbers(&out["reflectance_from_below"]);
    let up = numbers(&out["transmittance_from_below"]);
    for c in 0..3 {
        assert!(below[c] >= 0.0 && up[c] > 0.0 && below[c] + up[c] <= 1.0 + 1e-9);
    }
    // The plot has the one panel of totals: R and T per channel.
    let plot = scratch("stam-contact-plot").join("contact.svg");
    let run = sssbake(&[
        "profile",
        "--preset",
        "stam-skin",
        "--model",
        "stam",
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert!(run.status.success());
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert_eq!(svg.matches("<polyline").count(), 6);
    let table = sssbake(&["profile", "--preset", "stam-skin", "--model", "stam"]);
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(text.contains("in contact with the layer beneath"), "{text}");
}

/// `--model empirical` prints the fitted lobes' profile and the fit's
/// error: a total inside (0, 1) per channel, matching the Monte Carlo the
/// CLI compares it with.
#[test]
fn the_empirical_model_prints_its_profile() {
    let out = json(&[
        "profile",
        "--preset",
        "ketchup",
        "--model",
        "empirical",
        "--compare-montecarlo",
        "--photons",
        "100000",
        "--json",
    ]);
    assert_eq!(out["model"], "empirical");
    let relative = numbers(&out["fit_error"]["mean_relative_rms"]);
    assert!(
        relative.iter().all(|e| *e >= 0.0 && *e < 0.5),
        "{relative:?}"
    );
    let total = numbers(&out["total_reflectance"]);
    let simulated = numbers(&out["montecarlo"]["total_reflectance"]);
    for (t, s) in total.iter().zip(&simulated) {
        assert!(*t > 0.0 && *t < 1.0, "total {total:?}");
        assert!((t - s).abs() < 0.05 * s, "{total:?} against {simulated:?}");
    }
}
