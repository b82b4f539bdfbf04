//! One object's map carried from lattices of texels: N where the light is
//! not smooth over a lattice's cells, the integrator's sums at the lattice
//! texels, and each texel's route between them.

use super::{KernelNear, NearSum, SMOOTH_SHARE, near_reach, smooth};
use crate::control::Control;
use crate::error::Error;
use crate::prepared::Prepared;
use crate::surface::lattice::{Lattice, on_surface_of};
use crate::surface::texels::TexelSurfels;
use crate::transport::brute::Reach;
use crate::transport::integrator::Summer;
use crate::transport::kernel::Kernel;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};

/// How one texel is carried: from the lattice of `step` texels (1: its
/// own sum), and whether with its own N (where the light about it is not
/// bilinear) or whole.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Route {
    /// The lattice's step (a byte: a route's step is at most 255).
    step: u8,
    with_near: bool,
}

/// One object's map carried from lattices of texels: N where the light is
/// not smooth over the cells (none when carried whole), and the
/// integrator's sums at the lattice texels summed so far (NaN elsewhere).
pub struct Carrier<'a> {
    lit: &'a Prepared,
    summer: &'a dyn Summer,
    /// What sums N; `None` when carried whole.
    near_sum: Option<Box<dyn NearSum + 'a>>,
    /// The share of the light by which it may miss its bilinear mean where
    /// the map is carried whole, N and all.
    smooth_share: f32,
    /// Per lattice step, per surfel: where the light is smooth.
    smooth: HashMap<u32, Vec<bool>>,
    /// N per surfel (NaN where not yet summed; empty when carried whole).
    near: Vec<[f32; 3]>,
    /// N's reach per surfel, mm ([`near_reach`]; empty when carried
    /// whole).
    near_radius: Vec<f32>,
    summed: Vec<[f32; 3]>,
    /// Whether lattice texel `j` may carry to texel `i` beyond lying on
    /// its surface; `None`: wherever it does.
    joins: Option<&'a (dyn Fn(usize, usize) -> bool + Sync)>,
    /// Whether cells whose corners' sums are [`steep`] are carried from
    /// finer lattices (whole maps only; [`Carrier::with_steep_cells`]).
    steep_cells: bool,
}

impl<'a> Carrier<'a> {
    /// The map of `lit` under `kernel` split as M = N + F, N (the sum
    /// within [`near_reach`] of each texel, tapered) found where the light
    /// is not within [`SMOOTH_SHARE`] of `tolerance` of bilinear over the
    /// lattice's cells, and carried with F elsewhere.
    pub fn split(
        lit: &'a Prepared,
        summer: &'a dyn Summer,
        kernel: &'a Kernel,
        tolerance: f64,
    ) -> Self {
        Self::split_by(lit, summer, Box::new(KernelNear { lit, kernel }), tolerance)
    }

    /// [`Carrier::split`] with N summed by `near_sum`: for sums whose
    /// kernel is not one for every target.
    pub fn split_by(
        lit: &'a Prepared,
        summer: &'a dyn Summer,
        near_sum: Box<dyn NearSum + 'a>,
        tolerance: f64,
    ) -> Self {
        let texels = lit.surfels.len();
        Carrier {
            lit,
            summer,
            near_sum: Some(near_sum),
            smooth_share: (SMOOTH_SHARE * tolerance) as f32,
            smooth: HashMap::new(),
            near: vec![[f32::NAN; 3]; texels],
            near_radius: near_reach::near_radii(&lit.surfels),
            summed: vec![[f32::NAN; 3]; texels],
            joins: None,
            steep_cells: false,
        }
    }

    /// `summer`'s sums over `lit` carried whole (N = 0): for a light with
    /// no edges, whose sums change only over the profile's spread.
    pub fn whole(lit: &'a Prepared, summer: &'a dyn Summer) -> Self {
        let texels = lit.surfels.len();
        Carrier {
            lit,
            summer,
            near_sum: None,
            smooth_share: 0.0,
            smooth: HashMap::new(),
            near: Vec::new(),
            near_radius: Vec::new(),
            summed: vec![[f32::NAN; 3]; texels],
            joins: None,
            steep_cells: false,
        }
    }

