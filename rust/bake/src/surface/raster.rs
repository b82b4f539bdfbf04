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

/// [`coverage`] from precomputed edge functions.
pub fn coverage_with(edges: &EdgeFunctions, x: u32, y: u32) -> f64 {
    moments_with(edges, x, y).area
}

/// The part of a texel a triangle covers, by its moments in texel-local
/// coordinates (origin at the texel's corner, one texel = 1): area ∫dA,
/// first moments ∫(x, y) dA and second moments ∫(x², xy, y²) dA. They add
/// over the triangles covering a texel, and give the centroid and the
/// spread of the surface the texel stands for.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TexelMoments {
    /// Covered area, texel units (0..=1).
    pub area: f64,
    /// ∫x dA and ∫y dA.
    pub first: DVec2,
    /// ∫x² dA, ∫xy dA and ∫y² dA.
    pub second: [f64; 3],
}

impl TexelMoments {
    /// The whole texel.
    pub const WHOLE: TexelMoments = TexelMoments {
        area: 1.0,
        first: DVec2::new(0.5, 0.5),
        second: [1.0 / 3.0, 0.25, 1.0 / 3.0],
    };

    /// Adds `other` (another triangle's share of the same texel).
    pub fn add(&mut self, other: &TexelMoments) {
        self.area += other.area;
        self.first += other.first;
        for k in 0..3 {
            self.second[k] += other.second[k];
        }
    }

    /// The centroid of the covered part, texel-local; the texel's centre
    /// when nothing is covered.
    pub fn centroid(&self) -> DVec2 {
        if self.area > 0.0 {
            self.first / self.area
        } else {
            DVec2::splat(0.5)
        }
    }

    /// The edges (texel units) of the parallelogram centred on the
    /// centroid with the covered part's area and the shape of its second
    /// moments about the centroid: the columns of S = √(12 C), C the
    /// covariance, whose parallelogram has covariance S Sᵀ/12 = C; then
    /// scaled to the covered area. The whole texel gives (1, 0) and (0, 1),
    /// a strip along an edge a rectangle of its width and length. S is the
    /// symmetric square root, which changes continuously with C (a basis
    /// of eigenvectors would turn freely where C is nearly round, and with
    /// it the samples a neighbour's light is spread over).
    pub fn parallelogram(&self) -> [DVec2; 2] {
        if self.area >= 1.0 - 1e-9 {
            return [DVec2::X, DVec2::Y];
        }
        if self.area <= 0.0 {
            return [DVec2::ZERO; 2];
        }
        let c = self.centroid();
        let xx = (self.second[0] / self.area - c.x * c.x).max(0.0);
        let xy = self.second[1] / self.area - c.x * c.y;
        let yy = (self.second[2] / self.area - c.y * c.y).max(0.0);
        // √ of the 2 × 2 symmetric positive semi-definite 12 C:
        // (M + √det M · I) / √(tr M + 2 √det M).
        let (a, b, d) = (12.0 * xx, 12.0 * xy, 12.0 * yy);
        let root_det = (a * d - b * b).max(0.0).sqrt();
        let norm = (a + d + 2.0 * root_det).sqrt();
        if norm <= 0.0 {
            return [DVec2::ZERO; 2];
        }
        let u = DVec2::new(a + root_det, b) / norm;
        let v = DVec2::new(b, d + root_det) / norm;
        let spanned = u.perp_dot(v).abs();
        if spanned <= 1e-12 {
            return [DVec2::ZERO; 2];
        }
        let scale = (self.area / spanned).sqrt();
        [u * scale, v * scale]
    }
}

/// [`TexelMoments`] of the part of texel (x, y) inside the triangle of
/// `edges`. Texels wholly inside or outside are decided from their
/// corners; for the rest the texel square is clipped by the edges that
/// cross it (usually one), which is exact: outside those edges nothing of
/// the square is lost.
pub fn moments_with(edges: &EdgeFunctions, x: u32, y: u32) -> TexelMoments {
    let (x0, y0) = (x as f64, y as f64);
    let mut polygon = [DVec2::ZERO; 8];
    polygon[..4].copy_from_slice(&[
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(0.0, 1.0),
    ]);
    let mut len = 4;
    let mut clipped_any = false;
    for &(a, b, c) in edges {
        let base = a * x0 + b * y0 + c;
        let corners = [base, base + a, base + a + b, base + b];
        let outside = corners.iter().filter(|&&e| e < 0.0).count();
        if outside == 4 {
            return TexelMoments::default();
        }
        if outside == 0 {
            continue;
        }
        clipped_any = true;
        let side = |p: DVec2| a * p.x + b * p.y + base;
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
            return TexelMoments::default();
        }
    }
    if !clipped_any {
        return TexelMoments::WHOLE;
    }
    polygon_moments(&polygon[..len])
}

