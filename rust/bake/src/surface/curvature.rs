//! How curved the surface is around each texel, at the scale light
//! explores there: the mean curvature H = (κ1 + κ2)/2, 1/mm, positive
//! where the surface bulges out.
//!
//! Between two points of a ball of radius r, (n_j − n_i)·(p_j − p_i) =
//! |p_j − p_i|²/r exactly, whatever their distance. So the weighted ratio
//!
//! H_i = Σ w_ij (n_j − n_i)·(p_j − p_i) / Σ w_ij |p_j − p_i|²
//!
//! is 1/r on any ball at any scale, 0 on a plane, 1/(2r) on a cylinder,
//! and on other shapes the mean curvature seen over the weights' reach
//! (w_ij = a_j exp(−|p_j − p_i|²/s²)). Points of another medium, and
//! points facing away by more than [`FACING_AWAY`] (the far face of a thin
//! part, which the slab of its thickness already accounts for), are left
//! out; the exactness on a ball holds for any subset of its pairs.
//!
//! The texels are first gathered into patches a fraction of the scale
//! across (by cell, medium and like normals, so the two faces of a thin
//! part and the faces of a box's edge stay apart, however the object is
//! turned), H is found at each patch,
//! and each texel takes a smooth mean of the patches around it: the work
//! grows with the texels and the patches, not with their product.

use crate::fast_hash::FastHash;
use crate::surface::lattice::{Lattice, on_surface_of};
use crate::surface::texels::TexelSurfels;
use crate::transport::sources::Grid;
use glam::{DVec3, IVec3, Vec3};
use rayon::prelude::*;
use std::collections::HashMap;

/// How far the weights reach, in units of the scale.
const REACH: f32 = 2.5;
/// A patch's size, in units of the scale: small enough that a patch of
/// a ball the size of the scale lies on it to a few per cent.
const PATCH: f32 = 0.35;
/// The cosine between normals below which a point faces away: past 120°,
/// so the faces of a box's edge see each other and a thin part's two
/// faces do not.
const FACING_AWAY: f32 = -0.5;
/// The cosine between normals at or above which texels face one way:
/// within about 75°. A texel joins a patch of its cell whose first texel
/// faces its way, and takes its curvature from the patches that do; so a
/// box's faces (90° apart) are never one patch, whichever of them face the
/// world's positive axes, and a thin part's two faces never meet.
const SAME_WAY: f32 = 0.25;
/// The widest lattice of texels the curvature is found at, texels apart.
const MOST_STEP: u32 = 16;
/// The most patches an object is gathered into: past it they grow, so the
/// work stays bounded on a large object at a short scale.
const MOST_PATCHES: f64 = 200_000.0;

/// About how many steps finding the curvature at `scale` mm takes on a
/// surface of `area_mm2` covered by `texels` texels: each texel gathered
/// into its patch and carried from the lattice, each patch's
/// neighbours within the reach, and each lattice texel's patches within
/// two sizes (0 for a scale that is not positive and finite).
pub fn planned_steps(texels: f64, area_mm2: f64, scale: f32) -> f64 {
    if !(is_scale(scale) && texels > 0.0 && area_mm2 > 0.0) {
        return 0.0;
    }
    let size = f64::from(patch_size(scale, area_mm2));
    // A patch holds a texel at least, and meets at most every patch.
    let patches = (area_mm2 / (size * size)).min(texels);
    let within = |radius: f64| (std::f64::consts::PI * (radius / size).powi(2)).min(patches);
    let texel = (area_mm2 / texels).sqrt();
    let step = step_for(texel as f32, size as f32);
    let found = texels / f64::from(step * step);
    2.0 * texels + patches * within(f64::from(REACH * scale)) + found * within(2.0 * size)
}

/// A patch's size, mm, at `scale` mm on a surface of `area_mm2`: a share
/// of the scale, grown where the patches would pass [`MOST_PATCHES`].
fn patch_size(scale: f32, area_mm2: f64) -> f32 {
    (PATCH * scale).max((area_mm2 / MOST_PATCHES).sqrt() as f32)
}

/// Whether `scale` (mm) is one curvature can be seen at: positive and
/// finite.
fn is_scale(scale: f32) -> bool {
    scale.is_finite() && scale > 0.0
}

/// Texels gathered into one patch.
#[derive(Clone, Copy, Debug, Default)]
struct Patch {
    position: Vec3,
    normal: Vec3,
    area: f32,
    medium: u32,
}

/// The mean curvature at every surfel of `surfels`, 1/mm, seen at `scale`
/// mm (0 for a scale that is not positive and finite).
pub fn mean_curvature(surfels: &TexelSurfels, scale: f32) -> Vec<f32> {
    mean_curvatures(surfels, [scale])
        .into_iter()
        .map(|[h]| h)
        .collect()
}

