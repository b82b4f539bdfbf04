//! The analytic exitant lobe H of Donner et al. 2009 (eq. 5–8): the
//! radiance leaving one surface point, as a function of the exit direction,
//! written in elliptic coordinates centred on the lobe's peak.

use crate::boundary::fresnel::dielectric_reflectance;
use crate::numerics::quadrature::gauss_legendre;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::OnceLock;

/// Smallest and largest focal distance a fit may give (disc units).
pub const FOCUS_RANGE: (f64, f64) = (1e-3, 8.0);

/// The parameters of eq. 8 for one slice: the peak's position on the unit
/// disc (eq. 5), the focal distances a± (along the plane of symmetry) and
/// b± (across it), the falloffs k_e and k_c, and the scale k_s.
///
/// At normal incidence the plane of symmetry ŝ_p holds the normal and the
/// radial direction from the entry point, and the disc's x-axis points
/// along the radial direction, away from the entry point.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Lobe {
    /// The peak's x_d on the unit disc (eq. 5); y_d is 0 by symmetry.
    pub peak_x: f64,
    /// a⁺: focal distance for x_d ≥ peak (disc units).
    pub a_plus: f64,
    /// a⁻: focal distance for x_d < peak.
    pub a_minus: f64,
    /// b⁺: focal distance for y_d ≥ 0.
    pub b_plus: f64,
    /// b⁻: focal distance for y_d < 0.
    pub b_minus: f64,
    /// k_e: falloff in the elliptic radius μ (dimensionless).
    pub k_e: f64,
    /// k_c: falloff in the disc distance χ from the peak (dimensionless).
    pub k_c: f64,
    /// k_s: radiance over Fresnel transmittance at the peak, per unit flux
    /// entering, 1/(ℓ² sr) in mean free paths ℓ.
    pub k_s: f64,
}

impl Lobe {
    /// A lobe that sends out no light (a slice no photon reached).
    pub fn dark() -> Self {
        Self {
            peak_x: 0.0,
            a_plus: 1.0,
            a_minus: 1.0,
            b_plus: 1.0,
            b_minus: 1.0,
            k_e: 0.0,
            k_c: 0.0,
            k_s: 0.0,
        }
    }

    /// The elliptic radius μ (eq. 6–7) of the disc point (x_d, y_d):
    /// cosh(μ + iν) = x/a± + i y/b± around the peak, so 2 cosh μ is the sum
    /// of the distances from x/a + iy/b to the foci ±1.
    pub fn elliptic_mu(&self, x_d: f64, y_d: f64) -> f64 {
        let x = x_d - self.peak_x;
        let a = if x >= 0.0 { self.a_plus } else { self.a_minus };
        let b = if y_d >= 0.0 {
            self.b_plus
        } else {
            self.b_minus
        };
        let (u, v) = (x / a, y_d / b);
        let sum = (u + 1.0).hypot(v) + (u - 1.0).hypot(v);
        (0.5 * sum).max(1.0).acosh()
    }

    /// The lobe without its Fresnel factor: k_s e^{−k_e μ − k_c χ}.
    pub fn shape(&self, x_d: f64, y_d: f64) -> f64 {
        let chi = (x_d - self.peak_x).hypot(y_d);
        let value = self.k_s * (-self.k_e * self.elliptic_mu(x_d, y_d) - self.k_c * chi).exp();
        if value.is_finite() {
            value.max(0.0)
        } else {
            0.0
        }
    }

    /// H (eq. 8): radiance in 1/(ℓ² sr) per unit flux entering, leaving in
    /// the direction at polar angle `theta_o` (rad from the normal) and
    /// azimuth `phi_o` (rad from the radial direction), through a smooth
    /// boundary of relative index `eta`.
    pub fn radiance(&self, theta_o: f64, phi_o: f64, eta: f64) -> f64 {
        let rho = theta_o / FRAC_PI_2;
        let (s, c) = phi_o.sin_cos();
        self.shape(rho * c, rho * s) * exit_transmittance(theta_o.cos(), eta)
    }

    /// Radiant exitance ∫ H cos θ_o dω over the hemisphere, 1/ℓ² per unit
    /// flux entering: the radial profile R(r) at this slice's radius.
    pub fn exitance(&self, eta: f64) -> f64 {
        if self.k_s <= 0.0 {
            return 0.0;
        }
        let rule = hemisphere_rule();
        rule.iter()
            .map(|&(theta, phi, w)| w * self.radiance(theta, phi, eta) * theta.cos())
            .sum()
    }
}

/// Fresnel transmittance F_t from inside a medium of relative index `eta`
/// to the outside, for light leaving at outside cosine `cos_o`: by
/// reciprocity, one minus the reflectance seen from outside at that angle.
pub fn exit_transmittance(cos_o: f64, eta: f64) -> f64 {
    1.0 - dielectric_reflectance(cos_o, 1.0, eta)
}

/// Nodes (θ, φ) and weights sin θ dθ dφ of a product Gauss rule over the
/// hemisphere, φ over the whole circle.
fn hemisphere_rule() -> &'static [(f64, f64, f64)] {
    static RULE: OnceLock<Vec<(f64, f64, f64)>> = OnceLock::new();
    RULE.get_or_init(|| {
        let theta_rule = gauss_legendre(48);
        let phi_rule = gauss_legendre(24);
        let mut nodes = Vec::new();
        for &(t, wt) in &theta_rule {
            let theta = FRAC_PI_2 * 0.5 * (t + 1.0);
            let w_theta = FRAC_PI_2 * 0.5 * wt * theta.sin();
            // φ in four quarters, so the kinks at the axes fall on edges.
            for quarter in 0..4 {
                for &(p, wp) in &phi_rule {
                    let phi = FRAC_PI_2 * (quarter as f64 + 0.5 * (p + 1.0));
                    nodes.push((theta, phi, w_theta * FRAC_PI_2 * 0.5 * wp));
                }
            }
        }
        debug_assert!((nodes.iter().map(|n| n.2).sum::<f64>() - 2.0 * PI).abs() < 1e-9);
        nodes
    })
}
