//! `sssbake_unwrap` as a host calls it: a cube given one vertex per triangle
//! corner comes back with a UV per corner, in [0, 1]², every face with UV
//! area and not mirrored, no two faces on the same texels, and each face's
//! shape kept; and
//! misuse answered with a status and a message.

use glam::{DVec2, DVec3};
use sssbake_ffi::*;
use std::ffi::{CStr, CString};

/// A unit cube as 12 triangles, one vertex per corner (36 vertices).
fn cube_corners() -> (Vec<f32>, Vec<u32>) {
    let faces = [
        ([0, 2, 6, 4], 0),
        ([1, 5, 7, 3], 1),
        ([0, 4, 5, 1], 2),
        ([2, 3, 7, 6], 3),
        ([0, 1, 3, 2], 4),
        ([4, 6, 7, 5], 5),
    ];
    let corner = |i: u32| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32];
    let mut positions = Vec::new();
    for (quad, _) in faces {
        for t in [[0, 1, 2], [0, 2, 3]] {
            for c in t {
                positions.extend(corner(quad[c]));
            }
        }
    }
    let indices = (0..36).collect();
    (positions, indices)
}

fn unwrap(positions: &[f32], indices: &[u32], resolution: u32, uvs: &mut [f32]) -> SssbakeStatus {
    let name = CString::new("Cube").unwrap();
    let mesh = SssbakeMesh {
        name: name.as_ptr(),
        positions: positions.as_ptr(),
        normals: std::ptr::null(),
        uvs: std::ptr::null(),
        vertex_count: positions.len() / 3,
        indices: indices.as_ptr(),
        index_count: indices.len(),
        ..SssbakeMesh::default()
    };
    unsafe {
        sssbake_unwrap(
            &mesh,
            resolution,
            4,
            uvs.as_mut_ptr(),
            uvs.len(),
            std::ptr::null_mut(),
        )
    }
}

fn area2(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

#[test]
fn a_cube_of_corners_unwraps_into_separate_faces_of_its_own_shape() {
    let (positions, indices) = cube_corners();
    let mut uvs = vec![f32::NAN; 2 * indices.len()];
    assert_eq!(
        unwrap(&positions, &indices, 64, &mut uvs),
        SssbakeStatus::Ok
    );
    assert!(uvs.iter().all(|&x| (0.0..=1.0).contains(&x)), "{uvs:?}");
    let uv = |i: usize| DVec2::new(uvs[2 * i] as f64, uvs[2 * i + 1] as f64);
    let point = |i: usize| DVec3::from_array([0, 1, 2].map(|k| positions[3 * i + k] as f64));
    // Every triangle keeps its shape: UV area over 3-D area is one scale for all.
    let ratios: Vec<f64> = (0..12)
        .map(|t| {
            let [a, b, c] = [3 * t, 3 * t + 1, 3 * t + 2];
            let uv_area = area2(uv(a), uv(b), uv(c)).abs() / 2.0;
            let area = (point(b) - point(a)).cross(point(c) - point(a)).length() / 2.0;
            uv_area / area
        })
        .collect();
    // Every triangle runs counter-clockwise in UV, as it does seen from outside.
    for t in 0..12 {
        assert!(
            area2(uv(3 * t), uv(3 * t + 1), uv(3 * t + 2)) > 0.0,
            "triangle {t} is mirrored"
        );
    }
    let first = ratios[0];
    assert!(first > 0.0);
    assert!(
        ratios.iter().all(|r| (r / first - 1.0).abs() < 0.02),
        "{ratios:?}"
    );
    // No texel centre of a 64² map lies inside two triangles.
    let n = 64;
    for y in 0..n {
        for x in 0..n {
            let p = DVec2::new((x as f64 + 0.5) / n as f64, (y as f64 + 0.5) / n as f64);
            let inside = (0..12)
                .filter(|&t| {
                    let [a, b, c] = [uv(3 * t), uv(3 * t + 1), uv(3 * t + 2)];
                    let s = [area2(a, b, p), area2(b, c, p), area2(c, a, p)];
                    s.iter().all(|&v| v > 1e-12) || s.iter().all(|&v| v < -1e-12)
                })
                .count();
            assert!(inside <= 1, "texel ({x}, {y}) in {inside} triangles");
        }
    }
}

#[test]
fn misuse_is_answered_with_a_status_and_a_message() {
    let (positions, indices) = cube_corners();
    let mut short = vec![0.0; 10];
    assert_eq!(
        unwrap(&positions, &indices, 64, &mut short),
        SssbakeStatus::InvalidArgument
    );
    let message = unsafe { CStr::from_ptr(sssbake_last_error()) }.to_string_lossy();
    assert!(
        message.contains("uvs_len is 10, but 36 indices need 72"),
        "{message}"
    );
    let mut uvs = vec![0.0; 72];
    let mut bad = indices.clone();
    bad[5] = 99;
    assert_eq!(
        unwrap(&positions, &bad, 64, &mut uvs),
        SssbakeStatus::BadInput
    );
    assert_eq!(
        unsafe {
            sssbake_unwrap(
                std::ptr::null(),
                64,
                4,
                uvs.as_mut_ptr(),
                72,
                std::ptr::null_mut(),
            )
        },
        SssbakeStatus::InvalidArgument
    );
}
