//! The reference: the exact discrete sum M(x) = Σ_j P(|x − x_j|) E_j A_j
//! over every source within d_max, in parallel over targets.

use super::disk_kernel::{DiskKernel, Slot};
use super::kernel::{Kernel, Separation};
use super::sources::{Grid, Sources, Targets};
use crate::control::{Cancelled, Control, parallel_fill};
use glam::Vec3;

/// Sources copied into grid order, so a row of cells is a contiguous run.
pub(super) struct Sorted {
    pub grid: Grid,
    pub position: Vec<Vec3>,
    pub normal: Vec<Vec3>,
    pub slot: Vec<Slot>,
    pub flux: Vec<[f32; 3]>,
}

impl Sorted {
    pub fn new(sources: &Sources, cell: f32, disks: &DiskKernel) -> Self {
        let grid = Grid::new(&sources.position, cell);
        let pick = |i: &u32| *i as usize;
        Sorted {
            position: grid
                .order
                .iter()
                .map(|i| sources.position[pick(i)])
                .collect(),
            normal: grid.order.iter().map(|i| sources.normal[pick(i)]).collect(),
            slot: grid
                .order
                .iter()
                .map(|i| disks.slot(sources.area[pick(i)]))
                .collect(),
            flux: grid
                .order
                .iter()
                .map(|i| {
                    let a = sources.area[pick(i)];
                    sources.irradiance[pick(i)].map(|e| e * a)
                })
                .collect(),
            grid,
        }
    }

    /// Σ over the samples within reach of a source at `p` with normal `n`
    /// in `slot` of its weight for them × their area: how much of its flux
    /// the source would send out.
    pub fn spread(&self, disks: &DiskKernel, p: Vec3, n: Vec3, slot: Slot) -> [f64; 3] {
        let kernel = disks.kernel();
        let reach2 = kernel.d_max * kernel.d_max;
        let mut sum = [0.0f64; 3];
        self.grid.for_each_run(p, kernel.d_max, |run| {
            for k in run {
                let d2 = (self.position[k] - p).length_squared();
                if d2 > reach2 {
                    continue;
                }
                // The source at p sends to receiver k.
                let separation = Separation::new(
                    p,
                    n,
                    self.position[k],
                    self.normal[k],
                    d2,
                    kernel.transmits(),
                );
                let w = disks.weight(separation, slot);
                // Receivers carry unit irradiance, so their flux is their area.
                let area = self.flux[k][0];
                for c in 0..3 {
                    sum[c] += (w[c] * area) as f64;
                }
            }
        });
        sum
    }

    /// Σ over sources within the kernel's reach of `p` of P·flux.
    #[inline]
    pub fn gather(&self, disks: &DiskKernel, p: Vec3, n: Vec3) -> [f64; 3] {
        let kernel = disks.kernel();
        let reach2 = kernel.d_max * kernel.d_max;
        let mut sum = [0.0f64; 3];
        self.grid.for_each_run(p, kernel.d_max, |run| {
            for j in run {
                let d2 = (self.position[j] - p).length_squared();
                if d2 > reach2 {
                    continue;
                }
                let separation = Separation::new(
                    self.position[j],
                    self.normal[j],
                    p,
                    n,
                    d2,
                    kernel.transmits(),
                );
                let w = disks.weight(separation, self.slot[j]);
                let f = self.flux[j];
                for c in 0..3 {
                    sum[c] += (w[c] * f[c]) as f64;
                }
            }
        });
        sum
    }
}

/// Radiant exitance (W/m²) at each target by the exact sum over `sources`.
pub fn integrate(
    kernel: &Kernel,
    sources: &Sources,
    targets: Targets,
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let (lo, hi) = area_range(&sources.area);
    let disks = DiskKernel::new(kernel, lo, hi);
    let sorted = Sorted::new(sources, 0.5 * kernel.d_max, &disks);
    let mut out = vec![[0.0f32; 3]; targets.position.len()];
    parallel_fill(&mut out, 256, control, |i| {
        sorted
            .gather(&disks, targets.position[i], targets.normal[i])
            .map(|v| v as f32)
    })?;
    Ok(out)
}

/// The smallest and largest of `areas` (mm²).
pub(super) fn area_range(areas: &[f32]) -> (f32, f32) {
    areas.iter().fold((f32::INFINITY, 0.0f32), |(lo, hi), &a| {
        (lo.min(a), hi.max(a))
    })
}
