//! Directions a walk takes: Henyey–Greenstein scattering, and the
//! cosine-distributed start into the medium (`StartDirection::Diffuse`).

use glam::Vec3;
use sssbake_profile::numerics::rng::Rng;
use std::f64::consts::TAU;

/// Below this |g| the phase function is sampled as isotropic: the
/// inversion formula divides by g.
const ISOTROPIC_G: f64 = 1e-4;

/// Two unit vectors completing unit `n` to an orthonormal frame, without
/// a branch that flips near the poles (Duff et al. 2017's construction).
pub fn frame(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// The unit direction at polar cosine `cos_theta` and azimuth `phi`
/// (radians) about unit `axis`.
fn about(axis: Vec3, cos_theta: f64, phi: f64) -> Vec3 {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let (t, b) = frame(axis);
    let (s, c) = phi.sin_cos();
    let d = t * (sin_theta * c) as f32 + b * (sin_theta * s) as f32 + axis * cos_theta as f32;
    d.normalize_or(axis)
}

/// A new direction after scattering from unit `incoming` by the
/// Henyey–Greenstein phase function of mean cosine `g` (in (−1, 1)).
pub fn scatter(incoming: Vec3, g: f64, rng: &mut Rng) -> Vec3 {
    let u = rng.uniform();
    let cos_theta = if g.abs() < ISOTROPIC_G {
        2.0 * u - 1.0
    } else {
        // The inverse of the HG cumulative distribution in cos θ.
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
        ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
    };
    about(incoming, cos_theta, TAU * rng.uniform())
}

/// A direction about unit `axis` with density cos θ / π over the
/// hemisphere (Malley's method), and its cosine to `axis`.
pub fn cosine_hemisphere(axis: Vec3, rng: &mut Rng) -> (Vec3, f64) {
    let cos_theta = rng.uniform_open().sqrt();
    (about(axis, cos_theta, TAU * rng.uniform()), cos_theta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scattering_keeps_the_mean_cosine() {
        let mut rng = Rng::new(3, 0);
        let axis = Vec3::new(0.3, -0.5, 0.8).normalize();
        for g in [-0.7, 0.0, 0.5, 0.9] {
            let n = 200_000;
            let mean = (0..n)
                .map(|_| scatter(axis, g, &mut rng).dot(axis) as f64)
                .sum::<f64>()
                / n as f64;
            // The cosine's variance is below 1, so 1/√n bounds its error.
            assert!((mean - g).abs() < 4.0 / (n as f64).sqrt(), "g {g}: {mean}");
        }
    }

    #[test]
    fn cosine_directions_stay_in_their_hemisphere_with_mean_two_thirds() {
        let mut rng = Rng::new(5, 1);
        let axis = Vec3::NEG_Z;
        let n = 100_000;
        let mut sum = 0.0;
        for _ in 0..n {
            let (d, cos) = cosine_hemisphere(axis, &mut rng);
            assert!(d.dot(axis) >= 0.0 && (d.length() - 1.0).abs() < 1e-5);
            sum += cos;
        }
        // E[cos θ] under cos θ/π is 2/3.
        assert!((sum / n as f64 - 2.0 / 3.0).abs() < 0.005);
    }
}
