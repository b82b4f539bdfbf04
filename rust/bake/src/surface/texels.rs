//! Texel surfels: every texel the UV layout covers, with the surface point,
//! normal and area it stands for (Mikkelsen §3.3, eq. 43–44).

use crate::mesh::Mesh;
use crate::surface::medium::medium_pieces;
use crate::surface::raster::{
    EdgeFunctions, TexelMoments, TexelTriangle, barycentric, contains, edge_functions,
    moments_with, signed_area2, texel_bounds,
};
use glam::{DVec2, Vec2, Vec3};
use rayon::prelude::*;

/// Marks a texel no triangle covers.
pub const EMPTY: u32 = u32::MAX;

/// Rows rasterised together by one task.
const BAND: u32 = 8;

/// Surfels in structure-of-arrays form, one per covered texel, in texel order.
#[derive(Clone, Debug, Default)]
pub struct TexelSurfels {
    /// Texels per side.
    pub resolution: u32,
    /// Surfel index of each texel (row-major, y·N + x), or [`EMPTY`].
    pub index: Vec<u32>,
    /// Texel (y·N + x) of each surfel.
    pub texel: Vec<u32>,
    /// Surface point at the centroid of the part of the texel the layout
    /// covers (the texel's centre when it covers all of it), on the
    /// texel's triangle, mm.
    pub position: Vec<Vec3>,
    /// Unit interpolated normal.
    pub normal: Vec<Vec3>,
    /// The triangle the texel belongs to.
    pub triangle: Vec<u32>,
    /// Surface area the texel stands for, mm²: the sum over the triangles
    /// covering it of covered fraction × texel size × A_tri/A_uv.
    pub area: Vec<f32>,
    /// Surface length of one texel step along u and along v, mm
    /// (|σs|/N and |σt|/N of Mikkelsen eq. 43–44).
    pub stretch: Vec<Vec2>,
    /// The covered part of the texel as a parallelogram about `position`
    /// with its area and second moments, edges in texel units: (1, 0) and
    /// (0, 1) for a whole texel, a strip's width and length at a chart's
    /// edge, so the light a part-covered texel stands for is spread over
    /// the surface it covers and not over the next chart's.
    pub extent: Vec<[Vec2; 2]>,
    /// The medium the texel's triangle belongs to ([`medium_pieces`]):
    /// light scatters only between texels of one medium.
    pub piece: Vec<u32>,
    /// The medium of each triangle of the mesh, by triangle index: what
    /// `piece` reads, kept for the integrators that start from triangles.
    pub triangle_medium: Vec<u32>,
    /// The piece of the mesh the texel's triangle lies on, and whether it
    /// lies inside the medium ([`crate::surface::medium::Media::piece`]),
    /// where some medium joins several pieces (empty otherwise): light
    /// crossing from one piece of a medium to another must pass between
    /// their faces ([`crate::transport::through_medium::pieces_joined`]).
    pub part: Vec<u32>,
    /// What `part` reads, by triangle index (empty where `part` is).
    pub triangle_part: Vec<u32>,
}

impl TexelSurfels {
    /// Number of surfels.
    pub fn len(&self) -> usize {
        self.texel.len()
    }

    /// True when no texel is covered.
    pub fn is_empty(&self) -> bool {
        self.texel.is_empty()
    }

    /// Total area of the surfels, mm².
    pub fn total_area(&self) -> f64 {
        self.area.iter().map(|&a| a as f64).sum()
    }

    /// The side of the mean texel, mm: √(total area / surfels), 0 when
    /// none is covered.
    pub fn mean_side(&self) -> f64 {
        (self.total_area().max(0.0) / self.len().max(1) as f64).sqrt()
    }
}

/// A fully covered `n`² map of a plane of unit texels, texel (x, y) at
/// (x, y, 0) mm: the layout the lattice's tests carry fields over.
#[cfg(test)]
pub(crate) fn unit_plane(n: u32) -> TexelSurfels {
    let count = (n * n) as usize;
    TexelSurfels {
        resolution: n,
        index: (0..n * n).collect(),
        texel: (0..n * n).collect(),
        position: (0..n * n)
            .map(|t| Vec3::new((t % n) as f32, (t / n) as f32, 0.0))
            .collect(),
        normal: vec![Vec3::Z; count],
        area: vec![1.0; count],
        stretch: vec![Vec2::ONE; count],
        ..TexelSurfels::default()
    }
}

