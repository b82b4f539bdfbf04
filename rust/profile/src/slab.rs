//! One slab (or a semi-infinite medium) in one channel: the multipole of
//! Donner & Jensen 2005 with signed pole positions (Mikkelsen eq. 31–32), in
//! real space and in closed form per spatial frequency.
//!
//! Depth z runs into the slab from the side the light enters ("near"); the
//! slab fills 0 ≤ z ≤ d. The extrapolated boundaries lie z_b = 2AD outside
//! each face. Every pole z(1+σtr ρ)e^{−σtr ρ}/(4πρ³), ρ = √(r²+z²), has the
//! 2-D Fourier transform ½·sgn(z)·e^{−|z|√(σtr²+k²)}, so the infinite image
//! series sums to the 1-D Green's function of the extrapolated slab:
//! R̂(k) = α' cosh(q z_b,near) sinh(q(d + z_b,far − z_s)) / sinh(qL),
//! T̂(k) = α' sinh(q(z_s + z_b,near)) cosh(q z_b,far) / sinh(qL),
//! with q = √(σtr² + k²) and L = d + z_b,near + z_b,far. Both are written
//! below in overflow-free exponential form.

use crate::fresnel::{boundary_a, dielectric_reflectance, diffuse_reflectance_exact};
use crate::medium::Medium;
use std::f64::consts::PI;

/// Most image pairs a real-space evaluation will sum; beyond this the series
/// converges too slowly (σtr·thickness → 0) and callers tabulate the closed
/// frequency form instead.
pub const MAX_POLE_PAIRS: usize = 600;

/// Reflectance and transmittance of a slab for light entering from one side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SideResponse {
    /// Diffuse reflectance back out of the entry face.
    pub reflectance: f64,
    /// Diffuse transmittance out of the opposite face.
    pub transmittance: f64,
}

/// Frequency responses of a slab lit from above (`down`) and from below (`up`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlabResponse {
    /// R⁺ and T⁺: light entering the top face.
    pub down: SideResponse,
    /// R⁻ and T⁻: light entering the bottom face.
    pub up: SideResponse,
}

/// How light arriving from above is distributed: the top layer receives the
/// refracted beam (collimated, normal incidence); deeper layers receive the
/// diffuse light of the layers above.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Incidence {
    /// A beam at normal incidence.
    Collimated,
    /// Diffuse light.
    Diffuse,
}

/// One slab in one channel, ready to evaluate.
#[derive(Clone, Debug)]
pub struct SlabChannel {
    /// Source strength: α', reduced for slabs thinner than two mean free paths.
    strength: f64,
    /// What thin slabs return and pass without scattering: deltas at r = 0,
    /// constant in frequency; zero for slabs at least 2ℓ thick.
    ballistic: SlabResponse,
    /// σtr, 1/mm.
    sigma_tr: f64,
    /// Thickness d in mm; infinite for a semi-infinite medium.
    thickness: f64,
    /// Depth of the real source below the entry face, mm.
    source_depth: f64,
    /// Extrapolation distance 2AD above the top face, mm.
    zb_top: f64,
    /// Extrapolation distance 2AD below the bottom face, mm.
    zb_bottom: f64,
}

impl SlabChannel {
    /// A slab of `medium`, `thickness_mm` thick (infinite for a semi-infinite
    /// medium), with relative indices `eta_top` = n_slab/n_above and
    /// `eta_bottom` = n_slab/n_below.
    ///
    /// The diffusion source sits one mean free path ℓ deep. A slab thinner
    /// than 2ℓ cannot hold it: there the source moves to mid-depth and takes
    /// a share w = (1 − e^{−σt' d})/(1 − e^{−2}) of the light, the share that
    /// interacts inside the slab scaled to meet the ordinary multipole
    /// continuously at d = 2ℓ; the rest, b = 1 − w, crosses unscattered and
    /// bounces between the two faces by their Fresnel reflectance (at normal
    /// incidence for collimated light from above, the diffuse F_dr for light
    /// from below) until it leaves. As d → 0 the slab becomes a pair of
    /// interfaces instead of producing nonsense.
    pub fn new(
        medium: Medium,
        thickness_mm: f64,
        eta_top: f64,
        eta_bottom: f64,
        from_above: Incidence,
    ) -> Self {
        let sigma_t = medium.sigma_t_reduced();
        let diffusion = medium.diffusion();
        let ell = medium.mean_free_path();
        let mut share = 1.0;
        let mut source_depth = ell;
        if thickness_mm < 2.0 * ell {
            source_depth = 0.5 * thickness_mm;
            share = (-(-sigma_t * thickness_mm).exp_m1() / -(-2.0f64).exp_m1()).clamp(0.0, 1.0);
        }
        let b = 1.0 - share;
        let (down_faces, up_faces) = (
            match from_above {
                Incidence::Collimated => (
                    dielectric_reflectance(1.0, eta_bottom, 1.0),
                    dielectric_reflectance(1.0, eta_top, 1.0),
                ),
                Incidence::Diffuse => (
                    diffuse_reflectance_exact(eta_bottom),
                    diffuse_reflectance_exact(eta_top),
                ),
            },
            (
                diffuse_reflectance_exact(eta_top),
                diffuse_reflectance_exact(eta_bottom),
            ),
        );
        Self {
            strength: medium.albedo_reduced() * share,
            ballistic: SlabResponse {
                down: bounce_between_faces(b, down_faces),
                up: bounce_between_faces(b, up_faces),
            },
            sigma_tr: medium.sigma_tr(),
            thickness: thickness_mm,
            source_depth,
            zb_top: 2.0 * boundary_a(eta_top) * diffusion,
            zb_bottom: 2.0 * boundary_a(eta_bottom) * diffusion,
        }
    }

