//! Texel surfels, UV analysis and dilation on hand-made meshes.

mod shapes;
use glam::{Vec2, Vec3};
use shapes::*;
use sssbake::surface::dilation::dilation_offsets;
use sssbake::surface::texels::EMPTY;
use sssbake::{Mesh, MeshError, analyse_uvs, rasterize};

#[test]
fn texel_areas_add_up_to_the_surface_area() {
    for mesh in [quad(100.0), cube(20.0), sphere(15.0, 48, 96)] {
        let uvs = mesh.uvs.clone().unwrap();
        for resolution in [64, 1024] {
            let surfels = rasterize(&mesh, &uvs, resolution);
            let (baked, surface) = (surfels.total_area(), mesh.area());
            assert!(
                (baked - surface).abs() < 0.01 * surface,
                "{} at {resolution}²: {baked} vs {surface}",
                mesh.name
            );
        }
    }
}

#[test]
fn a_flat_quad_has_equal_surfels_in_the_right_places() {
    let mesh = quad(100.0);
    let surfels = rasterize(&mesh, mesh.uvs.as_ref().unwrap(), 32);
    assert_eq!(surfels.len(), 32 * 32);
    let texel_area = (100.0f32 / 32.0).powi(2);
    for i in 0..surfels.len() {
        assert!(
            (surfels.area[i] - texel_area).abs() < 1e-3 * texel_area,
            "surfel {i}: {}",
            surfels.area[i]
        );
        let (x, y) = (surfels.texel[i] % 32, surfels.texel[i] / 32);
        let expected = Vec3::new(
            (x as f32 + 0.5) * 100.0 / 32.0,
            (y as f32 + 0.5) * 100.0 / 32.0,
            0.0,
        );
        assert!(
            surfels.position[i].distance(expected) < 1e-3,
            "{:?} vs {expected:?}",
            surfels.position[i]
        );
        assert!(surfels.normal[i].distance(Vec3::Z) < 1e-6);
        assert!((surfels.stretch[i] - Vec2::splat(100.0 / 32.0)).length() < 1e-4);
    }
}

#[test]
fn sphere_surfels_lie_on_the_sphere_and_face_out() {
    let mesh = sphere(15.0, 24, 48);
    let surfels = rasterize(&mesh, mesh.uvs.as_ref().unwrap(), 256);
    for i in 0..surfels.len() {
        let p = surfels.position[i];
        assert!((p.length() - 15.0).abs() < 0.15, "{p:?}");
        assert!((surfels.normal[i].length() - 1.0).abs() < 1e-5);
        assert!(
            surfels.normal[i].dot(p.normalize()) > 0.999,
            "{:?} at {p:?}",
            surfels.normal[i]
        );
    }
}

#[test]
fn uv_verdicts() {
    let report = analyse_uvs(&cube(10.0), None, 256);
    assert!(report.usable(), "{}", report.verdict());
    assert_eq!(
        (report.overlapping, report.flipped, report.outside),
        (0, 0, 0)
    );

    let report = analyse_uvs(&overlapping_quads(), None, 256);
    assert_eq!(report.overlapping, 4, "{}", report.verdict());
    assert!(!report.usable());

    let mut bare = quad(10.0);
    bare.uvs = None;
    assert!(analyse_uvs(&bare, None, 64).missing);

    let quad = quad(10.0);
    let outside = [Vec2::ZERO, Vec2::new(1.5, 0.0), Vec2::ONE, Vec2::Y];
    assert_eq!(analyse_uvs(&quad, Some(&outside), 64).outside, 1);
    let collapsed = [Vec2::ZERO, Vec2::ZERO, Vec2::ONE, Vec2::Y];
    let report = analyse_uvs(&quad, Some(&collapsed), 64);
    assert_eq!(report.zero_area, 1);
    assert!(!report.usable());
    let mirrored = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::new(1.0, 2.0)];
    let report = analyse_uvs(
        &quad,
        Some(&[mirrored[0], mirrored[1], mirrored[2], Vec2::new(1.0, 0.9)]),
        64,
    );
    assert_eq!(report.flipped, 1, "{}", report.verdict());
    let squashed = [
        Vec2::ZERO,
        Vec2::new(1.0, 0.0),
        Vec2::new(1.0, 0.01),
        Vec2::new(0.0, 0.01),
    ];
    assert_eq!(analyse_uvs(&quad, Some(&squashed), 64).stretched, 2);
}

