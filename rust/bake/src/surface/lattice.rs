//! A lattice of texels: every `step`-th texel along u and along v. A
//! quantity that changes over many texels is found at the lattice alone
//! and carried to the texels between by the bilinear mean of the four
//! lattice texels around each, where all four lie on its surface.

use crate::surface::texels::TexelSurfels;

/// The cosine between two texels' normals above which one lies on the
/// other's surface and carries what the lattice holds to it.
pub const SAME_FACING: f32 = 0.9;

/// True when texel `j` lies on texel `i`'s surface as far as the layout
/// can tell: in its medium and facing its way (a texel beside it in the
/// layout may lie on another chart, across a crease or on another piece).
pub fn on_surface_of(surfels: &TexelSurfels, i: usize, j: usize) -> bool {
    let medium = |s: usize| surfels.piece.get(s).copied();
    medium(j) == medium(i) && surfels.normal[j].dot(surfels.normal[i]) > SAME_FACING
}

/// The texels `step` apart along u and along v of a `resolution`² map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lattice {
    /// Texels between neighbouring lattice texels along u and along v.
    pub step: u32,
    /// Texels per side of the map.
    pub resolution: u32,
}

impl Lattice {
    /// Every `step`-th texel (at least 1: every texel) of `surfels`' map.
    pub fn new(surfels: &TexelSurfels, step: u32) -> Self {
        Lattice {
            step: step.max(1),
            resolution: surfels.resolution.max(1),
        }
    }

    /// True when `texel` (y·N + x) lies on the lattice.
    pub fn holds(&self, texel: u32) -> bool {
        self.place(texel).is_some()
    }

    /// Lattice places per row (and rows).
    fn columns(&self) -> u32 {
        self.resolution.div_ceil(self.step)
    }

    /// How many places the lattice has: one per lattice texel of the map's
    /// square, covered or not.
    pub fn places(&self) -> usize {
        let columns = self.columns() as usize;
        columns * columns
    }

    /// Where `texel` (y·N + x) sits among the lattice's places, row by
    /// row; `None` off the lattice.
    pub fn place(&self, texel: u32) -> Option<usize> {
        let (x, y) = (texel % self.resolution, texel / self.resolution);
        let on = x.is_multiple_of(self.step) && y.is_multiple_of(self.step);
        on.then(|| (y / self.step) as usize * self.columns() as usize + (x / self.step) as usize)
    }

    /// The texel (y·N + x) at lattice place `place`.
    pub fn texel_at(&self, place: usize) -> u32 {
        let columns = self.columns() as usize;
        let (x, y) = ((place % columns) as u32, (place / columns) as u32);
        y * self.step * self.resolution + x * self.step
    }

    /// The surfels of `surfels` on the lattice, in order.
    pub fn surfels(&self, surfels: &TexelSurfels) -> Vec<usize> {
        (0..surfels.len())
            .filter(|&s| self.holds(surfels.texel[s]))
            .collect()
    }

    /// The four lattice texels around surfel `i` with their bilinear
    /// weights, each as its surfel where it is covered; `None` past the
    /// map's last lattice row or column. A surfel on the lattice is its own
    /// four corners, and one on a lattice line needs none past it.
    pub fn around(&self, surfels: &TexelSurfels, i: usize) -> Option<[(Option<usize>, f32); 4]> {
        let n = self.resolution;
        let t = surfels.texel[i];
        let (x, y) = (t % n, t / n);
        let (x0, y0) = (x - x % self.step, y - y % self.step);
        let x1 = if x == x0 { x0 } else { x0 + self.step };
        let y1 = if y == y0 { y0 } else { y0 + self.step };
        if x1 >= n || y1 >= n {
            return None;
        }
        let corner = |cx: u32, cy: u32| -> Option<usize> {
            let j = *surfels.index.get((cy * n + cx) as usize)? as usize;
            (j < surfels.len()).then_some(j)
        };
        let (fx, fy) = (
            (x - x0) as f32 / self.step as f32,
            (y - y0) as f32 / self.step as f32,
        );
        Some([
            (corner(x0, y0), (1.0 - fx) * (1.0 - fy)),
            (corner(x1, y0), fx * (1.0 - fy)),
            (corner(x0, y1), (1.0 - fx) * fy),
            (corner(x1, y1), fx * fy),
        ])
    }

    /// The four lattice surfels around surfel `i` with their bilinear
    /// weights ([`Lattice::around`]), where each is covered and `alike(j)`
    /// says it lies on `i`'s surface; `None` otherwise (a chart's edge, a
    /// crease, another medium), where the caller finds `i`'s own value.
    pub fn corners(
        &self,
        surfels: &TexelSurfels,
        i: usize,
        alike: impl Fn(usize) -> bool,
    ) -> Option<[(usize, f32); 4]> {
        let around = self.around(surfels, i)?;
        let mut corners = [(0, 0.0); 4];
        for (corner, (j, w)) in corners.iter_mut().zip(around) {
            let j = j.filter(|&j| alike(j))?;
            *corner = (j, w);
        }
        Some(corners)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::texels::{EMPTY, unit_plane as plane};

    #[test]
    fn a_linear_field_is_carried_exactly_and_the_lattice_is_its_own() {
        let surfels = plane(9);
        let lattice = Lattice::new(&surfels, 4);
        let field = |s: usize| {
            let p = surfels.position[s];
            2.0 * p.x - 3.0 * p.y + 1.0
        };
        for i in 0..surfels.len() {
            let corners = lattice.corners(&surfels, i, |_| true).unwrap();
            let carried: f32 = corners.iter().map(|&(j, w)| w * field(j)).sum();
            assert!((carried - field(i)).abs() < 1e-4, "{i}: {carried}");
            if lattice.holds(surfels.texel[i]) {
                assert!(corners.iter().all(|&(j, w)| j == i || w == 0.0));
            }
        }
        assert_eq!(lattice.surfels(&surfels).len(), 9);
        // Each lattice texel has a place, and the place leads back to it.
        assert_eq!(lattice.places(), 9);
        for t in 0..81 {
            match lattice.place(t) {
                Some(place) => assert_eq!(lattice.texel_at(place), t),
                None => assert!(!lattice.holds(t)),
            }
        }
    }

    #[test]
    fn no_corners_past_the_map_nor_where_one_is_not_alike_or_empty() {
        let mut surfels = plane(10);
        let lattice = Lattice::new(&surfels, 4);
        // Texel (9, 1) lies past the last lattice column (8).
        assert!(lattice.corners(&surfels, 19, |_| true).is_none());
        assert!(lattice.corners(&surfels, 11, |j| j != 4).is_none());
        surfels.index[4] = EMPTY;
        assert!(lattice.corners(&surfels, 11, |_| true).is_none());
        assert!(lattice.corners(&surfels, 51, |_| true).is_some());
    }
}
