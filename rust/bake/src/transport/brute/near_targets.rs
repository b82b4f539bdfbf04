//! Which sources lie within reach of a few targets. The exact sum at a
//! few hundred texels (an estimate's, a pilot's) reads only the sources
//! within reach of them, yet sorting and copying every source into its
//! grid cost more than the sums themselves at 4096² (11.6 million texels,
//! over a second each time). A coarse grid of cells marks those within one
//! cell of a target's; a source outside them sends no target anything, so
//! it is left out of the walk without changing the sum's terms.

use glam::{IVec3, Vec3};
use rayon::prelude::*;

/// The most cells the marks hold, and the most per source (so the marks
/// of a small bake stay small beside its sources): a finer cell is
/// coarsened to fit.
const MOST_CELLS: usize = 1 << 24;
const MOST_CELLS_PER_SOURCE: usize = 4;

/// The cells within reach of some target.
pub(super) struct NearTargets {
    origin: Vec3,
    cell: f32,
    dims: IVec3,
    /// One per cell, x fastest: true within one cell of a target's.
    marked: Vec<bool>,
}

impl NearTargets {
    /// The cells within `reach` (mm) of `targets`, when they are few
    /// beside `sources` (else `None`: nearly every source would be kept,
    /// and the marks would cost more than they save).
    pub fn of(targets: &[Vec3], reach: f32, sources: usize) -> Option<Self> {
        if targets.is_empty() || targets.len() * 4 > sources || !(reach.is_finite() && reach > 0.0)
        {
            return None;
        }
        let finite = targets.iter().filter(|p| p.is_finite());
        let (lo, hi) = finite.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
        if !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        // A source within reach of a target lies in the target's cell or
        // a neighbour when the cell is at least the reach; one cell of
        // margin about the box holds those neighbours.
        let mut cell = reach;
        let cells = |cell: f32| ((hi - lo) / cell).floor().as_ivec3() + IVec3::splat(3);
        // At least the 27 cells about one target's, which any cell holds.
        let most = MOST_CELLS.min(MOST_CELLS_PER_SOURCE * sources).max(64) as f64;
        while cells(cell).as_dvec3().element_product() > most {
            cell *= 1.5;
        }
        let dims = cells(cell);
        let origin = lo - Vec3::splat(cell);
        let index = |c: IVec3| (c.x + dims.x * (c.y + dims.y * c.z)) as usize;
        let mut own = vec![false; dims.element_product() as usize];
        for p in targets.iter().filter(|p| p.is_finite()) {
            own[index(((*p - origin) / cell).floor().as_ivec3())] = true;
        }
        // Each marked cell's neighbours marked too, an axis at a time.
        let mut marked = own;
        for axis in 0..3 {
            let step = [1, dims.x, dims.x * dims.y][axis] as usize;
            let size = dims[axis];
            let before = marked;
            marked = (0..before.len())
                .into_par_iter()
                .map(|i| {
                    let along = (i / step) as i32 % size;
                    before[i]
                        || (along > 0 && before[i - step])
                        || (along + 1 < size && before[i + step])
                })
                .collect();
        }
        Some(NearTargets {
            origin,
            cell,
            dims,
            marked,
        })
    }

    /// True when a source at `p` may lie within reach of a target.
    #[inline]
    pub fn holds(&self, p: Vec3) -> bool {
        let c = ((p - self.origin) / self.cell).floor();
        if !(c.cmpge(Vec3::ZERO).all() && c.cmplt(self.dims.as_vec3()).all()) {
            return false;
        }
        let c = c.as_ivec3();
        self.marked[(c.x + self.dims.x * (c.y + self.dims.y * c.z)) as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on a 1 mm lattice over a 100 mm cube.
    fn lattice() -> Vec<Vec3> {
        (0..100 * 100 * 100)
            .map(|i| {
                Vec3::new(
                    (i % 100) as f32,
                    ((i / 100) % 100) as f32,
                    (i / 10000) as f32,
                )
            })
            .collect()
    }

    #[test]
    fn every_source_within_reach_is_held_and_far_ones_are_not() {
        let sources = lattice();
        let targets = [Vec3::new(10.3, 50.0, 80.7), Vec3::new(90.0, 2.5, 3.0)];
        let reach = 4.0;
        let near = NearTargets::of(&targets, reach, sources.len()).unwrap();
        let mut held = 0;
        for &q in &sources {
            let distance = targets
                .iter()
                .map(|t| t.distance(q))
                .fold(f32::MAX, f32::min);
            if distance <= reach {
                assert!(near.holds(q), "{q} lies {distance} mm from a target");
            }
            if near.holds(q) {
                held += 1;
                // Held only within the cells about a target's: 3 cells
                // of the reach across at most.
                assert!(distance <= 2.0 * reach * 3f32.sqrt(), "{q}: {distance} mm");
            }
        }
        assert!(
            held < sources.len() / 50,
            "{held} of {} held",
            sources.len()
        );
    }

    #[test]
    fn many_targets_or_no_reach_keep_every_source() {
        let sources = lattice();
        assert!(NearTargets::of(&sources[..300_000], 2.0, sources.len()).is_none());
        let one = [Vec3::ZERO];
        assert!(NearTargets::of(&one, 0.0, sources.len()).is_none());
        assert!(NearTargets::of(&one, f32::INFINITY, sources.len()).is_none());
        assert!(NearTargets::of(&[Vec3::NAN], 1.0, sources.len()).is_none());
        assert!(NearTargets::of(&[], 1.0, sources.len()).is_none());
    }

    #[test]
    fn a_reach_finer_than_the_marks_allow_is_coarsened_and_still_holds() {
        let targets = [Vec3::ZERO, Vec3::splat(1e5)];
        let near = NearTargets::of(&targets, 1e-3, 1 << 30).unwrap();
        assert!(near.marked.len() <= MOST_CELLS);
        // A bake of few sources keeps few marks.
        let few = NearTargets::of(&targets, 1e-3, 1000).unwrap();
        assert!(few.marked.len() <= 4000, "{}", few.marked.len());
        assert!(few.holds(Vec3::splat(1e-4)) && few.holds(Vec3::splat(1e5 - 1e-4)));
        // As few sources as targets allow: the cells grow, and end.
        let least = NearTargets::of(&targets[..1], 1e-3, 4).unwrap();
        assert!(least.marked.len() <= 64 && least.holds(Vec3::splat(1e-4)));
        assert!(near.holds(Vec3::splat(1e-4)) && near.holds(Vec3::splat(1e5 - 1e-4)));
        assert!(!near.holds(Vec3::splat(5e4)) && !near.holds(Vec3::splat(-1e6)));
        assert!(!near.holds(Vec3::NAN));
    }
}
