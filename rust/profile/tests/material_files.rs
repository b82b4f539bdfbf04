//! Material files: valid ones load, invalid ones fail naming file and field.

use sssbake_profile::material::TopLayer;
use sssbake_profile::model::Model;
use sssbake_profile::{Material, Optics};

fn load(text: &str) -> Result<Material, String> {
    Material::from_toml(text, "skin.toml", "skin").map_err(|e| e.to_string())
}

fn assert_error(text: &str, field: &str, words: &str) {
    let error = load(text).expect_err("the material should be rejected");
    assert!(error.starts_with("skin.toml: "), "no file in: {error}");
    assert!(error.contains(field), "no field `{field}` in: {error}");
    assert!(error.contains(words), "no `{words}` in: {error}");
}

const TWO_LAYERS: &str = r#"
name = "two-layer skin"
[[layers]]
sigma_a = [0.5, 1.0, 2.0]
sigma_s = 20
g = 0.8
ior = 1.4
thickness_mm = 0.1

[[layers]]
sigma_a = 0.03
sigma_s = [0.7, 0.9, 1.1]
"#;

#[test]
fn a_valid_file_loads_with_defaults() {
    let material = load(TWO_LAYERS).unwrap();
    assert_eq!(material.name, "two-layer skin");
    let Optics::Layers(layers) = &material.optics else {
        panic!("layers expected")
    };
    assert_eq!(layers.len(), 2);
    assert_eq!(layers[0].sigma_s, [20.0; 3]);
    assert_eq!(layers[0].thickness_mm, Some(0.1));
    assert_eq!(
        (layers[1].g, layers[1].ior, layers[1].thickness_mm),
        (0.0, 1.3, None)
    );
    assert_eq!(layers[1].sigma_s, [0.7, 0.9, 1.1]);
    let unnamed = load("[[layers]]\nsigma_a = 1\nsigma_s = 1\n").unwrap();
    assert_eq!(unnamed.name, "skin");
}

#[test]
fn bad_values_name_their_field() {
    let one = |field: &str| format!("[[layers]]\nsigma_a = 0.1\nsigma_s = 1.0\n{field}\n");
    assert_error(
        "[[layers]]\nsigma_a = -0.1\nsigma_s = 1\n",
        "layers[0].sigma_a",
        "non-negative",
    );
    assert_error(
        "[[layers]]\nsigma_a = 0.1\nsigma_s = [1, nan, 1]\n",
        "layers[0].sigma_s",
        "finite",
    );
    assert_error(
        "[[layers]]\nsigma_a = inf\nsigma_s = 1\n",
        "layers[0].sigma_a",
        "finite",
    );
    assert_error(&one("ior = 0"), "layers[0].ior", "positive");
    assert_error(&one("ior = -1.3"), "layers[0].ior", "positive");
    assert_error(&one("g = 1.0"), "layers[0].g", "between -1 and 1");
    assert_error(
        &one("thickness_mm = 0"),
        "layers[0].thickness_mm",
        "positive",
    );
    assert_error(
        &one("thickness_mm = inf"),
        "layers[0].thickness_mm",
        "finite",
    );
    assert_error(
        "[[layers]]\nsigma_a = 0\nsigma_s = 0\n",
        "layers[0].sigma_s",
        "neither scatters nor absorbs",
    );
}

#[test]
fn bad_structure_is_named() {
    assert_error("name = \"x\"\n", "layers", "missing");
    assert_error("layers = []\n", "layers", "empty");
    assert_error("layers = 3\n", "layers", "array of tables");
    assert_error(
        "[[layers]]\nsigma_a = 0.1\n",
        "layers[0].sigma_s",
        "missing",
    );
    assert_error(
        "[[layers]]\nsigma_a = [0.1, 0.2]\nsigma_s = 1\n",
        "layers[0].sigma_a",
        "3 entries",
    );
    assert_error(
        "[[layers]]\nsigma_a = \"red\"\nsigma_s = 1\n",
        "layers[0].sigma_a",
        "number",
    );
    assert_error(
        "[[layers]]\nsigma_a = 0.1\nsigma_s = 1\nsigma_t = 3\n",
        "layers[0].sigma_t",
        "unknown field",
    );
    assert_error(
        "colour = 1\n[[layers]]\nsigma_a = 0.1\nsigma_s = 1\n",
        "colour",
        "unknown field",
    );
    assert_error(
        "[[layers]]\nsigma_a = 0.1\nsigma_s = 1\n[[layers]]\nsigma_a = 0.1\nsigma_s = 1\n",
        "layers[0].thickness_mm",
        "only the last layer may be semi-infinite",
    );
    assert_error("[[layers]\nsigma_a = 0.1", "", "not valid TOML");
}

