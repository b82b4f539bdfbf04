//! The dipole of Jensen et al. 2001 in the corrected form of Mikkelsen eq. 30,
//! for a semi-infinite medium under a boundary of relative index η.

use crate::boundary::rough::boundary_a;
use crate::diffusion::images::{pole, pole_enclosed};
use crate::diffusion::medium::Medium;
use crate::numerics::roots::radius_where;
use crate::profile::Profile;
use crate::{Rgb, rgb_map};

/// One channel of a dipole.
#[derive(Clone, Copy, Debug)]
struct DipoleChannel {
    albedo: f64,
    sigma_tr: f64,
    /// Depth of the real source, ℓ = 1/σt', mm.
    z_r: f64,
    /// Height of the virtual source, ℓ + 4AD, mm.
    z_v: f64,
    /// Boundary constant A.
    a: f64,
}

/// A semi-infinite medium's reflectance by the classical dipole.
#[derive(Clone, Debug)]
pub struct Dipole {
    channels: [DipoleChannel; 3],
}

impl Dipole {
    /// The dipole of a medium per channel below a boundary with relative
    /// index `eta` = n_medium / n_outside.
    pub fn new(media: [Medium; 3], eta: f64) -> Self {
        Self::with_roughness(media, eta, 0.0)
    }

    /// [`Self::new`] under a rough boundary of RMS facet slope `roughness`:
    /// A from the boundary's diffuse reflectance ρd (Donner & Jensen 2005
    /// eq. 24).
    pub fn with_roughness(media: [Medium; 3], eta: f64, roughness: f64) -> Self {
        let a = boundary_a(eta, roughness);
        Self {
            channels: media.map(|m| DipoleChannel {
                albedo: m.albedo_reduced(),
                sigma_tr: m.sigma_tr(),
                z_r: m.mean_free_path(),
                z_v: m.mean_free_path() + 4.0 * a * m.diffusion(),
                a,
            }),
        }
    }

    /// Fraction of the reflectance falling outside radius `s` (Mikkelsen eq. 40).
    pub fn fraction_outside(&self, s: f64) -> Rgb {
        rgb_map(|c| {
            let ch = &self.channels[c];
            let d_r = (s * s + ch.z_r * ch.z_r).sqrt();
            let d_v = (s * s + ch.z_v * ch.z_v).sqrt();
            let denominator = (-ch.sigma_tr * ch.z_v).exp() + (-ch.sigma_tr * ch.z_r).exp();
            let numerator = ch.z_r / d_r * (-ch.sigma_tr * d_r).exp()
                + ch.z_v / d_v * (-ch.sigma_tr * d_v).exp();
            if denominator > 0.0 {
                (numerator / denominator).clamp(0.0, 1.0)
            } else {
                0.0
            }
        })
    }
}

/// Total diffuse reflectance of the dipole in closed form:
/// α'/2 · (1 + e^{−(4/3)A√(3(1−α'))}) e^{−√(3(1−α'))}.
pub fn dipole_total_reflectance(albedo_reduced: f64, a: f64) -> f64 {
    let s = (3.0 * (1.0 - albedo_reduced.clamp(0.0, 1.0))).sqrt();
    0.5 * albedo_reduced * (1.0 + (-4.0 / 3.0 * a * s).exp()) * (-s).exp()
}

