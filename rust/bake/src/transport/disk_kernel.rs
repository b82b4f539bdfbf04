//! The kernel's disk means tabulated for the sample sizes at hand, so the
//! integrators' inner loops cost two table reads per pair.
//!
//! Each size has a row of means over distance, at distances spaced evenly
//! in √(d/d_max) and the same for every row, so one index serves both rows
//! a sample sits between (the spacing is finest at the centre, where a
//! small disk's mean turns; beyond a few radii the disk mean still exceeds
//! the centre value by about a²∇²R/8, percents where R curves sharply, so
//! the far field is averaged too). Sizes are spaced geometrically; a
//! sample's place among them is found once per sample.
//!
//! Each entry is a `Vec4` (three channels and a zero), so a read between
//! two distances and two sizes is four aligned loads and three vector
//! lerps; the last row is stored twice so the row above always exists.

use super::kernel::{Kernel, Separation};
use super::sample_sizes::SampleSizes;
use glam::Vec4;
use rayon::prelude::*;
use std::f32::consts::FRAC_1_PI;

/// Distances tabulated in [0, d_max].
const ROW: usize = 1152;
/// Disk radii tabulated across a range of sample areas.
const SIZES: usize = 24;

/// The most one table holds, bytes: every size and the last again, each a
/// row of `Vec4`s for R and, for a kernel that transmits, for T.
pub const fn most_bytes(transmits: bool) -> usize {
    let row = (SIZES + 1) * ROW * std::mem::size_of::<Vec4>();
    if transmits { 2 * row } else { row }
}

/// Share of the circle of radius `r` about the entry point that lies in
/// the disk of radius `a` centred `d` away.
pub(super) fn ring_share(r: f32, d: f32, a: f32) -> f32 {
    if r <= 0.0 || d <= 0.0 {
        return if r < a { 1.0 } else { 0.0 };
    }
    let c = ((d * d + r * r - a * a) / (2.0 * d * r)).clamp(-1.0, 1.0);
    c.acos() * FRAC_1_PI
}

/// A sample's place among the tabulated sizes.
#[derive(Clone, Copy, Debug, Default)]
pub struct Slot {
    /// Lower row, or `u32::MAX` when the size is outside the table.
    row: u32,
    /// Weight of the row above.
    fraction: f32,
    /// The sample's disk radius, mm.
    radius: f32,
}

impl Slot {
    /// True when the sample's size lies inside the table.
    #[inline]
    pub(super) fn tabulated(&self) -> bool {
        self.row != u32::MAX
    }
}

/// The sample sizes a table's rows hold: slots found in one table read
/// the same rows of any other with the same sizes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rows {
    a0: f32,
    log_step: f32,
    count: usize,
}

/// A kernel with disk means tabulated for a range of sample sizes.
pub struct DiskKernel<'k> {
    kernel: &'k Kernel,
    a0: f32,
    log_step: f32,
    /// Each row's disk radius.
    radii: Vec<f32>,
    /// Where a distance falls in a row: x = √(d·`per_mm`)·(ROW − 1) with
    /// `per_mm` = 1/d_max (0 for an empty kernel, so every read is entry 0).
    per_mm: f32,
    /// [size][distance] → R mean, the last size repeated.
    reflected: Vec<Vec4>,
    /// [size][distance] → T mean, likewise; empty when the kernel
    /// transmits nothing.
    transmitted: Vec<Vec4>,
}

impl<'k> DiskKernel<'k> {
    /// The sample sizes of this table's rows.
    pub(super) fn rows(&self) -> Rows {
        Rows {
            a0: self.a0,
            log_step: self.log_step,
            count: self.radii.len(),
        }
    }

    /// Tabulates `kernel`'s disk means for sample areas in
    /// [`area_min`, `area_max`] (mm²).
    pub fn new(kernel: &'k Kernel, area_min: f32, area_max: f32) -> Self {
        let mut table = Self::sized(kernel, area_min, area_max);
        table.fill(&vec![true; table.radii.len()]);
        table
    }

