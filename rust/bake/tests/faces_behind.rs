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
