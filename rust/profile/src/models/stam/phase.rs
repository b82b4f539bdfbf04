//! Henyey–Greenstein scattering in the azimuthal cosine series (Stam 2001,
//! appendices A and C), with δ-M scaling.
//!
//! HG's Legendre moments are gᵏ (Stam appendix C). A forward-peaked phase
//! function needs far more moments than a rule of M ordinates resolves:
//! plain truncation after L terms drops the peak's weight g^L into wrong
//! side-scattering (at g = 0.9 and L = 16, g^L ≈ 0.19). δ-M (Wiscombe 1977)
//! instead takes f = g^L of the scattering as exactly forward, which is no
//! scattering at all, and rescales the rest: moments (gⁿ − f)/(1 − f),
//! albedo Ω(1 − f)/(1 − Ωf), optical depth τ(1 − Ωf). The totals R and T
//! converge far faster that way; the forward lobe of the transmitted light
//! travels with the unscattered beam.

/// A layer's scattering after δ-M scaling.
#[derive(Clone, Debug, PartialEq)]
pub struct ScaledScattering {
    /// Legendre moments χ₀ = 1, χ₁, … of the scaled phase function.
    pub moments: Vec<f64>,
    /// Scaled single-scattering albedo Ω′.
    pub albedo: f64,
    /// Factor the optical depth is multiplied by, 1 − Ωf.
    pub depth_factor: f64,
}

/// δ-M scaling of HG with mean cosine `g` and albedo `albedo`, keeping
/// `terms` moments (n = 0 … terms − 1).
pub fn delta_m(g: f64, albedo: f64, terms: usize) -> ScaledScattering {
    let terms = terms.max(1);
    // Only a forward peak is taken out; a backward-peaked function is
    // truncated as it is.
    let f = if g > 0.0 { g.powi(terms as i32) } else { 0.0 };
    let moments = (0..terms)
        .map(|n| (g.powi(n as i32) - f) / (1.0 - f))
        .collect();
    ScaledScattering {
        moments,
        albedo: albedo * (1.0 - f) / (1.0 - albedo * f),
        depth_factor: 1.0 - albedo * f,
    }
}

/// Normalised associated Legendre functions Λₙᵏ(μ) = √((n−k)!/(n+k)!)·Pₙᵏ(μ)
/// for n = 0 … `terms` − 1 (zero for n < k), by the upward recurrence that
/// stays bounded for high orders.
pub fn normalised_legendre(k: usize, terms: usize, mu: f64) -> Vec<f64> {
    let mut out = vec![0.0; terms];
    if k >= terms {
        return out;
    }
    let s = (1.0 - mu * mu).max(0.0).sqrt();
    let mut diagonal = 1.0;
    for j in 1..=k {
        let j = j as f64;
        diagonal *= ((2.0 * j - 1.0) / (2.0 * j)).sqrt() * s;
    }
    out[k] = diagonal;
    if k + 1 < terms {
        out[k + 1] = (2.0 * k as f64 + 1.0).sqrt() * mu * diagonal;
    }
    let kf = k as f64;
    for n in k + 2..terms {
        let nf = n as f64;
        out[n] = ((2.0 * nf - 1.0) * mu * out[n - 1]
            - ((nf - 1.0) * (nf - 1.0) - kf * kf).sqrt() * out[n - 2])
            / (nf * nf - kf * kf).sqrt();
    }
    out
}

/// Ωₖ·pₖ(μ′, μ) of Stam's appendix A for every pair of signed cosines:
/// `(same, opposite)` with `same[n][m]` = Ωₖ pₖ(μm, μn) and `opposite[n][m]` =
/// Ωₖ pₖ(−μm, μn), where Ωₖ = Ω(1 + δₖ₀)/4 and pₖ = (2 − δₖ₀)Σ(2n+1)χₙΛₙᵏΛₙᵏ.
pub fn mode_kernels(
    k: usize,
    scattering: &ScaledScattering,
    mu: &[f64],
) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let terms = scattering.moments.len();
    let table: Vec<Vec<f64>> = mu
        .iter()
        .map(|&m| normalised_legendre(k, terms, m))
        .collect();
    // Ωₖ(2 − δₖ₀) = Ω/2 for every k.
    let scale = scattering.albedo / 2.0;
    let size = mu.len();
    let mut same = vec![vec![0.0; size]; size];
    let mut opposite = vec![vec![0.0; size]; size];
    for n in 0..size {
        for m in 0..size {
            let (mut s, mut o) = (0.0, 0.0);
            let pairs = table[n].iter().zip(&table[m]).zip(&scattering.moments);
            for (l, ((a, b), chi)) in pairs.enumerate().skip(k) {
                let term = (2 * l + 1) as f64 * chi * a * b;
                s += term;
                // Λₗᵏ(−μ) = (−1)^(l+k) Λₗᵏ(μ).
                o += if (l + k).is_multiple_of(2) {
                    term
                } else {
                    -term
                };
            }
            same[n][m] = scale * s;
            opposite[n][m] = scale * o;
        }
    }
    (same, opposite)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn legendre_matches_closed_forms() {
        let mu: f64 = 0.3;
        let s = (1.0 - mu * mu).sqrt();
        let p0 = normalised_legendre(0, 4, mu);
        assert!((p0[2] - 0.5 * (3.0 * mu * mu - 1.0)).abs() < 1e-14);
        assert!((p0[3] - 0.5 * (5.0 * mu.powi(3) - 3.0 * mu)).abs() < 1e-14);
        // P₂¹ = 3μs, normalised by √(1/3!).
        let p1 = normalised_legendre(1, 4, mu);
        assert!((p1[2] - 3.0 * mu * s / 6f64.sqrt()).abs() < 1e-14);
        // P₂² = 3s², normalised by √(1/4!).
        let p2 = normalised_legendre(2, 4, mu);
        assert!((p2[2] - 3.0 * s * s / 24f64.sqrt()).abs() < 1e-14);
    }

    #[test]
    fn delta_m_keeps_the_mean_cosine_of_what_scatters() {
        // Moments of the scaled function times (1 − f) plus f give gⁿ back.
        let s = delta_m(0.9, 0.99, 8);
        let f = 0.9f64.powi(8);
        for (n, chi) in s.moments.iter().enumerate() {
            assert!((chi * (1.0 - f) + f - 0.9f64.powi(n as i32)).abs() < 1e-14);
        }
        assert!(s.albedo < 0.99 && s.albedo > 0.0);
    }
}