    /// [`DiskKernel::new`] for each of `kernels`, for samples of `sizes`,
    /// with only the rows they may read ([`SampleSizes::spans`]); the
    /// others hold zeros and are never read. The rows depend on the sizes
    /// alone, so they are found once for every kernel.
    pub(super) fn for_sizes(kernels: &[&'k Kernel], sizes: &SampleSizes) -> Vec<Self> {
        let Some(&first) = kernels.first() else {
            return Vec::new();
        };
        let (area_min, area_max) = sizes.range();
        let table = Self::sized(first, area_min, area_max);
        let last = table.radii.len() - 1;
        let mut needed = vec![false; last + 1];
        for (a, b) in sizes.spans() {
            // A slot's row rises with the area: a size within the span
            // reads rows from the least's to the one above the greatest's.
            let (low, high) = (table.slot(a), table.slot(b));
            let from = if low.tabulated() { low.row as usize } else { 0 };
            let to = if high.tabulated() {
                high.row as usize + 1
            } else {
                last
            };
            needed[from.min(last)..=to.min(last)].fill(true);
        }
        if !needed.contains(&true) {
            needed.fill(true);
        }
        kernels
            .iter()
            .map(|&kernel| {
                let mut table = Self::sized(kernel, area_min, area_max);
                table.fill(&needed);
                table
            })
            .collect()
    }

    /// The table's sizes for sample areas in [`area_min`, `area_max`], its
    /// rows not yet filled.
    fn sized(kernel: &'k Kernel, area_min: f32, area_max: f32) -> Self {
        let radius = |area: f32| (area.max(0.0) * FRAC_1_PI).sqrt().max(1e-9);
        let (lo, hi) = (radius(area_min), radius(area_max));
        let (a0, a1) = (lo.min(hi), lo.max(hi));
        let sizes = if a1 / a0 < 1.001 { 1 } else { SIZES };
        let log_step = if sizes > 1 {
            (a1 / a0).ln() / (sizes - 1) as f32
        } else {
            0.0
        };
        let radii: Vec<f32> = (0..sizes)
            .map(|i| a0 * (log_step * i as f32).exp())
            .collect();
        let per_mm = if kernel.d_max > 0.0 {
            1.0 / kernel.d_max
        } else {
            0.0
        };
        DiskKernel {
            kernel,
            a0,
            log_step,
            radii,
            per_mm,
            reflected: Vec::new(),
            transmitted: Vec::new(),
        }
    }

    /// Computes the rows marked in `needed` (zeros elsewhere), in parallel:
    /// each is independent, and a bake of a few thousand texels would
    /// otherwise wait on them.
    fn fill(&mut self, needed: &[bool]) {
        let kernel = self.kernel;
        let rows: Vec<Vec<[[f32; 3]; 2]>> = self
            .radii
            .par_iter()
            .zip(needed)
            .map(|(&a, &needed)| {
                if !needed {
                    return vec![[[0.0; 3]; 2]; ROW];
                }
                (0..ROW)
                    .map(|j| kernel.disk_mean(distance(j, kernel.d_max), a))
                    .collect()
            })
            .collect();
        let last = rows.len() - 1;
        let stored = rows.iter().chain(std::iter::once(&rows[last]));
        let stored_len = (rows.len() + 1) * ROW;
        self.reflected = Vec::with_capacity(stored_len);
        self.transmitted = if kernel.transmits() {
            Vec::with_capacity(stored_len)
        } else {
            Vec::new()
        };
        for row in stored {
            for &[r, t] in row {
                self.reflected.push(Vec4::new(r[0], r[1], r[2], 0.0));
                if kernel.transmits() {
                    self.transmitted.push(Vec4::new(t[0], t[1], t[2], 0.0));
                }
            }
        }
    }

    /// The kernel these means come from.
    pub fn kernel(&self) -> &Kernel {
        self.kernel
    }

    /// Where a sample of `area` (mm²) sits among the tabulated sizes.
    pub fn slot(&self, area: f32) -> Slot {
        let radius = (area.max(0.0) * FRAC_1_PI).sqrt();
        let last = self.radii.len() - 1;
        let s = if last == 0 {
            if (radius / self.a0 - 1.0).abs() < 0.01 {
                0.0
            } else {
                -1.0
            }
        } else {
            (radius / self.a0).ln() / self.log_step
        };
        if !(-1e-3..=last as f32 + 1e-3).contains(&s) {
            return Slot {
                row: u32::MAX,
                fraction: 0.0,
                radius,
            };
        }
        let row = (s.max(0.0) as usize).min(last.saturating_sub(1));
        Slot {
            row: row as u32,
            fraction: if last == 0 {
                0.0
            } else {
                (s - row as f32).clamp(0.0, 1.0)
            },
            radius,
        }
    }

    /// The mean of P = (1 − t)R + tT over the disk of a sample in `slot`
    /// seen across `separation`: what the sample's flux is multiplied by,
    /// 1/mm². Zero beyond d_max.
    #[inline]
    pub fn weight(&self, separation: Separation, slot: Slot) -> [f32; 3] {
        let w = self.weight4(separation, slot);
        [w.x, w.y, w.z]
    }

    /// [`DiskKernel::weight`] as a `Vec4` (the fourth lane 0).
    #[inline(always)]
    pub(super) fn weight4(&self, separation: Separation, slot: Slot) -> Vec4 {
        let k = self.kernel;
        let t = separation.t;
        if separation.distance > k.d_max {
            return Vec4::ZERO;
        }
        if t <= 0.0 || !k.transmits() {
            return self.mean_at(slot, separation.distance, 0);
        }
        let tr = self.mean_at(slot, separation.across, 1);
        // A pair across a slab's faces is wholly transmitted: R unread.
        if t >= 1.0 {
            return tr;
        }
        let r = self.mean_at(slot, separation.distance, 0);
        r + (tr - r) * t
    }

    /// The disk mean of R for a sample in `slot` inside the table, at a
    /// distance whose place in a row ([`DiskKernel::place`]) is split into
    /// `entry` and `fraction` ([`split_place`]): the exact sum's inner loop,
    /// one bilinear read.
    #[inline]
    pub(super) fn reflected_entry(&self, slot: Slot, entry: u32, fraction: f32) -> Vec4 {
        read(&self.reflected, slot, entry as usize, fraction)
    }

    /// Where distance `d` (mm, at most d_max) falls in a row: the
    /// fractional entry index.
    #[inline]
    pub(super) fn place(&self, d: f32) -> f32 {
        (d * self.per_mm).min(1.0).sqrt() * (ROW - 1) as f32
    }

    /// The disk mean of R (`which` 0) or T (1) at distance `d`.
    #[inline]
    fn mean_at(&self, slot: Slot, d: f32, which: usize) -> Vec4 {
        if !slot.tabulated() {
            let [r, t] = self.untabulated(d, slot.radius);
            let v = if which == 0 { r } else { t };
            return Vec4::new(v[0], v[1], v[2], 0.0);
        }
        let table = if which == 0 {
            &self.reflected
        } else {
            &self.transmitted
        };
        bilinear(table, slot, self.place(d))
    }

    /// Sizes outside the table are octree nodes taken whole: their centre
    /// value stands for them, as in Jensen & Buhler (the error ε bounds);
    /// only a node close to its own size gets a disk mean.
    fn untabulated(&self, d: f32, a: f32) -> [[f32; 3]; 2] {
        if d > 2.0 * a {
            [
                self.kernel.reflectance(d),
                self.kernel.point_transmittance(d),
            ]
        } else {
            self.kernel.disk_mean(d, a)
        }
    }
}

/// The distance of entry `j` of every row.
fn distance(j: usize, d_max: f32) -> f32 {
    let x = j as f32 / (ROW - 1) as f32;
    d_max * x * x
}

/// The table read at fractional entry `x` (clamped to the row) between
/// the rows of `slot`: linear in distance within each row, then across.
#[inline]
fn bilinear(table: &[Vec4], slot: Slot, x: f32) -> Vec4 {
    let (j, f) = split_place(x);
    read(table, slot, j as usize, f)
}

/// A place in a row ([`DiskKernel::place`]) as the entry below it and the
/// fraction towards the next, kept inside the row.
#[inline]
pub(super) fn split_place(x: f32) -> (u32, f32) {
    let j = (x.max(0.0) as u32).min(ROW as u32 - 2);
    (j, x - j as f32)
}

/// The table between entries `j` and `j` + 1 (fraction `f`) and between
/// the rows of `slot`.
#[inline]
fn read(table: &[Vec4], slot: Slot, j: usize, f: f32) -> Vec4 {
    let at = slot.row as usize * ROW + j;
    let (a, b) = (table[at], table[at + 1]);
    let (c, e) = (table[at + ROW], table[at + ROW + 1]);
    let lower = a + (b - a) * f;
    let upper = c + (e - c) * f;
    lower + (upper - lower) * slot.fraction
}

#[cfg(test)]
mod tests {
    use super::*;
    use sssbake_profile::model::{Model, build_profile};
    use sssbake_profile::numerics::rng::Rng;
    use sssbake_profile::presets::preset;

