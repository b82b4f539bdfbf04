//! Sources copied into the order an integrator walks them, with what the
//! weight of each (source, target) pair needs: the one definition of a
//! pair's weight that the exact sum and the octree's leaves share, so the
//! octree at ε = 0 is the exact sum, not an approximation of it.

use super::disk_kernel::{DiskKernel, Rows, Slot, split_place};
use super::kernel::{Kernel, Separation};
use super::sample_sizes::SampleSizes;
use super::sources::{Sources, Target};
use glam::{Vec3, Vec4};
use rayon::prelude::*;
use std::borrow::Cow;
use std::sync::Arc;

/// Sub-samples per side of a texel's parallelogram in the near field.
pub(super) const SUBDIVISIONS: usize = 4;

/// How far apart a source and an exit are.
#[derive(Clone, Copy, Debug)]
pub(super) struct Apart {
    /// Their squared straight distance, mm².
    pub distance2: f32,
    /// True when the pair is known to be joined straight through the
    /// medium; else its path is found ([`super::through_medium`]).
    pub straight: bool,
}

impl Apart {
    /// A pair `distance2` mm² apart whose path is yet to be found.
    pub fn unknown(distance2: f32) -> Self {
        Apart {
            distance2,
            straight: false,
        }
    }
}

/// Sources in a walking order with their light, structure of arrays: the
/// sources' places ([`PlacedSources`], which every light on the same
/// sources in the same order shares) and each one's flux.
pub(super) struct SourceTable<'a> {
    placed: Arc<PlacedSources>,
    /// E·A per channel (fourth lane 0).
    pub flux: Vec<Vec4>,
    /// The sources' parallelograms, by their index in the sources (empty
    /// for shapeless samples); borrowed from the layout where the sources
    /// borrow theirs.
    pub footprint: Cow<'a, [[Vec3; 2]]>,
}

/// What a table holds of its sources apart from their light: where each
/// lies and how it is weighed, in the walking order. It depends on the
/// sources' geometry, the order and the disk means' sizes alone, so an
/// integrator that sums several lights over the same sources in the same
/// order (the octree's shape does) makes it once.
pub(super) struct PlacedSources {
    /// The positions' coordinates apart (mm), so distances to a run of
    /// sources are computed a vector at a time ([`SourceTable::position`]).
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
    pub normal: Vec<Vec3>,
    /// Each source's disk-mean slot, in the sizes of [`Self::rows`].
    pub slot: Vec<Slot>,
    /// The disk means' sizes the slots were found in.
    rows: Rows,
    /// Each source's area, mm², for the weight of its own light when it has
    /// no parallelogram.
    pub area: Vec<f32>,
    /// Each source's place in this order, by its index in the sources
    /// (`u32::MAX` for a source the order leaves out).
    pub rank: Vec<u32>,
    /// Each source's index in the sources, by its place in this order.
    order: Vec<u32>,
    /// True when the sources have parallelograms.
    shaped: bool,
    /// The squared radius (mm²) within which a source is summed in
    /// sub-samples (0 for shapeless samples: never).
    pub near2: Vec<f32>,
    /// True when every source's size lies inside the disk means' table.
    pub tabulated: bool,
    /// The medium of each source (empty: all in one).
    pub piece: Vec<u32>,
    /// The piece of its medium each source lies on ([`Sources::part`];
    /// empty: every medium is one piece).
    pub part: Vec<u32>,
}

impl PlacedSources {
    /// Bytes the places hold per source: position, normal, slot, area,
    /// rank, index, sub-sampling radius, medium and piece.
    pub const BYTES_PER_SOURCE: usize =
        2 * std::mem::size_of::<Vec3>() + std::mem::size_of::<Slot>() + 6 * 4;

