//! The light an object sends onto itself: what leaves one part of its
//! surface and enters another across air (an eye socket, a fold, the
//! inside of an ear). A path tracer's diffuse bake carries it as indirect
//! light, redder than the light that made it on skin (each bounce is
//! tinted by the albedo again); docs/lights.md measures it against Cycles.
//!
//! Every part is taken to send out what a plane of the material would
//! under its own light: the transmitted irradiance there times the
//! material's reflectance (the profile's total at light's level), the
//! base colour and the exit Fresnel at the normal, as Lambertian radiance.
//! That is the scattered light of the part up to the profile's blur, which
//! the gather across the hemisphere averages out. Cosine-weighted rays
//! from a regular subset of the texels find which texel each direction
//! sees (checked against the face met, as UVs may overlap); the light they
//! gather is spread back to every texel by distance on the surface, and
//! the bounces repeat on the gathered hits, so more bounces cost no more
//! rays. Other objects shade (they block the light like any occluder) but
//! send nothing.

use super::entry::EntryTransmittance;
use super::sequence::{cosine_hemisphere, hammersley, rotation};
use crate::control::{Cancelled, Control, parallel_fill};
use crate::layout::Layout;
use crate::rays::RayScene;
use crate::surface::frame::own_frame;
use crate::surface::gathering::{Spread, gathering_texels, stride};
use crate::surface::texels::EMPTY;
use glam::Vec3;
use rayon::prelude::*;

/// Bounces of the light an object sends onto itself a bake carries by
/// default: each brings at most the albedo times the share of the sky the
/// object fills of the one before, so a fourth adds little.
pub const DEFAULT_BOUNCES: u32 = 3;
/// The most bounces asked for (each is a pass over the gathered hits).
pub const MOST_BOUNCES: u32 = 16;
/// About how many texels gather the light (a regular subset of them).
const GATHERING: usize = 16_384;
/// Cosine-weighted rays per gathering texel.
const RAYS: u32 = 128;
/// The most surfels of one face a ray's hit is compared with, where the
/// texel under the hit's UVs lies elsewhere.
const MOST_SEARCHED: usize = 64;

/// What one ray of a gathering texel found: the texel it sees and the
/// entry transmittance of the light it brings.
#[derive(Clone, Copy, Debug)]
struct Seen {
    surfel: u32,
    entering: [f32; 3],
}

/// The transmitted irradiance (W/m², in the units of `direct`) each surfel
/// of `layout` receives from the rest of its own surface over `bounces`
/// bounces, where `direct` is the light entering it straight from the
/// lights and `leaving[s]` how much of the light entering surfel `s` leaves
/// it (per channel, dimensionless). `mesh` is the object's mesh in `rays`.
#[allow(clippy::too_many_arguments)]
pub fn interreflected(
    layout: &Layout,
    mesh: u32,
    rays: &RayScene,
    entry: &EntryTransmittance,
    direct: &[[f32; 3]],
    leaving: &[[f32; 3]],
    bounces: u32,
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let surfels = &layout.surfels;
    let count = surfels.len();
    if bounces == 0 || count == 0 || direct.len() != count || leaving.len() != count {
        return Ok(vec![[0.0; 3]; count]);
    }
    let gathering = gathering_texels(layout, GATHERING);
    let by_place = Surfels::new(layout);
    let mut seen = vec![Vec::new(); gathering.len()];
    parallel_fill(&mut seen, 16, control, |g| {
        look_around(layout, &by_place, mesh, rays, entry, gathering[g] as usize)
    })?;
    let spread = Spread::new(layout, &gathering);
    // A bounce before the last is read only where the rays hit: it is
    // spread to those surfels alone, each hit finding its surfel's place
    // among them.
    let hit = hit_surfels(&seen, count);
    let place = |s: u32| hit.binary_search(&s).unwrap_or_default();
    let mut bounced = vec![[0.0f32; 3]; hit.len()];
    let last = bounces.min(MOST_BOUNCES);
    for bounce in 1..=last {
        control.check()?;
        let gathered: Vec<[f32; 3]> = seen
            .par_iter()
            .map(|hits| {
                // Cosine-weighted: the irradiance is the mean radiance × π,
                // and a Lambertian texel's radiance × π is its exitance:
                // its whole light so far, direct and bounced, as it leaves.
                let mut sum = [0.0f32; 3];
                for hit in hits {
                    let (s, k) = (hit.surfel as usize, place(hit.surfel));
                    for c in 0..3 {
                        let out = (direct[s][c] + bounced[k][c]) * leaving[s][c];
                        sum[c] += out * hit.entering[c];
                    }
                }
                sum.map(|v| v / RAYS as f32)
            })
            .collect();
        if bounce == last {
            return spread.to_surfels(&gathered, control);
        }
        bounced = spread.to_some(&gathered, &hit, control)?;
    }
    Ok(vec![[0.0; 3]; count])
}

