//! A safeguarded root finder for increasing functions of a positive length.

/// The radius r > 0 at which the increasing function `fraction(r)` reaches
/// `target`, searched from `start` (mm).
///
/// The bracket grows geometrically from `start`; inside it an Illinois
/// (modified regula falsi) step in ln r is taken when it stays inside the
/// bracket and a bisection step otherwise, so the search always converges.
/// Returns 0 for a target at or below `fraction(0⁺)` and the upper search
/// limit 1e9 mm when the target is never reached.
pub fn radius_where(fraction: impl Fn(f64) -> f64, target: f64, start: f64) -> f64 {
    const SMALLEST: f64 = 1e-12;
    const LARGEST: f64 = 1e9;
    let start = if start.is_finite() && start > 0.0 {
        start.clamp(SMALLEST, LARGEST)
    } else {
        1.0
    };
    let g = |log_r: f64| fraction(log_r.exp()) - target;
    let (mut a, mut b) = (start.ln(), start.ln());
    let (mut ga, mut gb) = (g(a), g(b));
    while ga > 0.0 {
        if a <= SMALLEST.ln() {
            return 0.0;
        }
        b = a;
        gb = ga;
        a -= std::f64::consts::LN_2;
        ga = g(a);
    }
    while gb < 0.0 {
        if b >= LARGEST.ln() {
            return LARGEST;
        }
        a = b;
        ga = gb;
        b += std::f64::consts::LN_2;
        gb = g(b);
    }
    let mut side = 0i8;
    for _ in 0..200 {
        if (b - a).abs() < 1e-12 || gb == 0.0 {
            break;
        }
        let secant = b - gb * (b - a) / (gb - ga);
        let x = if secant.is_finite() && secant > a.min(b) && secant < a.max(b) {
            secant
        } else {
            0.5 * (a + b)
        };
        let gx = g(x);
        if gx == 0.0 {
            return x.exp();
        }
        if (gx < 0.0) == (ga < 0.0) {
            a = x;
            ga = gx;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        } else {
            b = x;
            gb = gx;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        }
    }
    (0.5 * (a + b)).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_known_radii() {
        let r = radius_where(|r| 1.0 - (-r).exp(), 0.99, 1.0);
        assert!((r - 100f64.ln()).abs() < 1e-9, "{r}");
        let r = radius_where(|r| r * r / (1.0 + r * r), 0.5, 1e-6);
        assert!((r - 1.0).abs() < 1e-9);
        assert_eq!(radius_where(|_| 1.0, 0.5, 1.0), 0.0);
        assert_eq!(radius_where(|_| 0.0, 0.5, 1.0), 1e9);
    }
}
