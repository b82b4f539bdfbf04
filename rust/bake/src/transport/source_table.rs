//! Sources copied into the order an integrator walks them, with what the
//! weight of each (source, target) pair needs: the one definition of a
//! pair's weight that the exact sum and the octree's leaves share, so the
//! octree at ε = 0 is the exact sum, not an approximation of it.

use super::disk_kernel::{DiskKernel, Slot};
use super::kernel::{Kernel, Separation};
use super::sources::Sources;
use glam::Vec3;

/// Sub-samples per side of a texel's parallelogram in the near field.
pub(super) const SUBDIVISIONS: usize = 4;

/// Sources in a walking order, structure of arrays.
pub(super) struct SourceTable {
    pub position: Vec<Vec3>,
    pub normal: Vec<Vec3>,
    pub slot: Vec<Slot>,
    pub flux: Vec<[f32; 3]>,
    /// Each source's area, mm², for the weight of its own light when it has
    /// no parallelogram.
    pub area: Vec<f32>,
    /// Each source's place in this order, by its index in the sources.
    pub rank: Vec<u32>,
    /// Texel parallelograms (empty for shapeless samples), with the slot of
    /// a sub-sample and the squared radius within which they are used.
    pub footprint: Vec<([Vec3; 2], Slot, f32)>,
}

impl SourceTable {
    /// `sources` in `order` (indices into them), with slots in `disks`.
    pub fn new(sources: &Sources, order: &[u32], disks: &DiskKernel) -> Self {
        let pick = |i: &u32| *i as usize;
        let shaped = sources.footprint.len() == sources.len();
        let sub = (SUBDIVISIONS * SUBDIVISIONS) as f32;
        SourceTable {
            position: order.iter().map(|i| sources.position[pick(i)]).collect(),
            normal: order.iter().map(|i| sources.normal[pick(i)]).collect(),
            slot: order
                .iter()
                .map(|i| disks.slot(disk_area(sources, pick(i))))
                .collect(),
            flux: order
                .iter()
                .map(|i| {
                    let a = sources.area[pick(i)];
                    sources.irradiance[pick(i)].map(|e| e * a)
                })
                .collect(),
            area: order.iter().map(|i| sources.area[pick(i)]).collect(),
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
                        let near = subdivision_radius(u, v);
                        ([u, v], disks.slot(sources.area[pick(i)] / sub), near * near)
                    })
                    .collect()
            } else {
                Vec::new()
            },
        }
    }

    /// The place in this order of source `i`, if it is one.
    pub fn rank_of(&self, i: Option<usize>) -> Option<usize> {
        i.and_then(|i| self.rank.get(i)).map(|&r| r as usize)
    }

    /// P·flux of source `j` (this order) at exit `p` with normal `n`,
    /// `d2` = |x_j − p|² within the kernel's reach. A texel's own light
    /// (`own`) is weighed by the reflectance within its parallelogram;
    /// texels near `p` are integrated over their parallelogram in
    /// sub-samples rather than as one disk: a stretched texel's footprint
    /// is long and thin, and texels crowded at a UV pole overlap as disks.
    #[inline]
    pub fn contribution(
        &self,
        disks: &DiskKernel,
        j: usize,
        p: Vec3,
        n: Vec3,
        d2: f32,
        own: Option<usize>,
    ) -> [f32; 3] {
        let w = match self.footprint.get(j) {
            _ if own == Some(j) => self.own_weight(disks, j),
            Some(&(edges, sub_slot, near2)) if d2 < near2 => {
                self.footprint_weight(disks, j, edges, sub_slot, p, n)
            }
            _ => {
                let transmits = disks.kernel().transmits();
                let separation =
                    Separation::new(self.position[j], self.normal[j], p, n, d2, transmits);
                disks.weight(separation, self.slot[j])
            }
        };
        let f = self.flux[j];
        [w[0] * f[0], w[1] * f[1], w[2] * f[2]]
    }

    /// Source `j`'s weight for its own light: the reflectance within its
    /// parallelogram (a disk of its area when it has none) over its area,
    /// 1/mm², computed exactly rather than read between the table's sizes,
    /// which for a profile sharper than a texel would misstate all of it.
    /// Computed when asked (once per target), so a check of a few texels
    /// does not pay for every texel's.
    fn own_weight(&self, disks: &DiskKernel, j: usize) -> [f32; 3] {
        match self.footprint.get(j) {
            Some(&([u, v], _, _)) if u.cross(v).length() > 0.0 => {
                disks.kernel().parallelogram_mean(u, v)
            }
            _ => {
                let radius = (self.area[j].max(0.0) * std::f32::consts::FRAC_1_PI).sqrt();
                disks.kernel().disk_mean(0.0, radius)[0]
            }
        }
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

/// The area (mm²) of the disk that stands for source `i` beyond its
/// neighbours: the disk with its parallelogram's second moment about the
/// centre, (|u|² + |v|²)/12 = a²/2, so the profile's curvature across it
/// is weighed as across the texel (a square's disk is 1.05× its area, a
/// 2:1 rectangle's 1.31×; the disk of equal area would understate both).
/// A sample without a shape is the disk of its area.
fn disk_area(sources: &Sources, i: usize) -> f32 {
    match sources.footprint.get(i) {
        Some(&[u, v]) if u.cross(v).length() > 0.0 => {
            std::f32::consts::PI * (u.length_squared() + v.length_squared()) / 6.0
        }
        _ => sources.area[i],
    }
}

/// The disk means that `sources` and their sub-samples need.
pub(super) fn texel_disks<'k>(kernel: &'k Kernel, sources: &Sources) -> DiskKernel<'k> {
    let (mut lo, mut hi) = (f32::INFINITY, 0.0f32);
    for i in 0..sources.len() {
        let sub = sources.area[i] / (SUBDIVISIONS * SUBDIVISIONS) as f32;
        let disk = disk_area(sources, i);
        lo = lo.min(sub).min(disk);
        hi = hi.max(sub).max(disk);
    }
    DiskKernel::new(kernel, lo, hi)
}

/// The distance (mm) within which a texel with edges `u`, `v` is summed in
/// sub-samples rather than as the disk of its area. A texel close to a
/// square has nearly a disk's second moments, so beyond its adjacent
/// texels the disk with its second moment (see [`disk_area`]) is the same
/// to the anisotropic part of the curvature term, which cancels around a
/// target; a texel stretched beyond 2:1 differs from its disk wherever the
/// profile curves across it, so it is subdivided four texels out.
fn subdivision_radius(u: Vec3, v: Vec3) -> f32 {
    // Eigenvalues of the parallelogram's second-moment tensor u uᵀ + v vᵀ
    // in its plane.
    let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
    let mean = 0.5 * (uu + vv);
    let spread = (0.25 * (uu - vv) * (uu - vv) + uv * uv).sqrt();
    let (large, small) = (mean + spread, mean - spread);
    if large <= 4.0 * small {
        1.5 * uu.max(vv).sqrt()
    } else {
        2.0 * (u.length() + v.length())
    }
}