/// The surfels, of `count`, that the rays in `seen` hit, in order.
fn hit_surfels(seen: &[Vec<Seen>], count: usize) -> Vec<u32> {
    let mut marked = vec![false; count];
    for hit in seen.iter().flatten() {
        marked[hit.surfel as usize] = true;
    }
    (0..count as u32).filter(|&s| marked[s as usize]).collect()
}

/// Rays the light an object sends onto itself casts for `texels` texels
/// over `bounces` bounces (the plan's count; none without bounces).
pub fn gathering_rays(texels: usize, bounces: u32) -> f64 {
    if bounces == 0 {
        return 0.0;
    }
    gathering_count(texels) * f64::from(RAYS)
}

/// About how many of `texels` texels gather ([`gathering_texels`]).
fn gathering_count(texels: usize) -> f64 {
    let stride = f64::from(stride(texels, GATHERING));
    texels as f64 / (stride * stride)
}

/// Bytes the light an object sends onto itself holds at its peak for
/// `texels` texels: per texel the share leaving, the light bounced so far
/// and next, and the surfels by face; per gathering texel what its rays
/// met.
pub fn gathering_bytes(texels: usize, bounces: u32) -> f64 {
    if bounces == 0 {
        return 0.0;
    }
    let per_texel = 3 * std::mem::size_of::<[f32; 3]>() + std::mem::size_of::<u32>();
    let per_gathering = RAYS as usize * std::mem::size_of::<Seen>()
        + std::mem::size_of::<Vec<Seen>>()
        + 2 * std::mem::size_of::<[f32; 3]>();
    texels as f64 * per_texel as f64 + gathering_count(texels) * per_gathering as f64
}

/// The texels the rays of gathering texel `surfel` see on the object's own
/// outside, with the entry transmittance at each ray's incidence.
fn look_around(
    layout: &Layout,
    surfels_by_place: &Surfels,
    mesh: u32,
    rays: &RayScene,
    entry: &EntryTransmittance,
    surfel: usize,
) -> Vec<Seen> {
    let surfels = &layout.surfels;
    let (p, n) = (surfels.position[surfel], surfels.normal[surfel]);
    // A frame that turns with the mesh: the rays a texel casts do not
    // depend on the axes the scene was written in.
    let (t, b) = own_frame(&layout.mesh, surfels.triangle[surfel], n);
    let skip = rays.scene_triangle(mesh, surfels.triangle[surfel]);
    let origin = p + n * rays.epsilon();
    let own = layout.mesh.triangles[surfels.triangle[surfel] as usize]
        .map(|v| layout.mesh.positions[v as usize]);
    // The same directions in every texel's own frame: the scene read from
    // another format (Y up, its V flipped, its triangles in another order)
    // gathers along the same rays, and a texel's error is its triangle's.
    let shift = rotation(0, 0x626f_756e_6365);
    let mut seen = Vec::new();
    for k in 0..RAYS {
        let local = cosine_hemisphere(hammersley(k, RAYS, shift));
        let direction = (t * local.x + b * local.y + n * local.z).normalize_or_zero();
        let Some(hit) = rays.closest_hit(origin, direction, 0.0, f32::INFINITY, skip) else {
            continue;
        };
        if hit.mesh != mesh {
            continue;
        }
        // Only the outside sends light out; a ray that meets a face from
        // behind has slipped through the surface.
        let corners = layout.mesh.triangles[hit.triangle as usize];
        let [a, b2, c] = corners.map(|v| layout.mesh.positions[v as usize]);
        if (b2 - a).cross(c - a).dot(direction) >= 0.0 {
            continue;
        }
        // A face beside the start that turns the same way is the same
        // smooth surface, faceted: the kink between two triangles of a
        // curved quad is not a fold that sees itself.
        let [wa, wb, wc] = [1.0 - hit.uv.x - hit.uv.y, hit.uv.x, hit.uv.y];
        let [na, nb, nc] = corners.map(|v| layout.mesh.normals[v as usize]);
        let smooth = (na * wa + nb * wb + nc * wc).normalize_or_zero();
        if smooth.dot(n) > 0.5 && [a, b2, c].iter().any(|q| own.contains(q)) {
            continue;
        }
        let point = origin + direction * hit.t;
        let [ua, ub, uc] = corners.map(|v| layout.uvs[v as usize]);
        let uv = ua * wa + ub * wb + uc * wc;
        if let Some(s) = surfels_by_place.at(hit.triangle, point, uv) {
            seen.push(Seen {
                surfel: s,
                entering: entry.at_rgb(local.z),
            });
        }
    }
    seen
}

