//! Gauss–Legendre quadrature, with nodes computed once by Newton's method.

/// Nodes and weights of an `n`-point Gauss–Legendre rule on [-1, 1].
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut rule = Vec::with_capacity(n);
    for i in 0..n {
        // Tricomi's initial guess for the i-th root, then Newton on P_n.
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut derivative = 1.0;
        for _ in 0..100 {
            let (p, dp) = legendre_with_derivative(n, x);
            derivative = dp;
            let step = p / dp;
            x -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        let (_, dp) = legendre_with_derivative(n, x);
        if dp.is_finite() {
            derivative = dp;
        }
        rule.push((x, 2.0 / ((1.0 - x * x) * derivative * derivative)));
    }
    rule
}

fn legendre_with_derivative(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    let n = n as f64;
    (p1, n * (x * p1 - p0) / (x * x - 1.0))
}

/// ∫_a^b f(x) dx with an `n`-point rule.
pub fn integrate(f: impl Fn(f64) -> f64, a: f64, b: f64, rule: &[(f64, f64)]) -> f64 {
    let half = 0.5 * (b - a);
    let mid = 0.5 * (a + b);
    rule.iter()
        .map(|&(x, w)| w * f(mid + half * x))
        .sum::<f64>()
        * half
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_exactly() {
        let rule = gauss_legendre(8);
        let weights: f64 = rule.iter().map(|(_, w)| w).sum();
        assert!((weights - 2.0).abs() < 1e-13);
        // A 15th-degree polynomial is integrated exactly by 8 points.
        let value = integrate(|x| x.powi(14) + x.powi(3), 0.0, 1.0, &rule);
        assert!((value - (1.0 / 15.0 + 0.25)).abs() < 1e-13);
    }
}
