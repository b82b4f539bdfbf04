//! Texture-space diffusion (d'Eon & Luebke 2007; Mikkelsen §3.4): the
//! profile as a sum of Gaussians, each a separable blur of the irradiance
//! texture, each built from the previous one by the difference of their
//! variances. Each texel's taps are spaced by its own stretch (mm per
//! texel along u and v), so the blur is measured on the surface, not in
//! UV space. Texels outside the layout are dilated first (across seams
//! where the caller gives seam-aware offsets) so blurs near chart borders
//! read the surface that continues there instead of black.
//!
//! The blur knows only the surface around each texel in the layout: light
//! cannot cross thin parts (ears, nostrils) to the far face; the 3-D
//! integrators do that.

use super::Method;
use super::integrator::{Integrated, Integrator};
use crate::control::{Cancelled, Control};
use crate::error::Error;
use crate::pipeline::Prepared;
use crate::scattering::Scattering;
use crate::surface::texels::TexelSurfels;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sssbake_profile::gaussians::SumOfGaussians;
use sssbake_profile::gaussians::fit_gaussians;

/// Blurs whose σ is below this many texels are skipped (a Gaussian that
/// narrow leaves a texel grid unchanged to within its sampling).
const SHARP: f32 = 0.2;

/// The widest blur, in texels either side; wider Gaussians are truncated.
pub const MAX_REACH: u32 = 512;

/// Radiant exitance (W/m²) at each surfel by texture-space blurs of its
/// irradiance. `dilation` lists (empty texel, covered texel it copies).
pub fn integrate(
    gaussians: &SumOfGaussians,
    surfels: &TexelSurfels,
    irradiance: &[[f32; 3]],
    dilation: &[(u32, u32)],
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let n = surfels.resolution as usize;
    let texels = n * n;
    // Stretch per texel (mm per texel step), dilated with the irradiance.
    let mut stretch = vec![glam::Vec2::ZERO; texels];
    for (s, &t) in surfels.texel.iter().enumerate() {
        stretch[t as usize] = surfels.stretch[s];
    }
    for &(to, from) in dilation {
        stretch[to as usize] = stretch[from as usize];
    }
    let blurs: usize = gaussians.terms.iter().map(Vec::len).sum();
    control.plan((2 * blurs * texels) as u64);
    let mut out = vec![[0.0f32; 3]; surfels.len()];
    for c in 0..3 {
        let mut image = vec![0.0f32; texels];
        for (s, &t) in surfels.texel.iter().enumerate() {
            image[t as usize] = irradiance[s][c];
        }
        for &(to, from) in dilation {
            image[to as usize] = image[from as usize];
        }
        let mut terms = gaussians.terms[c].clone();
        terms.sort_by(|a, b| a.1.total_cmp(&b.1));
        let mut variance = 0.0f64;
        for (weight, v) in terms {
            let step = (v - variance).max(0.0);
            variance = v.max(variance);
            image = blur(&image, &stretch, n, step as f32, Axis::U, control)?;
            image = blur(&image, &stretch, n, step as f32, Axis::V, control)?;
            for (s, &t) in surfels.texel.iter().enumerate() {
                out[s][c] += weight as f32 * image[t as usize];
            }
        }
    }
    Ok(out)
}

#[derive(Clone, Copy, PartialEq)]
enum Axis {
    U,
    V,
}

/// One 1-D Gaussian pass of `variance` (mm²) along `axis`, gathering: each
/// texel's σ in texels is √variance over its own stretch along the axis.
fn blur(
    image: &[f32],
    stretch: &[glam::Vec2],
    n: usize,
    variance: f32,
    axis: Axis,
    control: &Control,
) -> Result<Vec<f32>, Cancelled> {
    if variance <= 0.0 {
        control.advance(image.len() as u64)?;
        return Ok(image.to_vec());
    }
    let sigma_mm = variance.sqrt();
    let mut out = vec![0.0f32; image.len()];
    out.par_chunks_mut(n).enumerate().try_for_each(|(y, row)| {
        control.check()?;
        let mut weights: Vec<f32> = Vec::new();
        for (x, value) in row.iter_mut().enumerate() {
            let texel = y * n + x;
            let step = match axis {
                Axis::U => stretch[texel].x,
                Axis::V => stretch[texel].y,
            };
            let sigma = if step > 0.0 { sigma_mm / step } else { 0.0 };
            if sigma.is_nan() || sigma < SHARP {
                *value = image[texel];
                continue;
            }
            let reach = ((3.0 * sigma).ceil() as u32).min(MAX_REACH) as i64;
            weights.clear();
            weights
                .extend((-reach..=reach).map(|k| (-(k * k) as f32 / (2.0 * sigma * sigma)).exp()));
            // Taps beyond the image's edge are left out and the rest
            // renormalised: a chart touching the edge continues past it (a
            // seam the layout cut there); it does not end.
            let (mut sum, mut norm) = (0.0f32, 0.0f32);
            for (i, k) in (-reach..=reach).enumerate() {
                let (sx, sy) = match axis {
                    Axis::U => (x as i64 + k, y as i64),
                    Axis::V => (x as i64, y as i64 + k),
                };
                if sx < 0 || sy < 0 || sx >= n as i64 || sy >= n as i64 {
                    continue;
                }
                sum += weights[i] * image[sy as usize * n + sx as usize];
                norm += weights[i];
            }
            *value = if norm > 0.0 { sum / norm } else { image[texel] };
        }
        control.advance(n as u64)
    })?;
    Ok(out)
}

/// d'Eon & Luebke's texture-space diffusion: the profile fitted by a sum
/// of Gaussians, each a separable blur of the irradiance texture.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TextureIntegrator {
    /// Gaussians in the fit, 1 to [`MAX_GAUSSIANS`].
    pub gaussians: usize,
}

/// The most Gaussians a fit takes.
pub const MAX_GAUSSIANS: usize = 16;

impl Default for TextureIntegrator {
    fn default() -> Self {
        TextureIntegrator { gaussians: 6 }
    }
}

impl TextureIntegrator {
    /// Refuses settings it cannot run with.
    pub fn validate(&self) -> Result<(), Error> {
        if !(1..=MAX_GAUSSIANS).contains(&self.gaussians) {
            return Err(Error::field(
                "texture.gaussians",
                format!("{} must be between 1 and {MAX_GAUSSIANS}", self.gaussians),
            ));
        }
        Ok(())
    }
}

impl Integrator for TextureIntegrator {
    fn method(&self) -> Method {
        Method::Texture
    }

    fn integrate(
        &self,
        prepared: &Prepared,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Integrated, Error> {
        let fit = fit_gaussians(scattering.profile.as_ref(), self.gaussians);
        let exitance = integrate(
            &fit.gaussians,
            &prepared.surfels,
            &prepared.entering(),
            prepared.dilation(),
            control,
        )?;
        Ok(Integrated {
            exitance,
            sources: 0,
        })
    }
}
