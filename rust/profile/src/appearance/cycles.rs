//! Blender's Principled BSDF subsurface inputs as Cycles reads them.
//!
//! Cycles does not use Subsurface Radius × Scale as a mean free path
//! directly (its kernel, `closure/bssrdf.h` and
//! `integrator/subsurface_random_walk.h`):
//! - Christensen–Burley and Random Walk divide it by 4π and use the result
//!   as the mean free path 1/σt'.
//! - Random Walk (Skin) multiplies it by √(3(1 − α')), where α' is the
//!   reduced albedo whose dipole (Jensen et al. 2001, with Subsurface IOR)
//!   reflects the colour: Radius × Scale becomes the diffusion length 1/σtr.
//! - The random walk leaves the surface at the first crossing without a
//!   Fresnel test: its diffusion boundary is index-matched. The main IOR
//!   (with Specular IOR Level) only shapes the dielectric specular layer on
//!   top, which takes its share once, where the surface is viewed (the
//!   closure's weight); the light reaching the point the walk leaves is
//!   taken through a plain diffuse closure, with no Fresnel
//!   (`kernel/integrator/subsurface.h`). The material says so
//!   ([`crate::material::TopLayer::PrincipledSpecular`]).
//! - The colour becomes a single-scattering albedo by a fit to path-traced
//!   slabs (Chiang et al. 2016 for g = 0, extended in g by Wrenninge,
//!   Villemin & Hery 2017), not by inverting a diffusion formula.
//!
//! [`AlbedoMapping::Cycles`] follows the fit, so a bake looks like Cycles'
//! render of the same material; [`AlbedoMapping::Physical`] inverts the
//! dipole instead, so the bake's uniform-light reflectance is exactly the
//! colour.

use crate::Rgb;
use crate::appearance::inversion::{InversionError, InversionModel, albedo_for, invert_albedo};
use crate::appearance::{MAX_ANISOTROPY, MIN_MEAN_FREE_PATH_MM};
use crate::boundary::fresnel::diffuse_reflectance_fit;
use crate::material::{Layer, Material, Optics};
use crate::models::dipole::dipole_total_reflectance;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Cycles' subsurface method (`subsurface_method` of the Principled BSDF).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, strum::EnumString)]
#[serde(rename_all = "snake_case")]
#[strum(serialize_all = "snake_case", ascii_case_insensitive)]
pub enum SubsurfaceMethod {
    /// Christensen–Burley: mean free path Radius × Scale / 4π.
    Burley,
    /// Random Walk: mean free path Radius × Scale / 4π, index-matched exit.
    #[default]
    RandomWalk,
    /// Random Walk (Skin): Radius × Scale is the diffusion length; light
    /// enters through Subsurface IOR.
    RandomWalkSkin,
}

/// How the colour becomes an albedo.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, strum::EnumString)]
#[serde(rename_all = "snake_case")]
#[strum(serialize_all = "snake_case", ascii_case_insensitive)]
pub enum AlbedoMapping {
    /// Cycles' fit from colour to single-scattering albedo: the bake looks
    /// like Cycles' render (the uniform-light level a few percent under
    /// the colour, as in Cycles).
    #[default]
    Cycles,
    /// The dipole inverted so that the uniform-light reflectance is exactly
    /// the colour.
    Physical,
}

/// The subsurface inputs of a Principled BSDF, in millimetres.
#[derive(Clone, Debug, PartialEq)]
pub struct PrincipledSubsurface {
    /// Material name for reports.
    pub name: String,
    /// Base Color, linear RGB in [0, 1] (clamped).
    pub colour: Rgb,
    /// Subsurface Radius × Subsurface Scale per channel, mm.
    pub radius_mm: Rgb,
    /// The subsurface method.
    pub method: SubsurfaceMethod,
    /// The main IOR (of the specular layer).
    pub ior: f64,
    /// Specular IOR Level: 0.5 leaves the IOR's reflectance, 0 removes it,
    /// 1 doubles it at normal incidence.
    pub specular_ior_level: f64,
    /// Subsurface IOR (Random Walk (Skin) only).
    pub subsurface_ior: f64,
    /// Subsurface Anisotropy (Henyey–Greenstein g).
    pub anisotropy: f64,
    /// How the colour becomes an albedo.
    pub albedo: AlbedoMapping,
}

