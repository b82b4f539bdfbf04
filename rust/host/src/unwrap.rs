//! A host's mesh unwrapped by the library's xatlas, the way a bake unwraps
//! an object whose UVs are unusable, with the UVs handed back per triangle
//! corner so the host keeps them as a UV map of its own.

use glam::{Vec2, Vec3};
use sssbake::{Error, Mesh};
use std::collections::HashMap;

/// Unwraps the mesh `name` of flat `positions` (3 floats per vertex, scene
/// units) and `indices` (three per triangle) with xatlas into charts packed
/// in [0, 1]² for a `resolution`² map with `padding` texels between charts
/// (a bake grows each chart by its margin, so twice the margin keeps charts
/// apart). Vertices at one position are joined, so a host may pass one
/// vertex per triangle corner. Returns the UV of each index (u, v with v
/// running up; 2 floats per index; a degenerate triangle gets UVs with no
/// area) and each triangle's chart number (a host whose faces have more than
/// three corners sees there which triangles of a face were cut apart).
/// Every chart runs counter-clockwise in UV as its triangles do in 3-D
/// (xatlas may hand a chart back mirrored; it is mirrored again in place).
pub fn unwrap_corners(
    name: &str,
    positions: &[f32],
    indices: &[u32],
    resolution: u32,
    padding: u32,
) -> Result<(Vec<f32>, Vec<u32>), Error> {
    if !positions.len().is_multiple_of(3) {
        return Err(Error::field(
            "mesh",
            format!(
                "object `{name}`: {} position floats is not 3 per vertex",
                positions.len()
            ),
        ));
    }
    let n = positions.len() / 3;
    if indices.is_empty() || !indices.len().is_multiple_of(3) {
        return Err(Error::field(
            "mesh",
            format!(
                "object `{name}`: {} indices is not one or more triangles",
                indices.len()
            ),
        ));
    }
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(Error::input(format!("index {bad} but {n} vertices")).for_object(name));
    }
    let joined = joined_mesh(name, positions, indices)?;
    let (unwrapped, _) =
        sssbake::surface::unwrap::unwrap_with_sources(&joined, resolution.max(1), padding)
            .map_err(|e| Error::input(e.to_string()))?;
    let mut uvs = unwrapped.uvs.clone().unwrap_or_default();
    let charts = chart_of_each_triangle(&unwrapped.triangles, uvs.len());
    orient_charts(&unwrapped.triangles, &charts, &mut uvs);
    // xatlas keeps every triangle in its place, so corner i is index i.
    let corners = unwrapped
        .triangles
        .iter()
        .flatten()
        .flat_map(|&vertex| {
            let uv = uvs.get(vertex as usize).copied().unwrap_or(Vec2::ZERO);
            [uv.x, uv.y]
        })
        .collect();
    Ok((corners, charts))
}

/// The chart of each triangle: triangles sharing an unwrapped vertex are in
/// one chart (xatlas splits vertices along chart seams), numbered from 0.
fn chart_of_each_triangle(triangles: &[[u32; 3]], vertices: usize) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..vertices as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            parent[v as usize] = parent[parent[v as usize] as usize];
            v = parent[v as usize];
        }
        v
    }
    for t in triangles {
        let a = root(&mut parent, t[0]);
        for &v in &t[1..] {
            let b = root(&mut parent, v);
            parent[b as usize] = a;
        }
    }
    let mut numbers = HashMap::new();
    triangles
        .iter()
        .map(|t| {
            let r = root(&mut parent, t[0]);
            let next = numbers.len() as u32;
            *numbers.entry(r).or_insert(next)
        })
        .collect()
}

/// Mirrors (in u, within its own bounds, so packing is kept) every chart
/// whose triangles run clockwise in UV overall.
fn orient_charts(triangles: &[[u32; 3]], charts: &[u32], uvs: &mut [Vec2]) {
    let count = charts.iter().max().map_or(0, |&c| c as usize + 1);
    let mut signed = vec![0.0f64; count];
    let mut bounds = vec![(f32::INFINITY, f32::NEG_INFINITY); count];
    for (t, &chart) in triangles.iter().zip(charts) {
        let [a, b, c] = t.map(|v| uvs[v as usize]);
        signed[chart as usize] += f64::from((b - a).perp_dot(c - a));
        for p in [a, b, c] {
            let bound = &mut bounds[chart as usize];
            *bound = (bound.0.min(p.x), bound.1.max(p.x));
        }
    }
    let mut chart_of_vertex = vec![None; uvs.len()];
    for (t, &chart) in triangles.iter().zip(charts) {
        for &v in t {
            chart_of_vertex[v as usize] = Some(chart as usize);
        }
    }
    for (uv, chart) in uvs.iter_mut().zip(chart_of_vertex) {
        if let Some(chart) = chart.filter(|&c| signed[c] < 0.0) {
            let (low, high) = bounds[chart];
            uv.x = low + high - uv.x;
        }
    }
}

/// The host's triangles over vertices joined by position (bit for bit), every
/// triangle kept in its place, degenerate or not, so corners map back.
fn joined_mesh(name: &str, positions: &[f32], indices: &[u32]) -> Result<Mesh, Error> {
    let mut joined: HashMap<[u32; 3], u32> = HashMap::new();
    let mut points = Vec::new();
    let mut remap = Vec::with_capacity(positions.len() / 3);
    for p in positions.chunks_exact(3) {
        let point = Vec3::from_slice(p);
        if !point.is_finite() {
            return Err(Error::input(format!("position {point} is not finite")).for_object(name));
        }
        let index = *joined
            .entry(point.to_array().map(f32::to_bits))
            .or_insert_with(|| {
                points.push(point);
                (points.len() - 1) as u32
            });
        remap.push(index);
    }
    let triangles = indices
        .chunks_exact(3)
        .map(|t| [0, 1, 2].map(|c| remap[t[c] as usize]))
        .collect();
    Ok(Mesh {
        name: name.to_string(),
        normals: vec![Vec3::ZERO; points.len()],
        positions: points,
        uvs: None,
        triangles,
    })
}
