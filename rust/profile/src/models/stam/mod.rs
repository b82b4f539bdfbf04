//! Stam 2001: plane-parallel light transport in one layer bounded by
//! smooth or rough dielectric faces, by discrete ordinates.
//!
//! A layer of single-scattering albedo Ω, optical depth τ (finite, or
//! infinite for a semi-infinite layer), Henyey–Greenstein g and relative
//! index η against air above and below, whose faces are smooth or have
//! Beckmann facets of RMS slope m. The radiance is expanded in a cosine
//! series in azimuth (eq. 7); each mode is discretised on a double Gauss
//! rule of ordinates ([`ordinates`]), scattering by HG's Legendre series
//! with δ-M scaling ([`phase`]), solved by the eigen-structure of the
//! transfer matrix ([`eigen`]) and a boundary system with scaled
//! exponentials ([`solve`]); the faces enter as discrete BRDF and BTDF
//! operators ([`boundary`], [`microfacet`]).
//!
//! The outputs are the layer's BRDF and BTDF (faces and the light beneath
//! them together) on the outside ordinates, per azimuthal mode, and the
//! total reflectance R(θi) and transmittance T(θi) for light arriving from
//! each outside ordinate. Light is collimated: a unit irradiance (on the
//! layer's plane) from ordinate e is the radiance 1/(2π we μe) in the cell
//! of e in mode 0 and twice that in the others (the cosine series of a
//! delta in azimuth), so each column of the matrices is the response to a
//! collimated beam and R(θe) = 2π Σo wo μo BRDF₀(o, e).
//!
//! Albedo 1 makes mode 0's slowest eigenvalue 0 and the two solutions it
//! pairs coincide; the albedo is held at most 1 − 10⁻⁹ (Stam held it at
//! 1 − 10⁻⁶), which absorbs about 10⁻⁹ per scattering event.

pub mod boundary;
pub mod contact;
pub mod eigen;
pub mod epidermis;
pub mod material;
pub mod microfacet;
pub mod ordinates;
pub mod phase;
pub mod solve;
pub mod topped;

use crate::boundary::rough::MAX_ROUGHNESS;
use nalgebra::DMatrix;
use ordinates::Ordinates;
use std::f64::consts::PI;

/// The highest albedo solved; Ω = 1 is solved as this.
pub const MAX_ALBEDO: f64 = 1.0 - 1e-9;

/// Ordinates per half range by default: 32 (Stam used 24, and 30 for the
/// smoothest rough faces); the phase function keeps 16 Legendre moments
/// when the rule is split at the critical cosine.
pub const DEFAULT_ORDINATES: usize = 32;

/// One plane-parallel layer between air above and below.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StamLayer {
    /// Single-scattering albedo Ω = σs/σt, in [0, 1].
    pub albedo: f64,
    /// Optical depth τ = σt·thickness (dimensionless, > 0; infinite for a
    /// semi-infinite layer).
    pub optical_depth: f64,
    /// Henyey–Greenstein mean cosine g, in (−1, 1).
    pub g: f64,
    /// Index of the layer over that of air, > 0.
    pub eta: f64,
    /// RMS slope m of the faces' Beckmann facets, in [0, 1]; 0 is smooth.
    pub roughness: f64,
}

/// A layer the solver cannot take, with what is wrong.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("stam layer: {0}")]
pub struct StamError(pub String);

/// The layer's response on the outside ordinates.
#[derive(Clone, Debug)]
pub struct StamResponse {
    /// Cosines of the outside ordinates (incidence and exit), increasing.
    pub cosines: Vec<f64>,
    /// Their weights on [0, 1] (Σ w μ = 1/2).
    pub weights: Vec<f64>,
    /// BRDF cosine coefficients per mode k: brdf[k][(o, e)] in 1/sr, the
    /// radiance reflected towards ordinate o per unit irradiance from e;
    /// f(o, e, Δφ) = Σk brdf[k][(o, e)] cos kΔφ. Includes the faces'
    /// own reflection (for smooth faces a delta on the diagonal cell).
    pub brdf: Vec<DMatrix<f64>>,
    /// The BTDF likewise, for light leaving the bottom face into air (Δφ
    /// measured from the incident azimuth; the straight-through beam is
    /// included, a delta on the diagonal cell for smooth faces).
    pub btdf: Vec<DMatrix<f64>>,
    /// Total reflectance R(θe) per incidence ordinate (faces included).
    pub reflectance: Vec<f64>,
    /// Total transmittance T(θe) per incidence ordinate.
    pub transmittance: Vec<f64>,
    /// The share the top face reflects by itself, per incidence ordinate.
    pub surface_reflectance: Vec<f64>,
}

impl StamResponse {
    /// The BRDF (1/sr) towards ordinate `o` from ordinate `e` with azimuth
    /// difference `delta_phi` (radians; 0 is the forward, specular side).
    /// The cosine series is truncated, so next to a narrow lobe it rings
    /// below zero; those values are returned as 0.
    pub fn brdf_at(&self, o: usize, e: usize, delta_phi: f64) -> f64 {
        series(&self.brdf, o, e, delta_phi)
    }

    /// The BTDF (1/sr) likewise.
    pub fn btdf_at(&self, o: usize, e: usize, delta_phi: f64) -> f64 {
        series(&self.btdf, o, e, delta_phi)
    }
}

