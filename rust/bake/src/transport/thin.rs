//! How much of an object's scattered light crosses its thin parts.
//!
//! The exact sum gathers from every texel within the profile's reach in 3-D,
//! so where the object is thinner than that reach (an ear, a nostril's rim,
//! a leaf) light arrives from the far face as well. Texture-space blurs see
//! only the surface around a texel in its chart and miss that light. For
//! two parallel faces a thickness t apart under the same light, the far face
//! gives ∫_plane P(√(ρ² + t²)) dA = 2π ∫_t^∞ P(r) r dr of the exitance, the
//! profile's reflectance beyond radius t: the share 1 − E(t)/R, E the
//! enclosed reflectance and R the total. Averaged over the surface by area,
//! it is the share of the exact sum that texture space cannot carry.

use crate::mesh::Mesh;
use crate::rays::RayScene;
use crate::surface::texels::TexelSurfels;
use rayon::prelude::*;
use sssbake_profile::profile::Profile;

/// Texels probed: enough to find thin parts of a few percent of the area.
const PROBES: usize = 2048;

/// The area-weighted mean, over about [`PROBES`] texels spread through the
/// layout, of the share of a texel's exitance (the largest over the
/// channels) that comes across the object's thickness below it, under a
/// profile reaching `d_max` mm; 0 where the object is thicker than that.
pub fn crossing_share(
    mesh: &Mesh,
    surfels: &TexelSurfels,
    profile: &dyn Profile,
    d_max: f32,
) -> f64 {
    let total = profile.total_reflectance();
    let (share, area) = probed_thickness(mesh, surfels, d_max)
        .into_iter()
        .map(|(s, t)| {
            let area = f64::from(surfels.area[s].max(0.0));
            let share = t.map_or(0.0, |t| {
                let enclosed = profile.enclosed_reflectance(f64::from(t));
                (0..3)
                    .filter(|&c| total[c] > 0.0)
                    .map(|c| (1.0 - enclosed[c] / total[c]).clamp(0.0, 1.0))
                    .fold(0.0, f64::max)
            });
            (share * area, area)
        })
        .fold((0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
    if area > 0.0 { share / area } else { 0.0 }
}

/// At most the share of an object's texels (by count) with a face behind
/// nearer than `thinner_than` mm, from about [`PROBES`] texels spread
/// through the layout: the share found, raised by three standard errors
/// and three probes' worth; 0 when no probe finds one (a part too small to
/// meet a probe holds few texels). What thin parts hold is planned by it
/// ([`crate::transport::slab_profiles::SlabProfiles::planned_bytes`]).
pub fn thin_share(mesh: &Mesh, surfels: &TexelSurfels, thinner_than: f32) -> f64 {
    let probed = probed_thickness(mesh, surfels, thinner_than);
    let thin = probed.iter().filter(|(_, t)| t.is_some()).count();
    if thin == 0 {
        return 0.0;
    }
    let (n, share) = (probed.len() as f64, thin as f64 / probed.len() as f64);
    (share + 3.0 * (share * (1.0 - share) / n).sqrt() + 3.0 / n).min(1.0)
}

/// About [`PROBES`] surfels spread through the layout, each with the
/// distance (mm) to where the object ends below it when nearer than
/// `t_max` mm; none for an empty layout or a `t_max` that is not positive.
fn probed_thickness(mesh: &Mesh, surfels: &TexelSurfels, t_max: f32) -> Vec<(usize, Option<f32>)> {
    let count = surfels.len();
    if count == 0 || t_max.is_nan() || t_max <= 0.0 {
        return Vec::new();
    }
    let rays = RayScene::new(&[mesh]);
    let stride = count.div_ceil(PROBES).max(1);
    (0..count)
        .into_par_iter()
        .step_by(stride)
        .map(|s| (s, inward_thickness(&rays, surfels, s, t_max)))
        .collect()
}

/// The distance (mm) along surfel `s`'s inward normal to where the object
/// ends, when that is nearer than `t_max` mm.
pub(crate) fn inward_thickness(
    rays: &RayScene,
    surfels: &TexelSurfels,
    s: usize,
    t_max: f32,
) -> Option<f32> {
    let inward = -surfels.normal[s];
    let origin = surfels.position[s] + inward * rays.epsilon();
    let mut nearest = f32::INFINITY;
    rays.for_each_hit(origin, inward, rays.epsilon(), t_max, |hit| {
        if hit.triangle != surfels.triangle[s] {
            nearest = nearest.min(hit.t);
        }
    });
    nearest.is_finite().then_some(nearest)
}
