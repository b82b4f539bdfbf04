//! How much light crosses the surface into the material: the entry Fresnel
//! transmittance ρt(θ) = 1 − F(θ) of a smooth boundary, or the rough
//! boundary's ρdt(θ) of Donner & Jensen 2005 §2.4 (eq. 26) for a
//! Torrance–Sparrow surface with a Beckmann distribution.

use sssbake_profile::fresnel::dielectric_reflectance;

/// The boundary light enters through.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Boundary {
    /// A smooth dielectric: ρt = 1 − F(θ).
    Smooth,
    /// A rough dielectric with Beckmann RMS slope `roughness` (> 0).
    Rough {
        /// RMS microfacet slope m.
        roughness: f64,
    },
}

/// ρt or ρdt tabulated over the cosine of incidence.
#[derive(Clone, Debug)]
pub struct EntryTransmittance {
    table: Vec<f32>,
}

const ENTRIES: usize = 256;

impl EntryTransmittance {
    /// The table for a boundary into a material of relative index `eta`
    /// (inside over outside).
    pub fn new(eta: f64, boundary: Boundary) -> Self {
        let eta = if eta.is_finite() && eta > 0.0 {
            eta
        } else {
            1.0
        };
        let table = (0..ENTRIES)
            .map(|i| {
                let cos = i as f64 / (ENTRIES - 1) as f64;
                let value = match boundary {
                    Boundary::Smooth => 1.0 - dielectric_reflectance(cos, 1.0, eta),
                    Boundary::Rough { roughness } => 1.0 - rough_albedo(cos, eta, roughness),
                };
                value.clamp(0.0, 1.0) as f32
            })
            .collect();
        EntryTransmittance { table }
    }

    /// ρt at incidence cosine `cos` (clamped to [0, 1]), linear between
    /// table entries.
    pub fn at(&self, cos: f32) -> f32 {
        let x = cos.clamp(0.0, 1.0) * (ENTRIES - 1) as f32;
        let i = (x as usize).min(ENTRIES - 2);
        let f = x - i as f32;
        self.table[i] * (1.0 - f) + self.table[i + 1] * f
    }
}

/// Directional albedo ∫ f_r cos θi dωi of a Torrance–Sparrow surface
/// (Beckmann D, Cook–Torrance G, Fresnel F) seen from incidence cosine
/// `cos_o`, by stratified sampling of the Beckmann normals: each sample
/// weighs G·F·(o·h)/(cos θo · cos θh).
fn rough_albedo(cos_o: f64, eta: f64, roughness: f64) -> f64 {
    let m = roughness.clamp(1e-3, 10.0);
    let cos_o = cos_o.max(1e-4);
    let o = [(1.0 - cos_o * cos_o).sqrt(), 0.0, cos_o];
    let strata = 64;
    let mut sum = 0.0;
    for a in 0..strata {
        for b in 0..strata {
            let xi1 = (a as f64 + 0.5) / strata as f64;
            let xi2 = (b as f64 + 0.5) / strata as f64;
            let tan2 = -m * m * (1.0 - xi1).ln();
            let cos_h = 1.0 / (1.0 + tan2).sqrt();
            let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
            let phi = std::f64::consts::TAU * xi2;
            let h = [sin_h * phi.cos(), sin_h * phi.sin(), cos_h];
            let o_h = o[0] * h[0] + o[1] * h[1] + o[2] * h[2];
            if o_h <= 0.0 {
                continue;
            }
            let cos_i = 2.0 * o_h * h[2] - o[2];
            if cos_i <= 0.0 {
                continue;
            }
            let g = (2.0 * cos_h * cos_o / o_h)
                .min(2.0 * cos_h * cos_i / o_h)
                .min(1.0);
            let f = dielectric_reflectance(o_h, 1.0, eta);
            sum += g * f * o_h / (cos_o * cos_h);
        }
    }
    (sum / (strata * strata) as f64).clamp(0.0, 1.0)
}
