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

/// The three edges of a triangle as functions e(p) = a·x + b·y + c that
/// are non-negative inside, for either winding.
pub type EdgeFunctions = [(f64, f64, f64); 3];

/// The edge functions of `t`.
pub fn edge_functions(t: &TexelTriangle) -> EdgeFunctions {
    let orientation = signed_area2(t).signum();
    std::array::from_fn(|i| {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        // (b − a) × (p − a) = (b.x − a.x)(p.y − a.y) − (b.y − a.y)(p.x − a.x)
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        (
            -dy * orientation,
            dx * orientation,
            (dy * a.x - dx * a.y) * orientation,
        )
    })
}

/// The area of triangle `t` inside texel (x, y), in texel units (0..=1).
pub fn coverage(t: &TexelTriangle, x: u32, y: u32) -> f64 {
    coverage_with(&edge_functions(t), x, y)
}

/// [`coverage`] from precomputed edge functions. Texels wholly inside or
/// outside are decided from their corners; for the rest the texel square
/// is clipped by the edges that cross it (usually one), which is exact:
/// outside those edges nothing of the square is lost.
pub fn coverage_with(edges: &EdgeFunctions, x: u32, y: u32) -> f64 {
    let (x0, y0) = (x as f64, y as f64);
    let mut polygon = [DVec2::ZERO; 8];
    polygon[..4].copy_from_slice(&[
        DVec2::new(x0, y0),
        DVec2::new(x0 + 1.0, y0),
        DVec2::new(x0 + 1.0, y0 + 1.0),
        DVec2::new(x0, y0 + 1.0),
    ]);
    let mut len = 4;
    let mut clipped_any = false;
    for &(a, b, c) in edges {
        let base = a * x0 + b * y0 + c;
        let corners = [base, base + a, base + a + b, base + b];
        let outside = corners.iter().filter(|&&e| e < 0.0).count();
        if outside == 4 {
            return 0.0;
        }
        if outside == 0 {
            continue;
        }
        clipped_any = true;
        let side = |p: DVec2| a * p.x + b * p.y + c;
        // Keep the part of the polygon on the inner side of this edge.
        let mut clipped = [DVec2::ZERO; 8];
        let mut count = 0;
        for k in 0..len {
            let (p, q) = (polygon[k], polygon[(k + 1) % len]);
            let (dp, dq) = (side(p), side(q));
            if dp >= 0.0 && count < 8 {
                clipped[count] = p;
                count += 1;
            }
            if (dp >= 0.0) != (dq >= 0.0) && count < 8 {
                clipped[count] = p + (q - p) * (dp / (dp - dq));
                count += 1;
            }
        }
        polygon = clipped;
        len = count;
        if len < 3 {
            return 0.0;
        }
    }
    if !clipped_any {
        return 1.0;
    }
    let twice: f64 = (0..len)
        .map(|k| polygon[k].perp_dot(polygon[(k + 1) % len]))
        .sum();
    (0.5 * twice).abs().min(1.0)
}

/// True when the point is inside or on the triangle of `edges`.
pub fn contains(edges: &EdgeFunctions, p: DVec2) -> bool {
    edges.iter().all(|&(a, b, c)| a * p.x + b * p.y + c >= 0.0)
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
