//! Turk points as sources: each point gathers the texels nearest to it (its
//! Voronoi cell on the surface, found through the texels), and carries
//! their area, their flux and the flux-weighted centre (Mikkelsen §3.2:
//! uneven points need Voronoi areas). The points then carry exactly the
//! light the texels received, shadow edges included, and the hierarchy
//! sums clusters of texels instead of fresh, aliased irradiance samples.

use super::sources::{Grid, Sources};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Clusters `texels` (sources with area and irradiance) around `centres`
/// spaced about `spacing` mm apart. Cells that hold no texel are dropped.
pub fn cluster(texels: &Sources, centres: &[Vec3], spacing: f32) -> Sources<'static> {
    if centres.is_empty() || texels.is_empty() {
        return Sources::default();
    }
    let grid = Grid::new(centres, spacing.max(1e-6));
    let nearest: Vec<u32> = texels
        .position
        .par_iter()
        .map(|&p| nearest_centre(&grid, centres, p, spacing.max(1e-6)))
        .collect();
    #[derive(Clone, Default)]
    struct Cell {
        area: f64,
        flux: [f64; 3],
        by_light: DVec3,
        light: f64,
        by_area: DVec3,
        normal: DVec3,
    }
    // A cell per centre, medium and piece of it, in that order: texels of
    // two pieces near one centre stay apart, as their light does.
    let pieces = texels.piece.len() == texels.len();
    let parts = texels.part.len() == texels.len();
    let mut cells: BTreeMap<(u32, u32, u32), Cell> = BTreeMap::new();
    for (t, &c) in nearest.iter().enumerate() {
        let piece = if pieces { texels.piece[t] } else { 0 };
        let part = if parts { texels.part[t] } else { 0 };
        let cell = cells.entry((c, piece, part)).or_default();
        let a = texels.area[t] as f64;
        let e = texels.irradiance[t];
        let p = texels.position[t].as_dvec3();
        cell.area += a;
        for (flux, &e) in cell.flux.iter_mut().zip(&e) {
            *flux += e as f64 * a;
        }
        let light = (0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2]).max(0.0) as f64 * a;
        cell.by_light += p * light;
        cell.light += light;
        cell.by_area += p * a;
        cell.normal += texels.normal[t].as_dvec3() * a;
    }
    let mut out = Sources::default();
    for ((_, piece, part), cell) in cells.into_iter().filter(|(_, c)| c.area > 0.0) {
        if pieces {
            out.piece.to_mut().push(piece);
        }
        if parts {
            out.part.to_mut().push(part);
        }
        let centre = if cell.light > 0.0 {
            cell.by_light / cell.light
        } else {
            cell.by_area / cell.area
        };
        out.position.to_mut().push(centre.as_vec3());
        out.normal
            .to_mut()
            .push(cell.normal.normalize_or_zero().as_vec3());
        out.area.to_mut().push(cell.area as f32);
        out.irradiance
            .push(cell.flux.map(|f| (f / cell.area) as f32));
    }
    out
}

/// The index of the centre nearest to `p`, searching outwards from its
/// cell of the grid.
fn nearest_centre(grid: &Grid, centres: &[Vec3], p: Vec3, spacing: f32) -> u32 {
    let mut radius = 2.0 * spacing;
    loop {
        let mut best = (f32::INFINITY, u32::MAX);
        grid.for_each_run(p, radius, |run| {
            for &c in &grid.order[run] {
                let d2 = (centres[c as usize] - p).length_squared();
                if d2 < best.0 {
                    best = (d2, c);
                }
            }
        });
        // A centre found within the searched radius is the nearest overall.
        if best.1 != u32::MAX && best.0 <= radius * radius {
            return best.1;
        }
        radius *= 2.0;
        if radius > 1e9 {
            return best.1.min(centres.len() as u32 - 1);
        }
    }
}
