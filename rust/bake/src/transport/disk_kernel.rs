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

use super::kernel::{Kernel, Separation};
use std::f32::consts::FRAC_1_PI;

/// Distances tabulated in [0, d_max].
const ROW: usize = 1152;
/// Disk radii tabulated across a range of sample areas.
const SIZES: usize = 24;

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

/// A kernel with disk means tabulated for a range of sample sizes.
pub struct DiskKernel<'k> {
    kernel: &'k Kernel,
    a0: f32,
    log_step: f32,
    /// Each row's disk radius.
    radii: Vec<f32>,
    /// [size][distance] → R mean.
    reflected: Vec<[f32; 3]>,
    /// [size][distance] → T mean; empty when the kernel transmits nothing.
    transmitted: Vec<[f32; 3]>,
}

impl<'k> DiskKernel<'k> {
    /// Tabulates `kernel`'s disk means for sample areas in
    /// [`area_min`, `area_max`] (mm²).
    pub fn new(kernel: &'k Kernel, area_min: f32, area_max: f32) -> Self {
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
        let mut reflected = Vec::with_capacity(sizes * ROW);
        let mut transmitted = Vec::new();
        for &a in &radii {
            for j in 0..ROW {
                let [r, t] = kernel.disk_mean(distance(j, kernel.d_max), a);
                reflected.push(r);
                if kernel.transmits() {
                    transmitted.push(t);
                }
            }
        }
        DiskKernel {
            kernel,
            a0,
            log_step,
            radii,
            reflected,
            transmitted,
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
        let k = self.kernel;
        let t = separation.t;
        if separation.distance > k.d_max {
            return [0.0; 3];
        }
        let r = self.mean_at(slot, separation.distance, 0);
        if t <= 0.0 || !k.transmits() {
            return r;
        }
        let tr = self.mean_at(slot, separation.across, 1);
        [0, 1, 2].map(|c| (1.0 - t) * r[c] + t * tr[c])
    }

    /// The disk mean of R (`which` 0) or T (1) at distance `d`.
    #[inline]
    fn mean_at(&self, slot: Slot, d: f32, which: usize) -> [f32; 3] {
        if slot.row == u32::MAX {
            return self.untabulated(d, slot.radius)[which];
        }
        let table = if which == 0 {
            &self.reflected
        } else {
            &self.transmitted
        };
        let (j, f) = index(d, self.kernel.d_max);
        let at = slot.row as usize * ROW + j;
        let lower = lerp(table[at], table[at + 1], f);
        if slot.fraction <= 0.0 {
            return lower;
        }
        let upper = lerp(table[at + ROW], table[at + ROW + 1], f);
        lerp(lower, upper, slot.fraction)
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

/// The entry below distance `d` in every row, and the fraction towards the
/// next.
#[inline]
fn index(d: f32, d_max: f32) -> (usize, f32) {
    if d_max.is_nan() || d_max <= 0.0 {
        return (0, 0.0);
    }
    let x = (d / d_max).clamp(0.0, 1.0).sqrt() * (ROW - 1) as f32;
    let j = (x as usize).min(ROW - 2);
    (j, x - j as f32)
}

#[inline]
fn lerp(a: [f32; 3], b: [f32; 3], f: f32) -> [f32; 3] {
    [
        a[0] + (b[0] - a[0]) * f,
        a[1] + (b[1] - a[1]) * f,
        a[2] + (b[2] - a[2]) * f,
    ]
}
