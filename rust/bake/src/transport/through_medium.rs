//! How far light travels inside the medium between two surface points.
//!
//! A profile is a function of the distance light travels in the medium.
//! Between two points of a flat or convex surface that is the straight
//! distance; where the surface is concave (a crease, an eye socket, a fold
//! of skin, the gap between a lip and the next) the straight line runs
//! through air, and light must go round through the medium instead.
//!
//! Near each point the medium is taken to be the half-space below its
//! tangent plane. When each point lies above the other's plane the
//! straight segment leaves both half-spaces, and the medium near the pair
//! is their union (a concave crease). The shortest path inside that union
//! runs from one point to the planes' common line and on to the other:
//! unfolding the two half-planes into one, its length is
//! √((ρ_a + ρ_b)² + t²), where ρ = h / sin θ is a point's distance to the
//! line within its own plane (h its height above the other point's plane,
//! θ the angle between the normals) and t the offset of the two points
//! along the line. At a 90° crease this is the sum of the two points'
//! distances to the crease; on a gently concave surface it is the straight
//! distance to second order; for two faces that face each other across a
//! gap (parallel planes) it is unbounded, and nothing crosses.

use crate::surface::medium::INSIDE;
use glam::Vec3;

/// A point counts as above the other's tangent plane only when its height
/// exceeds this share of their distance. A flat surface's points lie on
/// each other's planes to rounding, which must not read as a crease; and
/// below it a crease turns by less than about 2°, where the path round it
/// is longer than the straight one by less than 0.1%.
const ABOVE: f32 = 0.02;

/// The length (mm) of the shortest path through the medium from `entry`
/// (unit normal `entry_normal`, pointing out of the medium) to `exit`
/// (`exit_normal`), `distance` (mm) being their straight distance: the
/// straight distance unless the pair sits across a concave crease or a
/// gap, where it is the path round the crease ([module docs](self)), and
/// `f32::INFINITY` where the two faces face each other.
#[inline]
pub fn path_length(
    entry: Vec3,
    entry_normal: Vec3,
    exit: Vec3,
    exit_normal: Vec3,
    distance: f32,
) -> f32 {
    longer_path(entry, entry_normal, exit, exit_normal, distance * distance).unwrap_or(distance)
}

/// [`path_length`] where it is longer than the straight distance, `None`
/// where the pair is joined straight; `distance2` is |exit − entry|², mm².
/// The common case costs a dot product and no square root.
#[inline]
pub fn longer_path(
    entry: Vec3,
    entry_normal: Vec3,
    exit: Vec3,
    exit_normal: Vec3,
    distance2: f32,
) -> Option<f32> {
    let d = exit - entry;
    // The exit's side first: an integrator holds the exit fixed while it
    // runs over entries, so this test reads nothing of the entry's normal.
    let entry_height = -d.dot(exit_normal);
    if !may_cross_air(entry_height, distance2) {
        return None;
    }
    round_the_crease(d, entry_normal, exit_normal, entry_height, distance2)
}

/// False when the pair's path is surely straight: the entry lies at most
/// `entry_height` (mm) above the exit's tangent plane, `distance2` (mm²)
/// being their squared distance. A sum that has the height at hand tests
/// this before [`path_length`], which reads the entry's normal.
#[inline]
pub fn may_cross_air(entry_height: f32, distance2: f32) -> bool {
    entry_height > 0.0 && entry_height * entry_height > ABOVE * ABOVE * distance2
}

/// Whether a pair of one medium, the entry on piece `entry_piece` and the
/// exit on `exit_piece` (as [`crate::surface::medium::Media::piece`]
/// numbers them), is joined through it: always on one piece, or where
/// either lies inside the medium (medium on both its sides), else as
/// [`joined_across_pieces`] says.
#[inline]
pub fn pieces_joined(
    entry_piece: u32,
    entry: Vec3,
    entry_normal: Vec3,
    exit_piece: u32,
    exit: Vec3,
    exit_normal: Vec3,
) -> bool {
    entry_piece == exit_piece
        || (entry_piece | exit_piece) & INSIDE != 0
        || joined_across_pieces(
            entry,
            entry_normal,
            exit,
            exit_normal,
            (exit - entry).length_squared(),
        )
}

