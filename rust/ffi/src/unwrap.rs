//! A host's mesh unwrapped by the library's xatlas, the way a bake unwraps
//! an object whose UVs are unusable, with the UVs handed back per triangle
//! corner so the host keeps them as a UV map of its own.

use crate::errors::{Failure, SssbakeStatus, guarded, slice, text};
use crate::scene::SssbakeMesh;
use glam::{Vec2, Vec3};
use sssbake::Mesh;
use std::collections::HashMap;

/// Unwraps `mesh` with xatlas into charts packed in [0, 1]² for a
/// `resolution`² map with `padding` texels between charts (a bake grows
/// each chart by its margin, so twice the margin keeps charts apart).
/// Only the positions and indices are read; vertices at one position are
/// joined, so a host may pass one vertex per triangle corner. On success
/// `uvs_out` holds the UV (u, v with v running up, as the mesh's `uvs`
/// would) of each index, 2 × `index_count` floats; a degenerate triangle
/// gets UVs with no area. `uvs_len` is the length of `uvs_out` in floats.
/// Every chart runs counter-clockwise in UV as its triangles do in 3-D
/// (xatlas may hand a chart back mirrored; it is mirrored again in place).
/// `charts_out`, unless null, gets each triangle's chart number
/// (`index_count` / 3 values): a host whose faces have more than three
/// corners sees there which triangles of a face were cut apart.
///
/// # Safety
/// `mesh` points to a mesh whose arrays hold the lengths it states;
/// `uvs_out` points to `uvs_len` writable floats; `charts_out` is null or
/// points to `index_count` / 3 writable values.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sssbake_unwrap(
    mesh: *const SssbakeMesh,
    resolution: u32,
    padding: u32,
    uvs_out: *mut f32,
    uvs_len: usize,
    charts_out: *mut u32,
) -> SssbakeStatus {
    guarded(|| {
        // SAFETY: the caller passes a valid mesh or null.
        let Some(mesh) = (unsafe { mesh.as_ref() }) else {
            return Err(Failure::argument("mesh is null"));
        };
        // SAFETY: forwarded from the caller.
        let name = unsafe { text(mesh.name, "mesh name") }?.to_string();
        let at = |what: &str| format!("object `{name}`: {what}");
        let n = mesh.vertex_count;
        // SAFETY: forwarded from the caller.
        let positions = unsafe { slice(mesh.positions, 3 * n, &at("positions")) }?;
        // SAFETY: forwarded from the caller.
        let indices = unsafe { slice(mesh.indices, mesh.index_count, &at("indices")) }?;
        if indices.is_empty() || !indices.len().is_multiple_of(3) {
            return Err(Failure::argument(at(&format!(
                "{} indices is not one or more triangles",
                indices.len()
            ))));
        }
        if uvs_len != 2 * indices.len() {
            return Err(Failure::argument(at(&format!(
                "uvs_len is {uvs_len}, but {} indices need {}",
                indices.len(),
                2 * indices.len()
            ))));
        }
        if uvs_out.is_null() {
            return Err(Failure::argument("uvs_out is null"));
        }
        if let Some(bad) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(Failure::input(at(&format!("index {bad} but {n} vertices"))));
        }
        let joined = joined_mesh(&name, positions, indices)?;
        let (unwrapped, _) =
            sssbake::surface::unwrap::unwrap_with_sources(&joined, resolution.max(1), padding)
                .map_err(|e| Failure::input(e.to_string()))?;
        let mut uvs = unwrapped.uvs.clone().unwrap_or_default();
        let charts = chart_of_each_triangle(&unwrapped.triangles, uvs.len());
        orient_charts(&unwrapped.triangles, &charts, &mut uvs);
        if !charts_out.is_null() {
            // SAFETY: checked non-null; the caller gives index_count / 3 values.
            let out = unsafe { std::slice::from_raw_parts_mut(charts_out, charts.len()) };
            out.copy_from_slice(&charts);
        }
        // SAFETY: checked non-null; the caller gives `uvs_len` writable floats.
        let out = unsafe { std::slice::from_raw_parts_mut(uvs_out, uvs_len) };
        // xatlas keeps every triangle in its place, so corner i is index i.
        for (corner, &vertex) in unwrapped.triangles.iter().flatten().enumerate() {
            let uv = uvs.get(vertex as usize).copied().unwrap_or(Vec2::ZERO);
            out[2 * corner] = uv.x;
            out[2 * corner + 1] = uv.y;
        }
        Ok(())
    })
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
fn joined_mesh(name: &str, positions: &[f32], indices: &[u32]) -> Result<Mesh, Failure> {
    let mut joined: HashMap<[u32; 3], u32> = HashMap::new();
    let mut points = Vec::new();
    let mut remap = Vec::with_capacity(positions.len() / 3);
    for p in positions.chunks_exact(3) {
        let point = Vec3::from_slice(p);
        if !point.is_finite() {
            return Err(Failure::input(format!(
                "object `{name}`: position {point} is not finite"
            )));
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
