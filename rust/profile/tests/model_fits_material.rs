//! A model refuses a material it cannot describe, saying which one does,
//! rather than bake part of it under its name.

mod common;

use common::*;
use sssbake_profile::material::{Material, Optics};
use sssbake_profile::model::ModelError;
use sssbake_profile::presets::preset;
use sssbake_profile::{Model, build_profile};

/// One layer of skin-like grey medium: semi-infinite, or `thickness` mm.
fn slab_material(thickness: Option<f64>, below: usize) -> Material {
    let mut layers = vec![grey_layer(0.05, 2.0, 0.0, 1.4, thickness)];
    for _ in 0..below {
        layers.push(grey_layer(0.1, 1.0, 0.0, 1.4, None));
    }
    Material {
        optics: Optics::Layers(layers),
        ..preset("skin1").unwrap()
    }
}

/// Why `model` refuses `material`; fails the test when it does not.
fn refusal(material: &Material, model: Model) -> ModelError {
    match build_profile(material, model, 6) {
        Ok(_) => panic!("{model} took a material it cannot describe"),
        Err(error) => error,
    }
}

#[test]
fn half_space_models_refuse_finite_and_layered_media() {
    for model in [Model::Dipole, Model::Empirical] {
        let thin = refusal(&slab_material(Some(2.0), 0), model);
        assert!(
            thin.reason.contains("2 mm thick") && thin.reason.contains("use multipole"),
            "{model}: {thin}"
        );
        let stacked = refusal(&slab_material(Some(0.1), 1), model);
        assert!(
            stacked.reason.contains("2 layers") && stacked.reason.contains("use layered"),
            "{model}: {stacked}"
        );
    }
    // What they do describe, and what describes the others.
    assert!(build_profile(&slab_material(None, 0), Model::Dipole, 6).is_ok());
    assert!(build_profile(&slab_material(Some(2.0), 0), Model::Multipole, 6).is_ok());
    assert!(build_profile(&slab_material(Some(0.1), 1), Model::Layered, 6).is_ok());
    let three = preset("skin3layer").unwrap();
    assert_eq!(Model::default_for(&three), Model::Layered);
    assert!(build_profile(&three, Model::Dipole, 6).is_err());
}
