//! `--method auto`: which integrator suits this object and profile, and why.

use super::Method;
use super::texture_space::MAX_REACH;

/// Pairs the exact sum may visit before it stops being the cheap choice.
const BRUTE_PAIRS: f64 = 3e8;

/// The chosen method and the reason, for the plan and the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    /// The method to run.
    pub method: Method,
    /// Why, in one sentence.
    pub reason: String,
}

/// Chooses for `texels` surfels of mean area `texel_area_mm2` under a
/// profile reaching `d_max_mm`, which carries light through thin parts
/// when `transmits`.
pub fn choose(texels: usize, texel_area_mm2: f64, d_max_mm: f64, transmits: bool) -> Choice {
    let neighbours = std::f64::consts::PI * d_max_mm * d_max_mm / texel_area_mm2.max(1e-12);
    let pairs = texels as f64 * neighbours.max(1.0);
    let reach_texels = d_max_mm / texel_area_mm2.max(1e-12).sqrt();
    let (method, reason) = if pairs <= BRUTE_PAIRS {
        (
            Method::Brute,
            format!(
                "the exact sum is cheap here ({texels} texels × {neighbours:.0} within d_max = {d_max_mm:.3} mm)"
            ),
        )
    } else if transmits {
        (
            Method::Octree,
            "the material transmits through thin parts, which only the 3-D integrators carry"
                .to_string(),
        )
    } else if reach_texels <= MAX_REACH as f64 {
        (
            Method::Texture,
            format!(
                "the profile reaches {reach_texels:.1} texels: separable blurs in texture space are the fastest within a few percent"
            ),
        )
    } else {
        (
            Method::Octree,
            format!(
                "the profile reaches {reach_texels:.0} texels, wider than texture-space blurs go ({MAX_REACH})"
            ),
        )
    };
    Choice { method, reason }
}