/// The surfel a ray meets: the texel under the point's UVs where that
/// texel lies on the same face or beside the point, else the nearest
/// surfel of the face met, since UVs may overlap (Suzanne's own do) and
/// the texel under them may be another part's.
struct Surfels<'a> {
    layout: &'a Layout,
    /// Surfels by triangle: those of triangle t are
    /// `order[starts[t]..starts[t + 1]]`.
    starts: Vec<u32>,
    order: Vec<u32>,
    /// A texel's length on the surface, squared, mm².
    texel2: f32,
}

impl<'a> Surfels<'a> {
    fn new(layout: &'a Layout) -> Self {
        let surfels = &layout.surfels;
        let triangles = layout.mesh.triangles.len();
        let mut starts = vec![0u32; triangles + 1];
        for &t in &surfels.triangle {
            starts[t as usize + 1] += 1;
        }
        for t in 0..triangles {
            starts[t + 1] += starts[t];
        }
        let mut fill = starts.clone();
        let mut order = vec![0u32; surfels.len()];
        for (s, &t) in surfels.triangle.iter().enumerate() {
            order[fill[t as usize] as usize] = s as u32;
            fill[t as usize] += 1;
        }
        let area: f64 = surfels.area.iter().map(|&a| f64::from(a.max(0.0))).sum();
        Surfels {
            layout,
            starts,
            order,
            texel2: (area / surfels.len().max(1) as f64) as f32,
        }
    }

    /// The surfel at `point` on `triangle`, whose texture coordinate is
    /// `uv`.
    fn at(&self, triangle: u32, point: Vec3, uv: glam::Vec2) -> Option<u32> {
        let surfels = &self.layout.surfels;
        let beside = |s: u32| {
            surfels.triangle[s as usize] == triangle
                || (surfels.position[s as usize] - point).length_squared() <= 4.0 * self.texel2
        };
        if let Some(s) = surfel_under(self.layout, uv).filter(|&s| beside(s)) {
            return Some(s);
        }
        let own = &self.order
            [self.starts[triangle as usize] as usize..self.starts[triangle as usize + 1] as usize];
        // A large face whose texels another face's UVs cover: the nearest
        // of a regular share of its surfels, so a ray's cost stays bounded.
        let step = own.len().div_ceil(MOST_SEARCHED).max(1);
        own.iter().step_by(step).copied().min_by(|&a, &b| {
            let d = |s: u32| (surfels.position[s as usize] - point).length_squared();
            d(a).total_cmp(&d(b))
        })
    }
}

/// The surfel of the texel under `uv`, or of a texel beside it where the
/// point falls just outside the texels the layout covers.
fn surfel_under(layout: &Layout, uv: glam::Vec2) -> Option<u32> {
    let surfels = &layout.surfels;
    let n = surfels.resolution as i64;
    let cell = |x: f32| (x * n as f32).floor() as i64;
    let (x, y) = (cell(uv.x), cell(uv.y));
    let at = |x: i64, y: i64| -> Option<u32> {
        if x < 0 || y < 0 || x >= n || y >= n {
            return None;
        }
        let s = surfels.index[(y * n + x) as usize];
        (s != EMPTY).then_some(s)
    };
    at(x, y).or_else(|| {
        (-1..=1)
            .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
            .find_map(|(dx, dy)| at(x + dx, y + dy))
    })
}
