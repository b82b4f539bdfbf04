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
use sssbake::control::Control;
use sssbake::surface::medium::{INSIDE, medium_pieces};
use sssbake::transport::Method;
use sssbake::transport::integrator::IntegratorSettings;
use sssbake::transport::sources::{Sources, Target};
use sssbake::{BakeRequest, Mesh};
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
    let sources = Sources {
        position: vec![Vec3::ZERO].into(),
        normal: vec![Vec3::Z].into(),
        ..Sources::default()
    };
    let target = Target {
        position: Vec3::X,
        normal: Vec3::Z,
        own: None,
        piece: Some(3),
        part: Some(1),
    };
    assert!(
        sources.joins(0, &target),
        "a source without a piece joins any"
    );
}

#[test]
fn pieces_bounding_one_medium_or_crossing_are_joined_and_closed_ones_in_air_are_not() {
    let count = |media: &[u32]| media.iter().max().map_or(0, |&m| m + 1);
    // Two closed cubes a millimetre apart: rays from inside each meet only
    // itself.
    assert_eq!(count(&medium_pieces(&two_cubes()).medium), 2);
    // Two cubes crossing by a third of their side: one medium.
    assert_eq!(
        count(&medium_pieces(&two_cubes_apart(SIDE * 2.0 / 3.0)).medium),
        1
    );
    // A lid closing an open box: two pieces, one medium.
    let lidded = box_and_lid();
    let pieces = sssbake::surface::topology::triangle_pieces(&lidded);
    assert_eq!(count(&pieces), 2);
    assert_eq!(count(&medium_pieces(&lidded).medium), 1);
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
    assert_eq!(count(&medium_pieces(&nested).medium), 1);
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
    assert_eq!(count(&medium_pieces(&faces(true)).medium), 1);
    assert_eq!(count(&medium_pieces(&faces(false)).medium), 2);
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

/// Half the width of the box the cap is set into, its height, and the
/// cap's: half its width, how far it stands above the box's top and how
/// far its walls reach down into the box, mm.
const BOX_HALF: f32 = 15.0;
const BOX_HEIGHT: f32 = 20.0;
const CAP_HALF: f32 = 4.0;
const CAP_RISE: f32 = 4.0;
const CAP_SINK: f32 = 12.0;

/// A box whose top has a square hole, and a cap plugging it, its own
/// piece: four walls and a top standing [`CAP_RISE`] mm above the box's
/// top, open below, its walls reaching [`CAP_SINK`] mm down into the box
/// (each wall in two bands, at the box's top, so the band inside the box
/// is triangles of its own): one medium, as Suzanne's head and the eye domes
/// sunk into it. No UVs: the layout unwraps it.
fn capped_box() -> Mesh {
    let (mut positions, mut triangles) = (Vec::new(), Vec::new());
    let mut quad = |corners: [Vec3; 4]| {
        let base = positions.len() as u32;
        positions.extend(corners);
        triangles.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
    };
    let (b, h, c) = (BOX_HALF, BOX_HEIGHT, CAP_HALF);
    let v = Vec3::new;
    // The box on a 3 × 3 grid (lines at ±b and ±c), so every edge it has
    // is shared whole and it welds into one piece: its bottom (facing
    // −z), its walls three columns each, and its top without the middle
    // cell (facing +z), counter-clockwise seen from outside.
    let lines = [-b, -c, c, b];
    for i in 0..3 {
        let (x0, x1) = (lines[i], lines[i + 1]);
        for j in 0..3 {
            let (y0, y1) = (lines[j], lines[j + 1]);
            quad([
                v(x0, y0, 0.0),
                v(x0, y1, 0.0),
                v(x1, y1, 0.0),
                v(x1, y0, 0.0),
            ]);
            if (i, j) != (1, 1) {
                quad([v(x0, y0, h), v(x1, y0, h), v(x1, y1, h), v(x0, y1, h)]);
            }
        }
        let (s0, s1) = (lines[i], lines[i + 1]);
        quad([v(b, s0, 0.0), v(b, s1, 0.0), v(b, s1, h), v(b, s0, h)]);
        quad([v(-b, s1, 0.0), v(-b, s0, 0.0), v(-b, s0, h), v(-b, s1, h)]);
        quad([v(s1, b, 0.0), v(s0, b, 0.0), v(s0, b, h), v(s1, b, h)]);
        quad([v(s0, -b, 0.0), v(s1, -b, 0.0), v(s1, -b, h), v(s0, -b, h)]);
    }
    // The cap: its top, and each wall in a band inside the box and one
    // above it, facing out.
    // The bands part a hair below the box's top: the hole's edge lies on
    // the cap's walls, not along an edge of them, which would weld the two
    // into one piece.
    let (low, split, top) = (h - CAP_SINK, h - 0.01, h + CAP_RISE);
    quad([v(-c, -c, top), v(c, -c, top), v(c, c, top), v(-c, c, top)]);
    for (z0, z1) in [(low, split), (split, top)] {
        quad([v(c, -c, z0), v(c, c, z0), v(c, c, z1), v(c, -c, z1)]);
        quad([v(-c, c, z0), v(-c, -c, z0), v(-c, -c, z1), v(-c, c, z1)]);
        quad([v(c, c, z0), v(-c, c, z0), v(-c, c, z1), v(c, c, z1)]);
        quad([v(-c, -c, z0), v(c, -c, z0), v(c, -c, z1), v(-c, -c, z1)]);
    }
    Mesh::new("capped box", positions, None, None, triangles)
        .unwrap()
        .0
}

/// A roof above the cap, shading its top from a sun straight above and
/// the box's top within about half a millimetre of it. Set off the texels'
/// rows, so no shadow ray runs along the roof's diagonal edge.
fn cap_roof() -> Mesh {
    let mut mesh = centred_square(2.0 * CAP_HALF + 1.0, "roof");
    for p in &mut mesh.positions {
        *p += Vec3::new(0.1, 0.2, BOX_HEIGHT + CAP_RISE + 20.0);
    }
    mesh
}

#[test]
fn light_crosses_between_pieces_of_one_medium_only_through_it() {
    let mesh = capped_box();
    let pieces = sssbake::surface::topology::triangle_pieces(&mesh);
    assert_eq!(pieces.iter().max(), Some(&1), "the box and the cap");
    let media = medium_pieces(&mesh);
    assert_eq!(
        media.medium.iter().max(),
        Some(&0),
        "the cap and the box are one medium"
    );
    // The cap's band inside the box lies inside the medium; its band
    // above, its top and the box's faces do not.
    let inside = |t: usize| media.piece[t] & INSIDE != 0;
    let cap_first = 2 * (9 + 8 + 12);
    assert!((0..cap_first).all(|t| !inside(t)));
    assert!(
        (cap_first..cap_first + 2).all(|t| !inside(t)),
        "the cap's top"
    );
    for band in 0..2 {
        let walls = cap_first + 2 + 8 * band..cap_first + 2 + 8 * (band + 1);
        assert!(
            walls.clone().all(|t| inside(t) == (band == 0)),
            "band {band}"
        );
    }

    // A sun from straight above lights the box's top up to the cap; a roof
    // shades the cap's top, and the cap's walls take no light from above
    // (nor, without bounces, the light the box's top sends them).
    let scene = scene(vec![mesh, cap_roof()], vec![sun_from(Vec3::NEG_Z)]);
    let skin = scattering_of("skin1", Model::Dipole);
    let request = BakeRequest {
        bounces: 0,
        ..request(128)
    };
    let prepared = prepare_with(&scene, "capped box", &request, &Control::new()).unwrap();
    let surfels = &prepared.surfels;
    let on = |s: usize, z: f32, inner: bool| {
        let p = surfels.position[s];
        (p.z - z).abs() < 0.2
            && surfels.normal[s].z > 0.9
            && (p.x.abs().max(p.y.abs()) < CAP_HALF) == inner
    };
    let cap_top: Vec<usize> = (0..surfels.len())
        .filter(|&s| on(s, BOX_HEIGHT + CAP_RISE, true))
        .collect();
    let box_top: Vec<usize> = (0..surfels.len())
        .filter(|&s| on(s, BOX_HEIGHT, false))
        .collect();
    assert!(cap_top.len() > 10 && box_top.len() > 100);
    assert!(cap_top.iter().all(|&s| prepared.irradiance[s] == [0.0; 3]));
    let beyond_roof =
        |s: usize| surfels.position[s].x.abs().max(surfels.position[s].y.abs()) > CAP_HALF + 1.0;
    assert!(
        box_top
            .iter()
            .filter(|&&s| beyond_roof(s))
            .all(|&s| prepared.irradiance[s][0] > 0.5)
    );
    // The cap's band inside the box, near its top: medium on both sides.
    let sunk: Vec<usize> = (0..surfels.len())
        .filter(|&s| {
            let p = surfels.position[s];
            (p.x.abs().max(p.y.abs()) - CAP_HALF).abs() < 0.2
                && (BOX_HEIGHT - 3.0..BOX_HEIGHT - 0.5).contains(&p.z)
        })
        .collect();
    assert!(sunk.len() > 10);

    // The straight line from the box's lit top to the cap's top runs up
    // through the air and in through the cap's walls: gathered by 3-D
    // distance alone, as if the medium joined them straight, the cap's top
    // would glow.
    let mut sources = prepared.texel_sources();
    sources.part = Default::default();
    let straight = exact_sum_at(&prepared, &skin.kernel, &sources, &cap_top);
    let glow = |light: &[[f32; 3]]| {
        light.iter().map(|m| f64::from(m[0])).sum::<f64>() / light.len() as f64
    };
    let straight_glow = glow(&straight);
    assert!(
        straight_glow > 1e-3,
        "straight, the cap's top has {straight_glow}"
    );
    // Light itself goes down round the cap's walls and up inside it, 30 mm
    // and more, and brings the cap's top a small share of that.
    let (walked, _) = walked_at(&prepared, &skin, &cap_top, 4096);
    let light_glow = glow(&walked);
    eprintln!("the cap's top, red: straight {straight_glow:.4}, the walk {light_glow:.5}");
    assert!(
        light_glow < 0.1 * straight_glow,
        "the walk brings {light_glow}"
    );

    for method in [Method::Brute, Method::Octree, Method::Importance] {
        let exitance = exitance(&prepared, &skin, method, &IntegratorSettings::default());
        let top: Vec<[f32; 3]> = cap_top.iter().map(|&s| exitance[s]).collect();
        assert_eq!(
            glow(&top),
            0.0,
            "{method}: light crossed the air to the cap's top"
        );
        // The band inside the box takes the light of the box's top beside
        // it, from above its tangent plane as from below.
        let band: Vec<[f32; 3]> = sunk.iter().map(|&s| exitance[s]).collect();
        assert!(
            glow(&band) > 1e-3,
            "{method}: the sunk band has {}",
            glow(&band)
        );
    }
}