    /// `sources`' places in `order` (indices into them, each at most once;
    /// sources left out are not placed), with slots in `disks`.
    pub fn new(sources: &Sources, order: &[u32], disks: &DiskKernel) -> Self {
        let shaped = sources.footprint.len() == sources.len();
        let count = order.len();
        let (mut x, mut y, mut z) = (vec![0.0; count], vec![0.0; count], vec![0.0; count]);
        let mut normal = vec![Vec3::ZERO; count];
        let (mut area, mut near2) = (vec![0.0; count], vec![0.0; count]);
        let mut slot = vec![Slot::default(); count];
        // One pass over the order, in chunks, writing every column: the
        // sources are read at random, so each is read once, not once a
        // column (11.6 million sources at 4096²).
        const CHUNK: usize = 8192;
        (
            order.par_chunks(CHUNK),
            x.par_chunks_mut(CHUNK),
            y.par_chunks_mut(CHUNK),
            z.par_chunks_mut(CHUNK),
            normal.par_chunks_mut(CHUNK),
            area.par_chunks_mut(CHUNK),
            near2.par_chunks_mut(CHUNK),
            slot.par_chunks_mut(CHUNK),
        )
            .into_par_iter()
            .for_each(|(order, x, y, z, normal, area, near2, slot)| {
                for (k, &i) in order.iter().enumerate() {
                    let i = i as usize;
                    let p = sources.position[i];
                    (x[k], y[k], z[k]) = (p.x, p.y, p.z);
                    normal[k] = sources.normal[i];
                    area[k] = sources.area[i];
                    if shaped {
                        let [u, v] = sources.footprint[i];
                        near2[k] = subdivision_radius(u, v).powi(2);
                    }
                    slot[k] = disks.slot(disk_area(sources, i));
                }
            });
        // Each source's value in `order`, where every source has one.
        let in_order = |values: &[u32]| -> Vec<u32> {
            if values.len() != sources.len() {
                return Vec::new();
            }
            order.par_iter().map(|&i| values[i as usize]).collect()
        };
        PlacedSources {
            tabulated: slot.par_iter().all(Slot::tabulated),
            slot,
            rows: disks.rows(),
            x,
            y,
            z,
            normal,
            area,
            rank: {
                let mut rank = vec![u32::MAX; sources.len()];
                for (sorted, &i) in order.iter().enumerate() {
                    rank[i as usize] = sorted as u32;
                }
                rank
            },
            order: order.to_vec(),
            shaped,
            near2,
            // Kept only where the sources lie on several pieces: a one-piece
            // object's pairs then skip the lookup.
            piece: if sources.piece.par_iter().any(|&p| p != sources.piece[0]) {
                in_order(&sources.piece)
            } else {
                Vec::new()
            },
            part: in_order(&sources.part),
        }
    }

    /// True when these places were made over `count` sources with slots
    /// in `disks`' sizes.
    pub fn made_for(&self, count: usize, disks: &DiskKernel) -> bool {
        self.rank.len() == count && self.rows == disks.rows()
    }
}

impl std::ops::Deref for SourceTable<'_> {
    type Target = PlacedSources;

    fn deref(&self) -> &PlacedSources {
        &self.placed
    }
}

impl<'a> SourceTable<'a> {
    /// `sources` in `order` (indices into them, each at most once; sources
    /// left out are not in the table), with slots in `disks`.
    pub fn new(sources: &Sources<'a>, order: &[u32], disks: &DiskKernel) -> Self {
        Self::placed(sources, Arc::new(PlacedSources::new(sources, order, disks)))
    }

    /// `sources`' light over their `placed` places, made over the same
    /// sources ([`PlacedSources::made_for`]).
    pub fn placed(sources: &Sources<'a>, placed: Arc<PlacedSources>) -> Self {
        let flux = placed
            .order
            .par_iter()
            .map(|&i| {
                let a = sources.area[i as usize];
                let [r, g, b] = sources.irradiance[i as usize].map(|e| e * a);
                Vec4::new(r, g, b, 0.0)
            })
            .collect();
        SourceTable {
            footprint: if placed.shaped {
                sources.footprint.clone()
            } else {
                Cow::Borrowed(&[])
            },
            placed,
            flux,
        }
    }

    /// Source `j`'s position (this order), mm.
    #[inline]
    pub fn position(&self, j: usize) -> Vec3 {
        Vec3::new(self.x[j], self.y[j], self.z[j])
    }

    /// True when source `j` (this order) and `target` are joined by the
    /// medium ([`Target::joined_to`]).
    #[inline]
    pub fn joins(&self, j: usize, target: &Target) -> bool {
        target.joined_to(
            self.piece.get(j).copied(),
            self.part.get(j).copied(),
            self.position(j),
            self.normal[j],
        )
    }

    /// The place in this order of source `i`, if it is one.
    pub fn rank_of(&self, i: Option<usize>) -> Option<usize> {
        i.and_then(|i| self.rank.get(i))
            .filter(|&&r| r != u32::MAX)
            .map(|&r| r as usize)
    }

    /// P of source `j` (this order) at exit `p` with normal `n`, per unit
    /// of its flux, 1/mm², per channel, as a `Vec4` (the fourth lane 0);
    /// `apart` is how far the pair is within the kernel's reach. A
    /// texel's own light (`own`) is weighed by the reflectance within its
    /// parallelogram; texels near `p` are integrated over their
    /// parallelogram in sub-samples rather than as one disk: a stretched
    /// texel's footprint is long and thin, and texels crowded at a UV pole
    /// overlap as disks.
    #[inline(always)]
    pub fn weight4(
        &self,
        disks: &DiskKernel,
        j: usize,
        p: Vec3,
        n: Vec3,
        apart: Apart,
        own: Option<usize>,
    ) -> Vec4 {
        let d2 = apart.distance2;
        if own == Some(j) {
            self.own_weight(disks, j)
        } else if d2 < self.near2[j] {
            self.footprint_weight(disks, j, p, n)
        } else {
            let transmits = disks.kernel().transmits();
            let (q, m) = (self.position(j), self.normal[j]);
            let separation = if apart.straight {
                Separation::straight(q, m, p, n, d2, transmits)
            } else {
                Separation::new(q, m, p, n, d2, transmits)
            };
            disks.weight4(separation, self.slot[j])
        }
    }

