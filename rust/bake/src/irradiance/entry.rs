//! How much light crosses the surface into the material: the entry Fresnel
//! transmittance ρt(θ) = 1 − F(θ) of a smooth boundary, the rough
//! boundary's ρdt(θ) of Donner & Jensen 2005 §2.4 (eq. 26) for a
//! Torrance–Sparrow surface with a Beckmann distribution
//! ([`sssbake_profile::boundary::rough`]), or a Stam top layer's T(θi) per channel
//! ([`sssbake_profile::boundary::surface`]).

use sssbake_profile::boundary::surface::Surface;

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

/// ρt, ρdt or T(θi) tabulated over the cosine of incidence, per channel.
#[derive(Clone, Debug)]
pub struct EntryTransmittance {
    table: Vec<[f32; 3]>,
}

const ENTRIES: usize = 256;

impl EntryTransmittance {
    /// The table for a boundary into a material of relative index `eta`
    /// (inside over outside).
    pub fn new(eta: f64, boundary: Boundary) -> Self {
        Self::of_surface(&Surface::boundary(eta, boundary.roughness()))
    }

    /// The table of `surface`'s entry share.
    pub fn of_surface(surface: &Surface) -> Self {
        let table = (0..ENTRIES)
            .map(|i| {
                let cos = i as f64 / (ENTRIES - 1) as f64;
                surface.entry(cos).map(|t| t as f32)
            })
            .collect();
        EntryTransmittance { table }
    }

    /// The share entering at incidence cosine `cos` (clamped to [0, 1]),
    /// per channel, linear between table entries.
    pub fn at_rgb(&self, cos: f32) -> [f32; 3] {
        let x = cos.clamp(0.0, 1.0) * (ENTRIES - 1) as f32;
        let i = (x as usize).min(ENTRIES - 2);
        let f = x - i as f32;
        std::array::from_fn(|c| self.table[i][c] * (1.0 - f) + self.table[i + 1][c] * f)
    }

    /// [`Self::at_rgb`]'s first channel: the whole of it for a boundary,
    /// whose transmittance is the same in every channel.
    pub fn at(&self, cos: f32) -> f32 {
        self.at_rgb(cos)[0]
    }
}