impl Profile for Dipole {
    fn model(&self) -> &'static str {
        "dipole"
    }

    fn reflectance(&self, r: f64) -> Rgb {
        rgb_map(|c| {
            let ch = &self.channels[c];
            ch.albedo * (pole(ch.z_r, r, ch.sigma_tr) + pole(ch.z_v, r, ch.sigma_tr))
        })
    }

    fn total_reflectance(&self) -> Rgb {
        rgb_map(|c| dipole_total_reflectance(self.channels[c].albedo, self.channels[c].a))
    }

    /// Each source transforms to ½e^{−z√(σtr² + k²)}.
    fn reflectance_spectrum(&self, k: f64) -> Option<Rgb> {
        Some(rgb_map(|c| {
            let ch = &self.channels[c];
            let q = (ch.sigma_tr * ch.sigma_tr + k * k).sqrt();
            0.5 * ch.albedo * ((-q * ch.z_r).exp() + (-q * ch.z_v).exp())
        }))
    }

    /// Mertens et al. 2003 §4: pick the real or the virtual source by its
    /// share of the reflectance inside `r_max` (from `xi`, which, rescaled
    /// to the chosen share, is again uniform and places the radius), then
    /// invert that source's
    /// enclosed fraction ½(e^{−σz} − z e^{−σρ}/ρ) for ρ = √(r² + z²) by
    /// Newton's method on σρ + ln ρ (increasing and concave, so Newton from
    /// ρ = z climbs to the root without overshooting).
    fn sample_radius(&self, channel: usize, xi: f64, r_max: f64) -> Option<f64> {
        let ch = self.channels.get(channel)?;
        let sigma = ch.sigma_tr;
        if !(sigma > 0.0 && r_max > 0.0) {
            return None;
        }
        let mass = |z: f64| {
            let rho = (r_max * r_max + z * z).sqrt();
            0.5 * ((-sigma * z).exp() - z * (-sigma * rho).exp() / rho)
        };
        let (m_r, m_v) = (mass(ch.z_r), mass(ch.z_v));
        if (m_r + m_v).is_nan() || m_r + m_v <= 0.0 {
            return None;
        }
        let split = xi.clamp(0.0, 1.0) * (m_r + m_v);
        let (z, within) = if split < m_r {
            (ch.z_r, split / m_r)
        } else {
            (ch.z_v, ((split - m_r) / m_v).min(1.0))
        };
        let target = (-sigma * z).exp() - 2.0 * within * mass(z);
        let rho_max = (r_max * r_max + z * z).sqrt();
        if target.is_nan() || target <= 0.0 {
            return Some(r_max);
        }
        let goal = z.ln() - target.ln();
        let mut rho = z;
        for _ in 0..50 {
            let h = sigma * rho + rho.ln() - goal;
            let step = h / (sigma + 1.0 / rho);
            rho -= step;
            if step.abs() <= 1e-12 * rho {
                break;
            }
        }
        let rho = rho.clamp(z, rho_max);
        Some((rho * rho - z * z).max(0.0).sqrt())
    }

    fn enclosed_reflectance(&self, r: f64) -> Rgb {
        rgb_map(|c| {
            let ch = &self.channels[c];
            ch.albedo
                * (pole_enclosed(ch.z_r, r, ch.sigma_tr) + pole_enclosed(ch.z_v, r, ch.sigma_tr))
        })
    }

    fn length_scale(&self) -> Rgb {
        rgb_map(|c| {
            let ch = &self.channels[c];
            (1.0 / ch.sigma_tr).min(100.0 * ch.z_v).max(ch.z_r)
        })
    }

    /// Solves Mikkelsen eq. 40, ε(s) = `epsilon`, with the safeguarded root finder.
    fn d_max(&self, epsilon: f64) -> Rgb {
        let scale = self.length_scale();
        rgb_map(|c| {
            if self.channels[c].albedo <= 0.0 {
                return 0.0;
            }
            radius_where(
                |s| 1.0 - self.fraction_outside(s)[c],
                1.0 - epsilon,
                scale[c],
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn skin1() -> Dipole {
        let media =
            [(0.032, 0.74), (0.17, 0.88), (0.48, 1.01)].map(|(sigma_a, sigma_s_reduced)| Medium {
                sigma_a,
                sigma_s_reduced,
            });
        Dipole::new(media, 1.3)
    }

    #[test]
    fn eq_40_agrees_with_the_enclosed_reflectance() {
        let dipole = skin1();
        let total = dipole.total_reflectance();
        for s in [0.01, 0.5, 2.0, 10.0] {
            let outside = dipole.fraction_outside(s);
            let enclosed = dipole.enclosed_reflectance(s);
            for c in 0..3 {
                assert!((outside[c] - (1.0 - enclosed[c] / total[c])).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn d_max_holds_all_but_epsilon() {
        let dipole = skin1();
        for epsilon in [1e-1, 1e-3, 1e-6] {
            let d_max = dipole.d_max(epsilon);
            let outside = rgb_map(|c| dipole.fraction_outside(d_max[c])[c]);
            for c in 0..3 {
                assert!(
                    (outside[c] - epsilon).abs() < 1e-9 * epsilon.max(1e-3),
                    "{epsilon}: {outside:?}"
                );
            }
        }
        assert!(
            skin1().d_max(1e-3)[0] > skin1().d_max(1e-3)[2],
            "red reaches farther than blue"
        );
    }
}
