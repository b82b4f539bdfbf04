//! The hierarchical integrator of Jensen & Buhler 2002 (Mikkelsen §3.2):
//! an octree over the sources, each node summarising its flux, area,
//! area-weighted normal and irradiance-weighted centre; a target takes a
//! node whole when the node's area seen from it subtends less than ε
//! (A/d² < ε) and the target lies outside the node's box, else opens it.
//! At ε = 0 every node is opened and the sum is exactly `brute`'s over the
//! same sources.

use super::Method;
use super::brute::area_range;
use super::disk_kernel::{DiskKernel, Slot};
use super::integrator::{Integrated, Integrator};
use super::kernel::{Kernel, Separation};
use super::sources::{Sources, Targets};
use crate::control::{Cancelled, Control, parallel_fill};
use crate::error::Error;
use crate::pipeline::Prepared;
use crate::scattering::Scattering;
use crate::surface::turk::point_count;
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Sources per leaf.
const LEAF: usize = 8;

#[derive(Clone, Debug)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    /// Irradiance-weighted centre (area-weighted when unlit).
    centre: Vec3,
    /// Area-weighted mean normal, normalised.
    normal: Vec3,
    area: f32,
    slot: Slot,
    flux: [f32; 3],
    /// Children (first, count) in `nodes`, or sources (first, count) in
    /// the sorted arrays for a leaf.
    first: u32,
    count: u32,
    leaf: bool,
}

/// The tree over sources sorted into its leaf order.
pub struct Octree {
    nodes: Vec<Node>,
    position: Vec<Vec3>,
    normal: Vec<Vec3>,
    slot: Vec<Slot>,
    flux: Vec<[f32; 3]>,
}

impl Octree {
    /// Builds the tree over `sources`, with each sample's and node's place
    /// in `disks`.
    pub fn new(sources: &Sources, disks: &DiskKernel) -> Self {
        let mut order: Vec<u32> = (0..sources.len() as u32).collect();
        let mut tree = Octree {
            nodes: Vec::new(),
            position: Vec::new(),
            normal: Vec::new(),
            slot: Vec::new(),
            flux: Vec::new(),
        };
        if !order.is_empty() {
            tree.nodes.push(placeholder());
            tree.build(0, &mut order, sources, 0);
            for &i in &order {
                let i = i as usize;
                tree.position.push(sources.position[i]);
                tree.normal.push(sources.normal[i]);
                tree.slot.push(disks.slot(sources.area[i]));
                tree.flux
                    .push(sources.irradiance[i].map(|e| e * sources.area[i]));
            }
            for node in &mut tree.nodes {
                node.slot = disks.slot(node.area);
            }
        }
        tree
    }

    /// Fills node `at` from the sources in `items` (a slice of the order
    /// starting at `offset`), splitting at the box centre.
    fn build(&mut self, at: usize, items: &mut [u32], sources: &Sources, offset: usize) {
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let mut area = 0.0f64;
        let mut flux = [0.0f64; 3];
        let mut weighted = glam::DVec3::ZERO;
        let mut by_area = glam::DVec3::ZERO;
        let mut light = 0.0f64;
        let mut normal = Vec3::ZERO;
        for &i in items.iter() {
            let i = i as usize;
            let p = sources.position[i];
            lo = lo.min(p);
            hi = hi.max(p);
            let a = sources.area[i] as f64;
            let e = sources.irradiance[i];
            area += a;
            for c in 0..3 {
                flux[c] += e[c] as f64 * a;
            }
            let luminance = (0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2]).max(0.0) as f64 * a;
            weighted += p.as_dvec3() * luminance;
            light += luminance;
            by_area += p.as_dvec3() * a;
            normal += sources.normal[i] * a as f32;
        }
        let centre = if light > 0.0 {
            (weighted / light).as_vec3()
        } else if area > 0.0 {
            (by_area / area).as_vec3()
        } else {
            0.5 * (lo + hi)
        };
        self.nodes[at] = Node {
            lo,
            hi,
            centre,
            normal: normal.normalize_or_zero(),
            area: area as f32,
            slot: Slot::default(),
            flux: flux.map(|f| f as f32),
            first: offset as u32,
            count: items.len() as u32,
            leaf: true,
        };
        if items.len() <= LEAF || (hi - lo).max_element() <= 0.0 {
            return;
        }
        let mid = 0.5 * (lo + hi);
        let octant = |i: &u32| -> usize {
            let p = sources.position[*i as usize];
            (p.x > mid.x) as usize | ((p.y > mid.y) as usize) << 1 | ((p.z > mid.z) as usize) << 2
        };
        items.sort_unstable_by_key(octant);
        let mut bounds = [0usize; 9];
        for i in items.iter() {
            bounds[octant(i) + 1] += 1;
        }
        for k in 0..8 {
            bounds[k + 1] += bounds[k];
        }
        let children: Vec<(usize, usize)> = (0..8)
            .filter(|&k| bounds[k + 1] > bounds[k])
            .map(|k| (bounds[k], bounds[k + 1]))
            .collect();
        let first_child = self.nodes.len();
        self.nodes[at].first = first_child as u32;
        self.nodes[at].count = children.len() as u32;
        self.nodes[at].leaf = false;
        for _ in &children {
            self.nodes.push(placeholder());
        }
        for (k, (a, b)) in children.into_iter().enumerate() {
            self.build(first_child + k, &mut items[a..b], sources, offset + a);
        }
    }

    /// Σ over sources of P·flux at `p` with normal `n`, taking nodes whole
    /// below the solid-angle threshold `epsilon`.
    pub fn gather(&self, disks: &DiskKernel, p: Vec3, n: Vec3, epsilon: f32) -> [f64; 3] {
        let kernel = disks.kernel();
        let mut sum = [0.0f64; 3];
        if self.nodes.is_empty() {
            return sum;
        }
        let reach = kernel.d_max;
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        stack.push(0);
        while let Some(at) = stack.pop() {
            let node = &self.nodes[at as usize];
            // Skip nodes wholly beyond the reach.
            let outside = (node.lo - p).max(p - node.hi).max(Vec3::ZERO);
            if outside.length_squared() > reach * reach {
                continue;
            }
            let separation = |entry: Vec3, normal: Vec3, d2: f32| {
                Separation::new(entry, normal, p, n, d2, kernel.transmits())
            };
            if !node.leaf {
                let d2 = (node.centre - p).length_squared();
                let inside = outside == Vec3::ZERO;
                if !inside && node.area < epsilon * d2 {
                    let w = disks.weight(separation(node.centre, node.normal, d2), node.slot);
                    for c in 0..3 {
                        sum[c] += (w[c] * node.flux[c]) as f64;
                    }
                } else {
                    stack.extend(node.first..node.first + node.count);
                }
                continue;
            }
            for j in node.first as usize..(node.first + node.count) as usize {
                let d2 = (self.position[j] - p).length_squared();
                if d2 > reach * reach {
                    continue;
                }
                let w = disks.weight(
                    separation(self.position[j], self.normal[j], d2),
                    self.slot[j],
                );
                let f = self.flux[j];
                for c in 0..3 {
                    sum[c] += (w[c] * f[c]) as f64;
                }
            }
        }
        sum
    }
}

