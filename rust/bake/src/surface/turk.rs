//! Sample points spread evenly over the surface by Turk's repulsion
//! (Turk 1992; Mikkelsen §3.2): placed at random in proportion to area,
//! then pushed apart within a radius 2√(A/N), sliding across edges into
//! the neighbouring triangles.

use crate::fast_hash::FastHash;
use crate::mesh::Mesh;
use crate::surface::topology::{NONE, neighbours};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use sssbake_profile::numerics::rng::Rng;
use std::collections::HashMap;

/// Points on a mesh's surface, structure of arrays.
#[derive(Clone, Debug, Default)]
pub struct SurfacePoints {
    /// Position, mm.
    pub position: Vec<Vec3>,
    /// Unit interpolated normal.
    pub normal: Vec<Vec3>,
    /// The triangle each point lies on.
    pub triangle: Vec<u32>,
    /// Surface area each point stands for, mm² (A/N).
    pub area: Vec<f32>,
}

/// How relaxation went.
#[derive(Clone, Debug, PartialEq)]
pub struct Relaxation {
    /// Coefficient of variation of nearest-neighbour distances before.
    pub spread_before: f64,
    /// The same after.
    pub spread_after: f64,
    /// Root-mean-square move per iteration, in units of the repulsion radius:
    /// the convergence measure.
    pub moves: Vec<f64>,
}

/// Points for a surface of `area_mm2` at one per disk of the mean free
/// path, N = multiplier · A/(πℓ²), between one and a billion.
pub fn point_count(area_mm2: f64, mean_free_path_mm: f64, multiplier: f64) -> usize {
    let n = multiplier * area_mm2 / (std::f64::consts::PI * mean_free_path_mm * mean_free_path_mm);
    // At most a billion; a zero mean free path asks for that many.
    if n.is_nan() {
        1
    } else {
        n.ceil().clamp(1.0, 1e9) as usize
    }
}

/// `count` points placed uniformly at random by area (binary search over
/// the triangles' cumulative area, then Turk's √ξ sampling in the triangle).
pub fn place_points(mesh: &Mesh, count: usize, seed: u64) -> (SurfacePoints, Vec<[f64; 3]>) {
    let mut cumulative = Vec::with_capacity(mesh.triangles.len());
    let mut total = 0.0;
    for t in 0..mesh.triangles.len() {
        total += mesh.triangle_area(t);
        cumulative.push(total);
    }
    let mut rng = Rng::new(seed, 0x7475_726b);
    let mut triangles = Vec::with_capacity(count);
    let mut weights = Vec::with_capacity(count);
    for _ in 0..count {
        let target = rng.uniform() * total;
        let t = cumulative
            .partition_point(|&c| c <= target)
            .min(cumulative.len() - 1);
        let s = rng.uniform().sqrt();
        let r = rng.uniform();
        triangles.push(t as u32);
        weights.push([1.0 - s, s * (1.0 - r), s * r]);
    }
    let points = points_at(
        mesh,
        &triangles,
        &weights,
        (total / count.max(1) as f64) as f32,
    );
    (points, weights)
}

/// Relaxes `points` (with their barycentric `weights`) for `iterations`
/// rounds of repulsion with a linear force. The points come back sorted by
/// place, which keeps neighbours near each other in memory.
pub fn relax(
    mesh: &Mesh,
    points: &mut SurfacePoints,
    weights: &mut [[f64; 3]],
    iterations: u32,
) -> Relaxation {
    let count = points.position.len();
    let radius = 2.0 * (mesh.area() / count.max(1) as f64).sqrt();
    let across = neighbours(mesh);
    let start = Grid::new(&points.position, radius);
    let spread_before = spread_in(&start, radius);
    let order = start.order;
    let sorted_weights: Vec<[f64; 3]> = order.iter().map(|&i| weights[i as usize]).collect();
    weights.copy_from_slice(&sorted_weights);
    let triangles: Vec<u32> = order.iter().map(|&i| points.triangle[i as usize]).collect();
    let area = points.area.first().copied().unwrap_or(0.0);
    *points = points_at(mesh, &triangles, weights, area);
    let mut moves = Vec::with_capacity(iterations as usize);
    for _ in 0..iterations {
        let grid = Grid::new(&points.position, radius);
        // Walk the points cell by cell so neighbours are read from nearby memory.
        let sorted_pushes: Vec<DVec3> = grid
            .order
            .par_iter()
            .zip(&grid.sorted)
            .map(|(&i, &position)| {
                let i = i as usize;
                let p = position.as_dvec3();
                let mut push = DVec3::ZERO;
                grid.for_each_near(position, |j, q| {
                    let away = p - q.as_dvec3();
                    let d = away.length();
                    if j != i && d < radius && d > 0.0 {
                        push += away / d * (radius - d);
                    }
                });
                // A point with many close neighbours should not jump far.
                push * 0.1
            })
            .collect();
        let mut pushes = vec![DVec3::ZERO; count];
        for (&i, push) in grid.order.iter().zip(sorted_pushes) {
            pushes[i as usize] = push;
        }
        let moved: Vec<(u32, [f64; 3], f64)> = (0..count)
            .into_par_iter()
            .map(|i| {
                let (t, w) = slide(mesh, &across, points.triangle[i], weights[i], pushes[i]);
                (t, w, pushes[i].length_squared())
            })
            .collect();
        let mut square_sum = 0.0;
        for (i, (t, w, m)) in moved.into_iter().enumerate() {
            points.triangle[i] = t;
            weights[i] = w;
            square_sum += m;
        }
        let area = points.area.first().copied().unwrap_or(0.0);
        *points = points_at(mesh, &points.triangle, weights, area);
        moves.push((square_sum / count.max(1) as f64).sqrt() / radius);
    }
    let spread_after = nearest_neighbour_spread(&points.position, radius);
    Relaxation {
        spread_before,
        spread_after,
        moves,
    }
}

