//! The walks of [`crate::walk`] started at an object's texels.

use crate::control::{Cancelled, Control};
use crate::prepared::Prepared;
use crate::walk::{
    Enclosure, ExitLight, WalkEstimate, WalkMedium, WalkSettings, WalkTargets, walk_exitance,
};
use glam::Vec3;

/// The walks' exitance (before the colour after scattering) at the
/// surfels `picked` of `prepared` (every surfel when `None`), leaving into
/// the light entering it.
pub fn walk_surfels(
    prepared: &Prepared,
    medium: &WalkMedium,
    picked: Option<&[usize]>,
    settings: &WalkSettings,
    control: &Control,
) -> Result<WalkEstimate, Cancelled> {
    let surfels = &prepared.surfels;
    let all: Vec<usize>;
    let picked = match picked {
        Some(picked) => picked,
        None => {
            all = (0..surfels.len()).collect();
            &all
        }
    };
    let position: Vec<Vec3> = picked.iter().map(|&i| surfels.position[i]).collect();
    let normal: Vec<Vec3> = picked.iter().map(|&i| surfels.normal[i]).collect();
    let triangle: Vec<u32> = picked.iter().map(|&i| surfels.triangle[i]).collect();
    let texture = prepared.entering_texture();
    walk_exitance(
        &Enclosure::new(&prepared.mesh, &prepared.uvs),
        &ExitLight {
            irradiance: &texture,
            resolution: surfels.resolution,
        },
        medium,
        &WalkTargets {
            position: &position,
            normal: &normal,
            triangle: &triangle,
        },
        settings,
        control,
    )
}
