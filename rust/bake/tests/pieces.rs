//! Light scattered inside an object stays in the medium it entered: two
//! closed pieces of one mesh a millimetre apart are joined by air, not by
//! the medium, so a piece in full shadow receives nothing from its lit
//! neighbour, whatever the 3-D integrator. Pieces that bound one medium
//! together (a lid closing an open box, as Suzanne's eyes close the holes
//! in its head) or that cross each other share their light, as they do in
//! a walk through the mesh.

mod lit_scenes;

use glam::{Vec2, Vec3};
use lit_scenes::*;
use sssbake::Mesh;
use sssbake::surface::medium::medium_pieces;
use sssbake::transport::Method;
use sssbake::transport::integrator::IntegratorSettings;
use sssbake::transport::sources::Sources;
use sssbake_profile::model::Model;

/// Side of each cube, mm.
const SIDE: f32 = 30.0;
/// Air between the two cubes, mm.
const GAP: f32 = 1.0;

/// Two cubes of [`SIDE`] mm in one mesh, their centres `apart` mm apart
/// along x (the first at x < 0), each cube's UVs in its own half of the
/// map.
fn two_cubes_apart(apart: f32) -> Mesh {
    let one = cube(SIDE);
    let (mut positions, mut uvs, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for (k, shift) in [-apart / 2.0, apart / 2.0].into_iter().enumerate() {
        let base = positions.len() as u32;
        positions.extend(one.positions.iter().map(|p| *p + Vec3::X * shift));
        let uv = one.uvs.as_ref().unwrap();
        uvs.extend(uv.iter().map(|t| Vec2::new((t.x + k as f32) / 2.0, t.y)));
        triangles.extend(one.triangles.iter().map(|t| t.map(|v| v + base)));
    }
    Mesh::new("pieces", positions, None, Some(uvs), triangles)
        .unwrap()
        .0
}

/// Two cubes [`GAP`] mm apart.
fn two_cubes() -> Mesh {
    two_cubes_apart(SIDE + GAP)
}

/// A cube of [`SIDE`] mm open at the top (+z), and a lid: a square of the
/// same side set [`GAP`] mm inside the rim, its own piece (no edge
/// shared), facing up. The lid's UVs take the island of the missing face.
fn box_and_lid() -> Mesh {
    let one = cube(SIDE);
    let uv = one.uvs.as_ref().unwrap();
    // The cube's faces in order +x, −x, +y, −y, +z, −z: the top is the
    // fifth pair of triangles.
    let top = [8, 9];
    let top_vertices: Vec<u32> = top.iter().flat_map(|&t| one.triangles[t]).collect();
    let (low, high) = top_vertices
        .iter()
        .fold((Vec2::ONE, Vec2::ZERO), |(lo, hi), &v| {
            (lo.min(uv[v as usize]), hi.max(uv[v as usize]))
        });
    let mut positions = one.positions.clone();
    let mut uvs = uv.clone();
    let mut triangles: Vec<[u32; 3]> = one
        .triangles
        .iter()
        .enumerate()
        .filter(|(t, _)| !top.contains(t))
        .map(|(_, t)| *t)
        .collect();
    let base = positions.len() as u32;
    let h = SIDE / 2.0;
    for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        positions.push(Vec3::new(s * h, t * h, h - GAP));
        uvs.push(low + (high - low) * Vec2::new((s + 1.0) / 2.0, (t + 1.0) / 2.0));
    }
    triangles.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
    Mesh::new("box and lid", positions, None, Some(uvs), triangles)
        .unwrap()
        .0
}

/// A roof 40 mm above the second cube, shading all of its top from a sun
/// straight above, and none of the first cube's.
fn roof() -> Mesh {
    let mut mesh = quad(SIDE + 10.0);
    for p in &mut mesh.positions {
        *p += Vec3::new(GAP / 2.0 + 0.2, -(SIDE + 10.0) / 2.0, SIDE / 2.0 + 40.0);
    }
    mesh.name = "roof".into();
    mesh
}

#[test]
fn a_piece_in_shadow_receives_no_light_from_its_lit_neighbour() {
    let scene = scene(vec![two_cubes(), roof()], vec![sun_from(Vec3::NEG_Z)]);
    let skin = scattering_of("skin1", Model::Dipole);
    assert!(
        skin.kernel.d_max > 2.0 * GAP,
        "the profile must reach across the gap for the test to mean anything"
    );
    let prepared = prepared(&scene, "pieces", 256);
    let surfels = &prepared.surfels;
    let second = surfels.piece[(0..surfels.len())
        .find(|&s| surfels.position[s].x > 0.0)
        .unwrap()];
    let on_second: Vec<usize> = (0..surfels.len())
        .filter(|&s| surfels.piece[s] == second)
        .collect();
    let on_first: Vec<usize> = (0..surfels.len())
        .filter(|&s| surfels.piece[s] != second)
        .collect();
    assert!(on_second.iter().all(|&s| surfels.position[s].x > 0.0));
    assert!(on_first.iter().all(|&s| surfels.position[s].x < 0.0));
    // The set-up: the second cube is wholly dark, the first lit on top.
    assert!(
        on_second
            .iter()
            .all(|&s| prepared.irradiance[s] == [0.0; 3])
    );
    assert!(on_first.iter().any(|&s| prepared.irradiance[s][0] > 0.5));

    // Gathering by 3-D distance alone, as if one medium filled the gap, the
    // second cube's top near the gap would glow: what the pieces prevent.
    let mut sources = prepared.texel_sources();
    sources.piece = Default::default();
    let across_air = exact_sum_at(&prepared, &skin.kernel, &sources, &on_second);
    let leaked = across_air.iter().map(|m| m[0]).fold(0.0f32, f32::max);
    assert!(leaked > 1e-3, "across the air the gap would carry {leaked}");

    // Texture space blurs in the map, where charts of two pieces may lie
    // side by side: what it carries between them is part of the error its
    // estimate measures against the exact sum, which keeps the pieces apart.
    for method in [Method::Brute, Method::Octree, Method::Importance] {
        let exitance = exitance(&prepared, &skin, method, &IntegratorSettings::default());
        let dark = on_second
            .iter()
            .map(|&s| exitance[s].into_iter().fold(0.0f32, f32::max))
            .fold(0.0f32, f32::max);
        assert_eq!(
            dark, 0.0,
            "{method}: light crossed the air to the dark piece"
        );
        let lit = on_first.iter().map(|&s| exitance[s][0]).fold(0.0, f32::max);
        assert!(lit > 0.1, "{method}: the lit piece has {lit}");
    }
}