/// Whether a pair on two pieces of one medium is joined through it
/// (`entry`, `exit` and their unit normals as for [`path_length`],
/// `distance2` their squared distance, mm²). Pieces a medium joins meet
/// where one is set into the other (an eye dome sunk into the skin of a
/// head, a lid inside a box): a straight line that leaves one point into
/// the air above its tangent plane while the other point lies under its
/// own reaches that point only through the other piece's faces (the
/// skin beside an eye and the dome's top, whose line runs up through the
/// air and in through the dome's rim), which light must go round; it is
/// taken to exchange nothing. A pair each below the other's plane is
/// joined straight, and a pair each above it sits across a crease, which
/// [`path_length`] goes round. Within one piece the surface itself joins
/// the two and light goes round beneath it (a bump beside flat skin), so
/// the test is for pairs across pieces alone.
#[inline]
pub fn joined_across_pieces(
    entry: Vec3,
    entry_normal: Vec3,
    exit: Vec3,
    exit_normal: Vec3,
    distance2: f32,
) -> bool {
    let d = exit - entry;
    let entry_above = may_cross_air(-d.dot(exit_normal), distance2);
    let exit_above = may_cross_air(d.dot(entry_normal), distance2);
    entry_above == exit_above
}

/// The path round the common line of the two tangent planes (unit
/// normals `a` of the entry, `b` of the exit), `d` running from entry to
/// exit, `entry_height` the entry's height above the exit's plane (above
/// [`ABOVE`] of the distance) and `distance2` the squared distance; `None`
/// when the exit lies low enough under the entry's plane that the pair is
/// joined straight after all.
#[cold]
fn round_the_crease(d: Vec3, a: Vec3, b: Vec3, entry_height: f32, distance2: f32) -> Option<f32> {
    let exit_height = d.dot(a);
    if !may_cross_air(exit_height, distance2) {
        return None;
    }
    let line = a.cross(b);
    let sine = line.length();
    // Parallel faces (sine 0) face each other across a gap: unbounded.
    let across = (entry_height + exit_height) / sine;
    if !across.is_finite() {
        return Some(f32::INFINITY);
    }
    let along = d.dot(line / sine);
    let path = (across * across + along * along).max(distance2).sqrt();
    Some(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_or_convex_pair_is_joined_straight() {
        let up = Vec3::Z;
        // Flat: both on z = 0.
        let (a, b) = (Vec3::ZERO, Vec3::new(3.0, 4.0, 0.0));
        assert_eq!(path_length(a, up, b, up, 5.0), 5.0);
        // Rounding above the plane is not a crease.
        let b = Vec3::new(3.0, 4.0, 1e-6);
        assert_eq!(path_length(a, up, b, up, b.length()), b.length());
        // A box's convex edge: top face and side face.
        let (top, side) = (Vec3::new(-2.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -3.0));
        let d = (side - top).length();
        assert_eq!(path_length(top, Vec3::Z, side, Vec3::X, d), d);
        // Opposite faces of a thin slab keep their straight distance.
        let (upper, lower) = (Vec3::new(0.0, 0.0, 1.0), Vec3::new(2.0, 0.0, 0.0));
        let d = (upper - lower).length();
        assert_eq!(path_length(upper, Vec3::Z, lower, -Vec3::Z, d), d);
    }

    #[test]
    fn pieces_are_joined_where_each_point_lies_under_the_others_plane_or_both_above() {
        // Skin z = 0 facing up beside a dome's top 5 mm up, facing up: the
        // line from the skin runs up through the air.
        let (skin, top) = (Vec3::new(-8.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 5.0));
        let d2 = (top - skin).length_squared();
        assert!(!joined_across_pieces(skin, Vec3::Z, top, Vec3::Z, d2));
        assert!(!joined_across_pieces(top, Vec3::Z, skin, Vec3::Z, d2));
        // Two faces of a part modelled apart, each behind the other.
        let (upper, lower) = (Vec3::new(0.0, 0.0, 1.0), Vec3::new(3.0, 0.0, 0.0));
        let d2 = (upper - lower).length_squared();
        assert!(joined_across_pieces(upper, Vec3::Z, lower, -Vec3::Z, d2));
        // A floor and a wall across a crease: both above, left to the path
        // round it.
        let (floor, wall) = (Vec3::new(3.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 4.0));
        let d2 = (wall - floor).length_squared();
        assert!(joined_across_pieces(floor, Vec3::Z, wall, Vec3::X, d2));
        // Coplanar points (rounding) are joined.
        let (a, b) = (Vec3::ZERO, Vec3::new(3.0, 4.0, 1e-6));
        assert!(joined_across_pieces(a, Vec3::Z, b, Vec3::Z, 25.0));
    }

    #[test]
    fn a_piece_inside_the_medium_is_joined_from_either_side() {
        // The skin beside a dome's top, as above: apart, unless the dome's
        // face lies inside the medium.
        let (skin, top) = (Vec3::new(-8.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 5.0));
        assert!(!pieces_joined(0, skin, Vec3::Z, 1, top, Vec3::Z));
        assert!(pieces_joined(0, skin, Vec3::Z, 1 | INSIDE, top, Vec3::Z));
        assert!(pieces_joined(INSIDE, skin, Vec3::Z, 1, top, Vec3::Z));
        // One piece is always joined, inside or not.
        assert!(pieces_joined(1, skin, Vec3::Z, 1, top, Vec3::Z));
        assert!(pieces_joined(1, skin, Vec3::Z, 1 | INSIDE, top, Vec3::Z));
    }

    #[test]
    fn a_right_angled_crease_is_crossed_round_its_line() {
        // Medium where x < 0 or z < 0: the floor z = 0 (x > 0) faces +z,
        // the wall x = 0 (z > 0) faces +x.
        let (floor, wall) = (Vec3::new(3.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 4.0));
        let d = (wall - floor).length();
        let path = path_length(floor, Vec3::Z, wall, Vec3::X, d);
        // 3 to the line, 4 up the wall, 2 along the line.
        let expected = (7.0f32 * 7.0 + 2.0 * 2.0).sqrt();
        assert!((path - expected).abs() < 1e-5, "{path} vs {expected}");
        // The same either way round.
        let back = path_length(wall, Vec3::X, floor, Vec3::Z, d);
        assert!((back - path).abs() < 1e-5);
    }

    #[test]
    fn a_gently_concave_surface_keeps_nearly_its_straight_distance() {
        // Two points 10° apart on the inside of a bowl of radius 100 mm:
        // the path round the tangent planes is R·2·tan(5°), the chord
        // 2R·sin(5°), 0.4% apart.
        let radius = 100.0f32;
        let half = 5.0f32.to_radians();
        let at = |s: f32| radius * Vec3::new((s * half).sin(), 0.0, -(s * half).cos());
        let (a, b) = (at(-1.0), at(1.0));
        // Normals point out of the medium, toward the bowl's centre.
        let (na, nb) = (-a.normalize(), -b.normalize());
        let chord = (b - a).length();
        let path = path_length(a, na, b, nb, chord);
        let expected = 2.0 * radius * half.tan();
        assert!(path > chord && (path - expected).abs() < 1e-3 * expected);
    }

    #[test]
    fn faces_across_a_gap_are_not_joined() {
        // A fold: the lower face (z = 0) faces up, the upper (z = 0.5)
        // faces down, 3 mm apart along x.
        let (lower, upper) = (Vec3::ZERO, Vec3::new(3.0, 0.0, 0.5));
        let d = upper.length();
        let path = path_length(lower, Vec3::Z, upper, -Vec3::Z, d);
        assert_eq!(path, f32::INFINITY);
        // Nearly parallel faces are beyond any reach apart.
        let tilted = Vec3::new(0.0, 1e-5, -1.0).normalize();
        assert!(path_length(lower, Vec3::Z, upper, tilted, d) > 1e4 * d);
    }

    #[test]
    fn degenerate_inputs_stay_defined() {
        let p = Vec3::new(1.0, 0.0, 0.0);
        // The same point: distance 0.
        assert_eq!(path_length(p, Vec3::Z, p, Vec3::X, 0.0), 0.0);
        // A zero normal never makes a crease.
        assert_eq!(path_length(Vec3::ZERO, Vec3::ZERO, p, Vec3::X, 1.0), 1.0);
        // Non-finite positions give a non-finite or straight length, never
        // a panic.
        let far = Vec3::splat(f32::MAX);
        let _ = path_length(Vec3::ZERO, Vec3::Z, far, -Vec3::Z, f32::INFINITY);
    }
}
