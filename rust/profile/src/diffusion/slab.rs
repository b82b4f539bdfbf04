//! One slab (or a semi-infinite medium) in one channel, and its response to
//! light per spatial frequency.
//!
//! Depth z runs into the slab from the side the light enters ("near"); the
//! slab fills 0 ≤ z ≤ d. Light entering is replaced by an isotropic source
//! of strength α' at depth ℓ = 1/σt' (Mikkelsen 2.6); each face obeys the
//! diffusion boundary condition φ ∓ h ∂φ/∂z = 0 with h = 2AD (eq. 23).
//!
//! Two solutions of that problem live here. The image series of Donner &
//! Jensen 2005 ([`crate::diffusion::images`]) satisfies each boundary condition only
//! at an extrapolated plane h outside the face; per frequency it sums to
//! [`SlabChannel::image_response`]. Where a slab is thin next to the
//! difference of its two extrapolation distances, |h_top − h_bottom| > d,
//! that approximation puts the fluence maximum outside the slab and its
//! profiles turn negative. [`SlabChannel::frequency_response`] instead
//! solves the 1-D problem per frequency exactly (q = √(σtr² + k²)):
//! with u(z) = sinh(qz) + q h_n cosh(qz) meeting the near face and
//! v(z) = sinh(q(d−z)) + q h_f cosh(q(d−z)) the far face,
//! R̂ = α' q v(z_s)/W and T̂ = α' q u(z_s)/W, W = u'v − uv'. The exitance
//! is then the fluence at the face over h, which is never negative, so the
//! layered profiles built from it are not either.

use crate::boundary::fresnel::dielectric_reflectance;
use crate::boundary::rough;
use crate::diffusion::medium::Medium;
use crate::diffusion::split::{Split, SplitSlab};

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

/// One face of a slab, seen from inside: the relative index across it
/// (n_slab / n_beyond) and the RMS slope of its facets, with the two
/// reflectances the slab needs, computed once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// Relative index n_slab / n_beyond.
    pub eta: f64,
    /// RMS facet slope m; 0 is smooth.
    pub roughness: f64,
    /// Internal diffuse reflectance: F_dr, or ρd when rough.
    pub diffuse_reflectance: f64,
    /// Internal reflectance at normal incidence.
    pub normal_reflectance: f64,
}

impl Face {
    /// A smooth face of relative index `eta`.
    pub fn smooth(eta: f64) -> Self {
        Self::new(eta, 0.0)
    }

    /// A face of relative index `eta` and RMS facet slope `roughness`.
    pub fn new(eta: f64, roughness: f64) -> Self {
        let normal_reflectance = if roughness > 0.0 {
            rough::directional_albedo(1.0, eta, 1.0, roughness)
        } else {
            dielectric_reflectance(1.0, eta, 1.0)
        };
        Self {
            eta,
            roughness,
            diffuse_reflectance: rough::diffuse_reflectance(eta, roughness),
            normal_reflectance,
        }
    }

    /// The boundary constant A = (1 + ρd)/(1 − ρd) (eq. 7, or eq. 24 rough).
    pub fn boundary_a(&self) -> f64 {
        let rho = self.diffuse_reflectance.min(1.0 - 1e-12);
        (1.0 + rho) / (1.0 - rho)
    }
}