/// [`mean_curvature`] at each of `scales`, per surfel. Scales whose
/// patches are the same size (on an object large against them the patches
/// are sized by [`MOST_PATCHES`]) share the patches and the pass over the
/// texels, which at 4096² is most of the work; each is found as it would
/// be alone.
pub fn mean_curvatures<const K: usize>(surfels: &TexelSurfels, scales: [f32; K]) -> Vec<[f32; K]> {
    let mut out = vec![[0.0; K]; surfels.len()];
    if surfels.is_empty() {
        return out;
    }
    let area = surfels.total_area();
    let sizes = scales.map(|scale| is_scale(scale).then(|| patch_size(scale, area)));
    let mut sized: Vec<f32> = sizes.iter().flatten().copied().collect();
    sized.sort_by(f32::total_cmp);
    sized.dedup();
    match sized.as_slice() {
        [] => {}
        [size] => out = at_patch_size(surfels, *size, scales),
        _ => {
            for (k, size) in sizes.iter().enumerate() {
                let Some(size) = *size else { continue };
                let alone = at_patch_size(surfels, size, [scales[k]]);
                for (o, [h]) in out.iter_mut().zip(alone) {
                    o[k] = h;
                }
            }
        }
    }
    out
}

/// The mean curvature at every surfel at each of `scales` (0 at one that
/// is not a scale), from patches of `size` mm.
fn at_patch_size<const K: usize>(
    surfels: &TexelSurfels,
    size: f32,
    scales: [f32; K],
) -> Vec<[f32; K]> {
    let patches = patches(surfels, size);
    let positions: Vec<Vec3> = patches.iter().map(|p| p.position).collect();
    let mut at_patches = vec![[0.0f32; K]; patches.len()];
    for (k, &scale) in scales.iter().enumerate() {
        if !is_scale(scale) {
            continue;
        }
        let reach = REACH * scale;
        // Cells finer than the radius gathered within, so the rows of cells
        // visited hug the ball.
        let grid = Grid::new(&positions, 0.5 * reach);
        let found: Vec<f32> = patches
            .par_iter()
            .map(|p| {
                curvature_at(
                    &grid, &patches, p.position, p.normal, p.medium, scale, reach,
                )
            })
            .collect();
        for (at, h) in at_patches.iter_mut().zip(found) {
            at[k] = h;
        }
    }
    // Each texel: a smooth mean of the patches within two sizes, facing
    // its way, in its medium.
    let near = Grid::new(&positions, size);
    let smooth_mean = |i: usize| -> [f32; K] {
        let (p, n, m) = (
            surfels.position[i],
            surfels.normal[i],
            medium_of(surfels, i),
        );
        let (mut sum, mut weights) = ([0.0f32; K], 0.0f32);
        let within = 4.0 * size * size;
        near.for_each_run(p, 2.0 * size, |run| {
            for &k in &near.order[run] {
                let q = &patches[k as usize];
                let d2 = (q.position - p).length_squared();
                if d2 > within || q.medium != m || q.normal.dot(n) < SAME_WAY {
                    continue;
                }
                let w = (-d2 / (size * size)).exp();
                for (s, h) in sum.iter_mut().zip(&at_patches[k as usize]) {
                    *s += w * h;
                }
                weights += w;
            }
        });
        if weights > 0.0 {
            sum.map(|s| s / weights)
        } else {
            [0.0; K]
        }
    };
    // It changes over patches, not texels: it is found on a lattice of
    // texels up to a patch apart, and each texel between takes the
    // bilinear mean of the four lattice texels around it where they lie
    // on its surface (same medium, facing its way); elsewhere (a chart's
    // edge, a crease) it finds its own.
    let lattice = lattice_of(surfels, size);
    let at_lattice = OnLattice::found(surfels, lattice, smooth_mean);
    (0..surfels.len())
        .into_par_iter()
        .map(|i| {
            if let Some(found) = at_lattice.at(surfels, i) {
                return found;
            }
            let alike =
                |j: usize| on_surface_of(surfels, i, j) && at_lattice.at(surfels, j).is_some();
            match lattice.corners(surfels, i, alike) {
                Some(corners) => {
                    let mut carried = [0.0f32; K];
                    for (j, w) in corners {
                        let found = at_lattice.at(surfels, j).unwrap_or([0.0; K]);
                        for (c, h) in carried.iter_mut().zip(found) {
                            *c += w * h;
                        }
                    }
                    carried
                }
                None => smooth_mean(i),
            }
        })
        .collect()
}

/// Values found at the covered texels of a lattice, held by lattice
/// place (a quarter of the map's texels or fewer), not by surfel.
struct OnLattice<const K: usize> {
    lattice: Lattice,
    /// Per lattice place ([`Lattice::place`]): its value, or `None`
    /// uncovered.
    values: Vec<Option<[f32; K]>>,
}