impl PrincipledSubsurface {
    /// The mean free path 1/σt' per channel, mm, as Cycles derives it.
    pub fn mean_free_path_mm(&self) -> Rgb {
        let colour = self.colour.map(|c| c.clamp(0.0, 1.0));
        [0, 1, 2].map(|c| {
            let radius = self.radius_mm[c].max(0.0);
            let length = match self.method {
                SubsurfaceMethod::Burley | SubsurfaceMethod::RandomWalk => radius / (4.0 * PI),
                SubsurfaceMethod::RandomWalkSkin => {
                    radius * skin_radius_factor(colour[c], self.subsurface_ior)
                }
            };
            length.max(MIN_MEAN_FREE_PATH_MM)
        })
    }

    /// The index of the smooth dielectric the light crosses on entry: the
    /// specular layer's IOR after Specular IOR Level, or for Random Walk
    /// (Skin) the Subsurface IOR of its refractive entry.
    pub fn entry_index(&self) -> f64 {
        match self.method {
            SubsurfaceMethod::RandomWalkSkin => self.subsurface_ior,
            _ => specular_index(self.ior, self.specular_ior_level),
        }
    }

    /// One semi-infinite, index-matched layer carrying Cycles' medium, under
    /// Cycles' specular layer of [`Self::entry_index`].
    pub fn to_material(&self) -> Result<Material, InversionError> {
        for c in 0..3 {
            let value = self.colour[c];
            if !value.is_finite() {
                return Err(InversionError::Colour { channel: c, value });
            }
            let value = self.radius_mm[c];
            if !value.is_finite() || value < 0.0 {
                return Err(InversionError::MeanFreePath { channel: c, value });
            }
        }
        for value in [self.ior, self.subsurface_ior] {
            if !(value.is_finite() && value > 0.0) {
                return Err(InversionError::Index { value });
            }
        }
        let g = if self.anisotropy.is_finite() {
            self.anisotropy.clamp(-MAX_ANISOTROPY, MAX_ANISOTROPY)
        } else {
            0.0
        };
        let colour = self.colour.map(|c| c.clamp(0.0, 1.0));
        let mfp = self.mean_free_path_mm();
        let layer = match self.albedo {
            AlbedoMapping::Cycles => {
                let sigma_t = [0, 1, 2].map(|c| 1.0 / (mfp[c] * (1.0 - g)));
                let alpha = [0, 1, 2].map(|c| random_walk_albedo(colour[c], g));
                Layer {
                    sigma_a: [0, 1, 2].map(|c| (1.0 - alpha[c]) * sigma_t[c]),
                    sigma_s: [0, 1, 2].map(|c| alpha[c] * sigma_t[c]),
                    g,
                    ior: 1.0,
                    thickness_mm: None,
                }
            }
            AlbedoMapping::Physical => {
                let mut layer = invert_albedo(colour, mfp, 1.0, InversionModel::Dipole)?;
                layer.sigma_s = layer.sigma_s.map(|s| s / (1.0 - g));
                layer.g = g;
                layer
            }
        };
        let entry = self.entry_index();
        if !(entry.is_finite() && entry > 0.0) {
            return Err(InversionError::Index { value: entry });
        }
        Ok(Material {
            name: self.name.clone(),
            optics: Optics::Layers(vec![layer]),
            coat_ior: Some(entry),
            top_layer: crate::material::TopLayer::PrincipledSpecular,
            roughness: crate::material::DEFAULT_ROUGHNESS,
        })
    }
}

/// The index whose normal-incidence reflectance is the IOR's, scaled by
/// 2 × Specular IOR Level (Blender's definition); 1 when the level is 0.
pub fn specular_index(ior: f64, level: f64) -> f64 {
    let eta = if ior.is_finite() && ior > 0.0 {
        ior
    } else {
        1.5
    };
    let level = if level.is_finite() {
        level.clamp(0.0, 1.0)
    } else {
        0.5
    };
    let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2) * 2.0 * level;
    let root = f0.clamp(0.0, 0.99).sqrt();
    let matched = (1.0 + root) / (1.0 - root);
    // Keep which side of 1 the IOR lies on (an IOR below 1 is a bubble).
    if eta < 1.0 { 1.0 / matched } else { matched }
}