/// Points on `triangles` at barycentric `weights`, each standing for `area` mm².
pub fn points_at(mesh: &Mesh, triangles: &[u32], weights: &[[f64; 3]], area: f32) -> SurfacePoints {
    let (position, normal): (Vec<Vec3>, Vec<Vec3>) = triangles
        .iter()
        .zip(weights)
        .map(|(&t, w)| {
            let tri = mesh.triangles[t as usize];
            let p: DVec3 = (0..3)
                .map(|k| mesh.positions[tri[k] as usize].as_dvec3() * w[k])
                .sum();
            let n: Vec3 = (0..3)
                .map(|k| mesh.normals[tri[k] as usize] * w[k] as f32)
                .sum();
            (p.as_vec3(), n.try_normalize().unwrap_or(Vec3::Z))
        })
        .unzip();
    SurfacePoints {
        position,
        normal,
        triangle: triangles.to_vec(),
        area: vec![area; triangles.len()],
    }
}

/// Moves a point on triangle `t` at barycentric `w` by `push` (projected
/// into the triangle's plane), crossing edges into neighbouring triangles
/// and turning the rest of the move into each new triangle's plane. Stops
/// at a boundary edge.
fn slide(
    mesh: &Mesh,
    across: &[[u32; 3]],
    mut t: u32,
    mut w: [f64; 3],
    push: DVec3,
) -> (u32, [f64; 3]) {
    let corners =
        |t: u32| mesh.triangles[t as usize].map(|i| mesh.positions[i as usize].as_dvec3());
    let mut c = corners(t);
    let mut normal = (c[1] - c[0]).cross(c[2] - c[0]).normalize_or_zero();
    let mut remaining = push - normal * push.dot(normal);
    for _ in 0..16 {
        let from = c[0] * w[0] + c[1] * w[1] + c[2] * w[2];
        let target = barycentric_3d(from + remaining, &c);
        // The first edge the path leaves through, as a fraction of the path.
        let mut exit: Option<(f64, usize)> = None;
        for k in 0..3 {
            if target[k] < 0.0 {
                let fraction = w[k] / (w[k] - target[k]);
                if exit.is_none_or(|(f, _)| fraction < f) {
                    exit = Some((fraction, k));
                }
            }
        }
        let Some((fraction, k)) = exit else {
            return (t, target);
        };
        // Corner k's weight reaches zero: the edge opposite corner k.
        let mut at = [0.0; 3];
        for j in 0..3 {
            at[j] = (w[j] + fraction * (target[j] - w[j])).max(0.0);
        }
        at[k] = 0.0;
        let sum: f64 = at.iter().sum();
        at = at.map(|v| v / sum);
        // Edge opposite corner k runs from corner k+1 to corner k+2, which is
        // edge index k+1 in the (i, i+1) numbering of `across`.
        let edge = (k + 1) % 3;
        let next = across[t as usize][edge];
        if next == NONE {
            return (t, at);
        }
        let point = c[0] * at[0] + c[1] * at[1] + c[2] * at[2];
        let rest = remaining * (1.0 - fraction);
        let axis = (c[(k + 2) % 3] - c[(k + 1) % 3]).normalize_or_zero();
        let next_c = corners(next);
        let next_normal = (next_c[1] - next_c[0])
            .cross(next_c[2] - next_c[0])
            .normalize_or_zero();
        // Unfold: keep the component along the edge, turn the rest into the
        // new plane, pointing away from the edge into the new triangle.
        let along = axis * rest.dot(axis);
        let outward_length = (rest - along).length();
        let into_next = next_normal.cross(axis);
        let centre = (next_c[0] + next_c[1] + next_c[2]) / 3.0;
        let into_next = if into_next.dot(centre - point) >= 0.0 {
            into_next
        } else {
            -into_next
        };
        remaining = along + into_next * outward_length;
        t = next;
        c = next_c;
        normal = next_normal;
        w = barycentric_3d(point, &c).map(|v| v.max(0.0));
        let sum: f64 = w.iter().sum();
        w = w.map(|v| v / sum);
        remaining -= normal * remaining.dot(normal);
    }
    (t, w)
}

