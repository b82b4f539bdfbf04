//! The image series of a slab in real space (Donner & Jensen 2005 eq. 11–13
//! with signed poles, Mikkelsen eq. 31–32): R(r), T(r) and their enclosed
//! totals, summing as many image pairs as a requested accuracy needs.

use crate::diffusion::slab::SlabChannel;
use std::f64::consts::PI;

/// Most image pairs a real-space evaluation will sum; beyond this the series
/// converges too slowly (σtr·thickness → 0) and callers tabulate the closed
/// frequency form instead.
pub const MAX_POLE_PAIRS: usize = 600;

impl SlabChannel {
    /// Period of the image series, 2L, in mm.
    fn period(&self) -> f64 {
        2.0 * (self.thickness + self.zb_top + self.zb_bottom)
    }

    /// Signed depths of the real and virtual sources of image pair `i`
    /// (light entering the top face).
    fn poles(&self, i: i64) -> (f64, f64) {
        let shift = if self.is_semi_infinite() {
            0.0
        } else {
            i as f64 * self.period()
        };
        (
            shift + self.source_depth,
            shift - self.source_depth - 2.0 * self.zb_top,
        )
    }

    /// The smallest number of image pairs n (summing i = −n..=n) whose
    /// totals are within `accuracy` (relative) of the exact ones, or `None`
    /// if more than [`MAX_POLE_PAIRS`] would be needed.
    pub fn pole_pairs_for(&self, accuracy: f64) -> Option<usize> {
        if self.is_semi_infinite() {
            return Some(0);
        }
        let exact = self.image_totals();
        let tolerance = accuracy * (exact.reflectance + exact.transmittance).max(1e-300);
        let (mut r, mut t) = (0.0, 0.0);
        for n in 0..=MAX_POLE_PAIRS as i64 {
            for i in if n == 0 { vec![0] } else { vec![-n, n] } {
                let (zr, zv) = self.poles(i);
                r += self.pole_total(zr) - self.pole_total(zv);
                t += self.pole_total(self.thickness - zr) - self.pole_total(self.thickness - zv);
            }
            if (r - exact.reflectance).abs() <= tolerance
                && (t - exact.transmittance).abs() <= tolerance
            {
                return Some(n as usize);
            }
        }
        None
    }

    /// A bound on |R(r)| and |T(r)| of the images left out when summing
    /// `pairs` pairs, at any r: each pole contributes at most
    /// (1 + σ|z|)e^{−σ|z|}/(4πz²) (ρ ≥ |z|), and pair i lies at least
    /// (i − 2) periods from either face.
    pub fn truncation_bound(&self, pairs: usize) -> f64 {
        if self.is_semi_infinite() {
            return 0.0;
        }
        let mut bound = 0.0;
        for i in (pairs + 1).max(3)..pairs + 100_000 {
            let z = (i - 2) as f64 * self.period();
            let term =
                4.0 * (1.0 + self.sigma_tr * z) * (-self.sigma_tr * z).exp() / (4.0 * PI * z * z);
            bound += term;
            if term < 1e-6 * bound {
                break;
            }
        }
        if pairs < 3 {
            // Pairs 1..3 are closer than the estimate assumes: bound them
            // by the nearest possible distance, one slab thickness.
            bound += 8.0 / (4.0 * PI * self.thickness * self.thickness);
        }
        self.strength * bound
    }

    fn pole_total(&self, z: f64) -> f64 {
        0.5 * self.strength * z.signum() * (-self.sigma_tr * z.abs()).exp()
    }

    /// R(r) in 1/mm² at the entry face, summing `pairs` image pairs each side.
    pub fn reflectance(&self, r: f64, pairs: usize) -> f64 {
        self.sum_poles(pairs, |zr, zv| {
            pole(zr, r, self.sigma_tr) - pole(zv, r, self.sigma_tr)
        })
    }

    /// T(r) in 1/mm² at the opposite face.
    pub fn transmittance(&self, r: f64, pairs: usize) -> f64 {
        if self.is_semi_infinite() {
            return 0.0;
        }
        let d = self.thickness;
        self.sum_poles(pairs, |zr, zv| {
            pole(d - zr, r, self.sigma_tr) - pole(d - zv, r, self.sigma_tr)
        })
    }

    /// ∫_0^r 2πs R(s) ds, the reflectance inside radius r.
    pub fn enclosed_reflectance(&self, r: f64, pairs: usize) -> f64 {
        self.sum_poles(pairs, |zr, zv| {
            pole_enclosed(zr, r, self.sigma_tr) - pole_enclosed(zv, r, self.sigma_tr)
        })
    }

    fn sum_poles(&self, pairs: usize, term: impl Fn(f64, f64) -> f64) -> f64 {
        let n = if self.is_semi_infinite() {
            0
        } else {
            pairs as i64
        };
        // Smallest terms first keeps the alternating sum accurate.
        let (mut sum, mut magnitude) = (0.0, 0.0);
        let mut add = |(zr, zv): (f64, f64)| {
            let t = term(zr, zv);
            sum += t;
            magnitude += t.abs();
        };
        for i in (1..=n).rev() {
            add(self.poles(i));
            add(self.poles(-i));
        }
        add(self.poles(0));
        // Far out (r ≫ |z|) the images cancel to below the round-off of
        // ρ = √(r² + z²) in each term, and the sign of what is left is
        // noise; a larger negative would be a real error and stays.
        if sum < 0.0 && -sum <= 1e-9 * magnitude {
            sum = 0.0;
        }
        self.strength * sum
    }
}

/// One pole's flux density through the plane at lateral distance `r`:
/// z(1+σρ)e^{−σρ}/(4πρ³), 1/mm².
pub fn pole(z: f64, r: f64, sigma_tr: f64) -> f64 {
    let rho2 = r * r + z * z;
    if rho2 == 0.0 {
        return 0.0;
    }
    let rho = rho2.sqrt();
    z * (1.0 + sigma_tr * rho) * (-sigma_tr * rho).exp() / (4.0 * PI * rho2 * rho)
}

/// ∫_0^r 2πs·pole(z, s) ds = ½(sgn(z)e^{−σ|z|} − z e^{−σρ}/ρ).
pub fn pole_enclosed(z: f64, r: f64, sigma_tr: f64) -> f64 {
    let rho = (r * r + z * z).sqrt();
    if rho == 0.0 {
        return 0.0;
    }
    0.5 * (z.signum() * (-sigma_tr * z.abs()).exp() - z * (-sigma_tr * rho).exp() / rho)
}