    /// Every row a sample reads is made: at distance 0 each holds the
    /// disk's mean of a positive profile.
    #[test]
    fn every_row_a_sample_reads_is_made() {
        let profile = build_profile(&preset("skin1").unwrap(), Model::Dipole, 6).unwrap();
        let kernel = Kernel::new(profile.as_ref(), 1e-3);
        let mut rng = Rng::new(3, 0);
        // Sizes in two clusters a decade apart, so rows between are unread.
        let areas: Vec<f32> = (0..500)
            .map(|k| {
                let base = if k % 2 == 0 { 0.01 } else { 1.0 };
                base * (1.0 + rng.uniform() as f32)
            })
            .collect();
        let mut sizes = SampleSizes::default();
        areas.iter().for_each(|&a| sizes.add(a));
        let table = DiskKernel::for_sizes(&[&kernel], &sizes).remove(0);
        let made = |row: usize| table.reflected[row * ROW].x > 0.0;
        for &a in &areas {
            let slot = table.slot(a);
            assert!(slot.tabulated(), "{a}");
            assert!(
                made(slot.row as usize) && made(slot.row as usize + 1),
                "{a}"
            );
        }
        assert!(
            (0..table.radii.len()).any(|row| !made(row)),
            "rows no sample reads are left unmade"
        );
    }
}
