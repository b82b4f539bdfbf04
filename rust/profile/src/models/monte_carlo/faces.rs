//! A rough face against air for the slab Monte Carlo: the same
//! single-scattering Beckmann facets as the Stam layer's faces
//! ([`crate::models::stam::microfacet`]), made to conserve energy the same way.
//!
//! A photon meeting the face draws a facet normal h with density
//! D(h) cos θh, reflects off it with probability F(i·h) or refracts
//! through it, and carries Walter et al. 2007's weight
//! w = (i·h) G₁(i) G₁(o) / (cos θi cos θh), zero where o leaves on the wrong
//! side. The mean of w over facets is the face's albedo A(θi) below 1 (the
//! light the shadowing term blocks, which in fact scatters again among the
//! facets); dividing w by A(θi) returns that light along the lobes' own
//! shapes, exactly as the Stam solver scales each incidence column of its
//! faces. A(θi) is tabulated once per face and side by a stratified rule
//! over the facets.

use crate::boundary::fresnel::dielectric_reflectance;
use crate::models::stam::microfacet::smith_g1;
use crate::numerics::rng::Rng;
use std::f64::consts::PI;

/// Incidence cosines tabulated, evenly spaced in (0, 1].
const NODES: usize = 64;
/// Facets per incidence in the albedo's rule (per axis of the square).
const RULE: usize = 160;

/// Where a photon goes after meeting the face.
pub(crate) enum Crossing {
    /// Back into the side it came from, along the direction, with the
    /// weight factor.
    Back([f64; 3], f64),
    /// Through the face, along the direction, with the weight factor.
    Through([f64; 3], f64),
}

/// A rough dielectric face between air and a layer of index `eta`.
#[derive(Clone, Debug)]
pub(crate) struct RoughFace {
    m: f64,
    eta: f64,
    /// A(μ) met from air, at μ = (k + 1)/NODES.
    from_air: Vec<f64>,
    /// A(μ) met from inside.
    from_inside: Vec<f64>,
}

impl RoughFace {
    /// The face of RMS slope `m` (> 0) on a layer of index `eta`.
    pub(crate) fn new(m: f64, eta: f64) -> Self {
        let table = |n_i: f64, n_t: f64| -> Vec<f64> {
            (0..NODES)
                .map(|k| {
                    let mu = (k + 1) as f64 / NODES as f64;
                    albedo(mu, n_i, n_t, m)
                })
                .collect()
        };
        Self {
            m,
            eta,
            from_air: table(1.0, eta),
            from_inside: table(eta, 1.0),
        }
    }

