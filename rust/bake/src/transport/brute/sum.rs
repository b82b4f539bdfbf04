//! The reference: the exact discrete sum M(x) = Σ_j P(|x − x_j|) E_j A_j
//! over every source within d_max, in parallel over targets.

use super::near_targets::NearTargets;
use crate::control::{Cancelled, Control, parallel_fill};
use crate::prepared::Prepared;
use crate::scattering::Scattering;
use crate::transport::disk_kernel::{DiskKernel, split_place};
use crate::transport::kernel::Kernel;
use crate::transport::source_table::{Apart, SourceTable, texel_disks};
use crate::transport::sources::{Grid, Sources, Target, Targets};
use crate::transport::through_medium::{may_cross_air, path_length};
use glam::{DVec3, Vec3, Vec4};
use rayon::prelude::*;
use std::ops::Range;

/// Sources gathered a block at a time: the distances of a block are
/// computed together (a vector loop), then its pairs are weighed.
const BLOCK: usize = 64;

/// The sources that carry light, copied into grid order, so a row of cells
/// is a contiguous run. A source without flux adds exactly nothing to any
/// target (P·0), so it is left out of the walk: in a half-lit scene that
/// halves the pairs without changing a bit of the sum's terms.
pub(super) struct Sorted<'a> {
    pub grid: Grid,
    pub table: SourceTable<'a>,
    /// Whether a unit light's sum (each source's area for its flux) is
    /// gathered beside the light's.
    pub unit: bool,
}

impl<'a> Sorted<'a> {
    /// `sources` in grid order; with `unit`, a unit light's sum is gathered
    /// beside theirs, and every source with an area is kept. Only those
    /// `near` the targets are kept, where given.
    pub fn new(
        sources: &Sources<'a>,
        unit: bool,
        cell: f32,
        disks: &DiskKernel,
        near: Option<&NearTargets>,
    ) -> Self {
        let lit: Vec<u32> = (0..sources.len() as u32)
            .into_par_iter()
            .filter(|&i| {
                let (e, a) = (sources.irradiance[i as usize], sources.area[i as usize]);
                let carries = e.iter().any(|&e| e * a != 0.0) || (unit && a != 0.0);
                carries && near.is_none_or(|near| near.holds(sources.position[i as usize]))
            })
            .collect();
        let position: Vec<Vec3> = lit
            .par_iter()
            .map(|&i| sources.position[i as usize])
            .collect();
        let grid = Grid::new(&position, cell);
        let order: Vec<u32> = grid.order.par_iter().map(|&k| lit[k as usize]).collect();
        let table = SourceTable::new(sources, &order, disks);
        Sorted { grid, table, unit }
    }

    /// Σ over sources within `reach` of the target of P·flux: `own` is the
    /// source the target is, if any, and sources on another piece of the
    /// mesh than the target's send it nothing. The second sum is a unit
    /// light's, Σ P·A (zero unless [`Sorted::unit`]).
    #[inline]
    pub fn gather(&self, disks: &DiskKernel, target: Target, reach: Reach) -> [DVec3; 2] {
        // The target's own source by its place in the table.
        let target = Target {
            own: self.table.rank_of(target.own),
            ..target
        };
        let reflects_only = !disks.kernel().transmits();
        let mut sum = [DVec3::ZERO; 2];
        self.grid
            .for_each_run(target.position, reach.radius, |run| {
                let mut start = run.start;
                while start < run.end {
                    let block = start..(start + BLOCK).min(run.end);
                    start = block.end;
                    let part = if reflects_only {
                        self.reflected_block(disks, block, target, reach)
                    } else {
                        self.general_block(disks, block, target, reach)
                    };
                    for (sum, part) in sum.iter_mut().zip(part) {
                        *sum += part.truncate().as_dvec3();
                    }
                }
            });
        sum
    }