#[test]
fn dilation_never_reads_an_empty_texel() {
    let mesh = cube(10.0);
    let surfels = rasterize(&mesh, mesh.uvs.as_ref().unwrap(), 128);
    let offsets = dilation_offsets(&surfels.index, 128, 4);
    assert!(!offsets.is_empty());
    for &(target, source) in &offsets {
        assert_eq!(
            surfels.index[target as usize], EMPTY,
            "texel {target} is covered"
        );
        assert_ne!(
            surfels.index[source as usize], EMPTY,
            "texel {source} is empty"
        );
        let (dx, dy) = (
            (target % 128) as i64 - (source % 128) as i64,
            (target / 128) as i64 - (source / 128) as i64,
        );
        assert!(
            dx.abs().max(dy.abs()) <= 4,
            "{target} copies {source}, too far"
        );
    }
    let mut targets: Vec<u32> = offsets.iter().map(|o| o.0).collect();
    targets.dedup();
    assert_eq!(targets.len(), offsets.len(), "each texel is filled once");
}

#[test]
fn bad_meshes_are_refused_with_their_name() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    let err = Mesh::new("ear", p.clone(), None, None, vec![[0, 1, 5]]).unwrap_err();
    assert!(matches!(err, MeshError::IndexOutOfRange { index: 5, .. }));
    assert!(err.to_string().contains("`ear`"));
    let err = Mesh::new(
        "ear",
        vec![Vec3::ZERO, Vec3::X, Vec3::new(f32::NAN, 0.0, 0.0)],
        None,
        None,
        vec![[0, 1, 2]],
    )
    .unwrap_err();
    assert!(matches!(
        err,
        MeshError::NonFinitePosition { vertex: 2, .. }
    ));
    let err = Mesh::new(
        "ear",
        p.clone(),
        None,
        Some(vec![Vec2::ZERO]),
        vec![[0, 1, 2]],
    )
    .unwrap_err();
    assert!(matches!(err, MeshError::LengthMismatch { what: "uvs", .. }));
    let err = Mesh::new("ear", p.clone(), None, None, vec![[0, 1, 1]]).unwrap_err();
    assert!(matches!(err, MeshError::Empty { .. }));
    let (mesh, warnings) = Mesh::new(
        "ear",
        p,
        Some(vec![Vec3::ZERO; 3]),
        None,
        vec![[0, 1, 2], [0, 0, 2]],
    )
    .unwrap();
    assert_eq!(
        (warnings.degenerate_triangles, warnings.repaired_normals),
        (1, 3)
    );
    assert_eq!(mesh.normals[0], Vec3::Z);
}

#[test]
fn topology_counts_parts_and_open_edges() {
    use sssbake::surface::topology::topology_report;
    // The cube's faces are separate UV islands with split vertices, yet
    // welded by position it is one closed part.
    let cube = topology_report(&cube(10.0));
    assert_eq!(
        (cube.parts, cube.boundary_edges, cube.non_manifold_edges),
        (1, 0, 0)
    );
    let quads = topology_report(&overlapping_quads());
    assert_eq!((quads.parts, quads.boundary_edges), (2, 8));
    // Three triangles on one edge.
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::NEG_Y, Vec3::Z];
    let (fan, _) = Mesh::new("fan", p, None, None, vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap();
    assert_eq!(topology_report(&fan).non_manifold_edges, 1);
}

#[test]
fn seam_aware_dilation_continues_the_surface_across_seams() {
    use sssbake::surface::dilation::seam_aware_offsets;
    let mesh = cube(10.0);
    let uvs = mesh.uvs.clone().unwrap();
    let n = 128;
    let surfels = rasterize(&mesh, &uvs, n);
    let nearest = dilation_offsets(&surfels.index, n, 4);
    let aware = seam_aware_offsets(&mesh, &uvs, &surfels, 4);
    assert_eq!(nearest.len(), aware.len());
    let texel_mm = 10.0 / ((1.0 / 3.0 - 0.04) * n as f32);
    let mut crossed = 0;
    for (&(target, near), &(same_target, far)) in nearest.iter().zip(&aware) {
        assert_eq!(target, same_target);
        let (i, j) = (surfels.index[near as usize], surfels.index[far as usize]);
        assert_ne!(j, EMPTY, "texel {far} is empty");
        if near != far {
            crossed += 1;
            // The carried texel is another face's, but close on the surface:
            // it continues the surface past the seam.
            let (ti, tj) = (
                surfels.triangle[i as usize] / 2,
                surfels.triangle[j as usize] / 2,
            );
            assert_ne!(ti, tj, "a seam crossing lands on another face");
            let gap = surfels.position[i as usize].distance(surfels.position[j as usize]);
            assert!(
                gap < 6.0 * texel_mm,
                "texel {target}: {gap} mm between the two sources"
            );
        }
    }
    assert!(crossed > 100, "only {crossed} texels crossed a seam");
}
