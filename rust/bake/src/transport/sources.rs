//! Where light enters: surface samples with their area and transmitted
//! irradiance, and a uniform grid over them for gathering within d_max.

use crate::transport::through_medium::pieces_joined;
use glam::{IVec2, Vec2, Vec3};
use rayon::prelude::*;
use std::borrow::Cow;

/// Samples light enters through, structure of arrays. What does not
/// change with the light may be borrowed (a layout's texels lend theirs,
/// so the texels as sources cost their light alone).
#[derive(Clone, Debug, Default)]
pub struct Sources<'a> {
    /// Positions, mm.
    pub position: Cow<'a, [Vec3]>,
    /// Unit normals.
    pub normal: Cow<'a, [Vec3]>,
    /// Area each stands for, mm².
    pub area: Cow<'a, [f32]>,
    /// Transmitted irradiance E_t, W/m² per channel.
    pub irradiance: Vec<[f32; 3]>,
    /// For texels: the edges of the parallelogram of surface each stands
    /// for, mm (one texel step along u and along v for a whole texel; the
    /// covered part's rectangle for a texel at a chart's edge); empty for
    /// samples without a shape.
    pub footprint: Cow<'a, [[Vec3; 2]]>,
    /// The piece of the mesh each sample lies on (see
    /// [`crate::surface::medium::medium_pieces`]); empty when every
    /// sample is on one piece. Light travels only between samples of one
    /// piece.
    pub piece: Cow<'a, [u32]>,
    /// The piece of the mesh each sample lies on where some medium joins
    /// several ([`crate::surface::medium::Media::piece`]); empty
    /// otherwise. Light crosses between pieces of one medium only where
    /// [`pieces_joined`] says.
    pub part: Cow<'a, [u32]>,
}

impl Sources<'_> {
    /// True when source `i` and `target` are joined by the medium
    /// ([`Target::joined_to`]).
    #[inline]
    pub fn joins(&self, i: usize, target: &Target) -> bool {
        target.joined_to(
            self.piece.get(i).copied(),
            self.part.get(i).copied(),
            self.position[i],
            self.normal[i],
        )
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Σ E_t·A per channel: the flux entering, W/m² · mm².
    pub fn flux(&self) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        for (e, &a) in self.irradiance.iter().zip(self.area.iter()) {
            for c in 0..3 {
                sum[c] += e[c] as f64 * a as f64;
            }
        }
        sum
    }
}

/// Points at which exitance is wanted (texel surfels or any others).
#[derive(Clone, Copy, Debug)]
pub struct Targets<'a> {
    /// Positions, mm.
    pub position: &'a [Vec3],
    /// Unit normals.
    pub normal: &'a [Vec3],
    /// Which source each target is, if any.
    pub own: OwnSource<'a>,
    /// The piece of the mesh each target lies on; empty to gather from
    /// every piece (samples of one piece, or sources without pieces).
    pub piece: &'a [u32],
    /// The piece of its medium each target lies on, as
    /// [`Sources::part`]; empty where the sources' media have one piece
    /// each, or the targets do not say.
    pub part: &'a [u32],
}

impl Targets<'_> {
    /// The piece target `i` lies on, when the targets say.
    pub fn piece_of(&self, i: usize) -> Option<u32> {
        self.piece.get(i).copied()
    }

    /// Target `i` alone.
    pub fn at(&self, i: usize) -> Target {
        Target {
            position: self.position[i],
            normal: self.normal[i],
            own: self.own.of(i),
            piece: self.piece_of(i),
            part: self.part.get(i).copied(),
        }
    }
}

/// One point at which exitance is wanted.
#[derive(Clone, Copy, Debug)]
pub struct Target {
    /// Position, mm.
    pub position: Vec3,
    /// Unit normal.
    pub normal: Vec3,
    /// The source it is, if any.
    pub own: Option<usize>,
    /// The piece of the mesh it lies on, if known.
    pub piece: Option<u32>,
    /// The piece of its medium it lies on, if known ([`Targets::part`]).
    pub part: Option<u32>,
}