    /// Σ P·flux over the sources in `block` (at most [`BLOCK`]) for a
    /// kernel that only reflects: a pair away from the target's own texel
    /// and its near field is one bilinear read of the disk means.
    #[inline]
    fn reflected_block(
        &self,
        disks: &DiskKernel,
        block: Range<usize>,
        target: Target,
        reach: Reach,
    ) -> [Vec4; 2] {
        let (p, n) = (target.position, target.normal);
        let table = &self.table;
        let (tapered, reach) = (reach.tapered, reach.radius);
        let reach2 = reach * reach;
        let own = target.own.unwrap_or(usize::MAX);
        let (xs, ys, zs) = (
            &table.x[block.clone()],
            &table.y[block.clone()],
            &table.z[block.clone()],
        );
        let near2 = &table.near2[block.clone()];
        let mut squared = [0.0f32; BLOCK];
        let mut entry = [0u32; BLOCK];
        let mut fraction = [0.0f32; BLOCK];
        let mut taper = [1.0f32; BLOCK];
        // 0: beyond the reach, 1: one read, 2: the own texel or the near
        // field, weighed by `weight4`.
        let mut kind = [0u8; BLOCK];
        for k in 0..xs.len().min(BLOCK) {
            let (dx, dy, dz) = (xs[k] - p.x, ys[k] - p.y, zs[k] - p.z);
            let d2 = dx * dx + dy * dy + dz * dz;
            let j = block.start + k;
            let straight = d2.sqrt();
            let height = dx * n.x + dy * n.y + dz * n.z;
            let d = if may_cross_air(height, d2) {
                path_length(table.position(j), table.normal[j], p, n, straight)
            } else {
                straight
            };
            squared[k] = d2;
            if tapered {
                taper[k] = Reach::taper(d / reach);
            }
            (entry[k], fraction[k]) = split_place(disks.place(d));
            let within = d2 <= reach2 && d <= reach && table.joins(j, &target);
            let special = d2 < near2[k] || j == own;
            kind[k] = within as u8 * (1 + special as u8);
        }
        // The pairs of each kind, gathered without a branch per pair.
        let (mut far, mut near) = ([0u8; BLOCK], [0u8; BLOCK]);
        let (mut far_count, mut near_count) = (0, 0);
        for (k, &kind) in kind.iter().enumerate().take(xs.len()) {
            far[far_count] = k as u8;
            near[near_count] = k as u8;
            far_count += (kind == 1) as usize;
            near_count += (kind == 2) as usize;
        }
        let unit = self.unit;
        let mut sum = [Vec4::ZERO; 2];
        let mut add = |w: Vec4, j: usize, taper: f32| {
            sum[0] += w * table.flux[j] * taper;
            if unit {
                sum[1] += w * table.area[j] * taper;
            }
        };
        if table.tabulated {
            for &k in &far[..far_count] {
                let (k, j) = (k as usize, block.start + k as usize);
                let w = disks.reflected_entry(table.slot[j], entry[k], fraction[k]);
                add(w, j, taper[k]);
            }
        } else {
            for &k in &far[..far_count] {
                let (k, j) = (k as usize, block.start + k as usize);
                let w = table.weight4(disks, j, p, n, Apart::unknown(squared[k]), Some(own));
                add(w, j, taper[k]);
            }
        }
        for &k in &near[..near_count] {
            let (k, j) = (k as usize, block.start + k as usize);
            let w = table.weight4(disks, j, p, n, Apart::unknown(squared[k]), Some(own));
            add(w, j, taper[k]);
        }
        sum
    }

    /// Σ P·flux over the sources in `block`, pair by pair, for any kernel.
    fn general_block(
        &self,
        disks: &DiskKernel,
        block: Range<usize>,
        target: Target,
        reach: Reach,
    ) -> [Vec4; 2] {
        let (p, n, own) = (target.position, target.normal, target.own);
        let mut sum = [Vec4::ZERO; 2];
        let radius = reach.radius;
        for j in block {
            let d2 = (self.table.position(j) - p).length_squared();
            if d2 > radius * radius || !self.table.joins(j, &target) {
                continue;
            }
            let taper = if reach.tapered {
                Reach::taper(d2.sqrt() / radius)
            } else {
                1.0
            };
            let w = self.table.weight4(disks, j, p, n, Apart::unknown(d2), own);
            sum[0] += w * self.table.flux[j] * taper;
            if self.unit {
                sum[1] += w * self.table.area[j] * taper;
            }
        }
        sum
    }
}

