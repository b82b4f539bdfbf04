//! The face behind each texel is sought only as far as the profile
//! reaches: a part thicker than the reach is a half-space to every reader,
//! so its rays stop there.

mod lit_scenes;

use glam::Vec3;
use lit_scenes::*;

/// Side of the tile, mm.
const SIDE: f32 = 60.0;
/// Thickness of the tile, mm.
const THICK: f32 = 3.0;

/// A tile [`SIDE`] mm square and [`THICK`] mm thick, lit from above.
fn tile() -> sssbake::Scene {
    let tile = stretched(cube(1.0), Vec3::new(SIDE, SIDE, THICK), "tile");
    scene(vec![tile], vec![sun_from(Vec3::NEG_Z)])
}

/// Texels whose normal points along z (the two broad faces) and along x
/// or y (the rims).
fn faces(prepared: &sssbake::prepared::Prepared) -> (Vec<usize>, Vec<usize>) {
    (0..prepared.surfels.len()).partition(|&i| prepared.surfels.normal[i].z.abs() > 0.9)
}

#[test]
fn the_faces_behind_are_found_within_the_reach_asked_and_none_beyond() {
    let scene = tile();
    let prepared = prepared(&scene, "tile", 64);
    let (broad, rims) = faces(&prepared);
    assert!(!broad.is_empty() && !rims.is_empty());

    // Within 5 mm: every texel of the broad faces finds the other face
    // 3 mm behind it; the rims, 60 mm across, find nothing.
    let near = prepared.opposites(5.0);
    for &i in &broad {
        let o = near[i].unwrap_or_else(|| panic!("broad texel {i} has no face behind"));
        assert!((o.thickness - THICK).abs() < 1e-3, "{o:?}");
        let behind = prepared.surfels.normal[o.surfel as usize];
        assert!(behind.dot(prepared.surfels.normal[i]) < -0.9, "{behind}");
    }
    assert!(rims.iter().all(|&i| near[i].is_none()));
    assert!(prepared.has_thin_parts(THICK + 0.01));

    // A longer reach finds the rims' faces across the tile; the faces
    // found before are the same.
    let far = prepared.opposites(100.0);
    let across = rims.iter().filter_map(|&i| far[i]).collect::<Vec<_>>();
    assert!(
        across.len() > rims.len() / 2,
        "{} of {}",
        across.len(),
        rims.len()
    );
    assert!(across.iter().all(|o| (o.thickness - SIDE).abs() < 1e-2));
    assert!(broad.iter().all(|&i| far[i] == near[i]));

    // Asked for less than the thickness on a fresh object: nothing.
    let fresh = lit_scenes::prepared(&scene, "tile", 64);
    assert!(fresh.opposites(THICK - 0.5).iter().all(Option::is_none));
    assert!(!fresh.has_thin_parts(THICK - 0.5));
}

/// A block 40 × 40 × 12 mm (its top at z = 6) with a smaller one, 10 ×
/// 10 × 4 mm, set inside it [`SUNK`] mm under its top: two closed pieces
/// of one mesh, one medium, each in its own half of the map.
fn block_with_a_piece_set_in() -> sssbake::Mesh {
    let outer = stretched(cube(1.0), Vec3::new(40.0, 40.0, 12.0), "outer");
    let inner = stretched(cube(1.0), Vec3::new(10.0, 10.0, 4.0), "inner");
    let (mut positions, mut uvs, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for (k, (part, shift)) in [(outer, 0.0), (inner, 4.0 - SUNK)].into_iter().enumerate() {
        let base = positions.len() as u32;
        positions.extend(part.positions.iter().map(|p| *p + Vec3::Z * shift));
        let uv = part.uvs.as_ref().unwrap();
        uvs.extend(
            uv.iter()
                .map(|t| glam::Vec2::new((t.x + k as f32) / 2.0, t.y)),
        );
        triangles.extend(part.triangles.iter().map(|t| t.map(|v| v + base)));
    }
    sssbake::Mesh::new("block", positions, None, Some(uvs), triangles)
        .unwrap()
        .0
}

/// Depth of the inner block's top under the outer's, mm.
const SUNK: f32 = 2.0;

#[test]
fn a_face_set_into_the_medium_ends_it_whichever_way_it_faces() {
    // The inner block's top faces up, towards a ray going down from the
    // outer top: the walk and Cycles' Random Walk end there all the same,
    // so the skin above it is a layer SUNK mm thick, its far face the
    // inner top.
    let scene = scene(
        vec![block_with_a_piece_set_in()],
        vec![sun_from(Vec3::NEG_Z)],
    );
    let prepared = prepared(&scene, "block", 128);
    let surfels = &prepared.surfels;
    let behind = prepared.opposites(20.0);
    let on_top = |i: usize, half: f32| {
        let p = surfels.position[i];
        surfels.normal[i].z > 0.9 && p.x.abs() < half && p.y.abs() < half && p.z > 5.9
    };
    let above_the_piece: Vec<usize> = (0..surfels.len()).filter(|&i| on_top(i, 4.0)).collect();
    assert!(
        above_the_piece.len() > 20,
        "{} texels",
        above_the_piece.len()
    );
    for &i in &above_the_piece {
        let o = behind[i].unwrap_or_else(|| panic!("texel {i} above the piece has no face behind"));
        assert!((o.thickness - SUNK).abs() < 1e-3, "{o:?}");
        let far = o.surfel as usize;
        assert!(
            surfels.normal[far].z > 0.9 && (surfels.position[far].z - (6.0 - SUNK)).abs() < 0.1
        );
    }
    // Beside it, the outer block's own bottom, 12 mm down.
    let beside: Vec<usize> = (0..surfels.len())
        .filter(|&i| on_top(i, 18.0) && !on_top(i, 7.0))
        .collect();
    assert!(!beside.is_empty());
    assert!(
        beside
            .iter()
            .all(|&i| behind[i].is_some_and(|o| (o.thickness - 12.0).abs() < 1e-3))
    );
}
