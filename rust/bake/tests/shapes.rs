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