fn placeholder() -> Node {
    Node {
        lo: Vec3::ZERO,
        hi: Vec3::ZERO,
        centre: Vec3::ZERO,
        normal: Vec3::ZERO,
        area: 0.0,
        slot: Slot::default(),
        flux: [0.0; 3],
        first: 0,
        count: 0,
        leaf: true,
    }
}

/// Radiant exitance (W/m²) at each target through the octree with
/// solid-angle threshold `epsilon` (steradians; 0 = exact).
pub fn integrate(
    kernel: &Kernel,
    sources: &Sources,
    targets: Targets,
    epsilon: f32,
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let (lo, hi) = area_range(&sources.area);
    let disks = DiskKernel::new(kernel, lo, hi);
    let tree = Octree::new(sources, &disks);
    let mut out = vec![[0.0f32; 3]; targets.position.len()];
    parallel_fill(&mut out, 256, control, |i| {
        tree.gather(
            &disks,
            targets.position[i],
            targets.normal[i],
            epsilon.max(0.0),
        )
        .map(|v| v as f32)
    })?;
    Ok(out)
}

/// The octree integrator over relaxed Turk points, each carrying the
/// texels of its Voronoi cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OctreeIntegrator {
    /// Solid angle (sr) below which a node is taken whole; 0 is exact.
    pub epsilon: f32,
    /// Turk points per disk of one mean free path.
    pub points_per_disk: f64,
    /// Seed of the point placement.
    pub seed: u64,
}

impl Default for OctreeIntegrator {
    fn default() -> Self {
        OctreeIntegrator {
            epsilon: 0.05,
            points_per_disk: 4.0,
            seed: 1,
        }
    }
}

impl OctreeIntegrator {
    /// Refuses settings it cannot run with.
    pub fn validate(&self) -> Result<(), Error> {
        if !(self.epsilon.is_finite() && self.epsilon >= 0.0) {
            return Err(Error::field(
                "octree.epsilon",
                format!("{} must be a non-negative solid angle", self.epsilon),
            ));
        }
        if !(self.points_per_disk.is_finite() && self.points_per_disk > 0.0) {
            return Err(Error::field(
                "octree.points_per_disk",
                format!("{} must be positive", self.points_per_disk),
            ));
        }
        Ok(())
    }

    /// Points for a surface of `area_mm2` under a material whose finest
    /// mean free path is `mean_free_path_mm`: `points_per_disk` per disk
    /// of it, but never more than the `texels` that carry the light (a
    /// point finer than a texel adds nothing).
    pub fn point_count(&self, area_mm2: f64, mean_free_path_mm: f64, texels: usize) -> usize {
        point_count(area_mm2, mean_free_path_mm, self.points_per_disk).min(texels.max(1))
    }
}

impl Integrator for OctreeIntegrator {
    fn method(&self) -> Method {
        Method::Octree
    }

    fn integrate(
        &self,
        prepared: &Prepared,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Integrated, Error> {
        let count = self.point_count(
            prepared.mesh.area(),
            scattering.material.finest_mean_free_path_mm(),
            prepared.surfels.len(),
        );
        let sources = prepared.point_sources(count, self.seed, control)?;
        let exitance = integrate(
            &scattering.kernel,
            &sources,
            prepared.targets(),
            self.epsilon,
            control,
        )?;
        Ok(Integrated {
            exitance,
            sources: sources.len(),
        })
    }
}
