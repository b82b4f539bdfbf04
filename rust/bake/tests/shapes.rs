//! Hand-made meshes for the tests.
#![allow(dead_code)]

use glam::{Vec2, Vec3};
use sssbake::Mesh;

/// A `size` mm square in the xy plane, UVs filling [0, 1]².
pub fn quad(size: f32) -> Mesh {
    let positions = vec![
        Vec3::ZERO,
        Vec3::new(size, 0.0, 0.0),
        Vec3::new(size, size, 0.0),
        Vec3::new(0.0, size, 0.0),
    ];
    let uvs = vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    Mesh::new(
        "quad",
        positions,
        None,
        Some(uvs),
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap()
    .0
}

/// `mesh` stretched by `scale` along each axis, its normals made anew.
pub fn stretched(mesh: Mesh, scale: Vec3, name: &str) -> Mesh {
    let positions = mesh.positions.iter().map(|p| *p * scale).collect();
    Mesh::new(name, positions, None, mesh.uvs, mesh.triangles)
        .unwrap()
        .0
}

/// A cube of side `size` mm centred at the origin; each face its own UV
/// island in a 3 × 2 atlas with a gap between islands.
pub fn cube(size: f32) -> Mesh {
    let h = size / 2.0;
    let faces: [(Vec3, Vec3, Vec3); 6] = [
        (Vec3::X, Vec3::Y, Vec3::Z),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::Z, Vec3::X),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::Y, Vec3::X),
    ];
    let (mut positions, mut uvs, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for (f, (normal, a, b)) in faces.iter().enumerate() {
        let base = positions.len() as u32;
        let origin = Vec2::new((f % 3) as f32 / 3.0, (f / 3) as f32 / 2.0) + Vec2::splat(0.02);
        let extent = Vec2::new(1.0 / 3.0, 0.5) - Vec2::splat(0.04);
        for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            positions.push(*normal * h + *a * h * s + *b * h * t);
            uvs.push(origin + extent * Vec2::new((s + 1.0) / 2.0, (t + 1.0) / 2.0));
        }
        // Wind counter-clockwise seen from outside.
        if a.cross(*b).dot(*normal) > 0.0 {
            triangles.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
        } else {
            triangles.extend([[base, base + 2, base + 1], [base, base + 3, base + 2]]);
        }
    }
    Mesh::new("cube", positions, None, Some(uvs), triangles)
        .unwrap()
        .0
}

/// A UV sphere of `radius` mm with `rings` × `segments` quads and
/// latitude–longitude UVs and normals. As an exporter writes one, the
/// vertices duplicated along the seam (u = 0 and 1) and at the poles share
/// their positions exactly, so the surface is closed.
pub fn sphere(radius: f32, rings: u32, segments: u32) -> Mesh {
    let (mut positions, mut uvs, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..=rings {
        let v = i as f32 / rings as f32;
        let theta = v * std::f32::consts::PI;
        let (sin_theta, cos_theta) = match i {
            0 => (0.0, 1.0),
            _ if i == rings => (0.0, -1.0),
            _ => theta.sin_cos(),
        };
        for j in 0..=segments {
            let u = j as f32 / segments as f32;
            let phi = (j % segments) as f32 / segments as f32 * std::f32::consts::TAU;
            positions
                .push(radius * Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta));
            uvs.push(Vec2::new(u, 1.0 - v));
        }
    }
    let row = segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (
                i * row + j,
                i * row + j + 1,
                (i + 1) * row + j + 1,
                (i + 1) * row + j,
            );
            triangles.extend([[a, d, c], [a, c, b]]);
        }
    }
    // Analytic normals, as an exporter writes them: the duplicated pole
    // vertices only touch sliver triangles whose face normals mean nothing.
    let normals = positions.iter().map(|p| p.normalize()).collect();
    Mesh::new("sphere", positions, Some(normals), Some(uvs), triangles)
        .unwrap()
        .0
}

/// Two separate quads mapped onto the same UV square.
pub fn overlapping_quads() -> Mesh {
    let mut positions = quad(10.0).positions;
    positions.extend(
        quad(10.0)
            .positions
            .iter()
            .map(|p| *p + Vec3::new(0.0, 0.0, 5.0)),
    );
    let uvs = [quad(10.0).uvs.unwrap(), quad(10.0).uvs.unwrap()].concat();
    Mesh::new(
        "overlapping",
        positions,
        None,
        Some(uvs),
        vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]],
    )
    .unwrap()
    .0
}

/// The closed surface of a solid made of boxes: the cells of the grid with
/// lines at `xs`, `ys`, `zs` (mm, increasing) for which `filled(i, j, k)`
/// holds. Each face between a filled cell and an empty one (or the
/// outside) is a quad of its own with a flat normal and its own square of
/// a UV atlas; faces meet exactly along the grid's lines, so the surface
/// is closed and one piece wherever the cells touch by a face.
pub fn boxes(
    name: &str,
    xs: &[f32],
    ys: &[f32],
    zs: &[f32],
    filled: impl Fn(usize, usize, usize) -> bool,
) -> Mesh {
    let lines = [xs, ys, zs];
    let cells = [xs.len() - 1, ys.len() - 1, zs.len() - 1];
    let inside = |c: [i64; 3]| {
        (0..3).all(|a| c[a] >= 0 && (c[a] as usize) < cells[a])
            && filled(c[0] as usize, c[1] as usize, c[2] as usize)
    };
    // Each face: the axis it faces along, the side, and its cell.
    let mut faces = Vec::new();
    for i in 0..cells[0] {
        for j in 0..cells[1] {
            for k in 0..cells[2] {
                let cell = [i as i64, j as i64, k as i64];
                if !inside(cell) {
                    continue;
                }
                for axis in 0..3 {
                    for side in [-1i64, 1] {
                        let mut next = cell;
                        next[axis] += side;
                        if !inside(next) {
                            faces.push((axis, side, [i, j, k]));
                        }
                    }
                }
            }
        }
    }
    let per_row = (faces.len() as f32).sqrt().ceil() as usize;
    let square = 1.0 / per_row as f32;
    let (mut positions, mut uvs, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for (f, &(axis, side, cell)) in faces.iter().enumerate() {
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let bound = |ax: usize, high: bool| lines[ax][cell[ax] + high as usize];
        let plane = bound(axis, side > 0);
        let base = positions.len() as u32;
        let origin = Vec2::new((f % per_row) as f32, (f / per_row) as f32) * square;
        for (s, t) in [(false, false), (true, false), (true, true), (false, true)] {
            let mut p = [0.0f32; 3];
            p[axis] = plane;
            p[a] = bound(a, s);
            p[b] = bound(b, t);
            positions.push(Vec3::from(p));
            let corner = Vec2::new(s as u8 as f32, t as u8 as f32);
            uvs.push(origin + (Vec2::splat(0.1) + corner * 0.8) * square);
        }
        // (a, b, axis) is right-handed: counter-clockwise seen from +axis.
        if side > 0 {
            triangles.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
        } else {
            triangles.extend([[base, base + 2, base + 1], [base, base + 3, base + 2]]);
        }
    }
    Mesh::new(name, positions, None, Some(uvs), triangles)
        .unwrap()
        .0
}
