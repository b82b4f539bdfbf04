//! Where an object's texels are: the mesh with the UVs the bake uses and the
//! texels they cover, decided by the plan ([`decide`]) and read by every stage
//! after it.

mod decide;

use crate::mesh::Mesh;
use crate::surface::texels::{TexelSurfels, uv_jacobian};
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::OnceLock;

/// Where an object's texels are: the mesh with the UVs the bake uses and
/// the texels they cover. Made by the plan, shared by every stage after.
#[derive(Clone, Debug)]
pub struct Layout {
    /// The mesh with the UVs the bake uses.
    pub mesh: Mesh,
    /// Those UVs.
    pub uvs: Vec<Vec2>,
    /// True when the UVs came from unwrapping.
    pub unwrapped: bool,
    /// For an unwrapped mesh, the scene mesh's vertex each vertex copies;
    /// empty otherwise.
    pub source_vertex: Vec<u32>,
    /// The texels.
    pub surfels: TexelSurfels,
    /// The base colour per surfel relative to the nominal colour the
    /// profile is built for, C/m (crate::colour); empty: the same colour
    /// everywhere. Set by the plan.
    pub relative_colour: Vec<[f32; 3]>,
    /// Each texel's parallelogram on the surface ([`Layout::texel_footprints`]),
    /// found on first use.
    pub footprints: OnceLock<Vec<[Vec3; 2]>>,
}

/// The layout's verdict on an object's own UVs, and what it did.
#[derive(Clone, Debug, PartialEq)]
pub struct UvDecision {
    /// The UV analysis in words.
    pub verdict: String,
    /// Whether the object is unwrapped.
    pub unwrap: bool,
    /// Why (or why not).
    pub reason: String,
    /// What is wrong with UVs kept although they overlap or stretch.
    pub warning: Option<String>,
}

impl Layout {
    /// Each texel's covered parallelogram, from texel units onto its
    /// triangle's plane, scaled to the area it stands for (which adds the
    /// shares of every triangle in the texel, at their own scale): a
    /// texel's own light then returns exactly R_total where the profile is
    /// sharper than the texel, neither more nor less. Edges in mm; zero
    /// for a texel on a degenerate triangle. Found once, shared by every
    /// light's sources.
    pub fn texel_footprints(&self) -> &[[Vec3; 2]] {
        self.footprints.get_or_init(|| {
            let surfels = &self.surfels;
            let n = surfels.resolution as f32;
            (0..surfels.len())
                .into_par_iter()
                .map(|i| {
                    let (t, extent, area) =
                        (surfels.triangle[i], surfels.extent[i], surfels.area[i]);
                    let Some((du, dv)) = uv_jacobian(&self.mesh, &self.uvs, t as usize) else {
                        return [Vec3::ZERO; 2];
                    };
                    let (du, dv) = (du.as_vec3() / n, dv.as_vec3() / n);
                    let edges = extent.map(|e| du * e.x + dv * e.y);
                    let spanned = edges[0].cross(edges[1]).length();
                    if spanned > 0.0 && area > 0.0 {
                        edges.map(|e| e * (area / spanned).sqrt())
                    } else {
                        [Vec3::ZERO; 2]
                    }
                })
                .collect()
        })
    }

    /// The centre of surfel `s`'s texel in UV space.
    pub(crate) fn texel_uv(&self, s: usize) -> Vec2 {
        let n = self.surfels.resolution;
        let t = self.surfels.texel[s];
        Vec2::new(
            ((t % n) as f32 + 0.5) / n as f32,
            ((t / n) as f32 + 0.5) / n as f32,
        )
    }
}
