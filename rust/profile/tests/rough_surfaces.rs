//! Donner & Jensen 2005 §2.4: a rough surface changes the diffusion
//! boundary through A = (1 + ρd)/(1 − ρd) (eq. 24) in every diffusion model.

mod common;
use common::grey_layer;
use sssbake_profile::boundary::fresnel;
use sssbake_profile::boundary::rough::{boundary_a, diffuse_reflectance};
use sssbake_profile::models::dipole::dipole_total_reflectance;
use sssbake_profile::{Layer, Material, Model, Optics, build_profile};

fn material(layer: Layer, roughness: f64) -> Material {
    Material {
        name: "rough".into(),
        optics: Optics::Layers(vec![layer]),
        coat_ior: None,
        top_layer: sssbake_profile::material::TopLayer::Diffusion,
        roughness,
    }
}

#[test]
fn the_dipole_takes_a_from_the_rough_diffuse_reflectance() {
    let layer = grey_layer(0.01, 1.0, 0.0, 1.4, None);
    let albedo = layer.medium(0).albedo_reduced();
    for m in [0.1, 0.5, 1.0] {
        let dipole = build_profile(&material(layer.clone(), m), Model::Dipole, 6).unwrap();
        let expected = dipole_total_reflectance(albedo, boundary_a(1.4, m));
        assert!((dipole.total_reflectance()[0] - expected).abs() < 1e-12);
        // Eq. 24 with ρd, not eq. 7 with the smooth F_dr.
        let rho = diffuse_reflectance(1.4, m);
        assert!(
            rho < fresnel::diffuse_reflectance_exact(1.4),
            "{m}: ρd {rho}"
        );
    }
    let smooth = build_profile(&material(layer, 0.0), Model::Dipole, 6).unwrap();
    let expected = dipole_total_reflectance(albedo, fresnel::boundary_a(1.4));
    assert!((smooth.total_reflectance()[0] - expected).abs() < 1e-12);
}

/// A semi-infinite layer's multipole is its dipole (one image pair), and
/// the layered solver's exact boundary condition sees the same A: all
/// three move together with the roughness.
#[test]
fn every_diffusion_model_sees_the_rough_boundary() {
    let semi = grey_layer(0.01, 1.0, 0.0, 1.4, None);
    let slab = grey_layer(0.01, 1.0, 0.0, 1.4, Some(3.0));
    for m in [0.0, 0.3, 1.0] {
        let dipole = build_profile(&material(semi.clone(), m), Model::Dipole, 6).unwrap();
        let multipole = build_profile(&material(semi.clone(), m), Model::Multipole, 6).unwrap();
        let (d, p) = (
            dipole.total_reflectance()[0],
            multipole.total_reflectance()[0],
        );
        assert!((d - p).abs() < 1e-9, "{m}: dipole {d}, multipole {p}");
        let layered = build_profile(&material(semi.clone(), m), Model::Layered, 6).unwrap();
        let l = layered.total_reflectance()[0];
        // The exact boundary condition differs from the image series by a
        // few percent of the total; the rough A moves both.
        assert!((l - d).abs() < 0.05 * d, "{m}: layered {l}, dipole {d}");
    }
    // Rougher: a smaller ρd, a smaller A, less light held in: more is
    // reflected, and with both faces against air rough, less is trapped
    // between them to be absorbed, so more leaves in all.
    let totals = |m: f64| {
        let p = build_profile(&material(slab.clone(), m), Model::Layered, 6).unwrap();
        (p.total_reflectance()[0], p.total_transmittance()[0])
    };
    let (smooth, rough) = (totals(0.0), totals(0.5));
    assert!(
        rough.0 > smooth.0 && rough.0 + rough.1 > smooth.0 + smooth.1,
        "(R, T) smooth {smooth:?}, rough {rough:?}"
    );
    let multipole = |m: f64| {
        build_profile(&material(slab.clone(), m), Model::Multipole, 6)
            .unwrap()
            .total_reflectance()[0]
    };
    assert!(multipole(0.5) > multipole(0.0));
}
