//! Stam 2001 §4: the BRDF and BTDF of an isotropic Gaussian rough
//! dielectric surface, evaluated in a frame where light arrives from the
//! +z side.
//!
//! The facet normals follow the Beckmann distribution of RMS slope m (the
//! material's `roughness`, the m of Donner & Jensen; Stam's σ is the slope
//! deviation per axis, σ = m/√2). Stam's eq. 17 normalises the density of
//! normals per solid angle (∫P dω = 1); the facets of a surface tile it
//! when the density is normalised by projected area, D = P/cos θa
//! (∫D cos θa dω = 1, Cook–Torrance's and van Ginneken's form), which is
//! what conserves energy at normal incidence, so D is used below. With it
//! the reflected radiance is F·D/(4 cos θo cos θi) (Stam's r) and the
//! refracted one follows from his Jacobian dωt = (c − η ct)²/(η² ct) dωa
//! (c = cos θ′₀, ct the refracted cosine at the facet; appendix B):
//! t = (1 − F)·D·c·η²·ct / (cos θi cos θt (c − η ct)²), Walter et al.
//! 2007's form. Both are multiplied by Smith's shadowing for a Gaussian
//! surface, the one van Ginneken et al. use (through Walter's rational
//! fit of its Beckmann G₁, within 0.4% of the erfc form).

use crate::boundary::fresnel::dielectric_reflectance;
use std::f64::consts::PI;

/// A unit vector.
pub type Direction = [f64; 3];

fn dot(a: Direction, b: Direction) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalised(v: Direction) -> Option<Direction> {
    let n = dot(v, v).sqrt();
    (n > 1e-300 && n.is_finite()).then(|| v.map(|x| x / n))
}

/// Beckmann density D(h) (per unit solid angle, projected-area
/// normalised) of facet normal `h` for RMS slope `m`, 1/sr.
pub fn beckmann(h: Direction, m: f64) -> f64 {
    let cos = h[2];
    if cos <= 0.0 {
        return 0.0;
    }
    let cos2 = cos * cos;
    let tan2 = (1.0 - cos2) / cos2;
    (-tan2 / (m * m)).exp() / (PI * m * m * cos2 * cos2)
}

