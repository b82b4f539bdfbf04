//! Where an object's texels are: the mesh with the UVs the bake uses and the
//! texels they cover, decided by the plan ([`decide`]) and read by every stage
//! after it.

mod decide;

use crate::mesh::Mesh;
use crate::surface::texels::TexelSurfels;
use glam::Vec2;

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
