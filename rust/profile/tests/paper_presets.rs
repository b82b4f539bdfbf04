//! The presets of Donner et al. 2009 carry the paper's own numbers: where
//! the paper states a medium's albedo beside its coefficients (orange
//! juice, §5), the preset's coefficients give that albedo; the lozenge of
//! figure 7, which the paper gives by albedo and g alone, has them.

use sssbake_profile::presets::preset;
use sssbake_profile::{Layer, Material, Optics};

fn only_layer(material: &Material) -> &Layer {
    match &material.optics {
        Optics::Layers(layers) if layers.len() == 1 => &layers[0],
        other => panic!("{}: {other:?}", material.name),
    }
}

fn albedo(layer: &Layer) -> [f64; 3] {
    std::array::from_fn(|c| layer.sigma_s[c] / (layer.sigma_s[c] + layer.sigma_a[c]))
}

#[test]
fn orange_juice_has_the_albedo_the_paper_states_for_its_coefficients() {
    // §5: σs (0.071, 0.1, 0.042), σa (0.093, 0.16, 1.15) "produces a
    // relatively low spectral albedo of α = (0.43, 0.38, 0.035)".
    let juice = preset("orangejuice").unwrap();
    let layer = only_layer(&juice);
    let stated = [0.43, 0.38, 0.035];
    for (c, a) in albedo(layer).into_iter().enumerate() {
        // The paper rounds to two figures (0.385 prints as 0.38).
        assert!((a - stated[c]).abs() <= 0.006, "channel {c}: {a}");
    }
    assert_eq!((layer.g, layer.ior), (0.9, 1.3));
}

#[test]
fn the_lozenge_has_figure_7s_albedo_and_g() {
    let lozenge = preset("lozenge").unwrap();
    let layer = only_layer(&lozenge);
    let stated = [0.16, 0.27, 0.15];
    for (c, a) in albedo(layer).into_iter().enumerate() {
        assert!((a - stated[c]).abs() < 1e-12, "channel {c}: {a}");
    }
    assert_eq!(layer.g, 0.5);
    assert!(layer.thickness_mm.is_none());
    // A bakeable medium: a finite, positive extinction in every channel.
    for c in 0..3 {
        let sigma_t = layer.sigma_s[c] + layer.sigma_a[c];
        assert!(sigma_t.is_finite() && sigma_t > 0.0);
    }
}
