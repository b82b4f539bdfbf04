//! Where light enters: surface samples with their area and transmitted
//! irradiance, and a uniform grid over them for gathering within d_max.

use glam::{IVec3, Vec3};

/// Samples light enters through, structure of arrays.
#[derive(Clone, Debug, Default)]
pub struct Sources {
    /// Positions, mm.
    pub position: Vec<Vec3>,
    /// Unit normals.
    pub normal: Vec<Vec3>,
    /// Area each stands for, mm².
    pub area: Vec<f32>,
    /// Transmitted irradiance E_t, W/m² per channel.
    pub irradiance: Vec<[f32; 3]>,
    /// For texels: the edges of the parallelogram of surface each stands
    /// for, mm (one texel step along u and along v for a whole texel; the
    /// covered part's rectangle for a texel at a chart's edge); empty for
    /// samples without a shape.
    pub footprint: Vec<[Vec3; 2]>,
    /// The piece of the mesh each sample lies on (see
    /// [`crate::surface::medium::medium_pieces`]); empty when every
    /// sample is on one piece. Light travels only between samples of one
    /// piece.
    pub piece: Vec<u32>,
}

impl Sources {
    /// True when source `i` and a target on `piece` are joined by the
    /// medium: on one piece, or when either side does not say.
    #[inline]
    pub fn joins(&self, i: usize, piece: Option<u32>) -> bool {
        piece.is_none_or(|q| self.piece.get(i).is_none_or(|&p| p == q))
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
        for (e, &a) in self.irradiance.iter().zip(&self.area) {
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

/// Sources sorted into cubic cells of a fixed size, each cell's members
/// contiguous (a counting sort), for gathering within a radius.
pub struct Grid {
    cell: f32,
    origin: Vec3,
    dims: IVec3,
    /// Start of each cell's run in `order` (cells + 1 entries).
    starts: Vec<u32>,
    /// Source indices, cell by cell (x fastest, so a row of cells is one
    /// run).
    pub order: Vec<u32>,
}

impl Grid {
    /// A grid over `positions` with cells of about `cell` mm (coarsened if
    /// the box would need more than ~16M cells).
    pub fn new(positions: &[Vec3], cell: f32) -> Self {
        let (lo, hi) = positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
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
        while (extent / cell).ceil().max(Vec3::ONE).element_product() > 16.0e6 {
            cell *= 1.5;
        }
        let dims = (extent / cell).floor().as_ivec3() + IVec3::ONE;
        let cells = (dims.x * dims.y * dims.z) as usize;
        let key = |p: Vec3| -> usize {
            let c = ((p - lo) / cell)
                .floor()
                .as_ivec3()
                .clamp(IVec3::ZERO, dims - 1);
            (c.x + dims.x * (c.y + dims.y * c.z)) as usize
        };
        let mut starts = vec![0u32; cells + 1];
        for &p in positions {
            starts[key(p) + 1] += 1;
        }
        for i in 0..cells {
            starts[i + 1] += starts[i];
        }
        let mut fill = starts.clone();
        let mut order = vec![0u32; positions.len()];
        for (i, &p) in positions.iter().enumerate() {
            let k = key(p);
            order[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
        Grid {
            cell,
            origin: lo,
            dims,
            starts,
            order,
        }
    }

    /// Calls `visit(range)` with the positions in [`Grid::order`] of every
    /// row of cells that meets the ball of `radius` around `p` (a superset
    /// of the ball: each row's cells from the first to the last that the
    /// ball's chord through the row's slab reaches).
    pub fn for_each_run(
        &self,
        p: Vec3,
        radius: f32,
        mut visit: impl FnMut(std::ops::Range<usize>),
    ) {
        let lo = ((p - radius - self.origin) / self.cell)
            .floor()
            .as_ivec3()
            .max(IVec3::ZERO);
        let hi = ((p + radius - self.origin) / self.cell)
            .floor()
            .as_ivec3()
            .min(self.dims - 1);
        if lo.x > hi.x {
            return;
        }
        // A little wider than the ball, so a point rounded into a cell at
        // its edge is never missed.
        let r2 = (radius + 1e-4 * self.cell).powi(2);
        // The distance from p to the slab of cells k along one axis.
        let gap = |k: i32, at: f32, origin: f32| {
            let near = origin + k as f32 * self.cell;
            (near - at).max(at - (near + self.cell)).max(0.0)
        };
        for z in lo.z..=hi.z {
            let dz = gap(z, p.z, self.origin.z);
            for y in lo.y..=hi.y {
                let dy = gap(y, p.y, self.origin.y);
                let left = r2 - dy * dy - dz * dz;
                if left < 0.0 {
                    continue;
                }
                let chord = left.sqrt();
                let first = (((p.x - chord - self.origin.x) / self.cell).floor() as i32).max(lo.x);
                let last = (((p.x + chord - self.origin.x) / self.cell).floor() as i32).min(hi.x);
                if first > last {
                    continue;
                }
                let row = (self.dims.x * (y + self.dims.y * z)) as usize;
                let a = self.starts[row + first as usize] as usize;
                let b = self.starts[row + last as usize + 1] as usize;
                if b > a {
                    visit(a..b);
                }
            }
        }
    }
}