fn series(modes: &[DMatrix<f64>], o: usize, e: usize, delta_phi: f64) -> f64 {
    let sum: f64 = modes
        .iter()
        .enumerate()
        .filter(|(_, m)| o < m.nrows() && e < m.ncols())
        .map(|(k, m)| m[(o, e)] * (k as f64 * delta_phi).cos())
        .sum();
    if sum.is_finite() { sum.max(0.0) } else { 0.0 }
}

/// How finely to solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StamSettings {
    /// Ordinates per half range (even; half each side of the critical
    /// cosine when η > 1).
    pub ordinates: usize,
    /// Azimuthal modes solved: 1 gives the totals R and T exactly (the
    /// higher modes integrate to zero over azimuth); `None`, twice the
    /// ordinates, as Stam (after Jin & Stamnes) took, which the BRDF's
    /// narrow lobes (the faces' own, the straight-through beam) need.
    pub modes: Option<usize>,
}

impl Default for StamSettings {
    fn default() -> Self {
        Self {
            ordinates: DEFAULT_ORDINATES,
            modes: None,
        }
    }
}

impl StamLayer {
    /// Checks the parameters, naming the one out of range.
    pub fn validate(&self) -> Result<(), StamError> {
        let bad = |what: &str| Err(StamError(what.to_string()));
        if !(0.0..=1.0).contains(&self.albedo) {
            return bad(&format!("albedo must lie in [0, 1], got {}", self.albedo));
        }
        if self.optical_depth.is_nan() || self.optical_depth <= 0.0 {
            return bad(&format!(
                "optical depth must be positive (or infinite), got {}",
                self.optical_depth
            ));
        }
        if !(self.g > -1.0 && self.g < 1.0) {
            return bad(&format!(
                "g must lie strictly between -1 and 1, got {}",
                self.g
            ));
        }
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return bad(&format!(
                "eta must be a positive finite index, got {}",
                self.eta
            ));
        }
        if !(0.0..=MAX_ROUGHNESS).contains(&self.roughness) {
            return bad(&format!(
                "roughness must lie in [0, {MAX_ROUGHNESS}], got {}",
                self.roughness
            ));
        }
        Ok(())
    }

    /// Solves the layer.
    pub fn solve(&self, settings: &StamSettings) -> Result<StamResponse, StamError> {
        self.validate()?;
        let ordinates = Ordinates::new(settings.ordinates, self.eta);
        // As many Legendre moments as the rule keeps orthogonal (it
        // integrates their products exactly), so the discrete scattering
        // conserves energy (mode 0 sums to Ω exactly) and never amplifies
        // (its eigenvalues are Ωχₙ ≤ Ω).
        let terms = ordinates.exact_degree().div_ceil(2);
        let scattering = phase::delta_m(self.g, self.albedo, terms);
        let scattering = phase::ScaledScattering {
            albedo: scattering.albedo.min(MAX_ALBEDO),
            ..scattering
        };
        let depth = self.optical_depth * scattering.depth_factor;
        let modes = settings.modes.unwrap_or(2 * ordinates.inside.len()).max(1);
        let smooth = self.roughness == 0.0 || (self.eta - 1.0).abs() < 1e-9;
        let boundaries = if smooth {
            boundary::smooth(&ordinates, modes)
        } else {
            boundary::rough(&ordinates, self.roughness, modes)
        };
        let outside = ordinates.outside.len();
        let mut brdf = Vec::with_capacity(modes);
        let mut btdf = Vec::with_capacity(modes);
        let mut surface = vec![0.0; outside];
        for (k, faces) in boundaries.iter().enumerate() {
            let (same, opposite) = phase::mode_kernels(k, &scattering, &ordinates.inside);
            let eigen = eigen::solve_mode(
                &same,
                &opposite,
                &ordinates.inside,
                &ordinates.inside_weights,
            )
            .map_err(|e| StamError(format!("mode {k}: {e}")))?;
            let delta = if k == 0 { 1.0 } else { 2.0 };
            let incident = DMatrix::from_fn(outside, outside, |o, e| {
                if o == e {
                    delta / (2.0 * PI * ordinates.outside_weights[e] * ordinates.outside[e])
                } else {
                    0.0
                }
            });
            if k == 0 {
                let by_face = &faces.reflect_outside * &incident;
                surface = flux(&ordinates, &by_face);
            }
            let solution = solve::solve_mode(&eigen, faces, depth, &incident)
                .map_err(|e| StamError(format!("mode {k}: {e}")))?;
            brdf.push(solution.reflected);
            btdf.push(solution.transmitted);
        }
        let reflectance = flux(&ordinates, &brdf[0]);
        let transmittance = flux(&ordinates, &btdf[0]);
        Ok(StamResponse {
            cosines: ordinates.outside.clone(),
            weights: ordinates.outside_weights.clone(),
            brdf,
            btdf,
            reflectance,
            transmittance,
            surface_reflectance: surface,
        })
    }
}

/// 2π Σo wo μo L(o, e) per column e: the flux a mode-0 radiance carries.
fn flux(ordinates: &Ordinates, radiance: &DMatrix<f64>) -> Vec<f64> {
    (0..radiance.ncols())
        .map(|e| {
            let sum: f64 = (0..radiance.nrows())
                .map(|o| ordinates.outside_weights[o] * ordinates.outside[o] * radiance[(o, e)])
                .sum();
            (2.0 * PI * sum).max(0.0)
        })
        .collect()
}