/// Area, first and second moments of a simple polygon (either winding),
/// by the shoelace sums over its edges.
fn polygon_moments(polygon: &[DVec2]) -> TexelMoments {
    let mut m = TexelMoments::default();
    let mut second = [0.0f64; 3];
    for k in 0..polygon.len() {
        let (p, q) = (polygon[k], polygon[(k + 1) % polygon.len()]);
        let cross = p.perp_dot(q);
        m.area += cross;
        m.first += (p + q) * cross;
        second[0] += cross * (p.x * p.x + p.x * q.x + q.x * q.x);
        second[1] += cross * (p.x * q.y + 2.0 * p.x * p.y + 2.0 * q.x * q.y + q.x * p.y);
        second[2] += cross * (p.y * p.y + p.y * q.y + q.y * q.y);
    }
    let sign = m.area.signum();
    m.area = (0.5 * m.area).abs().min(1.0);
    m.first *= sign / 6.0;
    m.second = [
        second[0] * sign / 12.0,
        second[1] * sign / 24.0,
        second[2] * sign / 12.0,
    ];
    m
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

    #[test]
    fn moments_of_a_texel_cut_in_two_add_up_to_the_whole() {
        // The diagonal x + y = 1.3 of texel (2, 3) cuts it into two parts.
        let below = [
            DVec2::new(0.0, 0.0),
            DVec2::new(3.3, 0.0),
            DVec2::new(0.0, 3.3),
        ]
        .map(|p| p + DVec2::new(1.0, 2.0));
        let above = [below[1], DVec2::new(9.0, 9.0), below[2]];
        let (a, b) = (
            moments_with(&edge_functions(&below), 2, 3),
            moments_with(&edge_functions(&above), 2, 3),
        );
        assert!(a.area > 0.1 && b.area > 0.1);
        let mut sum = a;
        sum.add(&b);
        assert!((sum.area - 1.0).abs() < 1e-12);
        assert!((sum.first - TexelMoments::WHOLE.first).length() < 1e-12);
        for k in 0..3 {
            assert!((sum.second[k] - TexelMoments::WHOLE.second[k]).abs() < 1e-12);
        }
        // The polygon sums give the whole texel's moments too.
        let square = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
        let whole = polygon_moments(&square);
        assert!((whole.area - 1.0).abs() < 1e-12);
        assert!((whole.second[1] - 0.25).abs() < 1e-12);
    }

    #[test]
    fn a_strip_along_an_edge_is_a_rectangle_of_its_width_and_length_a_corner_keeps_its_area() {
        // The left 0.3 of texel (0, 0), cut by the line x = 0.3.
        let left = [
            DVec2::new(-1.0, -1.0),
            DVec2::new(0.3, -1.0),
            DVec2::new(0.3, 5.0),
        ];
        let left = [left[0], left[1], left[2], DVec2::new(-1.0, 5.0)];
        let strip = moments_with(&edge_functions(&[left[0], left[1], left[2]]), 0, 0);
        let rest = moments_with(&edge_functions(&[left[0], left[2], left[3]]), 0, 0);
        let mut m = strip;
        m.add(&rest);
        assert!((m.area - 0.3).abs() < 1e-12);
        assert!((m.centroid() - DVec2::new(0.15, 0.5)).length() < 1e-12);
        let [u, v] = m.parallelogram();
        let (long, short) = if u.length() > v.length() {
            (u, v)
        } else {
            (v, u)
        };
        assert!((long.length() - 1.0).abs() < 1e-9, "{long}");
        assert!((short.length() - 0.3).abs() < 1e-9, "{short}");
        assert!(long.x.abs() < 1e-9);
        assert_eq!(TexelMoments::WHOLE.parallelogram(), [DVec2::X, DVec2::Y]);
        // A corner triangle: the parallelogram keeps its area.
        let corner = [DVec2::ZERO, DVec2::X, DVec2::Y].map(|p| p * 0.8);
        let m = moments_with(&edge_functions(&corner), 0, 0);
        let [u, v] = m.parallelogram();
        assert!((u.perp_dot(v).abs() - 0.32).abs() < 1e-9);
    }
}
