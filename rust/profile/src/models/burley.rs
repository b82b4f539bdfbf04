//! Christensen & Burley 2015 normalized diffusion, parameterised as Blender's
//! Cycles does (a colour and a radius), so Blender materials can be matched.

use crate::profile::Profile;
use crate::{Rgb, rgb_map};
use std::f64::consts::PI;

/// Which of the paper's fits gives the shape factor s from the albedo A.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScalingFit {
    /// Searchlight configuration, d from the diffuse mean free path 1/σtr:
    /// s = 1.85 − A + 7|A − 0.8|³.
    SearchlightDiffuseMfp,
    /// Diffuse surface transmission, diffuse mean free path (Cycles):
    /// s = 1.9 − A + 3.5(A − 0.8)².
    DiffuseDiffuseMfp,
    /// Searchlight configuration, d from the mean free path 1/σt:
    /// s = 3.5 + 100(A − 0.33)⁴.
    SearchlightMfp,
}

/// The shape factor s(A) of the chosen fit.
pub fn scaling_factor(fit: ScalingFit, albedo: f64) -> f64 {
    let a = albedo.clamp(0.0, 1.0);
    match fit {
        ScalingFit::SearchlightDiffuseMfp => 1.85 - a + 7.0 * (a - 0.8).abs().powi(3),
        ScalingFit::DiffuseDiffuseMfp => 1.9 - a + 3.5 * (a - 0.8).powi(2),
        ScalingFit::SearchlightMfp => 3.5 + 100.0 * (a - 0.33).powi(4),
    }
}

/// R(r) = A·(e^{−r/d} + e^{−r/3d}) / (8π d r) per channel; ∫2πrR dr = A.
#[derive(Clone, Debug, PartialEq)]
pub struct Burley {
    /// Surface albedo A per channel (the total diffuse reflectance).
    pub albedo: Rgb,
    /// Shape parameter d per channel, mm.
    pub d: Rgb,
}

impl Burley {
    /// From albedo and shape parameter d (mm), clamped to the physical range.
    pub fn new(albedo: Rgb, d: Rgb) -> Self {
        Self {
            albedo: albedo.map(|a| {
                if a.is_finite() {
                    a.clamp(0.0, 1.0)
                } else {
                    0.0
                }
            }),
            d: d.map(|x| {
                if x.is_finite() && x > 0.0 {
                    x.clamp(1e-12, 1e12)
                } else {
                    1e-12
                }
            }),
        }
    }

    /// As Cycles' Christensen–Burley: `colour` is the albedo and `radius`
    /// (mm; Subsurface Radius × Subsurface Scale in scene units converted to
    /// mm) becomes the mean free path l = radius/(4π), with d = l/s(A) by
    /// the diffuse-transmission fit.
    pub fn from_cycles(colour: Rgb, radius_mm: Rgb) -> Self {
        let d = rgb_map(|c| {
            radius_mm[c] / (4.0 * PI) / scaling_factor(ScalingFit::DiffuseDiffuseMfp, colour[c])
        });
        Self::new(colour, d)
    }

    /// From albedo and a mean free path (mm) with one of the paper's fits.
    pub fn from_mean_free_path(albedo: Rgb, mfp_mm: Rgb, fit: ScalingFit) -> Self {
        Self::new(
            albedo,
            rgb_map(|c| mfp_mm[c] / scaling_factor(fit, albedo[c])),
        )
    }

    /// The Burley profile with the same total reflectance and the same mean
    /// radius ∫r·2πrR dr / ∫2πrR dr as `profile` (for Burley the mean radius
    /// is 2.5 d).
    pub fn matching(profile: &dyn Profile) -> Self {
        let total = profile.total_reflectance();
        let reach = profile.d_max(1e-7);
        let d = rgb_map(|c| {
            let samples = 2000;
            let (lo, hi) = (reach[c] * 1e-7, reach[c]);
            if !(hi > 0.0 && hi.is_finite()) {
                return 1e-12;
            }
            let h = (hi / lo).ln() / samples as f64;
            let (mut moment, mut mass) = (0.0, 0.0);
            for i in 0..=samples {
                let r = lo * (i as f64 * h).exp();
                let w = if i == 0 || i == samples { 0.5 } else { 1.0 };
                let density = 2.0 * PI * r * r * profile.reflectance(r)[c] * h * w;
                mass += density;
                moment += r * density;
            }
            if mass > 0.0 {
                moment / mass / 2.5
            } else {
                1e-12
            }
        });
        Self::new(total, d)
    }
}

impl Profile for Burley {
    fn model(&self) -> &'static str {
        "burley"
    }

    /// R(0) is infinite (the profile goes as 1/r); radii below d·10⁻⁶ are
    /// evaluated at d·10⁻⁶ so the result stays finite.
    fn reflectance(&self, r: f64) -> Rgb {
        rgb_map(|c| {
            let d = self.d[c];
            let r = r.max(1e-6 * d);
            self.albedo[c] * ((-r / d).exp() + (-r / (3.0 * d)).exp()) / (8.0 * PI * d * r)
        })
    }

    fn total_reflectance(&self) -> Rgb {
        self.albedo
    }

    /// e^{−r/d}/r transforms to 2π/√(k² + 1/d²), so
    /// R̂(k) = A/4·(1/√(1 + (kd)²) + 3/√(1 + (3kd)²)).
    fn reflectance_spectrum(&self, k: f64) -> Option<Rgb> {
        Some(rgb_map(|c| {
            let kd = k * self.d[c];
            0.25 * self.albedo[c]
                * (1.0 / (1.0 + kd * kd).sqrt() + 3.0 / (1.0 + 9.0 * kd * kd).sqrt())
        }))
    }

    fn enclosed_reflectance(&self, r: f64) -> Rgb {
        rgb_map(|c| {
            let d = self.d[c];
            self.albedo[c] * (1.0 - 0.25 * (-r / d).exp() - 0.75 * (-r / (3.0 * d)).exp())
        })
    }

    fn length_scale(&self) -> Rgb {
        self.d.map(|d| 2.5 * d)
    }
}
