//! How much light crosses the surface into the material: the entry Fresnel
//! transmittance ρt(θ) = 1 − F(θ) of a smooth boundary, or the rough
//! boundary's ρdt(θ) of Donner & Jensen 2005 §2.4 (eq. 26) for a
//! Torrance–Sparrow surface with a Beckmann distribution
//! ([`sssbake_profile::rough`]).

use sssbake_profile::rough::diffuse_transmittance;

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

impl Boundary {
    /// A material's surface of RMS facet slope `roughness`: smooth at 0.
    pub fn of(roughness: f64) -> Self {
        if roughness > 0.0 {
            Boundary::Rough { roughness }
        } else {
            Boundary::Smooth
        }
    }

    /// The RMS facet slope; 0 when smooth.
    pub fn roughness(self) -> f64 {
        match self {
            Boundary::Smooth => 0.0,
            Boundary::Rough { roughness } => roughness,
        }
    }
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
                diffuse_transmittance(cos, eta, boundary.roughness()) as f32
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