#[test]
fn pieces_are_counted_through_welded_edges() {
    let mesh = two_cubes();
    let pieces = sssbake::surface::topology::triangle_pieces(&mesh);
    assert_eq!(pieces.len(), mesh.triangles.len());
    // Each cube face has its own vertices (UV islands), welded by position.
    let half = mesh.triangles.len() / 2;
    assert!(pieces[..half].iter().all(|&p| p == pieces[0]));
    assert!(pieces[half..].iter().all(|&p| p == pieces[half]));
    assert_ne!(pieces[0], pieces[half]);
    let sources = Sources::default();
    assert!(
        sources.joins(0, Some(3)),
        "a source without a piece joins any"
    );
}

#[test]
fn pieces_bounding_one_medium_or_crossing_are_joined_and_closed_ones_in_air_are_not() {
    let count = |media: &[u32]| media.iter().max().map_or(0, |&m| m + 1);
    // Two closed cubes a millimetre apart: rays from inside each meet only
    // itself.
    assert_eq!(count(&medium_pieces(&two_cubes())), 2);
    // Two cubes crossing by a third of their side: one medium.
    assert_eq!(count(&medium_pieces(&two_cubes_apart(SIDE * 2.0 / 3.0))), 1);
    // A lid closing an open box: two pieces, one medium.
    let lidded = box_and_lid();
    let pieces = sssbake::surface::topology::triangle_pieces(&lidded);
    assert_eq!(count(&pieces), 2);
    assert_eq!(count(&medium_pieces(&lidded)), 1);
    // A small cube inside a large one: light in the large one meets it.
    let (outer, inner) = (cube(SIDE), cube(SIDE / 3.0));
    let base = outer.positions.len() as u32;
    let positions = [outer.positions.clone(), inner.positions.clone()].concat();
    let mut triangles = outer.triangles.clone();
    triangles.extend(inner.triangles.iter().map(|t| t.map(|v| v + base)));
    let nested = Mesh::new("nested", positions, None, None, triangles)
        .unwrap()
        .0;
    assert_eq!(
        count(&sssbake::surface::topology::triangle_pieces(&nested)),
        2
    );
    assert_eq!(count(&medium_pieces(&nested)), 1);
    // Two open faces: back to back 3 mm apart (a leaf's two sides modelled
    // apart), one medium; side by side, two.
    let faces = |back_to_back: bool| {
        let one = quad(SIDE);
        let mut positions = one.positions.clone();
        let mut triangles = one.triangles.clone();
        let shift = if back_to_back {
            Vec3::new(0.0, 0.0, -3.0)
        } else {
            Vec3::new(2.0 * SIDE, 0.0, 0.0)
        };
        positions.extend(one.positions.iter().map(|p| *p + shift));
        // The second faces down when back to back, up beside the first.
        triangles.extend(one.triangles.iter().map(|&[a, b, c]| {
            if back_to_back {
                [a + 4, c + 4, b + 4]
            } else {
                [a + 4, b + 4, c + 4]
            }
        }));
        Mesh::new("faces", positions, None, None, triangles)
            .unwrap()
            .0
    };
    assert_eq!(count(&medium_pieces(&faces(true))), 1);
    assert_eq!(count(&medium_pieces(&faces(false))), 2);
}

#[test]
fn a_lid_in_shadow_receives_the_light_of_the_box_it_closes() {
    // A sun from below and one side lights the box's floor and a wall up
    // to the rim; the lid faces up, away from it, and receives no light of
    // its own.
    let scene = scene(
        vec![box_and_lid()],
        vec![sun_from(Vec3::new(1.0, 0.0, 0.4))],
    );
    let skin = scattering_of("skin1", Model::Dipole);
    let prepared = prepared(&scene, "box and lid", 128);
    let surfels = &prepared.surfels;
    let lid: Vec<usize> = (0..surfels.len())
        .filter(|&s| surfels.position[s].z > SIDE / 2.0 - 2.0 * GAP && surfels.normal[s].z > 0.9)
        .collect();
    assert!(lid.len() > 20, "{} texels on the lid", lid.len());
    assert!(lid.iter().all(|&s| prepared.irradiance[s] == [0.0; 3]));
    for method in [Method::Brute, Method::Octree] {
        let exitance = exitance(&prepared, &skin, method, &IntegratorSettings::default());
        // Along the lit wall, within red's reach, the lid glows.
        let glow = lid.iter().map(|&s| exitance[s][0]).fold(0.0f32, f32::max);
        assert!(glow > 1e-3, "{method}: the lid received {glow}");
    }
}