/// One triangle prepared for rasterisation.
struct Prepared {
    uv: TexelTriangle,
    edges: EdgeFunctions,
    bounds: (u32, u32, u32, u32),
    /// mm² of surface per texel² of layout.
    density: f64,
    /// Surface length of one texel step along u and v, mm.
    stretch: Vec2,
}

/// The best claim on a texel so far and the area gathered there.
#[derive(Clone, Copy, Default)]
struct Claim {
    owner: Option<(bool, f64, u32)>,
    area: f64,
    moments: TexelMoments,
}

/// Rasterises `mesh` with texture coordinates `uvs` at `resolution`²
/// texels. A texel belongs to the triangle covering its centre, else to the
/// one covering most of it; its area gathers every triangle's share, so
/// the areas add up to the surface area the layout covers. Triangles with
/// no UV area cover nothing.
pub fn rasterize(mesh: &Mesh, uvs: &[Vec2], resolution: u32) -> TexelSurfels {
    let n = resolution.max(1);
    let prepared: Vec<Prepared> = mesh
        .triangles
        .iter()
        .enumerate()
        .map(|(t, tri)| {
            let uv = tri.map(|i| uvs[i as usize].as_dvec2() * n as f64);
            let uv_area = 0.5 * signed_area2(&uv).abs();
            let density = if uv_area > 1e-12 {
                mesh.triangle_area(t) / uv_area
            } else {
                0.0
            };
            Prepared {
                bounds: texel_bounds(&uv, n),
                edges: edge_functions(&uv),
                uv,
                density,
                stretch: stretch(mesh, uvs, t) / n as f32,
            }
        })
        .collect();
    let bands = n.div_ceil(BAND) as usize;
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); bands];
    for (t, p) in prepared.iter().enumerate().filter(|(_, p)| p.density > 0.0) {
        let (_, _, y0, y1) = p.bounds;
        if y1 > y0 {
            for band in (y0 / BAND)..=((y1 - 1) / BAND) {
                buckets[band as usize].push(t as u32);
            }
        }
    }
    let claims: Vec<Vec<Claim>> = buckets
        .par_iter()
        .enumerate()
        .map(|(band, triangles)| rasterize_band(&prepared, triangles, band as u32, n))
        .collect();

    // Each band's surfels go straight to their place in the output arrays.
    let counts: Vec<usize> = claims
        .iter()
        .map(|c| c.iter().filter(|c| c.owner.is_some()).count())
        .collect();
    let total: usize = counts.iter().sum();
    let mut out = TexelSurfels {
        resolution: n,
        index: vec![EMPTY; (n as usize) * (n as usize)],
        texel: vec![0; total],
        position: vec![Vec3::ZERO; total],
        normal: vec![Vec3::ZERO; total],
        triangle: vec![0; total],
        area: vec![0.0; total],
        stretch: vec![Vec2::ZERO; total],
        extent: vec![[Vec2::ZERO; 2]; total],
        piece: Vec::new(),
        triangle_medium: Vec::new(),
        part: Vec::new(),
        triangle_part: Vec::new(),
    };
    let mut parts = Vec::with_capacity(counts.len());
    let (mut texel, mut position, mut normal) = (
        &mut out.texel[..],
        &mut out.position[..],
        &mut out.normal[..],
    );
    let (mut triangle, mut area, mut stretch, mut extent) = (
        &mut out.triangle[..],
        &mut out.area[..],
        &mut out.stretch[..],
        &mut out.extent[..],
    );
    for &count in &counts {
        let (a, rest) = std::mem::take(&mut texel).split_at_mut(count);
        texel = rest;
        let (b, rest) = std::mem::take(&mut position).split_at_mut(count);
        position = rest;
        let (c, rest) = std::mem::take(&mut normal).split_at_mut(count);
        normal = rest;
        let (d, rest) = std::mem::take(&mut triangle).split_at_mut(count);
        triangle = rest;
        let (e, rest) = std::mem::take(&mut area).split_at_mut(count);
        area = rest;
        let (f, rest) = std::mem::take(&mut stretch).split_at_mut(count);
        stretch = rest;
        let (g, rest) = std::mem::take(&mut extent).split_at_mut(count);
        extent = rest;
        parts.push((a, b, c, d, e, f, g));
    }
    parts
        .into_par_iter()
        .zip(claims.par_iter())
        .enumerate()
        .for_each(|(band, (part, claims))| {
            let (texels, positions, normals, triangles, areas, stretches, extents) = part;
            let first_texel = band as u32 * BAND * n;
            let owned = claims
                .iter()
                .enumerate()
                .filter_map(|(offset, c)| c.owner.map(|(_, _, t)| (offset, c, t)));
            for (k, (offset, claim, t)) in owned.enumerate() {
                let texel = first_texel + offset as u32;
                let p = &prepared[t as usize];
                let corner = DVec2::new((texel % n) as f64, (texel / n) as f64);
                let at = corner + claim.moments.centroid();
                let (position, normal) = interpolate(mesh, &p.uv, t, at);
                texels[k] = texel;
                positions[k] = position;
                normals[k] = normal;
                triangles[k] = t;
                areas[k] = claim.area as f32;
                stretches[k] = p.stretch;
                extents[k] = claim.moments.parallelogram().map(|e| e.as_vec2());
            }
        });
    for (surfel, &texel) in out.texel.iter().enumerate() {
        out.index[texel as usize] = surfel as u32;
    }
    let media = medium_pieces(mesh);
    out.triangle_medium = media.medium;
    out.piece = out
        .triangle
        .iter()
        .map(|&t| out.triangle_medium[t as usize])
        .collect();
    if !media.piece.is_empty() {
        out.part = out
            .triangle
            .iter()
            .map(|&t| media.piece[t as usize])
            .collect();
    }
    out.triangle_part = media.piece;
    out
}