/// One slab in one channel, ready to evaluate.
#[derive(Clone, Debug)]
pub struct SlabChannel {
    /// Source strength: α', reduced for slabs thinner than two mean free paths.
    pub(crate) strength: f64,
    /// What thin slabs return and pass without scattering: deltas at r = 0,
    /// constant in frequency; zero for slabs at least 2ℓ thick.
    ballistic: SlabResponse,
    /// σtr, 1/mm.
    pub(crate) sigma_tr: f64,
    /// Thickness d in mm; infinite for a semi-infinite medium.
    pub(crate) thickness: f64,
    /// Depth of the real source below the entry face, mm.
    pub(crate) source_depth: f64,
    /// h = 2AD of the top face (the extrapolation distance), mm.
    pub(crate) zb_top: f64,
    /// h = 2AD of the bottom face, mm.
    pub(crate) zb_bottom: f64,
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
        Self::with_faces(
            medium,
            thickness_mm,
            Face::smooth(eta_top),
            Face::smooth(eta_bottom),
            from_above,
        )
    }

    /// [`Self::new`] with faces that may be rough (Donner & Jensen 2005
    /// §2.4): each face's diffuse reflectance ρd sets its boundary constant
    /// A = (1 + ρd)/(1 − ρd) (eq. 24) and the bounces of the unscattered
    /// light.
    pub fn with_faces(
        medium: Medium,
        thickness_mm: f64,
        top: Face,
        bottom: Face,
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
                Incidence::Collimated => (bottom.normal_reflectance, top.normal_reflectance),
                Incidence::Diffuse => (bottom.diffuse_reflectance, top.diffuse_reflectance),
            },
            (top.diffuse_reflectance, bottom.diffuse_reflectance),
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
            zb_top: 2.0 * top.boundary_a() * diffusion,
            zb_bottom: 2.0 * bottom.boundary_a() * diffusion,
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

    /// The exact solution's responses at angular spatial frequency `k`
    /// (rad/mm), used to combine layers; at k = 0 they are its totals. They
    /// include the unscattered light, [`Self::ballistic`]; at k = ∞ they
    /// are that light alone.
    pub fn frequency_response(&self, k: f64) -> SlabResponse {
        self.split_response(k).map(Split::total)
    }

    /// [`Self::frequency_response`] kept in its unscattered and diffuse parts.
    pub fn split_response(&self, k: f64) -> SplitSlab {
        SplitSlab::new(self.ballistic, self.diffuse(k, Self::exact_side))
    }

    /// The image series' responses at `k` in closed form (Mikkelsen
    /// eq. 31–32 summed over every pole), with the unscattered light.
    pub fn image_response(&self, k: f64) -> SlabResponse {
        SplitSlab::new(self.ballistic, self.diffuse(k, Self::image_side)).map(Split::total)
    }

    /// The image series' diffuse response to light from above at `k`,
    /// without the unscattered part.
    pub fn image_diffuse(&self, k: f64) -> SideResponse {
        self.diffuse(k, Self::image_side).down
    }

    /// The diffuse responses from both sides by one of the two solutions.
    fn diffuse(&self, k: f64, side: fn(&Self, f64, f64, f64) -> SideResponse) -> SlabResponse {
        let q = (self.sigma_tr * self.sigma_tr + k * k).sqrt();
        SlabResponse {
            down: side(self, q, self.zb_top, self.zb_bottom),
            up: side(self, q, self.zb_bottom, self.zb_top),
        }
    }

    /// Total diffuse reflectance and transmittance of the image series for
    /// light from above, without the unscattered part.
    pub fn image_totals(&self) -> SideResponse {
        self.image_diffuse(0.0)
    }

    /// The exact 1-D Green's function, divided through by e^{qd}/2 so that
    /// nothing overflows: x = d − z_s is the source's distance to the far face.
    fn exact_side(&self, q: f64, h_near: f64, h_far: f64) -> SideResponse {
        let (alpha, z) = (self.strength, self.source_depth);
        if alpha == 0.0 || q.is_infinite() {
            return SideResponse {
                reflectance: 0.0,
                transmittance: 0.0,
            };
        }
        if self.is_semi_infinite() {
            return SideResponse {
                reflectance: alpha * (-q * z).exp() / (1.0 + q * h_near),
                transmittance: 0.0,
            };
        }
        let d = self.thickness;
        let x = d - z;
        let length = d + h_near + h_far;
        if q * length < 1e-10 {
            // q → 0: the Green's function becomes linear in z.
            return SideResponse {
                reflectance: alpha * (x + h_far) / length,
                transmittance: alpha * (z + h_near) / length,
            };
        }
        // (1 − e^{−2qy}) and (1 + e^{−2qy}) without cancellation.
        let minus = |y: f64| -(-2.0 * q * y).exp_m1();
        let plus = |y: f64| 1.0 + (-2.0 * q * y).exp();
        let wronskian = (1.0 + q * q * h_near * h_far) * minus(d) + q * (h_near + h_far) * plus(d);
        SideResponse {
            reflectance: alpha * (-q * z).exp() * (minus(x) + q * h_far * plus(x)) / wronskian,
            transmittance: alpha * (-q * x).exp() * (minus(z) + q * h_near * plus(z)) / wronskian,
        }
    }

    /// The image series summed per frequency: the 1-D Green's function of
    /// the slab with zero fluence at the extrapolated planes,
    /// R̂ = α' cosh(q h_n) sinh(q(d + h_f − z_s)) / sinh(qL),
    /// T̂ = α' sinh(q(z_s + h_n)) cosh(q h_f) / sinh(qL), L = d + h_n + h_f.
    fn image_side(&self, q: f64, zb_near: f64, zb_far: f64) -> SideResponse {
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
