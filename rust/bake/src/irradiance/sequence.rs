//! Deterministic low-discrepancy sample points: a Hammersley set per
//! receiver, rotated (Cranley–Patterson) by a hash of the receiver and the
//! light so neighbouring texels see different points and residual error
//! turns into fine dither instead of bands.

use glam::Vec2;

/// The `i`-th of `count` points in [0, 1)², shifted by `rotation`.
pub fn hammersley(i: u32, count: u32, rotation: Vec2) -> Vec2 {
    let x = (i as f32 + 0.5) / count.max(1) as f32;
    let y = i.reverse_bits() as f32 * (1.0 / 4_294_967_296.0);
    Vec2::new(wrap(x + rotation.x), wrap(y + rotation.y))
}

/// A rotation in [0, 1)² that depends only on `a` and `b`.
pub fn rotation(a: u64, b: u64) -> Vec2 {
    let h = mix(a.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ b);
    Vec2::new(
        (h >> 40) as f32 * (1.0 / 16_777_216.0),
        ((h >> 16) & 0xFF_FFFF) as f32 * (1.0 / 16_777_216.0),
    )
}

fn wrap(x: f32) -> f32 {
    let w = x - x.floor();
    if w >= 1.0 { 0.0 } else { w }
}

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Uniform point on the unit disk from `u` in [0, 1)², by the concentric
/// map (low distortion, so strata stay compact).
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let a = 2.0 * u - Vec2::ONE;
    if a == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let quarter = std::f32::consts::FRAC_PI_4;
    let (r, theta) = if a.x.abs() > a.y.abs() {
        (a.x, quarter * (a.y / a.x))
    } else {
        (a.y, 2.0 * quarter - quarter * (a.x / a.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
}

/// A unit vector in the cone of half-angle with cosine `cos_max` around
/// +Z, uniform in solid angle.
pub fn uniform_cone(u: Vec2, cos_max: f32) -> glam::Vec3 {
    let cos_t = 1.0 - u.x * (1.0 - cos_max);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * u.y;
    glam::Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

/// A unit vector in the +Z hemisphere with density cos θ / π.
pub fn cosine_hemisphere(u: Vec2) -> glam::Vec3 {
    let d = concentric_disk(u);
    glam::Vec3::new(d.x, d.y, (1.0 - d.length_squared()).max(0.0).sqrt())
}

/// An orthonormal basis (t, b) completing unit `n` (Duff et al. 2017).
pub fn basis(n: glam::Vec3) -> (glam::Vec3, glam::Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        glam::Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        glam::Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}
