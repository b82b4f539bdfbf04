//! Rough dielectric boundaries (Donner & Jensen 2005 §2.4): a
//! Torrance–Sparrow surface (eq. 23) of Beckmann facets with RMS slope m,
//! Cook–Torrance shadowing and the Fresnel reflectance of each facet.
//!
//! Two averages of it replace the smooth boundary's Fresnel terms in the
//! diffusion models:
//! - ρdt(θ) = 1 − ∫ f_r cos θi dωi seen from outside (eq. 26): the share of
//!   light from direction θ that crosses into the material, and the share
//!   of the diffuse light inside that leaves towards θ (eq. 25);
//! - ρd, the same BRDF's reflectance seen from inside, averaged over
//!   diffuse incidence: the internal diffuse reflectance that sets the
//!   boundary constant A = (1 + ρd)/(1 − ρd) (eq. 24). As m → 0 it is the
//!   smooth boundary's F_dr.
//!
//! Roughness m = 0 is the smooth boundary, evaluated in closed form.

use crate::boundary::fresnel::{dielectric_reflectance, diffuse_reflectance_exact};
use crate::numerics::quadrature::{gauss_legendre, integrate};
use std::sync::OnceLock;

/// The roughest surface a material may give: RMS facet slope 1 (facets at
/// 45° on average), the roughest of Donner & Jensen's figure 7.
pub const MAX_ROUGHNESS: f64 = 1.0;

/// Strata per axis of the facet-normal sampling (64² normals per direction).
const STRATA: usize = 64;

