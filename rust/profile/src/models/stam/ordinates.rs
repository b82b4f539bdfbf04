//! The discrete ordinates: a Gauss rule on the half range of cosines inside
//! the layer, and their images outside under refraction.
//!
//! Inside a layer of relative index η > 1 the directions that can leave it
//! form the cone μ ≥ μc = √(1 − 1/η²); beyond it light is totally
//! reflected. The rule is a double Gauss rule split at μc (Jin & Stamnes
//! 1994), so every ordinate of the cone refracts onto one ordinate outside
//! and a smooth boundary maps ordinates to ordinates. The outside weights
//! follow from étendue: 1 − μe² = η²(1 − μ²) gives μe dμe = η² μ dμ.

use crate::numerics::quadrature::gauss_legendre;

/// The ordinates of one layer.
#[derive(Clone, Debug, PartialEq)]
pub struct Ordinates {
    /// Cosines inside the layer, increasing, in (0, 1).
    pub inside: Vec<f64>,
    /// Their Gauss weights (summing to 1 over the half range).
    pub inside_weights: Vec<f64>,
    /// Index into `inside` of the first ordinate that can leave the layer.
    pub first_in_cone: usize,
    /// Cosines outside (air) of the refracted cone, one per ordinate from
    /// `first_in_cone` on, increasing.
    pub outside: Vec<f64>,
    /// Their weights, μe·we = η²·μ·w.
    pub outside_weights: Vec<f64>,
    /// Relative index η of the layer over air.
    pub eta: f64,
}

impl Ordinates {
    /// `count` ordinates on the half range (at least 2, rounded up to even)
    /// for a layer of relative index `eta`: half on [0, μc], half on [μc, 1]
    /// when η > 1, all on [0, 1] when η ≤ 1.
    pub fn new(count: usize, eta: f64) -> Self {
        let count = count.max(2).next_multiple_of(2);
        let mu_c = critical_cosine(eta);
        let mut inside = Vec::with_capacity(count);
        let mut inside_weights = Vec::with_capacity(count);
        let mut push_rule = |points: usize, a: f64, b: f64| {
            let mut rule = gauss_legendre(points);
            rule.sort_by(|x, y| x.0.total_cmp(&y.0));
            for (x, w) in rule {
                inside.push(a + 0.5 * (b - a) * (x + 1.0));
                inside_weights.push(0.5 * (b - a) * w);
            }
        };
        if mu_c > 0.0 {
            push_rule(count / 2, 0.0, mu_c);
            push_rule(count / 2, mu_c, 1.0);
        } else {
            push_rule(count, 0.0, 1.0);
        }
        let first_in_cone = inside.partition_point(|&mu| mu < mu_c);
        let (outside, outside_weights) = inside[first_in_cone..]
            .iter()
            .zip(&inside_weights[first_in_cone..])
            .map(|(&mu, &w)| {
                let mu_e = refracted_out(mu, eta);
                (mu_e, eta * eta * mu * w / mu_e)
            })
            .unzip();
        Self {
            inside,
            inside_weights,
            first_in_cone,
            outside,
            outside_weights,
            eta,
        }
    }

    /// The highest degree of polynomial in μ the inside rule integrates
    /// exactly over [−1, 1]: 2·points − 1 of its smallest Gauss piece.
    pub fn exact_degree(&self) -> usize {
        let pieces = if self.first_in_cone > 0 { 2 } else { 1 };
        2 * (self.inside.len() / pieces) - 1
    }
}

/// The cosine inside a layer of relative index `eta` beyond which light
/// cannot leave it (0 when η ≤ 1).
pub fn critical_cosine(eta: f64) -> f64 {
    if eta > 1.0 {
        (1.0 - 1.0 / (eta * eta)).sqrt()
    } else {
        0.0
    }
}

/// The cosine outside of the direction inside at cosine `mu` refracts to.
pub fn refracted_out(mu: f64, eta: f64) -> f64 {
    (1.0 - eta * eta * (1.0 - mu * mu)).max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_integrate_the_cosine_inside_and_out() {
        for eta in [1.0, 1.4, 2.0] {
            let o = Ordinates::new(12, eta);
            let inside: f64 = o.inside_weights.iter().sum();
            assert!((inside - 1.0).abs() < 1e-13);
            // ∫_0^1 μ dμ = 1/2 outside: the cone carries all of it.
            let flux: f64 = o
                .outside
                .iter()
                .zip(&o.outside_weights)
                .map(|(m, w)| m * w)
                .sum();
            assert!((flux - 0.5).abs() < 1e-12, "{eta}: {flux}");
        }
    }
}
