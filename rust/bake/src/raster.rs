//! Triangles on the texel grid: bounds, barycentric coordinates and the
//! exact area a triangle covers in a texel.

use glam::DVec2;

/// A triangle in texel units (uv × resolution), double precision.
pub type TexelTriangle = [DVec2; 3];

/// The texels (x0..x1, y0..y1, exclusive ends) a triangle's bounding box
/// touches, clipped to the `resolution`² grid; empty when off the grid.
pub fn texel_bounds(t: &TexelTriangle, resolution: u32) -> (u32, u32, u32, u32) {
    let n = resolution as f64;
    let lo = t[0].min(t[1]).min(t[2]);
    let hi = t[0].max(t[1]).max(t[2]);
    let clamp = |v: f64| v.clamp(0.0, n) as u32;
    (
        clamp(lo.x.floor()),
        clamp(hi.x.floor() + 1.0),
        clamp(lo.y.floor()),
        clamp(hi.y.floor() + 1.0),
    )
}

/// Twice the signed area of the triangle (positive counter-clockwise).
pub fn signed_area2(t: &TexelTriangle) -> f64 {
    (t[1] - t[0]).perp_dot(t[2] - t[0])
}

/// Barycentric coordinates of `p`; `None` for a degenerate triangle.
pub fn barycentric(p: DVec2, t: &TexelTriangle) -> Option<[f64; 3]> {
    let area = signed_area2(t);
    if area.abs() < 1e-300 {
        return None;
    }
    let w0 = (t[1] - p).perp_dot(t[2] - p) / area;
    let w1 = (t[2] - p).perp_dot(t[0] - p) / area;
    Some([w0, w1, 1.0 - w0 - w1])
}

/// The area of triangle `t` inside texel (x, y), in texel units (0..=1).
/// Texels wholly inside or outside are decided from their corners; the
/// rest are clipped against the texel's four sides.
pub fn coverage(t: &TexelTriangle, x: u32, y: u32) -> f64 {
    let (x0, y0) = (x as f64, y as f64);
    let orientation = signed_area2(t).signum();
    let corners = [
        DVec2::new(x0, y0),
        DVec2::new(x0 + 1.0, y0),
        DVec2::new(x0, y0 + 1.0),
        DVec2::new(x0 + 1.0, y0 + 1.0),
    ];
    let mut inside_all = true;
    for i in 0..3 {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        let side = |p: DVec2| orientation * (b - a).perp_dot(p - a);
        let outside = corners.iter().filter(|&&p| side(p) < 0.0).count();
        if outside == 4 {
            return 0.0;
        }
        inside_all &= outside == 0;
    }
    if inside_all {
        return 1.0;
    }
    clipped_area(t, x0, y0)
}

/// Sutherland–Hodgman clipping of the triangle to [x0, x0+1] × [y0, y0+1],
/// on the stack: a triangle cut by four lines has at most seven corners.
fn clipped_area(t: &TexelTriangle, x0: f64, y0: f64) -> f64 {
    let mut polygon = [DVec2::ZERO; 8];
    polygon[..3].copy_from_slice(t);
    let mut len = 3;
    // Keep the side where normal·p + offset ≥ 0 of each edge.
    let planes: [(DVec2, f64); 4] = [
        (DVec2::X, -x0),
        (DVec2::NEG_X, x0 + 1.0),
        (DVec2::Y, -y0),
        (DVec2::NEG_Y, y0 + 1.0),
    ];
    for (normal, offset) in planes {
        let inside = |p: DVec2| normal.dot(p) + offset;
        if polygon[..len].iter().all(|&p| inside(p) >= 0.0) {
            continue; // this side cuts nothing off
        }
        let mut clipped = [DVec2::ZERO; 8];
        let mut count = 0;
        for i in 0..len {
            let (a, b) = (polygon[i], polygon[(i + 1) % len]);
            let (da, db) = (inside(a), inside(b));
            if da >= 0.0 && count < 8 {
                clipped[count] = a;
                count += 1;
            }
            if (da >= 0.0) != (db >= 0.0) && count < 8 {
                clipped[count] = a + (b - a) * (da / (da - db));
                count += 1;
            }
        }
        polygon = clipped;
        len = count;
        if len < 3 {
            return 0.0;
        }
    }
    let twice: f64 = (0..len)
        .map(|i| polygon[i].perp_dot(polygon[(i + 1) % len]))
        .sum();
    (0.5 * twice).abs().min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coverage_of_a_half_texel_and_of_a_big_triangle() {
        let half = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.0, 1.0),
        ];
        assert!((coverage(&half, 0, 0) - 0.5).abs() < 1e-12);
        let big = [
            DVec2::new(-5.0, -5.0),
            DVec2::new(10.0, -5.0),
            DVec2::new(-5.0, 10.0),
        ];
        assert!((coverage(&big, 1, 1) - 1.0).abs() < 1e-12);
        // Summed over the grid the coverage is the triangle's area.
        let t = [
            DVec2::new(0.3, 0.2),
            DVec2::new(7.7, 1.1),
            DVec2::new(2.5, 6.4),
        ];
        let (x0, x1, y0, y1) = texel_bounds(&t, 16);
        let total: f64 = (y0..y1)
            .flat_map(|y| (x0..x1).map(move |x| (x, y)))
            .map(|(x, y)| coverage(&t, x, y))
            .sum();
        assert!((total - 0.5 * signed_area2(&t).abs()).abs() < 1e-9);
    }
}