/// How far a gather reaches, and whether its weights fall smoothly to 0
/// there.
#[derive(Clone, Copy, Debug)]
pub struct Reach {
    /// The distance beyond which no source is gathered, mm.
    pub radius: f32,
    /// Whether each pair's weight is scaled by [`Reach::taper`], so the
    /// part gathered changes smoothly as the target moves (the exact sum's
    /// is not).
    pub tapered: bool,
}

impl Reach {
    /// (1 − x²)², x the distance over the radius: 1 at the target, falling
    /// to 0 with a zero slope at the radius.
    #[inline]
    pub fn taper(x: f32) -> f32 {
        let inside = (1.0 - x * x).max(0.0);
        inside * inside
    }
}

/// The grid's cell (mm) for gathering within `reach` from `sources`: a
/// quarter of the reach where the reach spans many sources, so the rows
/// walked hug the ball; up to half of it where it spans few, so a row is
/// not mostly empty cells.
fn cell_size(reach: f32, sources: &Sources) -> f32 {
    let area: f64 = sources.area.iter().map(|&a| f64::from(a.max(0.0))).sum();
    let spacing = (area / sources.len().max(1) as f64).sqrt() as f32;
    (4.0 * spacing)
        .max(0.25 * reach)
        .min(0.5 * reach.max(8.0 * spacing))
}

/// Radiant exitance (W/m²) at each target by the exact sum over `sources`.
pub fn integrate(
    kernel: &Kernel,
    sources: &Sources,
    targets: Targets,
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let reach = Reach {
        radius: kernel.d_max,
        tapered: false,
    };
    let [sums, _] = sums_within(
        kernel,
        sources,
        false,
        targets,
        Reaches::All(reach),
        control,
    )?;
    Ok(sums)
}

/// The exact sum's part from the sources within each target's reach
/// (`reaches`, one per target, each at most the kernel's), W/m²: every
/// pair weighed as the whole sum weighs it, and by the taper where the
/// reach has one.
pub fn sum_within(
    kernel: &Kernel,
    sources: &Sources,
    targets: Targets,
    reaches: &[Reach],
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let clamped = |reach: &Reach| Reach {
        radius: reach.radius.clamp(0.0, kernel.d_max),
        ..*reach
    };
    let reaches: Vec<Reach> = reaches.iter().map(clamped).collect();
    let [sums, _] = sums_within(
        kernel,
        sources,
        false,
        targets,
        Reaches::Each(&reaches),
        control,
    )?;
    Ok(sums)
}

/// The reach of each target: one for all, or one each.
#[derive(Clone, Copy)]
enum Reaches<'a> {
    All(Reach),
    Each(&'a [Reach]),
}

impl Reaches<'_> {
    fn of(&self, target: usize) -> Reach {
        match *self {
            Reaches::All(reach) => reach,
            Reaches::Each(reaches) => reaches[target],
        }
    }

    /// The longest of the targets' reaches, mm.
    fn longest(&self) -> f32 {
        match *self {
            Reaches::All(reach) => reach.radius,
            Reaches::Each(reaches) => reaches.iter().map(|r| r.radius).fold(0.0, f32::max),
        }
    }

    /// The reach the sources' grid is sized for: the mean of the targets'.
    fn typical(&self) -> f32 {
        match *self {
            Reaches::All(reach) => reach.radius,
            Reaches::Each(reaches) => {
                let sum: f64 = reaches.iter().map(|r| f64::from(r.radius)).sum();
                (sum / reaches.len().max(1) as f64) as f32
            }
        }
    }
}

