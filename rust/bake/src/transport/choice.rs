//! `--method auto`: which integrator suits this object and profile, and why.

use super::Method;
use super::texture_space::MAX_REACH;

/// Pairs the exact sum may visit before it stops being the cheap choice:
/// about 7 s on two cores at the walk's 7·10⁷ pairs a second (fewer where
/// texels are unlit), which on the bundled head at 512² in skin1 beats the
/// octree with its error check (README "Speed").
const BRUTE_PAIRS: f64 = 5e8;

/// The chosen method and the reason, for the plan and the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    /// The method to run.
    pub method: Method,
    /// Why, in one sentence.
    pub reason: String,
}

/// Texels within `d_max_mm` of a texel of mean area `texel_area_mm2`.
pub fn neighbours(texel_area_mm2: f64, d_max_mm: f64) -> f64 {
    (std::f64::consts::PI * d_max_mm * d_max_mm / texel_area_mm2.max(1e-12)).max(1.0)
}

/// Pairs the exact sum may visit when `auto` falls back to it (about a
/// minute on two cores); beyond, the octree is as exact as a bake gets.
const FALLBACK_PAIRS: f64 = 10.0 * BRUTE_PAIRS;

/// The next more exact method after `method` missed its tolerance: the
/// octree (over the texels, its error set by ε alone, and cheaper than the
/// exact sum wherever the sum is not cheap), then the exact sum where it
/// stays affordable; `None` when nothing more exact is affordable.
pub fn more_exact(method: Method, texels: usize, neighbours: f64) -> Option<Method> {
    let brute_affordable = texels as f64 * neighbours <= FALLBACK_PAIRS;
    match method {
        Method::Brute | Method::Auto => None,
        Method::Texture | Method::Importance => Some(Method::Octree),
        Method::Octree if brute_affordable => Some(Method::Brute),
        Method::Octree => None,
    }
}

/// Chooses for `texels` surfels of mean area `texel_area_mm2` under a
/// profile reaching `d_max_mm`, which carries light through thin parts
/// when `transmits`.
pub fn choose(texels: usize, texel_area_mm2: f64, d_max_mm: f64, transmits: bool) -> Choice {
    let neighbours = neighbours(texel_area_mm2, d_max_mm);
    let pairs = texels as f64 * neighbours;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falling_back_stays_affordable() {
        assert_eq!(
            more_exact(Method::Texture, 1000, 100.0),
            Some(Method::Octree)
        );
        assert_eq!(
            more_exact(Method::Importance, 1000, 100.0),
            Some(Method::Octree)
        );
        assert_eq!(more_exact(Method::Octree, 1000, 100.0), Some(Method::Brute));
        let huge = FALLBACK_PAIRS;
        assert_eq!(more_exact(Method::Octree, 1_000_000, huge), None);
        assert_eq!(more_exact(Method::Brute, 10, 1.0), None);
    }
}
