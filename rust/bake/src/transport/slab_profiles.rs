//! Thin parts by the profile of their own slab: in each channel where a
//! part is thinner than about a diffusion length, a texel gathers with
//! R_t(r) and T_t(r), the light a slab of its thickness returns and sends
//! through at distance r, simulated by the Monte Carlo, instead of a
//! half-space's profile re-shared by the slab's totals
//! ([`super::local_slab`]).
//!
//! A slab spreads light less than a half-space: what goes sideways leaks
//! out through both faces as it goes. The totals alone keep a
//! half-space's spread, which on a thin part under a small light puts too
//! little light near it and too much far away (docs/accuracy.md, "Thin
//! parts spread red wider than light").
//!
//! Each rung of a thickness ladder is one simulated slab, its tallies of R
//! and T by radius ([`sssbake_profile::models::monte_carlo`], kept in the
//! cache folder) tabulated as a [`Kernel`] and read as the exact sum reads
//! a kernel: disk means, a texel's own light over its parallelogram, and
//! sub-samples of the texels near the target. A texel takes the two rungs about its thickness, linearly in
//! ln t. A part's two faces are told apart by which way they face, not
//! blended by the pair's normals: a source on the face behind (facing
//! away, deeper than half the part's thickness below the target) is
//! weighed by T_t at its offset along the face, any other by R_t at its
//! distance, and a surface deeper than one and a half thicknesses, beyond
//! the face behind, sends nothing through the part. The light that leaves
//! without scattering (straight through, or back after internal
//! reflections) is a point at the texel behind or at the texel itself, and
//! is added there rather than spread by a profile.
//!
//! This module is the reference sum of that model, at chosen texels; the
//! bake's integrators do not read it yet.

use crate::control::{Cancelled, Control, parallel_fill};
use crate::monte_carlo_cache::{cache_dir, monte_carlo_profile};
use crate::prepared::Prepared;
use crate::scattering::{D_MAX_EPSILON, Scattering};
use crate::transport::kernel::{Kernel, Separation};
use crate::transport::local_slab::{LocalSlab, MAX_GAIN, rungs_about};
use crate::transport::source_table::{SourceTable, texel_disks};
use crate::transport::sources::{Grid, Sources};
use crate::transport::through_medium::longer_path;
use glam::{DVec3, Vec3, Vec4};
use rayon::prelude::*;
use sssbake_profile::Rgb;
use sssbake_profile::material::{Layer, Material, Optics};
use sssbake_profile::models::monte_carlo::profile::ProfileSettings;
use sssbake_profile::models::tabulated::Tabulated;
use sssbake_profile::profile::Profile;

/// Parts thinner than this many diffusion lengths 1/σtr of a channel take
/// their slab's profile in that channel; thicker parts keep the
/// half-space's, with the slab's totals ([`super::local_slab`]). Over a
/// diffusion length a slab's spread has become a half-space's but for the
/// light it still sends through, which the totals carry.
const THIN_DIFFUSION_LENGTHS: f64 = 1.2;
/// Rungs per factor e of thickness: neighbouring rungs 22% apart.
const RUNGS_PER_E: f64 = 5.0;
/// The thinnest rung, as a share of the finest mean free path; thinner
/// parts take it.
const THINNEST_MEAN_FREE_PATHS: f64 = 0.05;

/// One simulated slab.
struct Rung {
    /// R_t(r) and T_t(r), tabulated.
    kernel: Kernel,
    /// Light returned without scattering (internal reflections of the
    /// entering beam), per unit flux entering.
    unscattered_back: Rgb,
    /// Light sent straight through without scattering.
    unscattered_through: Rgb,
    /// The scattered light the slab returns and sends through (the
    /// kernel holds all but a share [`D_MAX_EPSILON`] of it).
    scattered_total: Rgb,
}

/// The slabs of one material, by thickness.
pub struct SlabProfiles {
    /// The ladder's thicknesses, mm, increasing: one per rung.
    thickness: Vec<f64>,
    rungs: Vec<Rung>,
    /// Per channel, parts at least this thick (mm) keep the half-space's
    /// profile in that channel.
    pub thin_below: [f64; 3],
}