/// Smith's masking of direction `v` (unit, side of `v` by the sign of
/// v_z) by a Beckmann surface of RMS slope `m`, given the facet normal `h`.
pub fn smith_g1(v: Direction, h: Direction, m: f64) -> f64 {
    let cos = v[2].abs();
    if dot(v, h) * v[2] <= 0.0 || cos <= 0.0 {
        return 0.0;
    }
    let tan = (1.0 - cos * cos).max(0.0).sqrt() / cos;
    if tan == 0.0 {
        return 1.0;
    }
    let a = 1.0 / (m * tan);
    if a >= 1.6 {
        1.0
    } else {
        (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
    }
}

/// The BRDF (1/sr) for light arriving from direction `i` (pointing away
/// from the surface, i_z > 0) leaving towards `o` (o_z > 0), on a surface
/// between a medium of index `n_i` (the light's side) and `n_t`.
pub fn reflection(i: Direction, o: Direction, n_i: f64, n_t: f64, m: f64) -> f64 {
    if i[2] <= 0.0 || o[2] <= 0.0 {
        return 0.0;
    }
    let Some(h) = normalised([i[0] + o[0], i[1] + o[1], i[2] + o[2]]) else {
        return 0.0;
    };
    let c = dot(i, h);
    let f = dielectric_reflectance(c, n_i, n_t);
    let g = smith_g1(i, h, m) * smith_g1(o, h, m);
    f * beckmann(h, m) * g / (4.0 * i[2] * o[2])
}

/// The BTDF (1/sr, radiance out per irradiance in, so including the n²
/// change of radiance) for light arriving from `i` (i_z > 0) and leaving
/// into the other medium towards `o` (o_z < 0).
pub fn transmission(i: Direction, o: Direction, n_i: f64, n_t: f64, m: f64) -> f64 {
    if i[2] <= 0.0 || o[2] >= 0.0 {
        return 0.0;
    }
    // The facet normal that refracts i into o: −(n_i i + n_t o), on the +z side.
    let raw = [
        -(n_i * i[0] + n_t * o[0]),
        -(n_i * i[1] + n_t * o[1]),
        -(n_i * i[2] + n_t * o[2]),
    ];
    let Some(mut h) = normalised(raw) else {
        return 0.0;
    };
    if h[2] < 0.0 {
        h = h.map(|x| -x);
    }
    let c = dot(i, h);
    let ct = dot(o, h);
    if c <= 0.0 || ct >= 0.0 {
        return 0.0;
    }
    let denominator = n_i * c + n_t * ct;
    if denominator.abs() < 1e-300 {
        return 0.0;
    }
    let f = dielectric_reflectance(c, n_i, n_t);
    let g = smith_g1(i, h, m) * smith_g1(o, h, m);
    let value = c * (-ct) * n_t * n_t * (1.0 - f) * beckmann(h, m) * g
        / (i[2] * (-o[2]) * denominator * denominator);
    if value.is_finite() {
        value.max(0.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn beckmann_tiles_the_surface() {
        // ∫ D cos θ dω = 1 by a fine midpoint rule in tan θ.
        let m = 0.3;
        let steps = 20_000;
        let mut sum = 0.0;
        for s in 0..steps {
            let theta = (s as f64 + 0.5) / steps as f64 * PI / 2.0;
            let h = [theta.sin(), 0.0, theta.cos()];
            sum +=
                beckmann(h, m) * theta.cos() * theta.sin() * 2.0 * PI * (PI / 2.0) / steps as f64;
        }
        assert!((sum - 1.0).abs() < 1e-6, "{sum}");
    }

    /// ∫ f(θ, φ) sin θ dθ dφ over a hemisphere by a Gauss rule in each.
    fn hemisphere(f: impl Fn(Direction) -> f64, lower: bool) -> f64 {
        let rule = crate::numerics::quadrature::gauss_legendre(160);
        let mut sum = 0.0;
        for &(x, wx) in &rule {
            let theta = 0.25 * PI * (x + 1.0);
            for &(y, wy) in &rule {
                let phi = PI * (y + 1.0);
                let z = if lower { -theta.cos() } else { theta.cos() };
                let d = [theta.sin() * phi.cos(), theta.sin() * phi.sin(), z];
                sum += wx * wy * 0.25 * PI * PI * theta.sin() * f(d);
            }
        }
        sum
    }

    #[test]
    fn the_btdf_carries_what_the_facets_refract() {
        // Integrated over outgoing directions, Stam's BTDF (with his
        // refraction Jacobian) must carry exactly the flux the facets
        // refract, integrated over facet normals: ∫ D (i·h)/cos θi (1 − F) G dωh.
        // The same for the BRDF and the facets' reflection. An error in the
        // Jacobian (Stam first took dωt = dωa) breaks the equality.
        let m = 0.3;
        for (n_i, n_t) in [(1.0, 1.4), (1.4, 1.0)] {
            for cos_i in [0.9, 0.5] {
                let i: Direction = [-(1.0f64 - cos_i * cos_i).sqrt(), 0.0, cos_i];
                let by_directions_t =
                    hemisphere(|o| transmission(i, o, n_i, n_t, m) * o[2].abs(), true);
                let by_directions_r = hemisphere(|o| reflection(i, o, n_i, n_t, m) * o[2], false);
                // The facet-space integrals, by the same rule over normals h.
                let (mut by_facets_t, mut by_facets_r) = (0.0, 0.0);
                let rule = crate::numerics::quadrature::gauss_legendre(160);
                for &(x, wx) in &rule {
                    let theta = 0.25 * PI * (x + 1.0);
                    for &(y, wy) in &rule {
                        let phi = PI * (y + 1.0);
                        let h = [
                            theta.sin() * phi.cos(),
                            theta.sin() * phi.sin(),
                            theta.cos(),
                        ];
                        let c = dot(i, h);
                        if c <= 0.0 {
                            continue;
                        }
                        let weight =
                            wx * wy * 0.25 * PI * PI * theta.sin() * beckmann(h, m) * c / cos_i;
                        let f = dielectric_reflectance(c, n_i, n_t);
                        let r = [
                            2.0 * c * h[0] - i[0],
                            2.0 * c * h[1] - i[1],
                            2.0 * c * h[2] - i[2],
                        ];
                        if r[2] > 0.0 {
                            by_facets_r += weight * f * smith_g1(i, h, m) * smith_g1(r, h, m);
                        }
                        // Refraction through the facet: η = n_t/n_i.
                        let eta = n_t / n_i;
                        let k = c * c + eta * eta - 1.0;
                        if k > 0.0 {
                            let ct = k.sqrt();
                            let t = [
                                ((c - ct) * h[0] - i[0]) / eta,
                                ((c - ct) * h[1] - i[1]) / eta,
                                ((c - ct) * h[2] - i[2]) / eta,
                            ];
                            if t[2] < 0.0 {
                                by_facets_t +=
                                    weight * (1.0 - f) * smith_g1(i, h, m) * smith_g1(t, h, m);
                            }
                        }
                    }
                }
                for (what, a, b) in [
                    ("T", by_directions_t, by_facets_t),
                    ("R", by_directions_r, by_facets_r),
                ] {
                    assert!(
                        (a - b).abs() < 2e-3 * b.max(0.05),
                        "{n_i}→{n_t} cos {cos_i} {what}: directions {a}, facets {b}"
                    );
                }
            }
        }
    }
}
