//! The discrete boundary operators of Stam 2001 §3.2 and appendix D, per
//! azimuthal mode k: matrices L with u_out(μn) = Σm L(n, m) u_in(μm) for
//! the k-th cosine coefficient of the radiance, so that
//! L(n, m) = wm μm ∫₀^{2π} ρ(μm, 0; μn, ψ) cos kψ dψ for a BRDF or BTDF ρ.
//!
//! Both faces of the layer are against air and equally rough, so the
//! bottom face's operators are the top face's (mirrored in z).

use super::microfacet::{self, Direction};
use super::ordinates::Ordinates;
use crate::boundary::fresnel::dielectric_reflectance;
use crate::numerics::quadrature::gauss_legendre;
use nalgebra::DMatrix;
use std::f64::consts::PI;

/// Points of the Gauss rule over the azimuth ψ ∈ [0, π] of a rough
/// boundary's lobes.
const AZIMUTH_POINTS: usize = 96;

/// One mode's boundary operators (E outside ordinates, M inside).
#[derive(Clone, Debug)]
pub struct ModeBoundary {
    /// R₁₂, E×E: air → air, reflected off the face.
    pub reflect_outside: DMatrix<f64>,
    /// T₁₂, M×E: air → into the layer.
    pub transmit_in: DMatrix<f64>,
    /// R₂₁ (and R₂₃), M×M: inside → back inside.
    pub reflect_inside: DMatrix<f64>,
    /// T₂₁ (and T₂₃), E×M: inside → out into air.
    pub transmit_out: DMatrix<f64>,
}

/// Smooth Fresnel faces: every operator is diagonal on matched ordinates
/// (reflection keeps μ; refraction maps the cone's ordinates onto the
/// outside ones) and the same in every mode. Radiance entering is
/// multiplied by η²(1 − F), leaving by (1 − F)/η².
pub fn smooth(ordinates: &Ordinates, modes: usize) -> Vec<ModeBoundary> {
    let (m, e) = (ordinates.inside.len(), ordinates.outside.len());
    let eta = ordinates.eta;
    let cone = ordinates.first_in_cone;
    let fresnel_inside: Vec<f64> = ordinates
        .inside
        .iter()
        .map(|&mu| dielectric_reflectance(mu, eta, 1.0))
        .collect();
    let reflect_inside =
        DMatrix::from_fn(m, m, |n, j| if n == j { fresnel_inside[n] } else { 0.0 });
    let reflect_outside = DMatrix::from_fn(e, e, |n, j| {
        if n == j {
            dielectric_reflectance(ordinates.outside[n], 1.0, eta)
        } else {
            0.0
        }
    });
    let transmit_in = DMatrix::from_fn(m, e, |n, j| {
        if n == cone + j {
            eta * eta * (1.0 - fresnel_inside[n])
        } else {
            0.0
        }
    });
    let transmit_out = DMatrix::from_fn(e, m, |n, j| {
        if j == cone + n {
            (1.0 - fresnel_inside[j]) / (eta * eta)
        } else {
            0.0
        }
    });
    let mode = ModeBoundary {
        reflect_outside,
        transmit_in,
        reflect_inside,
        transmit_out,
    };
    vec![mode; modes]
}