impl SlabProfiles {
    /// The slabs of `scattering`'s material (one semi-infinite layer) that
    /// parts thinner than [`THIN_DIFFUSION_LENGTHS`] need in some channel,
    /// simulated once and kept in the cache folder; `None` for other
    /// materials.
    pub fn new(scattering: &Scattering) -> Option<Self> {
        let layer = LocalSlab::layer_of(scattering)?;
        let d_max = f64::from(scattering.kernel.d_max);
        let thin_below =
            [0, 1, 2].map(|c| (THIN_DIFFUSION_LENGTHS / layer.medium(c).sigma_tr()).min(d_max));
        let thickest = thin_below.iter().copied().fold(0.0, f64::max);
        let finest = (0..3)
            .map(|c| 1.0 / (layer.sigma_a[c] + layer.sigma_s[c]))
            .fold(f64::INFINITY, f64::min);
        let thinnest = THINNEST_MEAN_FREE_PATHS * finest;
        if !(thickest.is_finite() && thinnest.is_finite() && thickest > thinnest) {
            return None;
        }
        let count = ((thickest / thinnest).ln() * RUNGS_PER_E).ceil() as usize + 1;
        let step = (thickest / thinnest).ln() / (count - 1) as f64;
        let thickness: Vec<f64> = (0..count)
            .map(|i| thinnest * (step * i as f64).exp())
            .collect();
        let rungs = thickness
            .par_iter()
            .map(|&t| Self::rung(&scattering.material, layer, t))
            .collect::<Option<Vec<Rung>>>()?;
        Some(Self {
            thickness,
            rungs,
            thin_below,
        })
    }

    fn rung(material: &Material, layer: &Layer, thickness: f64) -> Option<Rung> {
        let slab = Material {
            optics: Optics::Layers(vec![Layer {
                thickness_mm: Some(thickness),
                ..layer.clone()
            }]),
            ..material.clone()
        };
        let simulated =
            monte_carlo_profile(&slab, &ProfileSettings::default(), cache_dir().as_deref())?;
        // The tallies as they are: the smoothing fit of the Monte Carlo
        // profile loses a slab's far tail (red 10% short 11–15 mm from a
        // light on 2 mm of skin1), and a kernel reads the near field
        // through its disk means, which average the tallies' noise there.
        let tallies = simulated.tallies();
        let binned: Vec<usize> = (0..tallies.radii_mm.len())
            .filter(|&i| tallies.radii_mm[i] > 0.0)
            .collect();
        let profile = Tabulated::new(
            "slab",
            binned.iter().map(|&i| tallies.radii_mm[i]).collect(),
            binned.iter().map(|&i| tallies.reflectance[i]).collect(),
            binned.iter().map(|&i| tallies.transmittance[i]).collect(),
            tallies.total_reflectance,
            tallies.total_transmittance,
        );
        let kernel = Kernel::new(&profile, D_MAX_EPSILON);
        let (reflected, sent) = (profile.total_reflectance(), profile.total_transmittance());
        Some(Rung {
            kernel,
            unscattered_back: tallies.unscattered_reflectance,
            unscattered_through: tallies.unscattered_transmittance,
            scattered_total: [0, 1, 2].map(|c| reflected[c] + sent[c]),
        })
    }

    /// The thicknesses of the rungs, mm.
    pub fn thicknesses(&self) -> &[f64] {
        &self.thickness
    }

    /// The two rungs about `t` mm and the weight of the second
    /// ([`rungs_about`]).
    fn about(&self, t: f64) -> (usize, usize, f64) {
        rungs_about(&self.thickness, t)
    }

    /// Whether a part `t` mm thick takes its slab's profile in channel `c`.
    pub fn is_thin(&self, t: f64, c: usize) -> bool {
        t < self.thin_below[c]
    }