impl Target {
    /// True when a source on piece `piece` of the mesh and piece `part` of
    /// its medium (each `None` where its sources do not say), at
    /// `position` (mm) with unit `normal`, is joined to this target by the
    /// medium: in one medium, and joined across its pieces where it has
    /// several ([`pieces_joined`]).
    #[inline]
    pub fn joined_to(
        &self,
        piece: Option<u32>,
        part: Option<u32>,
        position: Vec3,
        normal: Vec3,
    ) -> bool {
        self.piece.is_none_or(|q| piece.is_none_or(|p| p == q))
            && match (part, self.part) {
                (Some(p), Some(q)) => {
                    pieces_joined(p, position, normal, q, self.position, self.normal)
                }
                _ => true,
            }
    }
}

/// Which source each target is: a texel's own light is weighed by the
/// reflectance within its own disk, which only the texel itself gets.
#[derive(Clone, Copy, Debug)]
pub enum OwnSource<'a> {
    /// Target i is source i.
    Same,
    /// Target i is source `listed[i]`.
    Listed(&'a [usize]),
    /// The targets are not sources.
    None,
}

impl OwnSource<'_> {
    /// The source target `i` is.
    pub fn of(&self, i: usize) -> Option<usize> {
        match self {
            OwnSource::Same => Some(i),
            OwnSource::Listed(listed) => listed.get(i).copied(),
            OwnSource::None => None,
        }
    }
}

/// Sources sorted into rows: square cells of a fixed size across y and z,
/// each row's members contiguous (a counting sort) and in order of x, so
/// the members of a row within any span of x are one run, found by a
/// binary search. Only the rows are a dense array: a surface fills few of
/// a box's cubic cells, and rows let the cells stay as fine as the
/// gathers want on a large object.
pub struct Grid {
    cell: f32,
    origin: Vec3,
    /// Rows along y and along z.
    dims: IVec2,
    /// Start of each row's run in `order` (rows + 1 entries).
    starts: Vec<u32>,
    /// The x of each member, in `order`'s order.
    xs: Vec<f32>,
    /// Source indices, row by row (y fastest), each row in order of x.
    pub order: Vec<u32>,
}

/// The most rows a grid is given: a finer cell is coarsened to fit.
const MOST_ROWS: f32 = 16.0e6;

