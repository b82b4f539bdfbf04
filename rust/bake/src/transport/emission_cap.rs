//! Energy: no source sends out more than the profile lets it.
//!
//! On a plane a source's weights add up to the reflectance within d_max;
//! where the surface folds back on itself, or where samples crowd (texels
//! squeezed at a UV pole), the discrete weights can add up to more, and
//! the sum would create light. Each source's weights are therefore summed
//! over the sources around it, as receivers of its light, and its flux is
//! scaled down where that sum exceeds R + T within d_max.

use super::brute::Sorted;
use super::disk_kernel::DiskKernel;
use super::kernel::Kernel;
use super::sources::Sources;
use crate::control::{Cancelled, Control, parallel_fill};

/// Scales down the irradiance of every source of `sources` whose weights
/// over the others exceed what the profile emits within d_max. Meant for
/// texels, whose weights add up to the profile's within 0.1 % on a plane.
pub fn cap_emission(
    kernel: &Kernel,
    sources: &mut Sources,
    control: &Control,
) -> Result<(), Cancelled> {
    let (lo, hi) = super::brute::area_range(&sources.area);
    let disks = DiskKernel::new(kernel, lo, hi);
    let reflected = kernel.enclosed(kernel.d_max);
    let transmitted = kernel.enclosed_transmittance(kernel.d_max);
    let cap: [f32; 3] = [0, 1, 2].map(|c| reflected[c] + transmitted[c]);
    // Receivers are the sources themselves, each with unit irradiance.
    let receivers = Sources {
        irradiance: vec![[1.0; 3]; sources.len()],
        ..sources.clone()
    };
    let sorted = Sorted::new(&receivers, 0.5 * kernel.d_max, &disks);
    let mut scale = vec![[1.0f32; 3]; sources.len()];
    parallel_fill(&mut scale, 256, control, |j| {
        let slot = disks.slot(sources.area[j]);
        let p = sources.position[j];
        let n = sources.normal[j];
        let spread = sorted.spread(&disks, p, n, slot);
        [0, 1, 2].map(|c| {
            if spread[c] > cap[c] as f64 && spread[c] > 0.0 {
                (cap[c] as f64 / spread[c]) as f32
            } else {
                1.0
            }
        })
    })?;
    for (e, s) in sources.irradiance.iter_mut().zip(&scale) {
        for c in 0..3 {
            e[c] *= s[c];
        }
    }
    Ok(())
}