/// [`sum_within`] of the sources' light and, with `unit`, of a unit light
/// at the same sources (else empty), both in one walk over the pairs.
fn sums_within(
    kernel: &Kernel,
    sources: &Sources,
    unit: bool,
    targets: Targets,
    reaches: Reaches,
    control: &Control,
) -> Result<[Vec<[f32; 3]>; 2], Cancelled> {
    let disks = texel_disks(kernel, sources);
    let near = NearTargets::of(targets.position, reaches.longest(), sources.len());
    let cell = cell_size(reaches.typical(), sources);
    let sorted = Sorted::new(sources, unit, cell, &disks, near.as_ref());
    let single = |v: DVec3| v.to_array().map(|v| v as f32);
    if !unit {
        // One light's sums alone, without room for a second.
        let mut lit = vec![[0.0f32; 3]; targets.position.len()];
        parallel_fill(&mut lit, 256, control, |i| {
            single(sorted.gather(&disks, targets.at(i), reaches.of(i))[0])
        })?;
        return Ok([lit, Vec::new()]);
    }
    let mut out = vec![[[0.0f32; 3]; 2]; targets.position.len()];
    parallel_fill(&mut out, 256, control, |i| {
        sorted
            .gather(&disks, targets.at(i), reaches.of(i))
            .map(single)
    })?;
    let (lit, unit) = out.into_iter().map(|[a, b]| (a, b)).unzip();
    Ok([lit, unit])
}

/// The exact sum of `prepared`'s texels at `targets` under `scattering`:
/// with its oblique kernel and each light's incidence where it has one
/// and the light has directions ([`crate::transport::oblique_sum`]), else with its
/// radially symmetric kernel. `true` with the exitance when the oblique
/// kernel was used.
pub fn exact_sum(
    prepared: &Prepared,
    scattering: &Scattering,
    sources: &Sources,
    targets: Targets,
    control: &Control,
) -> Result<(Vec<[f32; 3]>, bool), Cancelled> {
    if let Some(kernel) = &scattering.oblique
        && let Some(incidence) = prepared.incidence(control)?
    {
        let reach = scattering.kernel.d_max;
        let exitance = crate::transport::oblique_sum::integrate(
            kernel,
            reach,
            sources,
            Some(incidence),
            targets,
            false,
            control,
        )?;
        return Ok((exitance, true));
    }
    Ok((
        integrate(&scattering.kernel, sources, targets, control)?,
        false,
    ))
}

/// [`exact_sum`] of `sources`' light and of a unit light (1 W/m² in every
/// channel) at the same sources: with the radially symmetric kernel both in
/// one walk over the pairs, which then cost about one sum.
pub fn exact_sum_and_unit(
    prepared: &Prepared,
    scattering: &Scattering,
    sources: &Sources,
    targets: Targets,
    control: &Control,
) -> Result<[Vec<[f32; 3]>; 2], Cancelled> {
    if scattering.oblique.is_some() && prepared.incidence(control)?.is_some() {
        let (lit, _) = exact_sum(prepared, scattering, sources, targets, control)?;
        let unit = Sources {
            position: sources.position.clone(),
            normal: sources.normal.clone(),
            area: sources.area.clone(),
            irradiance: vec![[1.0; 3]; sources.len()],
            footprint: sources.footprint.clone(),
            piece: sources.piece.clone(),
            part: sources.part.clone(),
        };
        let (unit, _) = exact_sum(prepared, scattering, &unit, targets, control)?;
        return Ok([lit, unit]);
    }
    integrate_with_unit(&scattering.kernel, sources, targets, control)
}

/// [`integrate`] of `sources`' light and of a unit light (1 W/m² in every
/// channel) at the same sources, W/m², in one walk over the pairs.
pub fn integrate_with_unit(
    kernel: &Kernel,
    sources: &Sources,
    targets: Targets,
    control: &Control,
) -> Result<[Vec<[f32; 3]>; 2], Cancelled> {
    let reach = Reach {
        radius: kernel.d_max,
        tapered: false,
    };
    sums_within(kernel, sources, true, targets, Reaches::All(reach), control)
}