fn rasterize_band(prepared: &[Prepared], triangles: &[u32], band: u32, n: u32) -> Vec<Claim> {
    let row0 = band * BAND;
    let rows = BAND.min(n - row0);
    let mut claims = vec![Claim::default(); (rows * n) as usize];
    for &t in triangles {
        let p = &prepared[t as usize];
        let (x0, x1, y0, y1) = p.bounds;
        for y in y0.max(row0)..y1.min(row0 + rows) {
            for x in x0..x1 {
                let moments = moments_with(&p.edges, x, y);
                let covered = moments.area;
                if covered <= 0.0 {
                    continue;
                }
                let centre = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                // A wholly covered texel holds its centre; others are tested.
                let holds_centre = covered >= 1.0 || contains(&p.edges, centre);
                let claim = &mut claims[((y - row0) * n + x) as usize];
                claim.area += covered * p.density;
                claim.moments.add(&moments);
                let better = match claim.owner {
                    None => true,
                    Some((centre_held, best, _)) => (holds_centre, covered) > (centre_held, best),
                };
                if better {
                    claim.owner = Some((holds_centre, covered, t));
                }
            }
        }
    }
    claims
}

/// Position and normal at `at` (texel units) on triangle `t`, pulled onto
/// the triangle when it lies just outside.
fn interpolate(mesh: &Mesh, uv: &TexelTriangle, t: u32, at: DVec2) -> (Vec3, Vec3) {
    let mut w = barycentric(at, uv)
        .unwrap_or([1.0 / 3.0; 3])
        .map(|w| w.max(0.0));
    let sum: f64 = w.iter().sum();
    w = w.map(|v| v / sum);
    let tri = mesh.triangles[t as usize];
    let position = (0..3)
        .map(|i| mesh.positions[tri[i] as usize].as_dvec3() * w[i])
        .sum::<glam::DVec3>();
    let normal = (0..3)
        .map(|i| mesh.normals[tri[i] as usize] * w[i] as f32)
        .sum::<Vec3>();
    (
        position.as_vec3(),
        normal.try_normalize().unwrap_or(Vec3::Z),
    )
}

/// |∂P/∂u| and |∂P/∂v| of triangle `t`, mm per unit of UV.
pub fn stretch(mesh: &Mesh, uvs: &[Vec2], t: usize) -> Vec2 {
    uv_jacobian(mesh, uvs, t).map_or(Vec2::ZERO, |(du, dv)| {
        Vec2::new(du.length() as f32, dv.length() as f32)
    })
}

/// ∂P/∂u and ∂P/∂v of triangle `t` (mm per unit of UV); `None` when the
/// triangle has no UV area.
pub fn uv_jacobian(mesh: &Mesh, uvs: &[Vec2], t: usize) -> Option<(glam::DVec3, glam::DVec3)> {
    let tri = mesh.triangles[t];
    let [p0, p1, p2] = tri.map(|i| mesh.positions[i as usize].as_dvec3());
    let [u0, u1, u2] = tri.map(|i| uvs[i as usize].as_dvec2());
    let (e1, e2) = (u1 - u0, u2 - u0);
    let det = e1.perp_dot(e2);
    if det.abs() < 1e-300 {
        return None;
    }
    let (q1, q2) = (p1 - p0, p2 - p0);
    Some(((q1 * e2.y - q2 * e1.y) / det, (q2 * e1.x - q1 * e2.x) / det))
}