#[test]
fn a_missing_file_is_named() {
    let error = Material::from_file(std::path::Path::new("/nonexistent/dir/wax.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        error.starts_with("/nonexistent/dir/wax.toml: cannot read"),
        "{error}"
    );
}

/// The whole message, so the file, the field path (`layers[0].x`, as the
/// validation errors write it) and the offending key are all checked.
fn assert_message(text: &str, expected: &str) {
    let error = load(text).expect_err("the material should be rejected");
    assert_eq!(error, expected);
}

#[test]
fn an_unknown_key_at_the_top_is_named() {
    assert_message(
        "sigma_z = 1\n[[layers]]\nsigma_a = 0.1\nsigma_s = 1\n",
        "skin.toml: sigma_z: unknown field `sigma_z`, expected one of `name`, `coat_ior`, `roughness`, `layers`",
    );
}

#[test]
fn an_unknown_key_in_a_layer_is_named_with_its_layer() {
    assert_message(
        "[[layers]]\nsigma_a = 0.1\nsigma_s = 20\nthickness_mm = 0.1\n\
         [[layers]]\nsigma_a = 0.1\nsigma_s = 1\nthikness_mm = 0.2\n",
        "skin.toml: layers[1].thikness_mm: unknown field `thikness_mm`, \
         expected one of `sigma_a`, `sigma_s`, `g`, `ior`, `thickness_mm`, `model`",
    );
}

#[test]
fn a_wrong_type_is_named_with_what_was_expected() {
    assert_message(
        "[[layers]]\nsigma_a = \"red\"\nsigma_s = 1\n",
        "skin.toml: layers[0].sigma_a: invalid type: string \"red\", \
         expected a number or [r, g, b] (1/mm)",
    );
    assert_message(
        "[[layers]]\nsigma_a = [0.1, \"x\", 1]\nsigma_s = 1\n",
        "skin.toml: layers[0].sigma_a[1]: invalid type: string \"x\", expected a number",
    );
    assert_message(
        "[[layers]]\nsigma_a = 0.1\nsigma_s = 1\nior = true\n",
        "skin.toml: layers[0].ior: invalid type: boolean `true`, expected a number",
    );
    assert_message(
        "layers = [1]\n",
        "skin.toml: layers[0]: invalid type: integer `1`, \
         expected a table of sigma_a, sigma_s, g, ior, thickness_mm and model",
    );
}

#[test]
fn a_coat_is_read_and_checked() {
    let layer = "[[layers]]\nsigma_a = 0.1\nsigma_s = 1.0\n";
    let coated = load(&format!("coat_ior = 1.45\n{layer}")).unwrap();
    assert_eq!(coated.coat_ior, Some(1.45));
    assert_eq!(coated.entry_index(), 1.45);
    assert_eq!(load(layer).unwrap().coat_ior, None);
    assert_message(
        &format!("coat_ior = -1.0\n{layer}"),
        "skin.toml: coat_ior: must be a positive finite index, got -1",
    );
}

#[test]
fn a_roughness_is_read_defaulted_and_checked() {
    let layer = "[[layers]]\nsigma_a = 0.1\nsigma_s = 1.0\n";
    let rough = load(&format!("roughness = 0.4\n{layer}")).unwrap();
    assert_eq!(rough.roughness, 0.4);
    assert_eq!(
        load(layer).unwrap().roughness,
        sssbake_profile::material::DEFAULT_ROUGHNESS
    );
    for bad in ["-0.1", "1.5", "nan"] {
        assert_error(
            &format!("roughness = {bad}\n{layer}"),
            "roughness",
            "between 0 (smooth) and 1",
        );
    }
}

#[test]
fn a_top_layer_declared_stam_is_read_and_only_the_top_may_be() {
    let two = |model_top: &str, model_below: &str| {
        format!(
            "roughness = 0.4\n[[layers]]\n{model_top}sigma_a = 2.1\nsigma_s = 48\nior = 1.4\nthickness_mm = 0.03\n\
             [[layers]]\n{model_below}sigma_a = 0.03\nsigma_s = 4.7\ng = 0.85\nior = 1.4\n"
        )
    };
    let stam = load(&two("model = \"stam\"\n", "")).unwrap();
    assert_eq!(stam.top_layer, TopLayer::Stam);
    assert_eq!(Model::default_for(&stam), Model::Stam);
    let plain = load(&two("model = \"diffusion\"\n", "")).unwrap();
    assert_eq!(plain.top_layer, TopLayer::Diffusion);
    assert_message(
        &two("", "model = \"stam\"\n"),
        "skin.toml: layers[1].model: only the top layer (layers[0]) may be solved by stam",
    );
    assert_message(
        &two("model = \"kubelka\"\n", ""),
        "skin.toml: layers[0].model: unknown layer model `kubelka` (known: diffusion, stam)",
    );
    assert_message(
        &format!("coat_ior = 1.5\n{}", two("model = \"stam\"\n", "")),
        "skin.toml: coat_ior: a stam top layer's faces are the surface; a coat over it is not modelled",
    );
}