    /// The exitance (W/m², before the colour after scattering) at the
    /// texels `picked` of `prepared`, by the profiles of their slabs in
    /// each channel where the part is thin ([`Self::is_thin`]), and
    /// `otherwise` (per texel of `prepared`) elsewhere.
    ///
    /// The light entering at every texel is raised by `halves` (√gain, as
    /// [`crate::prepared::Raised`] has it) except where a picked texel is
    /// thin, whose gains are found here as the corrected model finds them
    /// ([`super::local_slab`]): their slab's total over their sum under a
    /// unit light, within [1, [`MAX_GAIN`]], times `ball`'s gain of convex
    /// parts.
    pub fn exitance(
        &self,
        prepared: &Prepared,
        picked: &[usize],
        halves: &[[f32; 3]],
        ball: &[[f32; 3]],
        otherwise: &[[f32; 3]],
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        let opposites = prepared.opposites();
        let thickness: Vec<Option<(f64, usize)>> = picked
            .iter()
            .map(|&i| {
                let o = opposites.get(i).copied().flatten()?;
                let t = f64::from(o.thickness);
                (0..3)
                    .any(|c| self.is_thin(t, c))
                    .then_some((t, o.surfel as usize))
            })
            .collect();
        // Every picked texel's sums under each rung it reads, under a unit
        // light first (for its gain), then under the raised light.
        let texels = prepared.texel_sources();
        let unit = self.sums(prepared, &texels, picked, &thickness, None, control)?;
        let mut new_halves = halves.to_vec();
        for (k, &i) in picked.iter().enumerate() {
            let Some((t, _)) = thickness[k] else { continue };
            let (a, b, w) = self.about(t);
            let expected = mix(
                self.rungs[a].scattered_total,
                self.rungs[b].scattered_total,
                w,
            );
            let convex = ball.get(i).copied().unwrap_or([1.0; 3]);
            new_halves[i] = [0, 1, 2].map(|c| {
                if !self.is_thin(t, c) {
                    return halves[i][c];
                }
                let gain = expected[c] / f64::from(unit[k][c]);
                let gain = if gain.is_finite() {
                    gain.clamp(1.0, MAX_GAIN)
                } else {
                    1.0
                };
                (gain * f64::from(convex[c])).min(MAX_GAIN).sqrt() as f32
            });
        }
        let lit = self.sums(
            prepared,
            &texels,
            picked,
            &thickness,
            Some(&new_halves),
            control,
        )?;
        let entering = &texels.irradiance;
        Ok(picked
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                let Some((t, behind)) = thickness[k] else {
                    return otherwise[i];
                };
                let (a, b, w) = self.about(t);
                let back = mix(
                    self.rungs[a].unscattered_back,
                    self.rungs[b].unscattered_back,
                    w,
                );
                let through = mix(
                    self.rungs[a].unscattered_through,
                    self.rungs[b].unscattered_through,
                    w,
                );
                [0, 1, 2].map(|c| {
                    if !self.is_thin(t, c) {
                        return otherwise[i][c];
                    }
                    let raised = |j: usize| f64::from(entering[j][c] * new_halves[j][c]);
                    let m =
                        f64::from(lit[k][c]) + back[c] * raised(i) + through[c] * raised(behind);
                    (m * f64::from(new_halves[i][c])) as f32
                })
            })
            .collect())
    }

    /// The exact sums at `picked` (thin where `thickness` says) under the
    /// rungs about each thickness, mixed in ln t: of the light of `texels`
    /// (the object's texels as sources) raised by `halves`, or of a unit
    /// light where `None`.
    fn sums(
        &self,
        prepared: &Prepared,
        texels: &Sources,
        picked: &[usize],
        thickness: &[Option<(f64, usize)>],
        halves: Option<&[[f32; 3]]>,
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Cancelled> {
        let mut sources = texels.clone();
        for (j, e) in sources.irradiance.iter_mut().enumerate() {
            *e = match halves {
                Some(h) => [0, 1, 2].map(|c| e[c] * h[j][c]),
                None => [1.0; 3],
            };
        }
        let mut out = vec![[0.0f64; 3]; picked.len()];
        for (r, rung) in self.rungs.iter().enumerate() {
            // The picked texels that read this rung, with its weight.
            let (reading, weights): (Vec<usize>, Vec<(usize, f64)>) = thickness
                .iter()
                .enumerate()
                .filter_map(|(k, t)| {
                    let (a, b, w) = self.about(t.as_ref()?.0);
                    let weight = if r == a {
                        1.0 - w
                    } else if r == b {
                        w
                    } else {
                        0.0
                    };
                    (weight > 0.0).then_some((picked[k], (k, weight)))
                })
                .unzip();
            if reading.is_empty() {
                continue;
            }
            let sums = slab_sums(prepared, &sources, &rung.kernel, &reading, control)?;
            for (&(k, weight), sum) in weights.iter().zip(sums) {
                for c in 0..3 {
                    out[k][c] += weight * f64::from(sum[c]);
                }
            }
        }
        Ok(out.iter().map(|v| v.map(|x| x as f32)).collect())
    }
}

