//! The reference: the exact discrete sum M(x) = Σ_j P(|x − x_j|) E_j A_j
//! over every source within d_max, in parallel over targets.

use super::Method;
use super::disk_kernel::{DiskKernel, Slot};
use super::integrator::{Integrated, Integrator};
use super::kernel::{Kernel, Separation};
use super::sources::{Grid, OwnSource, Sources, Targets};
use crate::control::{Cancelled, Control, parallel_fill};
use crate::error::Error;
use crate::pipeline::Prepared;
use crate::scattering::Scattering;
use glam::Vec3;

/// Sub-samples per side of a texel's parallelogram in the near field.
const SUBDIVISIONS: usize = 4;

/// Sources copied into grid order, so a row of cells is a contiguous run.
pub(super) struct Sorted {
    pub grid: Grid,
    pub position: Vec<Vec3>,
    pub normal: Vec<Vec3>,
    pub slot: Vec<Slot>,
    pub flux: Vec<[f32; 3]>,
    /// Each source's weight for its own light: the reflectance within its
    /// parallelogram (a disk of its area when it has none) over its area,
    /// 1/mm², computed exactly rather than read between the table's sizes,
    /// which for a profile sharper than a texel would misstate all of it.
    pub own: Vec<[f32; 3]>,
    /// Each source's place in this order, by its index in the sources.
    pub rank: Vec<u32>,
    /// Texel parallelograms (empty for shapeless samples), with the slot of
    /// a sub-sample and the squared radius within which they are used.
    pub footprint: Vec<([Vec3; 2], Slot, f32)>,
}

impl Sorted {
    pub fn new(sources: &Sources, cell: f32, disks: &DiskKernel) -> Self {
        let grid = Grid::new(&sources.position, cell);
        let order = &grid.order;
        let pick = |i: &u32| *i as usize;
        let shaped = sources.footprint.len() == sources.len();
        let sub = (SUBDIVISIONS * SUBDIVISIONS) as f32;
        Sorted {
            position: order.iter().map(|i| sources.position[pick(i)]).collect(),
            normal: order.iter().map(|i| sources.normal[pick(i)]).collect(),
            slot: order
                .iter()
                .map(|i| disks.slot(sources.area[pick(i)]))
                .collect(),
            flux: order
                .iter()
                .map(|i| {
                    let a = sources.area[pick(i)];
                    sources.irradiance[pick(i)].map(|e| e * a)
                })
                .collect(),
            own: order
                .iter()
                .map(|i| match sources.footprint.get(pick(i)) {
                    Some(&[u, v]) if u.cross(v).length() > 0.0 => {
                        disks.kernel().parallelogram_mean(u, v)
                    }
                    _ => {
                        let area = sources.area[pick(i)];
                        let radius = (area.max(0.0) * std::f32::consts::FRAC_1_PI).sqrt();
                        disks.kernel().disk_mean(0.0, radius)[0]
                    }
                })
                .collect(),
            rank: {
                let mut rank = vec![0u32; order.len()];
                for (sorted, &i) in order.iter().enumerate() {
                    rank[i as usize] = sorted as u32;
                }
                rank
            },
            footprint: if shaped {
                order
                    .iter()
                    .map(|i| {
                        let [u, v] = sources.footprint[pick(i)];
                        let near = 2.0 * (u.length() + v.length());
                        ([u, v], disks.slot(sources.area[pick(i)] / sub), near * near)
                    })
                    .collect()
            } else {
                Vec::new()
            },
            grid,
        }
    }

    /// Σ over sources within the kernel's reach of `p` of P·flux. Texels
    /// near `p` are integrated over their parallelogram, in sub-samples,
    /// rather than as one disk: a stretched texel's footprint is long and
    /// thin, and texels crowded at a UV pole overlap as disks.
    #[inline]
    pub fn gather(&self, disks: &DiskKernel, p: Vec3, n: Vec3, own: Option<usize>) -> [f64; 3] {
        let own = own.and_then(|i| self.rank.get(i)).map(|&r| r as usize);
        let kernel = disks.kernel();
        let reach2 = kernel.d_max * kernel.d_max;
        let transmits = kernel.transmits();
        let mut sum = [0.0f64; 3];
        self.grid.for_each_run(p, kernel.d_max, |run| {
            for j in run {
                let d2 = (self.position[j] - p).length_squared();
                if d2 > reach2 {
                    continue;
                }
                // A texel's own light is its disk mean (the reflectance
                // within its disk, however sharp the profile); its
                // neighbours' are integrated over their parallelograms.
                let w = match self.footprint.get(j) {
                    _ if own == Some(j) => self.own[j],
                    Some(&(edges, sub_slot, near2)) if d2 < near2 => {
                        self.footprint_weight(disks, j, edges, sub_slot, p, n)
                    }
                    _ => {
                        let separation =
                            Separation::new(self.position[j], self.normal[j], p, n, d2, transmits);
                        disks.weight(separation, self.slot[j])
                    }
                };
                let f = self.flux[j];
                for c in 0..3 {
                    sum[c] += (w[c] * f[c]) as f64;
                }
            }
        });
        sum
    }

    /// The mean weight over source `j`'s parallelogram `edges`, from
    /// SUBDIVISIONS² sub-samples each standing for its share of the area.
    fn footprint_weight(
        &self,
        disks: &DiskKernel,
        j: usize,
        edges: [Vec3; 2],
        sub_slot: Slot,
        p: Vec3,
        n: Vec3,
    ) -> [f32; 3] {
        let transmits = disks.kernel().transmits();
        let mut w = [0.0f32; 3];
        let step = 1.0 / SUBDIVISIONS as f32;
        for a in 0..SUBDIVISIONS {
            for b in 0..SUBDIVISIONS {
                let offset = edges[0] * ((a as f32 + 0.5) * step - 0.5)
                    + edges[1] * ((b as f32 + 0.5) * step - 0.5);
                let q = self.position[j] + offset;
                let d2 = (q - p).length_squared();
                let separation = Separation::new(q, self.normal[j], p, n, d2, transmits);
                let v = disks.weight(separation, sub_slot);
                for c in 0..3 {
                    w[c] += v[c];
                }
            }
        }
        w.map(|v| v * step * step)
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
    // Texels' sub-samples need the table to reach down to their size.
    let shaped = sources.footprint.len() == sources.len() && !sources.is_empty();
    let smallest = if shaped {
        lo / (SUBDIVISIONS * SUBDIVISIONS) as f32
    } else {
        lo
    };
    let disks = DiskKernel::new(kernel, smallest, hi);
    let sorted = Sorted::new(sources, 0.5 * kernel.d_max, &disks);
    let mut out = vec![[0.0f32; 3]; targets.position.len()];
    parallel_fill(&mut out, 256, control, |i| {
        sorted
            .gather(
                &disks,
                targets.position[i],
                targets.normal[i],
                targets.own.of(i),
            )
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

/// The exact discrete sum over every texel within d_max: the reference
/// every other method is measured against. It has no settings.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BruteIntegrator;

impl Integrator for BruteIntegrator {
    fn method(&self) -> Method {
        Method::Brute
    }

    fn integrate(
        &self,
        prepared: &Prepared,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Integrated, Error> {
        let sources = prepared.texel_sources();
        // The targets are the texels the sources were made from, in order.
        let targets = Targets {
            own: OwnSource::Same,
            ..prepared.targets()
        };
        let exitance = integrate(&scattering.kernel, &sources, targets, control)?;
        Ok(Integrated {
            exitance,
            sources: sources.len(),
        })
    }
}