/// Barycentric coordinates of `p` projected onto the plane of `c`.
fn barycentric_3d(p: DVec3, c: &[DVec3; 3]) -> [f64; 3] {
    let (e1, e2, d) = (c[1] - c[0], c[2] - c[0], p - c[0]);
    let (a, b, cc) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (p1, p2) = (d.dot(e1), d.dot(e2));
    let det = a * cc - b * b;
    if det.abs() < 1e-300 {
        return [1.0, 0.0, 0.0];
    }
    let v = (cc * p1 - b * p2) / det;
    let w = (a * p2 - b * p1) / det;
    [1.0 - v - w, v, w]
}

/// Coefficient of variation (standard deviation over mean) of every
/// point's distance to its nearest neighbour.
pub fn nearest_neighbour_spread(positions: &[Vec3], radius: f64) -> f64 {
    spread_in(&Grid::new(positions, radius), radius)
}

/// [`nearest_neighbour_spread`] of the points already in `grid`.
fn spread_in(grid: &Grid, radius: f64) -> f64 {
    if grid.order.len() < 2 {
        return 0.0;
    }
    let distances: Vec<f64> = grid
        .order
        .par_iter()
        .zip(&grid.sorted)
        .map(|(&i, &p)| {
            let mut best = f64::INFINITY;
            grid.for_each_near(p, |j, q| {
                if j != i as usize {
                    best = best.min(p.as_dvec3().distance(q.as_dvec3()));
                }
            });
            if best.is_finite() { best } else { radius }
        })
        .collect();
    let n = distances.len() as f64;
    let mean = distances.iter().sum::<f64>() / n;
    let variance = distances.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / n;
    variance.sqrt() / mean
}

/// A uniform grid of cell size `radius` over the points: the points sorted
/// by cell, and each occupied cell's range in that order.
struct Grid {
    cell: f64,
    order: Vec<u32>,
    /// Positions in `order`, so a cell's points are read from one place.
    sorted: Vec<Vec3>,
    ranges: HashMap<u64, (u32, u32), FastHash>,
}

impl Grid {
    fn new(positions: &[Vec3], radius: f64) -> Self {
        let cell = radius.max(1e-12);
        let keys: Vec<u64> = positions
            .par_iter()
            .map(|p| Self::key(*p, cell, (0, 0, 0)))
            .collect();
        let mut order: Vec<u32> = (0..positions.len() as u32).collect();
        order.par_sort_unstable_by_key(|&i| keys[i as usize]);
        let mut ranges =
            HashMap::with_capacity_and_hasher(positions.len() / 2, FastHash::default());
        let mut start = 0;
        while start < order.len() {
            let key = keys[order[start] as usize];
            let mut end = start + 1;
            while end < order.len() && keys[order[end] as usize] == key {
                end += 1;
            }
            ranges.insert(key, (start as u32, end as u32));
            start = end;
        }
        let sorted = order.iter().map(|&i| positions[i as usize]).collect();
        Self {
            cell,
            order,
            sorted,
            ranges,
        }
    }

    /// The cell of `p` shifted by `offset` cells, packed in 63 bits.
    fn key(p: Vec3, cell: f64, offset: (i64, i64, i64)) -> u64 {
        let k = |v: f32, o: i64| (((v as f64 / cell).floor() as i64 + o) & 0x1F_FFFF) as u64;
        k(p.x, offset.0) | (k(p.y, offset.1) << 21) | (k(p.z, offset.2) << 42)
    }

    /// Calls `f` with the index and position of every point in the 27
    /// cells around `p`.
    fn for_each_near(&self, p: Vec3, mut f: impl FnMut(usize, Vec3)) {
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(&(start, end)) =
                        self.ranges.get(&Self::key(p, self.cell, (dx, dy, dz)))
                    {
                        let range = start as usize..end as usize;
                        for (&j, &q) in self.order[range.clone()].iter().zip(&self.sorted[range]) {
                            f(j as usize, q);
                        }
                    }
                }
            }
        }
    }
}