/// Random Walk (Skin)'s radius factor √(3(1 − α')), where α' is the reduced
/// albedo whose dipole total reflectance (boundary by the F_dr fit at
/// `subsurface_ior`) is `colour`.
pub fn skin_radius_factor(colour: f64, subsurface_ior: f64) -> f64 {
    let eta = if subsurface_ior.is_finite() && subsurface_ior > 0.0 {
        subsurface_ior
    } else {
        1.4
    };
    let fdr = diffuse_reflectance_fit(eta).min(1.0 - 1e-9);
    let a = (1.0 + fdr) / (1.0 - fdr);
    let albedo = albedo_for(colour.clamp(0.0, 1.0), |albedo| {
        dipole_total_reflectance(albedo, a)
    });
    (3.0 * (1.0 - albedo)).max(0.0).sqrt()
}

/// The single-scattering albedo a random walk in an index-matched
/// half-space needs to reflect `colour` with phase anisotropy `g`: the fit
/// of Wrenninge, Villemin & Hery 2017 (Pixar), which Cycles uses. Its
/// coefficients are polynomials in g (exponentials of polynomials for two
/// of them), blended by colour^¼.
pub fn random_walk_albedo(colour: f64, g: f64) -> f64 {
    let colour = colour.clamp(0.0, 1.0);
    let g = g.clamp(-MAX_ANISOTROPY, MAX_ANISOTROPY);
    let poly = |c: &[f64]| c.iter().rev().fold(0.0, |sum, &k| sum * g + k);
    let a = poly(&FIT_A);
    let b = 4.985_111_943_85 + 0.127_355_959_438 * poly(&FIT_B_EXPONENT).exp();
    let c = poly(&FIT_C);
    let d = poly(&FIT_D);
    let e = 4.231_902_997_01 + 0.003_106_039_490_88 * poly(&FIT_E_EXPONENT).exp();
    let f = poly(&FIT_F);
    let blend = colour.powf(0.25);
    let alpha =
        (1.0 - blend) * a * (b * colour).atan().powf(c) + blend * d * (e * colour).atan().powf(f);
    if alpha.is_finite() {
        alpha.clamp(0.0, 0.999_999)
    } else {
        0.0
    }
}

// The fit's coefficients, constant term first (Wrenninge et al. 2017).
const FIT_A: [f64; 8] = [
    1.826_052_378_2,
    -1.284_510_564_36,
    -1.799_046_293_12,
    9.193_932_892_02,
    -22.821_558_586_2,
    32.023_487_425_9,
    -23.626_480_333_3,
    7.210_670_026_58,
];
const FIT_B_EXPONENT: [f64; 8] = [
    0.0,
    31.149_158_143_3,
    -201.847_017_512,
    841.576_016_723,
    -2_018.092_885_05,
    2_731.715_602_86,
    -1_935.414_242_44,
    559.009_054_474,
];
const FIT_C: [f64; 8] = [
    1.096_861_024_24,
    -0.394_704_063_468,
    1.052_581_159_41,
    -8.839_637_127_26,
    28.864_323_066_1,
    -46.880_291_358_1,
    38.540_283_751_8,
    -12.718_104_253_8,
];
const FIT_D: [f64; 8] = [
    0.496_310_210_422,
    0.360_146_581_622,
    -2.151_393_097_47,
    17.889_689_921_7,
    -55.298_401_033_3,
    82.065_982_243,
    -58.510_600_857_8,
    15.847_829_502_1,
];
const FIT_E_EXPONENT: [f64; 8] = [
    0.0,
    76.731_625_395_2,
    -594.356_773_233,
    2_448.883_420_3,
    -5_576.685_289_98,
    7_116.601_719_12,
    -4_763.544_678_87,
    1_303.531_805_5,
];
const FIT_F: [f64; 8] = [
    2.406_029_994_08,
    -2.518_148_446_09,
    9.184_949_083_56,
    -79.219_170_868_2,
    259.082_868_209,
    -403.613_804_597,
    302.857_124_36,
    -87.437_047_356_7,
];

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // channels are indexed together across arrays
mod tests {
    use super::*;
    use crate::Profile;
    use crate::models::dipole::Dipole;

