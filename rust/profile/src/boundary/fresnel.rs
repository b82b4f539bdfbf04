//! Fresnel reflectance of a smooth dielectric boundary and its diffuse averages.
//!
//! `eta` is always the relative index n_inside / n_outside of the side the
//! light travels in over the side it would enter.

use crate::numerics::quadrature::{gauss_legendre, integrate};
use std::sync::OnceLock;

/// Unpolarised Fresnel reflectance for light travelling in a medium of index
/// `n_i` hitting a boundary to a medium of index `n_t`, at incidence cosine
/// `cos_i` (in [0, 1]). Returns 1 under total internal reflection.
pub fn dielectric_reflectance(cos_i: f64, n_i: f64, n_t: f64) -> f64 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let ratio = n_i / n_t;
    let sin2_t = ratio * ratio * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (n_i * cos_i - n_t * cos_t) / (n_i * cos_i + n_t * cos_t);
    let rp = (n_t * cos_i - n_i * cos_t) / (n_t * cos_i + n_i * cos_t);
    let r = 0.5 * (rs * rs + rp * rp);
    if r.is_finite() {
        r.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// Internal diffuse reflectance F_dr(η): the cosine-weighted hemispherical
/// average of the Fresnel reflectance seen from inside a medium whose index
/// is η times that outside (Mikkelsen eq. 21, with the 1/π).
pub fn diffuse_reflectance_exact(eta: f64) -> f64 {
    static RULE: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    let rule = RULE.get_or_init(|| gauss_legendre(48));
    if !(eta.is_finite() && eta > 0.0) || (eta - 1.0).abs() < 1e-12 {
        return 0.0;
    }
    // F_dr = ∫_0^1 F(μ) 2μ dμ = ∫_0^1 F(√t) dt. Beyond the critical angle
    // F = 1, which contributes μ_c² exactly. The rest has a square-root kink
    // at t = μ_c²; substituting t = μ_c² + (1 − μ_c²)u² makes it smooth.
    let mu_c2 = if eta > 1.0 {
        1.0 - 1.0 / (eta * eta)
    } else {
        0.0
    };
    let span = 1.0 - mu_c2;
    let smooth = integrate(
        |u| dielectric_reflectance((mu_c2 + span * u * u).sqrt(), eta, 1.0) * 2.0 * span * u,
        0.0,
        1.0,
        rule,
    );
    (mu_c2 + smooth).clamp(0.0, 1.0)
}

/// The Egan–Hilgeman polynomial fit of F_dr used by Jensen et al. 2001 and
/// Donner & Jensen 2005 (eq. 8). Outside about η ∈ [0.26, 3.8] the polynomial
/// leaves [0, 1]; the result is clamped there.
pub fn diffuse_reflectance_fit(eta: f64) -> f64 {
    let f = if eta < 1.0 {
        -0.4399 + 0.7099 / eta - 0.3319 / (eta * eta) + 0.0636 / (eta * eta * eta)
    } else {
        -1.4399 / (eta * eta) + 0.7099 / eta + 0.6681 + 0.0636 * eta
    };
    if f.is_finite() {
        f.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The boundary constant A = (1 + F_dr) / (1 − F_dr) for relative index η,
/// using the exact F_dr.
pub fn boundary_a(eta: f64) -> f64 {
    let fdr = diffuse_reflectance_exact(eta).min(1.0 - 1e-12);
    (1.0 + fdr) / (1.0 - fdr)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_matches_closed_form() {
        let r = dielectric_reflectance(1.0, 1.0, 1.5);
        assert!((r - 0.04).abs() < 1e-12);
        assert_eq!(dielectric_reflectance(0.1, 1.5, 1.0), 1.0);
        assert_eq!(dielectric_reflectance(0.7, 1.3, 1.3), 0.0);
    }

    #[test]
    fn exact_and_fitted_fdr_agree_where_the_fit_is_valid() {
        for eta in [0.5, 0.8, 1.1, 1.3, 1.4, 1.6, 2.0, 2.5] {
            let exact = diffuse_reflectance_exact(eta);
            let fit = diffuse_reflectance_fit(eta);
            assert!(
                (exact - fit).abs() < 0.012,
                "eta {eta}: exact {exact}, fit {fit}"
            );
        }
    }

    #[test]
    fn fdr_stays_in_unit_interval_at_extremes() {
        for eta in [1e-3, 0.1, 0.26, 1.0, 1.0 + 1e-9, 3.8, 10.0, 1e3] {
            for f in [diffuse_reflectance_exact(eta), diffuse_reflectance_fit(eta)] {
                assert!((0.0..=1.0).contains(&f), "eta {eta}: {f}");
            }
            assert!(boundary_a(eta).is_finite() && boundary_a(eta) >= 1.0);
        }
        assert_eq!(diffuse_reflectance_exact(1.0), 0.0);
    }
}
