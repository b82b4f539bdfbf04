//! The closed mesh a walk is confined to: its triangles in a BVH of their
//! own (no other object's surface bounds the medium, and light does not
//! cross air to another piece), and what a walk reads where it meets them.

use super::path::{Confinement, Meeting};
use crate::mesh::Mesh;
use crate::rays::{Hit, RayScene};
use glam::{Vec2, Vec3};

/// One object's mesh and the rays against it alone.
pub struct Enclosure<'a> {
    /// The mesh, lengths in mm.
    pub mesh: &'a Mesh,
    /// Its UVs, one per vertex, where the light a walk leaves into is read.
    pub uvs: &'a [Vec2],
    rays: RayScene,
}

impl<'a> Enclosure<'a> {
    /// Builds the BVH over `mesh`'s triangles; `uvs` are the layout's.
    pub fn new(mesh: &'a Mesh, uvs: &'a [Vec2]) -> Self {
        Enclosure {
            mesh,
            uvs,
            rays: RayScene::new(&[mesh]),
        }
    }

    /// The offset a ray leaving a surface starts past, mm.
    pub fn epsilon(&self) -> f32 {
        self.rays.epsilon()
    }

    /// The first surface from `origin` along unit `direction` within
    /// `t_max` mm, ignoring `leaving` (the triangle the ray starts on, or
    /// `None` from inside the medium). A ray from a surface starts
    /// `epsilon` out, so the neighbours of an edge it starts on are not hit
    /// at zero distance; a ray from inside starts at 0, so a walk that
    /// scattered just under the surface cannot step through it.
    pub fn first_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_max: f32,
        leaving: Option<u32>,
    ) -> Option<Hit> {
        let (t_min, skip) = match leaving {
            Some(triangle) => (self.epsilon(), triangle),
            None => (0.0, u32::MAX),
        };
        self.rays.closest_hit(origin, direction, t_min, t_max, skip)
    }

    /// The unit geometric normal of `triangle` by its winding (zero for a
    /// degenerate triangle).
    pub fn facet_normal(&self, triangle: u32) -> Vec3 {
        let [a, b, c] =
            self.mesh.triangles[triangle as usize].map(|v| self.mesh.positions[v as usize]);
        (b - a).cross(c - a).normalize_or_zero()
    }

    /// The texture coordinate of barycentric point `barycentric` (weights
    /// of vertices 1 and 2) on `triangle`.
    pub fn uv_at(&self, triangle: u32, barycentric: Vec2) -> Vec2 {
        let [a, b, c] = self.mesh.triangles[triangle as usize].map(|v| self.uvs[v as usize]);
        a * (1.0 - barycentric.x - barycentric.y) + b * barycentric.x + c * barycentric.y
    }
}

impl Confinement for Enclosure<'_> {
    fn meet(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_max: f32,
        leaving: Option<u32>,
    ) -> Option<Meeting> {
        let hit = self.first_hit(origin, direction, t_max, leaving)?;
        Some(Meeting {
            t: hit.t,
            triangle: hit.triangle,
            barycentric: hit.uv,
            normal: self.facet_normal(hit.triangle),
        })
    }
}