    /// The carrier with lattice texel `j` a corner of texel `i` only where
    /// `joins(i, j)` also holds: for sums that change sharply where
    /// something other than the surface does (a part's thickness).
    pub fn joining(mut self, joins: &'a (dyn Fn(usize, usize) -> bool + Sync)) -> Self {
        self.joins = Some(joins);
        self
    }

    /// The carrier of a whole map with each cell whose corners' sums are
    /// [`steep`] carried from finer lattices, down to each texel's own
    /// sum: for sums that change sharply in places the lattice cannot
    /// know beforehand (where what joins the surface within reach
    /// changes). The lattice texels summed so far are kept.
    pub fn with_steep_cells(mut self) -> Self {
        self.steep_cells = self.near_sum.is_none();
        self
    }

    /// The map at `texels`: each carried from the lattice of `step` texels
    /// where it has four corners on its surface, else from the lattice of
    /// half the step (rounding up), down to its own sum. The lattice texels
    /// and the N it needs are summed once and kept.
    pub fn at(
        &mut self,
        texels: &[usize],
        step: u32,
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Error> {
        self.carried(texels, step, false, control)
    }

    /// [`Carrier::at`] `texels`, the last map asked for: the summer lets
    /// go of its tree once the lattice is summed, before the map is
    /// carried into memory of its own.
    pub fn last_map(
        mut self,
        texels: &[usize],
        step: u32,
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Error> {
        self.carried(texels, step, true, control)
    }

    fn carried(
        &mut self,
        texels: &[usize],
        step: u32,
        last: bool,
        control: &Control,
    ) -> Result<Vec<[f32; 3]>, Error> {
        let mut routes = self.routes(texels, step);
        loop {
            let missing = marked(self.summed.len(), texels, &routes, |i, route, mark| {
                for (j, _) in self.corners(i, route.step.into()).into_iter().flatten() {
                    if self.summed[j][0].is_nan() {
                        mark(j);
                    }
                }
            });
            self.sum(&missing, control)?;
            if !self.steeper(texels, &mut routes) {
                break;
            }
        }
        if last {
            self.summer.release();
        }
        self.sum_near(texels, &routes, control)?;
        Ok(texels
            .par_iter()
            .zip(&routes)
            .map(|(&i, route)| self.carry(i, *route))
            .collect())
    }

    /// Finds N wherever the map at `texels` carried from `step` needs it,
    /// before the integrator's first sums, so the exact sum's table and the
    /// integrator's are not held at once.
    pub fn near_for(
        &mut self,
        texels: &[usize],
        step: u32,
        control: &Control,
    ) -> Result<(), Error> {
        let routes = self.routes(texels, step);
        self.sum_near(texels, &routes, control)
    }

    /// The share of `texels` whose light is smooth at `step`: carried
    /// whole, without their own N.
    pub fn smooth_share_at(&mut self, texels: &[usize], step: u32) -> f64 {
        let routes = self.routes(texels, step);
        let whole = routes.iter().filter(|r| r.step > 1 && !r.with_near);
        whole.count() as f64 / texels.len().max(1) as f64
    }

    /// How each of `texels` is carried from `step` down.
    fn routes(&mut self, texels: &[usize], step: u32) -> Vec<Route> {
        let mut routes = vec![
            Route {
                step: 1,
                with_near: false,
            };
            texels.len()
        ];
        let mut pending: Vec<usize> = (0..texels.len()).collect();
        let mut step = step.clamp(1, u8::MAX.into());
        // The light entering, found once for the steps that look for
        // smooth light and dropped with the routes, not kept with the
        // carrier, which lives while the integrator's tree is held.
        let mut light = None;
        while step > 1 && !pending.is_empty() {
            self.smooth_at(step, &mut light);
            let smooth = self.smooth.get(&step);
            let lattice = Lattice::new(&self.lit.surfels, step);
            let decided: Vec<Option<Route>> = pending
                .par_iter()
                .map(|&k| {
                    let i = texels[k];
                    self.corners(i, step)?;
                    let on_lattice = lattice.holds(self.lit.surfels.texel[i]);
                    let smooth = smooth.is_none_or(|s| s[i]);
                    Some(Route {
                        step: step as u8,
                        with_near: !on_lattice && !smooth,
                    })
                })
                .collect();
            let mut left = Vec::new();
            for (k, route) in pending.into_iter().zip(decided) {
                match route {
                    Some(route) => routes[k] = route,
                    None => left.push(k),
                }
            }
            pending = left;
            step = step.div_ceil(2);
        }
        routes
    }

    /// Routes each of `texels` carried whole from corners whose sums are
    /// [`steep`] from the next finer lattice (down to its own sum);
    /// whether any route changed. A whole map's sums change over the
    /// profile's spread except where what joins the surface within reach
    /// changes abruptly (a thin part's rim, a piece set into another),
    /// where a cell's bilinear mean misses.
    fn steeper(&self, texels: &[usize], routes: &mut [Route]) -> bool {
        if !self.steep_cells {
            return false;
        }
        let changed: Vec<(usize, Route)> = texels
            .par_iter()
            .zip(routes.par_iter())
            .enumerate()
            .filter_map(|(k, (&i, route))| {
                let corners = self.corners(i, route.step.into())?;
                if route.step <= 1 || !steep(corners.map(|(j, _)| self.summed[j])) {
                    return None;
                }
                let mut step = u32::from(route.step).div_ceil(2);
                while step > 1 && self.corners(i, step).is_none() {
                    step = step.div_ceil(2);
                }
                let with_near = false;
                Some((
                    k,
                    Route {
                        step: step as u8,
                        with_near,
                    },
                ))
            })
            .collect();
        for &(k, route) in &changed {
            routes[k] = route;
        }
        !changed.is_empty()
    }

    /// Finds where the light is smooth at `step`, once (nothing to find
    /// when carried whole), with `light` the light entering once found.
    fn smooth_at(&mut self, step: u32, light: &mut Option<Vec<[f32; 3]>>) {
        if self.near_sum.is_none() || self.smooth.contains_key(&step) {
            return;
        }
        let surfels = &self.lit.surfels;
        let lattice = Lattice::new(surfels, step);
        let light = light.get_or_insert_with(|| self.lit.entering());
        let smooth = smooth::smooth_texels(
            surfels,
            light,
            &lattice,
            &self.near_radius,
            self.smooth_share,
            |i, j| alike(surfels, &lattice, i, j),
        );
        self.smooth.insert(step, smooth);
    }

    /// The lattice surfels texel `i` is carried from at `step`, with their
    /// bilinear weights: itself alone (weight 1) at step 1 or on the
    /// lattice, else its four corners on its surface; `None` when it has
    /// not four.
    fn corners(&self, i: usize, step: u32) -> Option<[(usize, f32); 4]> {
        let surfels = &self.lit.surfels;
        let lattice = Lattice::new(surfels, step);
        if step <= 1 || lattice.holds(surfels.texel[i]) {
            return Some([(i, 1.0), (i, 0.0), (i, 0.0), (i, 0.0)]);
        }
        lattice.corners(surfels, i, |j| {
            alike(surfels, &lattice, i, j) && self.joins.is_none_or(|joins| joins(i, j))
        })
    }

    /// N at the texels of `texels` routed with it and at their corners,
    /// where not yet summed.
    fn sum_near(
        &mut self,
        texels: &[usize],
        routes: &[Route],
        control: &Control,
    ) -> Result<(), Error> {
        let Some(near_sum) = &self.near_sum else {
            return Ok(());
        };
        let listed = marked(self.near.len(), texels, routes, |i, route, mark| {
            if !route.with_near {
                return;
            }
            let corners = self.corners(i, route.step.into()).into_iter().flatten();
            for j in std::iter::once(i).chain(corners.map(|(j, _)| j)) {
                if self.near[j][0].is_nan() {
                    mark(j);
                }
            }
        });
        if listed.is_empty() {
            return Ok(());
        }
        let reaches: Vec<Reach> = listed
            .iter()
            .map(|&j| Reach {
                radius: self.near_radius[j],
                tapered: true,
            })
            .collect();
        let near = near_sum.within(&listed, &reaches, control)?;
        for (&j, n) in listed.iter().zip(near) {
            self.near[j] = n;
        }
        Ok(())
    }

    /// The integrator's sums at `listed` (none known yet), kept.
    fn sum(&mut self, listed: &[usize], control: &Control) -> Result<(), Error> {
        for (&s, m) in listed.iter().zip(self.summer.at(listed, control)?) {
            self.summed[s] = m;
        }
        Ok(())
    }

    /// Texel `i`'s exitance by `route`: the bilinear mean of the sums at
    /// the lattice texels it is carried from (its own sum at step 1 or on
    /// the lattice), with its own N for theirs where the light about it is
    /// not smooth.
    fn carry(&self, i: usize, route: Route) -> [f32; 3] {
        let Some(corners) = self.corners(i, route.step.into()) else {
            return self.summed[i];
        };
        let near = |j: usize| -> [f32; 3] {
            if route.with_near {
                self.near[j]
            } else {
                [0.0; 3]
            }
        };
        let far = |c: usize| -> f32 {
            corners
                .iter()
                .map(|&(j, w)| w * (self.summed[j][c] - near(j)[c]))
                .sum()
        };
        let own = near(i);
        [0, 1, 2].map(|c| own[c] + far(c))
    }
}

/// The spread of a cell's corner sums, as a share of their largest,
/// above which a whole map's cell is carried from a finer lattice. The
/// head in skin1 at 4096²: its sums under a unit light 8 texels apart
/// gave gains 2.4% from their direct sums (relative RMS at 16384 probes,
/// all of it from a few texels by rims, up to 300% off), so the map was
/// summed again at 4 (0.42%); with cells steeper than 10% carried from
/// finer lattices it misses by 0.11% at 8, with 23% more sums than the
/// lattice's own instead of four times as many (at 5%: 0.06%, 50% more;
/// at 20%: 0.31%, 8% more).
const STEEP: f32 = 0.1;

/// True when the four corner sums spread by more than [`STEEP`] of the
/// largest in some channel.
fn steep(sums: [[f32; 3]; 4]) -> bool {
    (0..3).any(|c| {
        let (lo, hi) = sums
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), s| {
                (lo.min(s[c]), hi.max(s[c]))
            });
        hi - lo > STEEP * hi.abs()
    })
}

/// The surfels below `count` that `each` marks for any of `texels` (given
/// each texel, its route and the mark), each once and in order; the
/// texels are visited in parallel.
fn marked(
    count: usize,
    texels: &[usize],
    routes: &[Route],
    each: impl Fn(usize, Route, &dyn Fn(usize)) + Sync,
) -> Vec<usize> {
    let marks: Vec<AtomicBool> = (0..count).map(|_| AtomicBool::new(false)).collect();
    let mark = |j: usize| marks[j].store(true, Ordering::Relaxed);
    texels
        .par_iter()
        .zip(routes)
        .for_each(|(&i, &route)| each(i, route, &mark));
    marks
        .into_par_iter()
        .enumerate()
        .filter_map(|(j, m)| m.into_inner().then_some(j))
        .collect()
}

/// True when lattice texel `j` lies on texel `i`'s surface
/// ([`on_surface_of`]) within a cell's reach, so it carries its share of
/// the map there.
fn alike(surfels: &TexelSurfels, lattice: &Lattice, i: usize, j: usize) -> bool {
    let within = 1.5 * lattice.step as f32 * surfels.stretch[i].length();
    on_surface_of(surfels, i, j)
        && surfels.position[j].distance_squared(surfels.position[i]) <= within * within
}