    /// A photon travelling along `d` (unit; d_z > 0 downwards) meets the
    /// face from air (`from_air`) or from inside.
    pub(crate) fn cross(&self, d: [f64; 3], from_air: bool, rng: &mut Rng) -> Crossing {
        let (n_i, n_t) = if from_air {
            (1.0, self.eta)
        } else {
            (self.eta, 1.0)
        };
        // A frame whose +z points back towards where the light comes from.
        let flip = if d[2] > 0.0 { -1.0 } else { 1.0 };
        let i = [-d[0], -d[1], -d[2] * flip];
        let h = facet(self.m, [rng.uniform(), rng.uniform()]);
        let f = dielectric_reflectance(dot(i, h).max(0.0), n_i, n_t);
        let reflect = rng.uniform() < f;
        let (o, w) = scatter(i, h, n_i, n_t, self.m, reflect);
        let table = if from_air {
            &self.from_air
        } else {
            &self.from_inside
        };
        let a = interpolate(table, i[2]);
        let w = if a > 1e-9 { w / a } else { 0.0 };
        let out = [o[0], o[1], o[2] * flip];
        if reflect {
            Crossing::Back(out, w)
        } else {
            Crossing::Through(out, w)
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// A facet normal (+z side) with density D(h) cos θh from two uniform
/// numbers: tan²θh = −m² ln(1 − u₀), φ = 2πu₁.
fn facet(m: f64, u: [f64; 2]) -> [f64; 3] {
    let tan2 = -m * m * (1.0 - u[0]).max(1e-300).ln();
    let cos = 1.0 / (1.0 + tan2).sqrt();
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let (s, c) = (2.0 * PI * u[1]).sin_cos();
    [sin * c, sin * s, cos]
}

/// The direction leaving facet `h` for light from `i` (both in the frame
/// whose +z faces the light; reflected or refracted), and Walter's
/// weight; zero where it leaves on the wrong side of the face.
fn scatter(i: [f64; 3], h: [f64; 3], n_i: f64, n_t: f64, m: f64, reflect: bool) -> ([f64; 3], f64) {
    let c = dot(i, h);
    if c <= 0.0 || i[2] <= 0.0 {
        return ([0.0, 0.0, 1.0], 0.0);
    }
    let o = if reflect {
        [0, 1, 2].map(|k| 2.0 * c * h[k] - i[k])
    } else {
        let eta = n_i / n_t;
        let cos_t2 = 1.0 - eta * eta * (1.0 - c * c);
        if cos_t2 <= 0.0 {
            return ([0.0, 0.0, 1.0], 0.0);
        }
        let k = eta * c - cos_t2.sqrt();
        [0, 1, 2].map(|j| -eta * i[j] + k * h[j])
    };
    let right_side = if reflect { o[2] > 0.0 } else { o[2] < 0.0 };
    if !right_side {
        return (o, 0.0);
    }
    let w = c * smith_g1(i, h, m) * smith_g1(o, h, m) / (i[2] * h[2]);
    (o, if w.is_finite() { w } else { 0.0 })
}

/// The face's albedo from incidence cosine `mu`: the mean of Walter's
/// weight over facets drawn with density D cos θh and Fresnel's choice,
/// by a stratified midpoint rule.
fn albedo(mu: f64, n_i: f64, n_t: f64, m: f64) -> f64 {
    let i = [(1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu];
    let mut sum = 0.0;
    for a in 0..RULE {
        for b in 0..RULE {
            let u = [
                (a as f64 + 0.5) / RULE as f64,
                (b as f64 + 0.5) / RULE as f64,
            ];
            let h = facet(m, u);
            let f = dielectric_reflectance(dot(i, h).max(0.0), n_i, n_t);
            let (_, reflected) = scatter(i, h, n_i, n_t, m, true);
            let (_, refracted) = scatter(i, h, n_i, n_t, m, false);
            sum += f * reflected + (1.0 - f) * refracted;
        }
    }
    sum / (RULE * RULE) as f64
}

/// Linear interpolation of a table at μ = (k + 1)/NODES, held below the
/// first node.
fn interpolate(table: &[f64], mu: f64) -> f64 {
    let x = (mu.clamp(0.0, 1.0) * NODES as f64 - 1.0).max(0.0);
    let k = (x.floor() as usize).min(NODES - 2);
    let f = (x - k as f64).min(1.0);
    table[k] * (1.0 - f) + table[k + 1] * f
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The facets lose light only to shadowing: none at normal incidence
    /// on a nearly smooth face, more towards grazing and as the slope
    /// grows, never more than arrives.
    #[test]
    fn a_face_loses_light_only_to_its_shadowing() {
        for (n_i, n_t) in [(1.0, 1.4), (1.4, 1.0)] {
            let smooth = albedo(1.0, n_i, n_t, 0.02);
            assert!((smooth - 1.0).abs() < 2e-3, "{smooth}");
            for m in [0.3, 0.6] {
                let a: Vec<f64> = [1.0, 0.7, 0.4].map(|mu| albedo(mu, n_i, n_t, m)).to_vec();
                println!("η {n_i}→{n_t}, m {m}: A at μ 1, 0.7, 0.4 = {a:.4?}");
                assert!(a.iter().all(|&x| x > 0.5 && x <= 1.0 + 1e-9), "{a:?}");
                assert!(a[0] >= a[2], "{a:?}");
            }
        }
    }
}