impl<const K: usize> OnLattice<K> {
    /// `find` at each covered texel of `lattice`.
    fn found(
        surfels: &TexelSurfels,
        lattice: Lattice,
        find: impl Fn(usize) -> [f32; K] + Sync,
    ) -> Self {
        let values = (0..lattice.places())
            .into_par_iter()
            .map(|place| {
                let surfel = *surfels.index.get(lattice.texel_at(place) as usize)? as usize;
                (surfel < surfels.len()).then(|| find(surfel))
            })
            .collect();
        OnLattice { lattice, values }
    }

    /// The value at surfel `i` where it lies on the lattice.
    fn at(&self, surfels: &TexelSurfels, i: usize) -> Option<[f32; K]> {
        self.values[self.lattice.place(surfels.texel[i])?]
    }
}

/// The widest lattice, in powers of two from 2 up to [`MOST_STEP`]
/// texels, whose cells are at most a patch of `size` mm across.
fn lattice_of(surfels: &TexelSurfels, size: f32) -> Lattice {
    Lattice::new(surfels, step_for(surfels.mean_side() as f32, size))
}

/// The lattice's step for texels `texel` mm across and patches of `size`
/// mm.
fn step_for(texel: f32, size: f32) -> u32 {
    let mut step = 2;
    while step < MOST_STEP && (2 * step) as f32 * texel <= size {
        step *= 2;
    }
    step
}

fn medium_of(surfels: &TexelSurfels, i: usize) -> u32 {
    surfels.piece.get(i).copied().unwrap_or(0)
}

/// The texels gathered by cell of `size` mm and medium, and within a cell
/// into groups facing one way ([`SAME_WAY`] to the group's first texel,
/// texels taken in the map's order).
fn patches(surfels: &TexelSurfels, size: f32) -> Vec<Patch> {
    #[derive(Default)]
    struct Sum {
        first: Vec3,
        position: DVec3,
        normal: DVec3,
        area: f64,
    }
    let mut cells: HashMap<(IVec3, u32), Vec<Sum>, FastHash> = HashMap::default();
    for i in 0..surfels.len() {
        let (p, n) = (surfels.position[i], surfels.normal[i]);
        let a = f64::from(surfels.area[i]);
        if !(a > 0.0 && p.is_finite() && n.is_finite()) {
            continue;
        }
        let cell = (p / size).floor().as_ivec3();
        let groups = cells.entry((cell, medium_of(surfels, i))).or_default();
        let k = match groups.iter().position(|g| g.first.dot(n) >= SAME_WAY) {
            Some(k) => k,
            None => {
                groups.push(Sum {
                    first: n,
                    ..Sum::default()
                });
                groups.len() - 1
            }
        };
        let sum = &mut groups[k];
        sum.position += p.as_dvec3() * a;
        sum.normal += n.as_dvec3() * a;
        sum.area += a;
    }
    let mut patches: Vec<((IVec3, u32, usize), Patch)> = cells
        .into_iter()
        .flat_map(|((cell, medium), groups)| {
            groups.into_iter().enumerate().map(move |(k, s)| {
                let patch = Patch {
                    position: (s.position / s.area).as_vec3(),
                    normal: s.normal.normalize_or_zero().as_vec3(),
                    area: s.area as f32,
                    medium,
                };
                ((cell, medium, k), patch)
            })
        })
        .collect();
    // A fixed order, so the sums (and the bake) do not depend on the map's.
    patches.sort_unstable_by_key(|(k, _)| (k.0.z, k.0.y, k.0.x, k.1, k.2));
    patches.into_iter().map(|(_, p)| p).collect()
}

/// H at a point `p` facing `n` in `medium`, from the patches within
/// `reach` of it weighted at `scale`.
fn curvature_at(
    grid: &Grid,
    patches: &[Patch],
    p: Vec3,
    n: Vec3,
    medium: u32,
    scale: f32,
    reach: f32,
) -> f32 {
    let (mut bend, mut spread) = (0.0f64, 0.0f64);
    grid.for_each_run(p, reach, |run| {
        for &k in &grid.order[run] {
            let q = &patches[k as usize];
            let d = q.position - p;
            let d2 = d.length_squared();
            if q.medium != medium
                || q.normal.dot(n) <= FACING_AWAY
                || d2 > reach * reach
                || d2 == 0.0
            {
                continue;
            }
            let w = f64::from(q.area * (-d2 / (scale * scale)).exp());
            bend += w * f64::from((q.normal - n).dot(d));
            spread += w * f64::from(d2);
        }
    });
    let h = bend / spread;
    if h.is_finite() { h as f32 } else { 0.0 }
}
