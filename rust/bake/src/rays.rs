//! Rays against a whole scene: shadow tests and every hit along a probe,
//! through a compressed wide BVH from the `obvhs` crate.

use crate::mesh::Mesh;
use glam::{Vec2, Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::Ray;
use obvhs::triangle::Triangle;
use std::time::Duration;

/// A hit along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Which mesh (index into the meshes the scene was built from).
    pub mesh: u32,
    /// The triangle within that mesh.
    pub triangle: u32,
    /// Distance along the (unit) ray, mm.
    pub t: f32,
    /// Barycentric weights of vertices 1 and 2 (vertex 0 has 1 − u − v).
    pub uv: Vec2,
}

/// Triangles of several meshes in one BVH.
pub struct RayScene {
    bvh: CwBvh,
    triangles: Vec<Triangle>,
    /// For each scene triangle, (mesh, triangle within the mesh).
    owner: Vec<(u32, u32)>,
    /// A length small against the scene but large against float rounding
    /// at its scale, mm: how far rays start off their surface.
    epsilon: f32,
}

impl RayScene {
    /// Builds the BVH over every triangle of `meshes`.
    pub fn new(meshes: &[&Mesh]) -> Self {
        let mut triangles = Vec::new();
        let mut owner = Vec::new();
        let mut extent = 0.0f32;
        for (m, mesh) in meshes.iter().enumerate() {
            for (t, tri) in mesh.triangles.iter().enumerate() {
                let [a, b, c] = tri.map(|i| Vec3A::from(mesh.positions[i as usize]));
                extent = extent.max(a.abs().max_element());
                triangles.push(Triangle {
                    v0: a,
                    v1: b,
                    v2: c,
                });
                owner.push((m as u32, t as u32));
            }
        }
        let bvh = build_cwbvh_from_tris(
            &triangles,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        // float32 positions carry ~1e-7 relative error; stay well above it.
        let epsilon = (extent * 2e-6).max(1e-6);
        RayScene {
            bvh,
            triangles,
            owner,
            epsilon,
        }
    }

    /// The offset rays leave a surface by, mm.
    pub fn epsilon(&self) -> f32 {
        self.epsilon
    }

    /// True when something blocks the segment from `origin` along unit
    /// `direction` before `distance` (mm). The triangle `skip` (scene index
    /// from [`RayScene::scene_triangle`], or `u32::MAX`) never blocks: the
    /// ray leaves from it, and on a curved surface its own plane would
    /// shadow a point lit past the shading normal.
    pub fn occluded(&self, origin: Vec3, direction: Vec3, distance: f32, skip: u32) -> bool {
        if self.triangles.is_empty() || distance <= self.epsilon {
            return false;
        }
        let ray = Ray::new(
            Vec3A::from(origin),
            positive_zeros(direction),
            self.epsilon,
            distance - self.epsilon,
        );
        !self.bvh.ray_traverse_miss(ray, |ray, id| {
            let scene_triangle = self.bvh.primitive_indices[id];
            if scene_triangle == skip {
                return f32::INFINITY;
            }
            self.triangles[scene_triangle as usize].intersect(ray)
        })
    }

    /// Calls `visit` for every triangle the segment from `origin` along unit
    /// `direction` crosses between `t_min` and `t_max` (mm), in no order.
    pub fn for_each_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
        mut visit: impl FnMut(Hit),
    ) {
        if self.triangles.is_empty() || t_max <= t_min {
            return;
        }
        let ray = Ray::new(Vec3A::from(origin), positive_zeros(direction), t_min, t_max);
        self.bvh.ray_traverse_anyhit(ray, |ray, id| {
            let scene_triangle = self.bvh.primitive_indices[id] as usize;
            let triangle = &self.triangles[scene_triangle];
            let t = triangle.intersect(ray);
            if t >= ray.tmin && t <= ray.tmax {
                let (mesh, local) = self.owner[scene_triangle];
                visit(Hit {
                    mesh,
                    triangle: local,
                    t,
                    uv: barycentric_at(triangle, Vec3::from(ray.origin + ray.direction * t)),
                });
            }
        });
    }

    /// The first triangle the segment from `origin` along unit `direction`
    /// crosses between `t_min` and `t_max` (mm; `t_max` may be infinite),
    /// or `None`. The triangle `skip` (scene index, or `u32::MAX`) is
    /// never hit: a ray leaving a flat triangle cannot meet it again, and
    /// skipping it keeps rounding from returning the start point.
    pub fn closest_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
        skip: u32,
    ) -> Option<Hit> {
        if self.triangles.is_empty() || t_max.is_nan() || t_max <= t_min {
            return None;
        }
        let ray = Ray::new(Vec3A::from(origin), positive_zeros(direction), t_min, t_max);
        let mut hit = obvhs::ray::RayHit::none();
        let found = self.bvh.ray_traverse(ray, &mut hit, |ray, id| {
            let scene_triangle = self.bvh.primitive_indices[id];
            if scene_triangle == skip {
                return f32::INFINITY;
            }
            self.triangles[scene_triangle as usize].intersect(ray)
        });
        if !found || !hit.t.is_finite() {
            return None;
        }
        let scene_triangle = self.bvh.primitive_indices[hit.primitive_id as usize] as usize;
        let triangle = &self.triangles[scene_triangle];
        let (mesh, local) = self.owner[scene_triangle];
        Some(Hit {
            mesh,
            triangle: local,
            t: hit.t,
            uv: barycentric_at(triangle, origin + direction * hit.t),
        })
    }

    /// The scene index of `triangle` of mesh `mesh`, for
    /// [`RayScene::occluded`]'s `skip`.
    pub fn scene_triangle(&self, mesh: u32, triangle: u32) -> u32 {
        // Meshes were appended in order, so their triangles are contiguous.
        let start = self.owner.partition_point(|&(m, _)| m < mesh);
        (start + triangle as usize) as u32
    }
}

/// Barycentric weights (of vertices 1 and 2) of point `p` on `triangle`.
fn barycentric_at(triangle: &Triangle, p: Vec3) -> Vec2 {
    let (a, b, c) = (
        Vec3::from(triangle.v0),
        Vec3::from(triangle.v1),
        Vec3::from(triangle.v2),
    );
    let n = (b - a).cross(c - a);
    let inv = 1.0 / n.length_squared().max(f32::MIN_POSITIVE);
    let u = (p - a).cross(c - a).dot(n) * inv;
    let v = (b - a).cross(p - a).dot(n) * inv;
    Vec2::new(u, v)
}

/// `direction` with −0 components made +0: the BVH's slab test inverts
/// components, and 1/−0 = −∞ sends an axis-parallel ray the wrong way.
fn positive_zeros(direction: Vec3) -> Vec3A {
    Vec3A::from(direction + Vec3::ZERO)
}