    /// The edges of source `j`'s parallelogram (this order), mm, when the
    /// sources have shapes.
    #[inline]
    fn edges(&self, j: usize) -> Option<[Vec3; 2]> {
        let i = *self.order.get(j).filter(|_| self.shaped)?;
        self.footprint.get(i as usize).copied()
    }

    /// [`Self::weight4`] under a mix of kernels (`mix`: indices into
    /// `disks`, sized alike, with their shares) with each pair placed by
    /// `separate` (from a source point and its normal, how it sits from the
    /// exit at `p`, or `None` where the pair exchanges nothing) instead of
    /// by the kernel's blend of reflection and transmission: for kernels
    /// whose faces the caller tells apart ([`super::slab_profiles`]). `d2`
    /// is the squared distance to the source's centre; the own texel and
    /// texels near `p` are weighed over their parallelograms as there. A
    /// pair is placed once for every kernel of the mix.
    #[inline]
    pub fn weight_placed(
        &self,
        disks: &[DiskKernel],
        mix: &[(usize, f32)],
        j: usize,
        d2: f32,
        own: Option<usize>,
        separate: &impl Fn(Vec3, Vec3) -> Option<Separation>,
    ) -> Vec4 {
        let mixed = |weigh: &dyn Fn(&DiskKernel) -> Vec4| {
            mix.iter()
                .filter(|&&(_, share)| share > 0.0)
                .fold(Vec4::ZERO, |w, &(k, share)| w + share * weigh(&disks[k]))
        };
        if own == Some(j) {
            return mixed(&|disks| self.own_weight(disks, j));
        }
        let m = self.normal[j];
        if d2 < self.near2[j]
            && let Some(edges) = self.edges(j)
        {
            // The kernels' disk means are sized alike: one slot for all.
            let sub_slot = disks[0].slot(self.area[j] / SUB_SAMPLES as f32);
            return self.sub_sampled(j, edges, |q| {
                separate(q, m).map_or(Vec4::ZERO, |s| mixed(&|disks| disks.weight4(s, sub_slot)))
            });
        }
        let slot = self.slot[j];
        separate(self.position(j), m).map_or(Vec4::ZERO, |s| mixed(&|disks| disks.weight4(s, slot)))
    }

    /// Source `j`'s weight for its own light: the reflectance within its
    /// parallelogram (a disk of its area when it has none) over its area,
    /// 1/mm², computed exactly rather than read between the table's sizes,
    /// which for a profile sharper than a texel would misstate all of it.
    /// Computed when asked (once per target), so a check of a few texels
    /// does not pay for every texel's.
    fn own_weight(&self, disks: &DiskKernel, j: usize) -> Vec4 {
        let [r, g, b] = match self.edges(j) {
            Some([u, v]) if u.cross(v).length() > 0.0 => disks.kernel().parallelogram_mean(u, v),
            _ => {
                let radius = (self.area[j].max(0.0) * std::f32::consts::FRAC_1_PI).sqrt();
                disks.kernel().disk_mean(0.0, radius)[0]
            }
        };
        Vec4::new(r, g, b, 0.0)
    }

    /// The mean over source `j`'s parallelogram (`edges`) of `weigh` at
    /// its SUBDIVISIONS² sub-samples, each standing for its share of the
    /// area.
    #[inline]
    fn sub_sampled(&self, j: usize, [u, v]: [Vec3; 2], weigh: impl Fn(Vec3) -> Vec4) -> Vec4 {
        let centre = self.position(j);
        let (along_u, along_v) = sub_sample_offsets();
        let mut w = Vec4::ZERO;
        for k in 0..SUB_SAMPLES {
            w += weigh(centre + (u * along_u[k] + v * along_v[k]));
        }
        let step = 1.0 / SUBDIVISIONS as f32;
        w * (step * step)
    }