    fn skin(method: SubsurfaceMethod, albedo: AlbedoMapping) -> PrincipledSubsurface {
        PrincipledSubsurface {
            name: "skin".into(),
            colour: [0.8, 0.55, 0.45],
            radius_mm: [2.0, 0.7, 0.4],
            method,
            ior: 1.4,
            specular_ior_level: 0.5,
            subsurface_ior: 1.4,
            anisotropy: 0.0,
            albedo,
        }
    }

    #[test]
    fn random_walk_mean_free_path_is_radius_over_four_pi() {
        let s = skin(SubsurfaceMethod::RandomWalk, AlbedoMapping::Cycles);
        let mfp = s.mean_free_path_mm();
        for c in 0..3 {
            assert!((mfp[c] - s.radius_mm[c] / (4.0 * PI)).abs() < 1e-12);
        }
        let layer = match s.to_material().unwrap().optics {
            Optics::Layers(l) => l[0].clone(),
            _ => unreachable!(),
        };
        assert_eq!(
            layer.ior, 1.0,
            "the random walk's boundary is index-matched"
        );
        for c in 0..3 {
            assert!((layer.medium(c).mean_free_path() - mfp[c]).abs() < 1e-9);
        }
    }

    #[test]
    fn skin_radius_is_the_diffusion_length() {
        let s = skin(SubsurfaceMethod::RandomWalkSkin, AlbedoMapping::Cycles);
        let mfp = s.mean_free_path_mm();
        for c in 0..3 {
            // 1/σtr = ℓ/√(3(1 − α')) equals Radius × Scale.
            let factor = skin_radius_factor(s.colour[c], 1.4);
            assert!((mfp[c] / factor - s.radius_mm[c]).abs() < 1e-9);
            assert!(factor > 0.0 && factor < 3f64.sqrt());
        }
        // A darker colour scatters less far in mean free paths: a larger factor.
        assert!(skin_radius_factor(0.2, 1.4) > skin_radius_factor(0.8, 1.4));
    }

    #[test]
    fn the_fit_is_monotone_and_bounded() {
        for g in [-0.9, -0.5, 0.0, 0.3, 0.8, 0.95] {
            let mut last = -1.0;
            for i in 0..=100 {
                let alpha = random_walk_albedo(f64::from(i) / 100.0, g);
                assert!((0.0..1.0).contains(&alpha), "g {g} colour {i}: {alpha}");
                assert!(alpha >= last - 1e-9, "g {g}: not monotone at {i}");
                last = alpha;
            }
        }
        // Chiang et al. 2016's g = 0 fit, an independent form of the same
        // mapping: 1 − exp(−5.09406 A + 2.61188 A² − 4.31805 A³).
        for colour in [0.1f64, 0.3, 0.5, 0.8, 0.95] {
            let chiang = 1.0 - (colour * (-5.09406 + colour * (2.61188 - colour * 4.31805))).exp();
            let pixar = random_walk_albedo(colour, 0.0);
            assert!(
                (pixar - chiang).abs() < 0.02,
                "{colour}: {pixar} vs {chiang}"
            );
        }
    }

    #[test]
    fn cycles_mapping_reflects_close_to_the_colour() {
        // The fit targets a path-traced total; the dipole at the same albedo
        // reflects less where the albedo is lower (0.96, 0.85, 0.80 of the
        // colour here, where Cycles' render shows 0.96, 0.90, 0.87), never more.
        let s = skin(SubsurfaceMethod::RandomWalk, AlbedoMapping::Cycles);
        let material = s.to_material().unwrap();
        let Optics::Layers(layers) = &material.optics else {
            unreachable!()
        };
        let dipole = Dipole::new([0, 1, 2].map(|c| layers[0].medium(c)), 1.0);
        let total = dipole.total_reflectance();
        for c in 0..3 {
            let ratio = total[c] / s.colour[c];
            assert!((0.78..1.0).contains(&ratio), "channel {c}: {ratio}");
        }
        let physical = skin(SubsurfaceMethod::RandomWalk, AlbedoMapping::Physical)
            .to_material()
            .unwrap();
        let Optics::Layers(layers) = &physical.optics else {
            unreachable!()
        };
        let total = Dipole::new([0, 1, 2].map(|c| layers[0].medium(c)), 1.0).total_reflectance();
        for c in 0..3 {
            assert!((total[c] - s.colour[c]).abs() < 1e-6);
        }
    }

