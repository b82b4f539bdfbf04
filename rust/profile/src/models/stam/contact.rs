//! A Stam layer whose top face is against air and whose bottom face is in
//! optical contact with a medium of its own index: a surface layer (an
//! epidermis) lying on the layer beneath it in a stack. Mode 0 only, so
//! the totals: R(θi) and T(θi) for light from air, and the response to
//! Lambertian light arriving from the medium below.
//!
//! The contact face neither reflects nor refracts: the radiance crosses it
//! on the inside ordinates as it is. A stack whose next layer has another
//! index puts that step in the next layer's own diffusion boundary, as the
//! layered stack does at every face between layers ([`crate::models::layered`]).

use super::boundary;
use super::eigen;
use super::ordinates::Ordinates;
use super::phase;
use super::solve::solve_between;
use super::{MAX_ALBEDO, StamError, StamLayer};
use nalgebra::DMatrix;
use std::f64::consts::PI;

/// A layer's totals with the bottom face in contact.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactTotals {
    /// Outside (air) cosines, increasing, in (0, 1).
    pub cosines: Vec<f64>,
    /// Their weights (Σ w μ = 1/2).
    pub weights: Vec<f64>,
    /// R(θi): the share of collimated light from air at each outside
    /// ordinate that returns to air (the face's own reflection included).
    pub reflectance: Vec<f64>,
    /// T(θi): the share that crosses into the medium below (scattered and
    /// unscattered).
    pub transmittance: Vec<f64>,
    /// The share of Lambertian light from below that returns below.
    pub reflectance_from_below: f64,
    /// The share of Lambertian light from below that leaves into air.
    pub transmittance_from_below: f64,
    /// π·L(θo)/M for that light: the radiance leaving into air at each
    /// outside ordinate per unit of the exitance M it makes, times π (1 at
    /// every angle for a Lambertian exitance; 2 Σ w μ of it is 1).
    pub exit_distribution: Vec<f64>,
}

impl StamLayer {
    /// Solves the layer with its bottom face in contact on `ordinates`
    /// ordinates per half range. The top face is the layer's own (smooth,
    /// or rough of its roughness) against air.
    pub fn solve_in_contact(&self, ordinates: usize) -> Result<ContactTotals, StamError> {
        self.validate()?;
        let fail = |e: String| StamError(format!("mode 0: {e}"));
        let rule = Ordinates::new(ordinates, self.eta);
        let terms = rule.exact_degree().div_ceil(2);
        let scattering = phase::delta_m(self.g, self.albedo, terms);
        let scattering = phase::ScaledScattering {
            albedo: scattering.albedo.min(MAX_ALBEDO),
            ..scattering
        };
        let depth = self.optical_depth * scattering.depth_factor;
        let smooth = self.roughness == 0.0 || (self.eta - 1.0).abs() < 1e-9;
        let mut faces = if smooth {
            boundary::smooth(&rule, 1)
        } else {
            boundary::rough(&rule, self.roughness, 1)
        };
        let face = faces.remove(0);
        let (same, opposite) = phase::mode_kernels(0, &scattering, &rule.inside);
        let eigen = eigen::solve_mode(&same, &opposite, &rule.inside, &rule.inside_weights)
            .map_err(fail)?;
        let (m, e) = (rule.inside.len(), rule.outside.len());
        let contact = DMatrix::zeros(m, m);
        let outside_flux =
            |radiance: &DMatrix<f64>| flux(&rule.outside, &rule.outside_weights, radiance);
        let inside_flux =
            |radiance: &DMatrix<f64>| flux(&rule.inside, &rule.inside_weights, radiance);

        // From air: a unit irradiance on each outside ordinate.
        let incident = DMatrix::from_fn(e, e, |o, j| {
            if o == j {
                1.0 / (2.0 * PI * rule.outside_weights[j] * rule.outside[j])
            } else {
                0.0
            }
        });
        let above = solve_between(
            &eigen,
            &face.reflect_inside,
            &contact,
            depth,
            &(&face.transmit_in * &incident),
        )
        .map_err(fail)?;
        let reflected = &face.reflect_outside * &incident + &face.transmit_out * &above.up_at_top;

        // From below: a unit Lambertian flux (radiance 1/π on every inside
        // ordinate) entering through the contact. The layer flipped in
        // depth has the contact on top and the air face below; the phase
        // function and the face operators are the same mirrored.
        let lambertian = DMatrix::from_element(m, 1, 1.0 / PI);
        let below = solve_between(&eigen, &contact, &face.reflect_inside, depth, &lambertian)
            .map_err(fail)?;
        let escaping = &face.transmit_out * &below.down_at_bottom;
        let transmittance_from_below = outside_flux(&escaping)[0];
        let exit_distribution = (0..e)
            .map(|o| {
                if transmittance_from_below > 0.0 {
                    (PI * escaping[(o, 0)] / transmittance_from_below).max(0.0)
                } else {
                    0.0
                }
            })
            .collect();
        Ok(ContactTotals {
            cosines: rule.outside.clone(),
            weights: rule.outside_weights.clone(),
            reflectance: outside_flux(&reflected),
            transmittance: inside_flux(&above.down_at_bottom),
            reflectance_from_below: inside_flux(&below.up_at_top)[0],
            transmittance_from_below,
            exit_distribution,
        })
    }
}

/// 2π Σ w μ L per column: the flux a mode-0 radiance on ordinates
/// `cosines` with weights `weights` carries (round-off below 0 as 0).
fn flux(cosines: &[f64], weights: &[f64], radiance: &DMatrix<f64>) -> Vec<f64> {
    (0..radiance.ncols())
        .map(|j| {
            let sum: f64 = (0..radiance.nrows())
                .map(|o| weights[o] * cosines[o] * radiance[(o, j)])
                .sum();
            (2.0 * PI * sum).max(0.0)
        })
        .collect()
}