    /// True for a semi-infinite medium.
    pub fn is_semi_infinite(&self) -> bool {
        self.thickness.is_infinite()
    }

    /// The light a thin slab reflects and transmits without scattering:
    /// deltas at r = 0 that [`Self::frequency_response`] includes and the
    /// real-space R(r), T(r) leave out.
    pub fn ballistic(&self) -> SlabResponse {
        self.ballistic
    }

    /// σtr, 1/mm.
    pub fn sigma_tr(&self) -> f64 {
        self.sigma_tr
    }

    /// Characteristic lengths (shortest, longest) in mm, for choosing grids.
    pub fn length_scales(&self) -> (f64, f64) {
        // The shallowest pole and the nearest pole to the far face set the
        // finest detail; the transport length or the slab sets the reach.
        let to_far_face = self.thickness - self.source_depth;
        let shortest = if to_far_face > 0.0 {
            self.source_depth.min(to_far_face)
        } else {
            self.source_depth
        };
        let mut longest = (1.0 / self.sigma_tr).min(1e7);
        if self.thickness.is_finite() {
            longest = longest.max(self.thickness + self.zb_top + self.zb_bottom);
        }
        (
            shortest.max(1e-12),
            longest.max(self.source_depth + 2.0 * self.zb_top),
        )
    }

    /// Closed-form responses at angular spatial frequency `k` (rad/mm); at
    /// k = 0 they are the exact total reflectance and transmittance. The
    /// responses include the unscattered light, [`Self::ballistic`]; at
    /// k = ∞ they are that light alone.
    pub fn frequency_response(&self, k: f64) -> SlabResponse {
        let q = (self.sigma_tr * self.sigma_tr + k * k).sqrt();
        let add = |a: SideResponse, b: SideResponse| SideResponse {
            reflectance: a.reflectance + b.reflectance,
            transmittance: a.transmittance + b.transmittance,
        };
        SlabResponse {
            down: add(
                self.side(q, self.zb_top, self.zb_bottom),
                self.ballistic.down,
            ),
            up: add(self.side(q, self.zb_bottom, self.zb_top), self.ballistic.up),
        }
    }

    fn side(&self, q: f64, zb_near: f64, zb_far: f64) -> SideResponse {
        let half = 0.5 * self.strength;
        let z = self.source_depth;
        if half == 0.0 || q.is_infinite() {
            return SideResponse {
                reflectance: 0.0,
                transmittance: 0.0,
            };
        }
        if self.is_semi_infinite() {
            return SideResponse {
                reflectance: half * (-q * z).exp() * (1.0 + (-2.0 * q * zb_near).exp()),
                transmittance: 0.0,
            };
        }
        let d = self.thickness;
        let length = d + zb_near + zb_far;
        // sinh(qx)/sinh(qL) · e^{q(L−x)}, stable for all q ≥ 0.
        let ratio = |x: f64| {
            if q * length < 1e-8 {
                x / length
            } else {
                (-2.0 * q * x).exp_m1() / (-2.0 * q * length).exp_m1()
            }
        };
        SideResponse {
            reflectance: half
                * (-q * z).exp()
                * (1.0 + (-2.0 * q * zb_near).exp())
                * ratio(d + zb_far - z),
            transmittance: half
                * (-q * (d - z)).exp()
                * (1.0 + (-2.0 * q * zb_far).exp())
                * ratio(z + zb_near),
        }
    }

    /// Total diffuse reflectance and transmittance for light from above,
    /// without the unscattered part.
    pub fn diffuse_totals(&self) -> SideResponse {
        self.side(self.sigma_tr, self.zb_top, self.zb_bottom)
    }

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
        let exact = self.diffuse_totals();
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

    /// ∫_0^r 2πs T(s) ds, the transmittance inside radius r.
    pub fn enclosed_transmittance(&self, r: f64, pairs: usize) -> f64 {
        if self.is_semi_infinite() {
            return 0.0;
        }
        let d = self.thickness;
        self.sum_poles(pairs, |zr, zv| {
            pole_enclosed(d - zr, r, self.sigma_tr) - pole_enclosed(d - zv, r, self.sigma_tr)
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

/// Unscattered light of share `b` entering one face and bouncing between
/// the far face (reflectance `faces.0`) and the entry face (`faces.1`). The
/// share is fixed on the first crossing; the bounces keep it whole, so
/// what enters leaves: reflectance + transmittance = b.
fn bounce_between_faces(b: f64, faces: (f64, f64)) -> SideResponse {
    let (far, near) = faces;
    let round_trips = 1.0 - far * near;
    if b <= 0.0 || round_trips <= 0.0 {
        return SideResponse {
            reflectance: 0.0,
            transmittance: 0.0,
        };
    }
    SideResponse {
        reflectance: b * far * (1.0 - near) / round_trips,
        transmittance: b * (1.0 - far) / round_trips,
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