    #[test]
    fn the_specular_layer_weighs_only_the_view() {
        // Cycles lights the walk's exit through a plain diffuse closure: light
        // enters whole at every angle, and the layer takes 1 − F(0) once, from
        // the light leaving towards the normal. A material file's coat of the
        // same index takes 1 − F(θ) from every light instead, and the light
        // it lets out, nearly isotropic inside, leaves towards the normal as
        // ρdt(0)/ρ̄dt of the exitance.
        use crate::boundary::fresnel::dielectric_reflectance;
        use crate::boundary::surface::Surface;
        use crate::model::Model;
        let material = skin(SubsurfaceMethod::RandomWalk, AlbedoMapping::Cycles)
            .to_material()
            .unwrap();
        let surface = Surface::of(&material, Model::Dipole).unwrap();
        for cos in [0.0, 0.2, 0.7, 1.0] {
            assert_eq!(surface.entry(cos), [1.0; 3], "cos {cos}");
        }
        let exit = 1.0 - dielectric_reflectance(1.0, 1.0, 1.4);
        for t in surface.exit_at_normal() {
            assert!((t - exit).abs() < 1e-6, "{t} against {exit}");
        }
        let coated = Material {
            top_layer: crate::material::TopLayer::Diffusion,
            ..material
        };
        let boundary = Surface::of(&coated, Model::Dipole).unwrap();
        assert!(boundary.entry(0.2)[0] < 0.9 * boundary.entry(1.0)[0]);
        let Surface::Boundary { eta, roughness } = boundary else {
            panic!("a coat is a boundary: {boundary:?}")
        };
        let through = crate::boundary::rough::hemispherical_transmittance(eta, roughness);
        assert!(through < 1.0);
        for (coat, layer) in boundary
            .exit_at_normal()
            .iter()
            .zip(surface.exit_at_normal())
        {
            assert!(
                (coat * through - layer).abs() < 1e-9,
                "{coat} · {through} against {layer}"
            );
        }
    }

    #[test]
    fn specular_level_moves_the_entry_index() {
        assert!((specular_index(1.5, 0.5) - 1.5).abs() < 1e-12);
        assert_eq!(specular_index(1.5, 0.0), 1.0);
        assert!(specular_index(1.5, 1.0) > 1.5);
        assert!(specular_index(f64::NAN, f64::NAN).is_finite());
        assert!((specular_index(1.0 / 1.5, 0.5) - 1.0 / 1.5).abs() < 1e-12);
    }

    #[test]
    fn extremes_stay_finite() {
        for colour in [0.0, 1e-9, 0.5, 1.0, 7.0] {
            for radius in [0.0, 1e-9, 1.0, 1e9] {
                for method in [
                    SubsurfaceMethod::Burley,
                    SubsurfaceMethod::RandomWalk,
                    SubsurfaceMethod::RandomWalkSkin,
                ] {
                    for albedo in [AlbedoMapping::Cycles, AlbedoMapping::Physical] {
                        let s = PrincipledSubsurface {
                            colour: [colour; 3],
                            radius_mm: [radius; 3],
                            anisotropy: 0.99,
                            ..skin(method, albedo)
                        };
                        let m = s.to_material().unwrap();
                        let Optics::Layers(layers) = &m.optics else {
                            unreachable!()
                        };
                        let l = &layers[0];
                        for c in 0..3 {
                            assert!(l.sigma_a[c].is_finite() && l.sigma_a[c] >= 0.0);
                            assert!(l.sigma_s[c].is_finite() && l.sigma_s[c] >= 0.0);
                        }
                    }
                }
            }
        }
        let bad = PrincipledSubsurface {
            radius_mm: [f64::NAN, 1.0, 1.0],
            ..skin(SubsurfaceMethod::RandomWalk, AlbedoMapping::Cycles)
        };
        assert!(bad.to_material().is_err());
    }
}