impl Grid {
    /// A grid over `positions` with rows about `cell` mm square (coarsened
    /// if the box would need more than [`MOST_ROWS`]).
    pub fn new(positions: &[Vec3], cell: f32) -> Self {
        let empty = || (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let (lo, hi) = positions
            .par_iter()
            .fold(empty, |(lo, hi), &p| (lo.min(p), hi.max(p)))
            .reduce(empty, |(a, b), (c, d)| (a.min(c), b.max(d)));
        let (lo, hi) = if positions.is_empty() {
            (Vec3::ZERO, Vec3::ZERO)
        } else {
            (lo, hi)
        };
        let extent = (hi - lo).max(Vec3::splat(1e-6));
        let mut cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            extent.max_element()
        };
        let across = Vec2::new(extent.y, extent.z);
        // Bounded even for a box without end (an infinite coordinate):
        // the cell grows past any finite extent, or to infinity.
        while cell.is_finite()
            && (across / cell).ceil().max(Vec2::ONE).element_product() > MOST_ROWS
        {
            cell *= 1.5;
        }
        let dims = (across / cell).floor().as_ivec2() + IVec2::ONE;
        let rows = (dims.x * dims.y) as usize;
        let key = |p: Vec3| -> usize {
            let c = ((Vec2::new(p.y, p.z) - Vec2::new(lo.y, lo.z)) / cell)
                .floor()
                .as_ivec2()
                .clamp(IVec2::ZERO, dims - 1);
            (c.x + dims.x * c.y) as usize
        };
        // Each position's row found once, in parallel; the counting sort
        // that follows is two cheap passes over them.
        let keys: Vec<u32> = positions.par_iter().map(|&p| key(p) as u32).collect();
        let mut starts = vec![0u32; rows + 1];
        for &k in &keys {
            starts[k as usize + 1] += 1;
        }
        for i in 0..rows {
            starts[i + 1] += starts[i];
        }
        let mut fill = starts.clone();
        let mut order = vec![0u32; positions.len()];
        for (i, &k) in keys.iter().enumerate() {
            let k = k as usize;
            order[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
        drop(keys);
        drop(fill);
        // Each row in order of x, rows apart in parallel.
        let mut runs = Vec::new();
        let mut rest = order.as_mut_slice();
        for row in starts.windows(2) {
            let (run, after) = rest.split_at_mut((row[1] - row[0]) as usize);
            if run.len() > 1 {
                runs.push(run);
            }
            rest = after;
        }
        runs.par_iter_mut().for_each(|run| {
            run.sort_unstable_by(|&a, &b| {
                positions[a as usize].x.total_cmp(&positions[b as usize].x)
            })
        });
        let xs = order.par_iter().map(|&i| positions[i as usize].x).collect();
        Grid {
            cell,
            origin: lo,
            dims,
            starts,
            xs,
            order,
        }
    }

    /// Calls `visit(range)` with the positions in [`Grid::order`] of the
    /// members of every row that meets the ball of `radius` around `p`
    /// whose x lies within the ball's chord through the row (a superset of
    /// the ball: the chord is taken where the row comes nearest to `p`).
    pub fn for_each_run(
        &self,
        p: Vec3,
        radius: f32,
        mut visit: impl FnMut(std::ops::Range<usize>),
    ) {
        let across = Vec2::new(p.y, p.z);
        let origin = Vec2::new(self.origin.y, self.origin.z);
        let lo = ((across - radius - origin) / self.cell)
            .floor()
            .as_ivec2()
            .max(IVec2::ZERO);
        let hi = ((across + radius - origin) / self.cell)
            .floor()
            .as_ivec2()
            .min(self.dims - 1);
        // A little wider than the ball, so a point rounded into a row at
        // its edge is never missed.
        let r2 = (radius + 1e-4 * self.cell).powi(2);
        // The distance from p to the slab of rows k along one axis.
        let gap = |k: i32, at: f32, origin: f32| {
            let near = origin + k as f32 * self.cell;
            (near - at).max(at - (near + self.cell)).max(0.0)
        };
        for z in lo.y..=hi.y {
            let dz = gap(z, p.z, self.origin.z);
            for y in lo.x..=hi.x {
                let dy = gap(y, p.y, self.origin.y);
                let left = r2 - dy * dy - dz * dz;
                if left < 0.0 {
                    continue;
                }
                let row = (y + self.dims.x * z) as usize;
                let (a, b) = (self.starts[row] as usize, self.starts[row + 1] as usize);
                if a == b {
                    continue;
                }
                let chord = left.sqrt();
                let xs = &self.xs[a..b];
                let first = a + xs.partition_point(|&x| x < p.x - chord);
                let last = a + xs.partition_point(|&x| x <= p.x + chord);
                if last > first {
                    visit(first..last);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sssbake_profile::numerics::rng::Rng;

    #[test]
    fn a_gather_meets_every_point_within_its_ball_once() {
        let mut rng = Rng::new(7, 0);
        let mut point = || {
            let mut c = || rng.uniform() as f32 * 10.0 - 5.0;
            Vec3::new(c(), c(), 0.1 * c())
        };
        let points: Vec<Vec3> = (0..4000).map(|_| point()).collect();
        for cell in [0.3, 1.0, 4.0, 50.0] {
            let grid = Grid::new(&points, cell);
            for _ in 0..50 {
                let (p, radius) = (point(), 1.3);
                let mut met = vec![0u32; points.len()];
                grid.for_each_run(p, radius, |run| {
                    for &i in &grid.order[run] {
                        met[i as usize] += 1;
                    }
                });
                for (q, &count) in points.iter().zip(&met) {
                    assert!(count <= 1, "met twice");
                    if q.distance(p) <= radius {
                        assert_eq!(count, 1, "missed {q} from {p} with rows of {cell}");
                    }
                }
            }
        }
    }

    #[test]
    fn rows_coarsen_past_their_bound_and_hold_every_source() {
        let points = [
            Vec3::ZERO,
            Vec3::new(0.0, 1.0e4, 1.0e4),
            Vec3::new(f32::NAN, 0.0, 0.0),
        ];
        let grid = Grid::new(&points, 1e-3);
        assert!(grid.starts.len() as f32 <= MOST_ROWS + 1.0);
        let mut order = grid.order.clone();
        order.sort_unstable();
        assert_eq!(order, [0, 1, 2]);
        let mut met = Vec::new();
        grid.for_each_run(Vec3::ZERO, 1.0, |run| {
            met.extend_from_slice(&grid.order[run])
        });
        assert!(met.contains(&0));
        // A coordinate without end still makes a grid, and holds every source.
        let points = [Vec3::ZERO, Vec3::new(0.0, f32::INFINITY, 1.0)];
        let grid = Grid::new(&points, 0.5);
        assert_eq!(grid.order.len(), 2);
    }
}