    /// The mean weight over source `j`'s parallelogram, from SUBDIVISIONS²
    /// sub-samples each standing for its share of the area.
    fn footprint_weight(&self, disks: &DiskKernel, j: usize, p: Vec3, n: Vec3) -> Vec4 {
        let Some([u, v]) = self.edges(j) else {
            return Vec4::ZERO;
        };
        let sub_slot = disks.slot(self.area[j] / SUB_SAMPLES as f32);
        let transmits = disks.kernel().transmits();
        if transmits || !sub_slot.tabulated() {
            let m = self.normal[j];
            return self.sub_sampled(j, [u, v], |q| {
                let d2 = (q - p).length_squared();
                disks.weight4(Separation::new(q, m, p, n, d2, transmits), sub_slot)
            });
        }
        let centre = self.position(j);
        let (along_u, along_v) = sub_sample_offsets();
        let step = 1.0 / SUBDIVISIONS as f32;
        let mut w = Vec4::ZERO;
        // Reflection only: the sub-samples' distances a vector at a time,
        // then one read each.
        let mut distance = [0.0f32; SUB_SAMPLES];
        let mut entry = [0u32; SUB_SAMPLES];
        let mut fraction = [0.0f32; SUB_SAMPLES];
        for k in 0..SUB_SAMPLES {
            let qx = centre.x + (u.x * along_u[k] + v.x * along_v[k]);
            let qy = centre.y + (u.y * along_u[k] + v.y * along_v[k]);
            let qz = centre.z + (u.z * along_u[k] + v.z * along_v[k]);
            let (dx, dy, dz) = (qx - p.x, qy - p.y, qz - p.z);
            let d = (dx * dx + dy * dy + dz * dz).sqrt();
            distance[k] = d;
            (entry[k], fraction[k]) = split_place(disks.place(d));
        }
        let reach = disks.kernel().d_max;
        for k in 0..SUB_SAMPLES {
            if distance[k] <= reach {
                w += disks.reflected_entry(sub_slot, entry[k], fraction[k]);
            }
        }
        w * (step * step)
    }
}

/// Sub-samples of a texel's parallelogram.
const SUB_SAMPLES: usize = SUBDIVISIONS * SUBDIVISIONS;

/// The sub-samples' offsets from a texel's centre along its edges u and v
/// (in units of the edge), u's index slowest.
fn sub_sample_offsets() -> ([f32; SUB_SAMPLES], [f32; SUB_SAMPLES]) {
    let step = 1.0 / SUBDIVISIONS as f32;
    let along = |i: usize| (i as f32 + 0.5) * step - 0.5;
    (
        std::array::from_fn(|k| along(k / SUBDIVISIONS)),
        std::array::from_fn(|k| along(k % SUBDIVISIONS)),
    )
}

/// The area (mm²) of the disk that stands for source `i` beyond its
/// neighbours: the disk with its parallelogram's second moment about the
/// centre, (|u|² + |v|²)/12 = a²/2, so the profile's curvature across it
/// is weighed as across the texel (a square's disk is 1.05× its area, a
/// 2:1 rectangle's 1.31×; the disk of equal area would understate both).
/// A sample without a shape is the disk of its area.
pub(super) fn disk_area(sources: &Sources, i: usize) -> f32 {
    match sources.footprint.get(i) {
        Some(&[u, v]) if u.cross(v).length() > 0.0 => {
            std::f32::consts::PI * (u.length_squared() + v.length_squared()) / 6.0
        }
        _ => sources.area[i],
    }
}

/// The disk means that `sources` and their sub-samples need under
/// `kernel`.
pub(super) fn texel_disks<'k>(kernel: &'k Kernel, sources: &Sources) -> DiskKernel<'k> {
    let mut one = texel_disks_for(&[kernel], sources);
    one.pop().expect("a table for the one kernel")
}

/// [`texel_disks`] for each of `kernels`, the sources' sizes read once.
pub(super) fn texel_disks_for<'k>(
    kernels: &[&'k Kernel],
    sources: &Sources,
) -> Vec<DiskKernel<'k>> {
    // In chunks, each noting its sizes into one set: a set carried from
    // texel to texel by value would be copied at every texel.
    const CHUNK: usize = 1 << 14;
    let sizes = (0..sources.len().div_ceil(CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let mut sizes = SampleSizes::default();
            for i in chunk * CHUNK..((chunk + 1) * CHUNK).min(sources.len()) {
                sizes.add(sources.area[i] / (SUBDIVISIONS * SUBDIVISIONS) as f32);
                sizes.add(disk_area(sources, i));
            }
            sizes
        })
        .reduce(SampleSizes::default, SampleSizes::join);
    DiskKernel::for_sizes(kernels, &sizes)
}

/// The distance (mm) within which a texel with edges `u`, `v` is summed in
/// sub-samples rather than as the disk of its area. A texel close to a
/// square has nearly a disk's second moments, so beyond its adjacent
/// texels the disk with its second moment (see [`disk_area`]) is the same
/// to the anisotropic part of the curvature term, which cancels around a
/// target; a texel stretched beyond 2:1 differs from its disk wherever the
/// profile curves across it, so it is subdivided four texels out.
pub(super) fn subdivision_radius(u: Vec3, v: Vec3) -> f32 {
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
