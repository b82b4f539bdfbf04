//! A tangent frame that belongs to the surface, not to the world's axes.

use crate::mesh::Mesh;
use glam::Vec3;

/// Two unit axes (t, b) completing unit `n` on `triangle` of `mesh`: t
/// along the triangle's longest edge (in its winding) laid into the plane
/// of `n`, b = n × t. They turn with the mesh, so rays a texel casts along
/// them meet the same surface however the scene is written (a glTF is
/// Y-up, Blender Z-up); a degenerate triangle, or an edge along `n`, takes
/// any pair about `n`.
pub fn own_frame(mesh: &Mesh, triangle: u32, n: Vec3) -> (Vec3, Vec3) {
    let Some(corners) = mesh.triangles.get(triangle as usize) else {
        return n.any_orthonormal_pair();
    };
    let [a, b, c] = corners.map(|v| mesh.positions[v as usize]);
    let edge = [b - a, c - b, a - c]
        .into_iter()
        .max_by(|x, y| x.length_squared().total_cmp(&y.length_squared()))
        .unwrap_or(Vec3::ZERO);
    let t = (edge - n * edge.dot(n)).normalize_or_zero();
    if t == Vec3::ZERO {
        return n.any_orthonormal_pair();
    }
    (t, n.cross(t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    fn triangle(corners: [Vec3; 3]) -> Mesh {
        Mesh::new("t", corners.to_vec(), None, None, vec![[0, 1, 2]])
            .unwrap()
            .0
    }

    #[test]
    fn the_frame_turns_with_the_mesh() {
        let corners = [
            Vec3::ZERO,
            Vec3::new(3.0, 0.5, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        let n = Vec3::Z;
        let (t, b) = own_frame(&triangle(corners), 0, n);
        assert!((t.dot(n)).abs() < 1e-6 && (b.dot(n)).abs() < 1e-6 && t.dot(b).abs() < 1e-6);
        assert!((t.length() - 1.0).abs() < 1e-6 && (b.length() - 1.0).abs() < 1e-6);
        let turn = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2) * Quat::from_rotation_z(0.3);
        let (t_turned, b_turned) = own_frame(&triangle(corners.map(|p| turn * p)), 0, turn * n);
        assert!(
            (t_turned - turn * t).length() < 1e-5,
            "{t_turned} against {}",
            turn * t
        );
        assert!((b_turned - turn * b).length() < 1e-5);
    }

    #[test]
    fn an_edge_along_the_normal_or_a_missing_triangle_still_has_a_frame() {
        // The longest edge along n (a sliver standing on the surface, under
        // an interpolated normal), and a triangle the mesh does not have.
        let standing = triangle([Vec3::ZERO, 10.0 * Vec3::Z, Vec3::new(0.1, 0.0, 5.0)]);
        let flat = triangle([Vec3::ZERO, Vec3::X, Vec3::Y]);
        for (mesh, index) in [(&standing, 0), (&flat, 7)] {
            let (t, b) = own_frame(mesh, index, Vec3::Z);
            assert!(t.is_finite() && b.is_finite());
            assert!((t.length() - 1.0).abs() < 1e-6 && t.dot(Vec3::Z).abs() < 1e-6);
            assert!((b.length() - 1.0).abs() < 1e-6 && b.dot(t).abs() < 1e-6);
        }
    }
}
