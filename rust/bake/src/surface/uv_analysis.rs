//! Is a mesh's UV layout fit to bake into? Missing, outside the unit square,
//! overlapping, flipped, zero-area or extremely stretched triangles.

use crate::mesh::Mesh;
use crate::surface::raster::{barycentric, signed_area2, texel_bounds};
use crate::surface::texels::uv_jacobian;
use glam::{DVec2, Vec2};

/// Above this ratio of a triangle's largest to smallest stretch, or of its
/// surface-per-UV density to the mesh's, a triangle counts as stretched.
const STRETCH_LIMIT: f64 = 10.0;

/// What the analysis found, in triangle counts.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct UvReport {
    /// Triangles analysed.
    pub triangles: usize,
    /// The mesh has no UVs at all.
    pub missing: bool,
    /// Triangles with a corner outside [0, 1]².
    pub outside: usize,
    /// Triangles with (next to) no UV area though their surface is worth at
    /// least a thousandth of a texel.
    pub zero_area: usize,
    /// Triangles wound against the majority (mirrored islands).
    pub flipped: usize,
    /// Triangles stretched beyond 10:1, in shape or against the mesh's density.
    pub stretched: usize,
    /// Triangles sharing texel centres with another at the analysed resolution.
    pub overlapping: usize,
}

impl UvReport {
    /// True when every surface point gets a texel of its own: UVs present,
    /// inside the unit square, with area, and without overlaps. Flipped
    /// and stretched triangles are reported but bake correctly.
    pub fn usable(&self) -> bool {
        !self.missing && self.outside == 0 && self.zero_area == 0 && self.overlapping == 0
    }

    /// One line for people.
    pub fn verdict(&self) -> String {
        if self.missing {
            return "no UVs: the mesh will be unwrapped".into();
        }
        let state = if self.usable() {
            "usable"
        } else {
            "unusable, the mesh will be unwrapped"
        };
        match self.problems() {
            None => format!("usable: {} triangles, no problems", self.triangles),
            Some(problems) => format!("{state}: {problems}"),
        }
    }

    /// The problems found, as "4 overlapping, 2 flipped of 3936
    /// triangles"; `None` when there are none.
    pub fn problems(&self) -> Option<String> {
        let mut problems = Vec::new();
        for (count, what) in [
            (self.outside, "outside [0,1]"),
            (self.zero_area, "with no UV area"),
            (self.overlapping, "overlapping"),
            (self.flipped, "flipped"),
            (self.stretched, "stretched beyond 10:1"),
        ] {
            if count > 0 {
                problems.push(format!("{count} {what}"));
            }
        }
        (!problems.is_empty())
            .then(|| format!("{} of {} triangles", problems.join(", "), self.triangles))
    }
}

/// Analyses the UVs of `mesh` (`uvs` overrides the mesh's own), checking
/// overlaps on a `resolution`² grid.
pub fn analyse_uvs(mesh: &Mesh, uvs: Option<&[Vec2]>, resolution: u32) -> UvReport {
    let mut report = UvReport {
        triangles: mesh.triangles.len(),
        ..Default::default()
    };
    let Some(uvs) = uvs.or(mesh.uvs.as_deref()) else {
        report.missing = true;
        return report;
    };
    let n = resolution.max(1);
    let corners = |t: &[u32; 3]| t.map(|i| uvs[i as usize].as_dvec2());
    let signed: Vec<f64> = mesh
        .triangles
        .iter()
        .map(|t| 0.5 * signed_area2(&corners(t)))
        .collect();
    let positive = signed.iter().filter(|&&a| a > 0.0).count();
    let majority = if 2 * positive >= signed.len() {
        1.0
    } else {
        -1.0
    };
    let total_uv: f64 = signed.iter().map(|a| a.abs()).sum();
    let mean_density = mesh.area() / total_uv.max(1e-300);

    for (t, tri) in mesh.triangles.iter().enumerate() {
        let c = corners(tri);
        if c.iter()
            .any(|p| p.x < 0.0 || p.y < 0.0 || p.x > 1.0 || p.y > 1.0)
        {
            report.outside += 1;
        }
        let area_3d = mesh.triangle_area(t);
        // The UV area the mesh's average density would give this triangle;
        // lost surface only matters when it is worth a thousandth of a texel.
        let expected_uv = area_3d / mean_density;
        if signed[t].abs() < 1e-6 * expected_uv {
            if expected_uv * (n as f64).powi(2) > 1e-3 {
                report.zero_area += 1;
            }
            continue;
        }
        if signed[t] * majority < 0.0 {
            report.flipped += 1;
        }
        let density = area_3d / signed[t].abs() / mean_density;
        if anisotropy(mesh, uvs, t) > STRETCH_LIMIT
            || !(1.0 / STRETCH_LIMIT..=STRETCH_LIMIT).contains(&density)
        {
            report.stretched += 1;
        }
    }
    report.overlapping = count_overlaps(mesh, uvs, n);
    report
}

/// Ratio of the largest to the smallest singular value of ∂P/∂(u, v).
fn anisotropy(mesh: &Mesh, uvs: &[Vec2], t: usize) -> f64 {
    let Some((du, dv)) = uv_jacobian(mesh, uvs, t) else {
        return f64::INFINITY;
    };
    let (a, b, c) = (du.length_squared(), du.dot(dv), dv.length_squared());
    let root = ((a - c).powi(2) + 4.0 * b * b).sqrt();
    let (large, small) = (0.5 * (a + c + root), 0.5 * (a + c - root));
    if small > 0.0 {
        (large / small).sqrt()
    } else {
        f64::INFINITY
    }
}

/// Triangles whose interior holds a texel centre another triangle's
/// interior also holds. Centres on shared edges do not count.
fn count_overlaps(mesh: &Mesh, uvs: &[Vec2], n: u32) -> usize {
    const NOBODY: u32 = u32::MAX;
    let mut owner = vec![NOBODY; (n as usize) * (n as usize)];
    let mut overlapping = vec![false; mesh.triangles.len()];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let c = tri.map(|i| uvs[i as usize].as_dvec2() * n as f64);
        let (x0, x1, y0, y1) = texel_bounds(&c, n);
        for y in y0..y1 {
            for x in x0..x1 {
                let centre = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                let inside = barycentric(centre, &c).is_some_and(|w| w.iter().all(|&w| w > 1e-9));
                if !inside {
                    continue;
                }
                let slot = &mut owner[(y * n + x) as usize];
                if *slot == NOBODY {
                    *slot = t as u32;
                } else if *slot != t as u32 {
                    overlapping[t] = true;
                    overlapping[*slot as usize] = true;
                }
            }
        }
    }
    overlapping.iter().filter(|&&o| o).count()
}