/// Σ_j P(x_i, x_j)·E_j·A_j at each texel `i` of `reading`, P the slab's
/// kernel read as its reflection where the pair lies on one face of the
/// part and as its transmission, at the offset along the face, where the
/// source lies on the face behind (facing away, deeper than half the
/// part's thickness below the target): a part's faces are told apart by
/// which way they face, not blended by their normals.
fn slab_sums(
    prepared: &Prepared,
    sources: &Sources,
    kernel: &Kernel,
    reading: &[usize],
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let disks = texel_disks(kernel, sources);
    let reach = kernel.d_max;
    // Rows a quarter of the reach wide hug the ball a target gathers from;
    // the table walks the sources in the grid's order.
    let grid = Grid::new(&sources.position, (0.25 * reach).max(f32::MIN_POSITIVE));
    let table = SourceTable::new(sources, &grid.order, &disks);
    let opposites = prepared.opposites();
    let surfels = &prepared.surfels;
    let mut out = vec![[0.0f32; 3]; reading.len()];
    parallel_fill(&mut out, 16, control, |k| {
        let i = reading[k];
        let (p, n) = (surfels.position[i], surfels.normal[i]);
        let piece = Some(surfels.piece[i]);
        // The texels are the sources, in the same order.
        let own = table.rank_of(Some(i));
        let half = 0.5 * opposites[i].map_or(0.0, |o| o.thickness);
        let separate = |q: Vec3, m: Vec3| separation(p, n, half, q, m, reach);
        // Each row's part in single precision, the whole in double.
        let mut sum = DVec3::ZERO;
        grid.for_each_run(p, reach, |run| {
            let mut part = Vec4::ZERO;
            for j in run {
                let d2 = (table.position(j) - p).length_squared();
                if d2 > reach * reach || !table.joins(j, piece) {
                    continue;
                }
                part += table.weight_placed(&disks, j, d2, own, &separate) * table.flux[j];
            }
            sum += part.truncate().as_dvec3();
        });
        sum.to_array().map(|v| v as f32)
    })?;
    Ok(out)
}

/// How a source at `q` (normal `m`) sits from a target at `p` (normal
/// `n`) on a part `2·half` mm thick, for the slab's kernel: across the
/// face behind (read as T at the offset along the face), along the same
/// face or round a crease (read as R), or `None` beyond `reach` mm or
/// deeper than the face behind.
fn separation(p: Vec3, n: Vec3, half: f32, q: Vec3, m: Vec3, reach: f32) -> Option<Separation> {
    let d = q - p;
    let d2 = d.length_squared();
    if d2 > reach * reach {
        return None;
    }
    if let Some(length) = longer_path(q, m, p, n, d2) {
        return Some(Separation {
            distance: length,
            across: length,
            t: 0.0,
        });
    }
    let along = d.dot(n);
    let distance = d2.sqrt();
    if m.dot(n) < 0.0 && along < -half {
        // Deeper than the face behind: another surface beyond the part,
        // which its slab does not join to this face.
        if along < -3.0 * half {
            return None;
        }
        return Some(Separation {
            distance,
            across: (d2 - along * along).max(0.0).sqrt(),
            t: 1.0,
        });
    }
    Some(Separation {
        distance,
        across: distance,
        t: 0.0,
    })
}

fn mix(a: Rgb, b: Rgb, w: f64) -> Rgb {
    [0, 1, 2].map(|c| a[c] + w * (b[c] - a[c]))
}