/// Directional albedo ∫ f_r(ωo, ωi) cos θi dωi of the rough boundary for
/// light in a medium of index `n_i` meeting one of index `n_t` at
/// incidence cosine `cos_o`, with RMS facet slope `roughness` (> 0).
/// Facets beyond the critical angle reflect everything. Evaluated by
/// stratified sampling of the Beckmann normals h (density D(h) cos θh),
/// each weighing G·F·(o·h)/(cos θo cos θh); energy the shadowing term
/// removes counts as not reflected, as the paper's eq. 26 assumes.
pub fn directional_albedo(cos_o: f64, n_i: f64, n_t: f64, roughness: f64) -> f64 {
    let m = roughness.clamp(1e-4, 10.0);
    let cos_o = cos_o.clamp(1e-4, 1.0);
    let o = [(1.0 - cos_o * cos_o).sqrt(), 0.0, cos_o];
    let mut sum = 0.0;
    for a in 0..STRATA {
        let xi1 = (a as f64 + 0.5) / STRATA as f64;
        let tan2 = -m * m * (1.0 - xi1).ln();
        let cos_h = 1.0 / (1.0 + tan2).sqrt();
        let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
        for b in 0..STRATA {
            let phi = std::f64::consts::TAU * (b as f64 + 0.5) / STRATA as f64;
            let h = [sin_h * phi.cos(), sin_h * phi.sin(), cos_h];
            let o_h = o[0] * h[0] + o[2] * h[2];
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
            let f = dielectric_reflectance(o_h, n_i, n_t);
            sum += g * f * o_h / (cos_o * cos_h);
        }
    }
    let albedo = sum / (STRATA * STRATA) as f64;
    if albedo.is_finite() {
        albedo.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// ρdt(θ) of eq. 26: the share of light arriving from outside at incidence
/// cosine `cos` that crosses a boundary into a material of relative index
/// `eta` (inside over outside), for RMS facet slope `roughness`; 0 is the
/// smooth boundary's 1 − F(θ).
pub fn diffuse_transmittance(cos: f64, eta: f64, roughness: f64) -> f64 {
    let value = if roughness > 0.0 {
        1.0 - directional_albedo(cos, 1.0, eta, roughness)
    } else {
        1.0 - dielectric_reflectance(cos, 1.0, eta)
    };
    value.clamp(0.0, 1.0)
}

/// The hemispherical transmittance from outside, 2∫_0^1 ρdt(μ) μ dμ: the
/// share of diffuse light from outside that crosses into a material of
/// relative index `eta` with RMS facet slope `roughness`; for a smooth
/// boundary 1 − F_dr(1/η), which reciprocity makes η²(1 − F_dr(η)).
pub fn hemispherical_transmittance(eta: f64, roughness: f64) -> f64 {
    static RULE: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    let rule = RULE.get_or_init(|| gauss_legendre(32));
    // ∫_0^1 ρdt(√t) dt: smooth in t from outside (no critical angle).
    let total = integrate(
        |t| diffuse_transmittance(t.max(0.0).sqrt(), eta, roughness),
        0.0,
        1.0,
        rule,
    );
    total.clamp(0.0, 1.0)
}

/// ρd of eq. 24: the rough boundary's reflectance seen from inside a
/// material of relative index `eta`, averaged over diffuse (cosine-weighted)
/// incidence, ∫_0^1 albedo(μ) 2μ dμ; for `roughness` 0, the exact F_dr.
pub fn diffuse_reflectance(eta: f64, roughness: f64) -> f64 {
    static RULE: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    if !(eta.is_finite() && eta > 0.0) {
        return 0.0;
    }
    if roughness <= 0.0 || (eta - 1.0).abs() < 1e-12 {
        return diffuse_reflectance_exact(eta);
    }
    let rule = RULE.get_or_init(|| gauss_legendre(24));
    let albedo = |t: f64| directional_albedo(t.max(0.0).sqrt(), eta, 1.0, roughness);
    // ∫_0^1 albedo(√t) dt. Near the critical cosine μ_c the albedo bends
    // sharply (a square-root kink as m → 0), so the rule splits there and
    // the upper piece substitutes t = μ_c² + (1 − μ_c²)u², as the smooth
    // F_dr does.
    let mu_c2 = if eta > 1.0 {
        1.0 - 1.0 / (eta * eta)
    } else {
        0.0
    };
    let span = 1.0 - mu_c2;
    let below = if mu_c2 > 0.0 {
        integrate(albedo, 0.0, mu_c2, rule)
    } else {
        0.0
    };
    let above = integrate(
        |u| albedo(mu_c2 + span * u * u) * 2.0 * span * u,
        0.0,
        1.0,
        rule,
    );
    (below + above).clamp(0.0, 1.0)
}

/// The boundary constant A = (1 + ρd)/(1 − ρd) of eq. 24 for a boundary of
/// relative index `eta` and RMS facet slope `roughness` (eq. 7 when 0).
pub fn boundary_a(eta: f64, roughness: f64) -> f64 {
    let rho = diffuse_reflectance(eta, roughness).min(1.0 - 1e-12);
    (1.0 + rho) / (1.0 - rho)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nearly_smooth_surface_is_the_smooth_boundary() {
        for eta in [0.8, 1.3, 1.4, 2.0] {
            let smooth = diffuse_reflectance_exact(eta);
            let nearly = diffuse_reflectance(eta, 0.01);
            assert!((smooth - nearly).abs() < 3e-3, "{eta}: {smooth} {nearly}");
            for cos in [0.25, 0.7, 1.0] {
                let t = diffuse_transmittance(cos, eta, 0.01);
                let t0 = diffuse_transmittance(cos, eta, 0.0);
                assert!((t - t0).abs() < 2e-3, "{eta} {cos}: {t} {t0}");
            }
        }
    }

    #[test]
    fn index_matched_boundaries_reflect_nothing_however_rough() {
        for m in [0.0, 0.3, 1.0] {
            assert!(diffuse_reflectance(1.0, m).abs() < 1e-12);
            assert!((diffuse_transmittance(0.5, 1.0, m) - 1.0).abs() < 1e-12);
            assert!((boundary_a(1.0, m) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn averages_stay_in_the_unit_interval_at_extremes() {
        for eta in [1e-3, 0.5, 1.3, 3.8, 1e3] {
            for m in [1e-9, 0.1, 1.0, 10.0] {
                let rho = diffuse_reflectance(eta, m);
                assert!((0.0..=1.0).contains(&rho), "{eta} {m}: {rho}");
                for cos in [0.0, 1e-6, 0.5, 1.0] {
                    let t = diffuse_transmittance(cos, eta, m);
                    assert!((0.0..=1.0).contains(&t), "{eta} {m} {cos}: {t}");
                }
                assert!(boundary_a(eta, m).is_finite() && boundary_a(eta, m) >= 1.0);
            }
        }
    }
}
