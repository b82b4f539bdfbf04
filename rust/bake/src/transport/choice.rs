//! `--method auto`: which integrator suits this object and profile, and why.

use super::Method;
use super::integrator::Integrator;
use super::texture_space::MAX_REACH;

/// Pairs the exact sum may visit before it stops being the cheap choice:
/// about 7 s on two cores at the walk's 7·10⁷ pairs a second (fewer where
/// texels are unlit), which on the bundled head at 512² in skin1 beats the
/// octree with its error check (docs/speed.md "Speed").
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

/// The method `auto` moves to after `integrator` missed its tolerance:
/// the one its integrator names, but the exact sum only where it stays
/// affordable (`texels` × `neighbours` pairs); `None` when nothing more
/// exact is affordable.
pub fn more_exact(integrator: &dyn Integrator, texels: usize, neighbours: f64) -> Option<Method> {
    let brute_affordable = texels as f64 * neighbours <= FALLBACK_PAIRS;
    integrator
        .more_exact()
        .filter(|&next| next != Method::Brute || brute_affordable)
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

/// `choice` again where the share `crossing` of the light comes across
/// thin parts (crate::transport::thin): texture space cannot carry it, so
/// where that share alone would exceed half the `tolerance` the octree
/// takes the object instead.
pub fn avoid_thin_parts(choice: Choice, crossing: f64, tolerance: f64) -> Choice {
    if choice.method != Method::Texture || crossing <= 0.5 * tolerance {
        return choice;
    }
    Choice {
        method: Method::Octree,
        reason: format!(
            "{:.1}% of the light crosses parts thinner than the profile's reach, which texture-space blurs do not carry",
            100.0 * crossing
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transport::integrator::IntegratorSettings;

    #[test]
    fn falling_back_stays_affordable() {
        let all = IntegratorSettings::default();
        let next = |method, texels, neighbours| more_exact(all.get(method), texels, neighbours);
        assert_eq!(next(Method::Texture, 1000, 100.0), Some(Method::Octree));
        assert_eq!(next(Method::Importance, 1000, 100.0), Some(Method::Octree));
        assert_eq!(next(Method::Octree, 1000, 100.0), Some(Method::Brute));
        assert_eq!(next(Method::Octree, 1_000_000, FALLBACK_PAIRS), None);
        assert_eq!(next(Method::Brute, 10, 1.0), None);
        assert_eq!(next(Method::Walk, 10, 1.0), None);
    }

    #[test]
    fn thin_parts_turn_texture_space_away() {
        let texture = || Choice {
            method: Method::Texture,
            reason: String::new(),
        };
        assert_eq!(
            avoid_thin_parts(texture(), 0.004, 0.01).method,
            Method::Texture
        );
        assert_eq!(
            avoid_thin_parts(texture(), 0.02, 0.01).method,
            Method::Octree
        );
        let brute = Choice {
            method: Method::Brute,
            reason: String::new(),
        };
        assert_eq!(avoid_thin_parts(brute, 0.5, 0.01).method, Method::Brute);
    }
}