/// Rough faces of RMS facet slope `roughness` (Stam §4, see
/// [`microfacet`]), projected on the modes by a Gauss rule in azimuth.
pub fn rough(ordinates: &Ordinates, roughness: f64, modes: usize) -> Vec<ModeBoundary> {
    let eta = ordinates.eta;
    let (inside, inside_w) = (&ordinates.inside, &ordinates.inside_weights);
    let (outside, outside_w) = (&ordinates.outside, &ordinates.outside_weights);
    let rule: Vec<(f64, f64)> = gauss_legendre(AZIMUTH_POINTS)
        .into_iter()
        .map(|(x, w)| (0.5 * PI * (x + 1.0), 0.5 * PI * w))
        .collect();
    // Projects ρ(μm → μn, ψ) on cos kψ for every k, times wm μm.
    let project = |from: &[f64], from_w: &[f64], to: &[f64], reflect: bool, n_i: f64, n_t: f64| {
        let mut out = vec![DMatrix::zeros(to.len(), from.len()); modes];
        for (m, (&mu_m, &w_m)) in from.iter().zip(from_w).enumerate() {
            let i: Direction = [-(1.0 - mu_m * mu_m).max(0.0).sqrt(), 0.0, mu_m];
            for (n, &mu_n) in to.iter().enumerate() {
                let s_n = (1.0 - mu_n * mu_n).max(0.0).sqrt();
                let mut coefficients = vec![0.0; modes];
                for &(psi, w) in &rule {
                    let z = if reflect { mu_n } else { -mu_n };
                    let o: Direction = [s_n * psi.cos(), s_n * psi.sin(), z];
                    let value = if reflect {
                        microfacet::reflection(i, o, n_i, n_t, roughness)
                    } else {
                        microfacet::transmission(i, o, n_i, n_t, roughness)
                    };
                    if value == 0.0 {
                        continue;
                    }
                    for (k, c) in coefficients.iter_mut().enumerate() {
                        // ρ is even in ψ: ∫₀^{2π} = 2∫₀^π.
                        *c += 2.0 * w * value * (k as f64 * psi).cos();
                    }
                }
                for (k, c) in coefficients.into_iter().enumerate() {
                    out[k][(n, m)] = w_m * mu_m * c;
                }
            }
        }
        out
    };
    let mut reflect_outside = project(outside, outside_w, outside, true, 1.0, eta);
    let mut transmit_in = project(outside, outside_w, inside, false, 1.0, eta);
    let mut reflect_inside = project(inside, inside_w, inside, true, eta, 1.0);
    let mut transmit_out = project(inside, inside_w, outside, false, eta, 1.0);
    conserve(
        &mut reflect_outside,
        &mut transmit_in,
        (outside, outside_w),
        (inside, inside_w),
    );
    conserve(
        &mut reflect_inside,
        &mut transmit_out,
        (inside, inside_w),
        (outside, outside_w),
    );
    (0..modes)
        .map(|k| ModeBoundary {
            reflect_outside: reflect_outside[k].clone(),
            transmit_in: transmit_in[k].clone(),
            reflect_inside: reflect_inside[k].clone(),
            transmit_out: transmit_out[k].clone(),
        })
        .collect()
}

/// Scales each incidence column of a face's reflection and transmission
/// (in every mode alike) so that the flux it reflects and transmits sums
/// to the flux arriving. A dielectric face absorbs nothing, but the
/// single-scattering microfacet model loses the light its shadowing term
/// blocks (light that in fact scatters again among the facets), and a rule
/// of ordinates under-resolves lobes narrower than its spacing; both would
/// otherwise create or destroy light at every bounce. This keeps the lobes'
/// shapes and returns the lost light along them.
fn conserve(
    reflect: &mut [DMatrix<f64>],
    transmit: &mut [DMatrix<f64>],
    (same_mu, same_w): (&[f64], &[f64]),
    (other_mu, other_w): (&[f64], &[f64]),
) {
    for m in 0..reflect[0].ncols() {
        let arriving = same_w[m] * same_mu[m];
        let leaving: f64 = (0..same_mu.len())
            .map(|n| same_w[n] * same_mu[n] * reflect[0][(n, m)])
            .chain((0..other_mu.len()).map(|n| other_w[n] * other_mu[n] * transmit[0][(n, m)]))
            .sum();
        let albedo = leaving / arriving;
        if !(albedo.is_finite() && albedo > 1e-12) {
            continue;
        }
        for k in 0..reflect.len() {
            reflect[k].column_mut(m).scale_mut(1.0 / albedo);
            transmit[k].column_mut(m).scale_mut(1.0 / albedo);
        }
    }
}
