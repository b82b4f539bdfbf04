//! One walk through the medium: exponential free flights in σt, the weight
//! times the single-scattering albedo at every scattering event,
//! Henyey–Greenstein turns, the boundary's Fresnel choice where a flight
//! meets the surface, Russian roulette for light walks, and a hard bound
//! on events.

use super::medium::{Boundary, ChannelMedium};
use super::phase::scatter;
use glam::{Vec2, Vec3};
use sssbake_profile::numerics::rng::Rng;

/// Below this weight a walk plays Russian roulette...
pub const ROULETTE_WEIGHT: f64 = 0.05;

/// Where a flight first meets the surface that bounds the medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Meeting {
    /// Distance along the flight, mm.
    pub t: f32,
    /// The triangle met (0 for a shape with no triangles).
    pub triangle: u32,
    /// Weights of that triangle's vertices 1 and 2.
    pub barycentric: Vec2,
    /// The unit outward normal of the surface there.
    pub normal: Vec3,
}

/// What bounds a walk's medium: an object's mesh ([`super::Enclosure`]),
/// or an exact shape ([`super::shapes`]) where the walk measures a law of
/// light rather than an object.
pub trait Confinement: Sync {
    /// The first surface from `origin` along unit `direction` within
    /// `t_max` mm, `leaving` the triangle the flight starts on (`None` from
    /// inside the medium).
    fn meet(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_max: f32,
        leaving: Option<u32>,
    ) -> Option<Meeting>;
}

/// Where a walk begins: on the surface, heading into the medium.
#[derive(Clone, Copy, Debug)]
pub struct WalkStart {
    /// The point on the surface, mm.
    pub position: Vec3,
    /// Unit direction into the medium.
    pub direction: Vec3,
    /// The triangle `position` lies on (a ray leaving it never hits it).
    pub triangle: u32,
}

/// How a walk ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ending {
    /// It crossed the surface out of the medium at barycentric point
    /// `barycentric` of `triangle` carrying `weight` (a share of the unit
    /// it started with).
    Left {
        /// The triangle it left through.
        triangle: u32,
        /// Weights of that triangle's vertices 1 and 2.
        barycentric: Vec2,
        /// What it carried out.
        weight: f64,
    },
    /// Absorbed, by Russian roulette: unbiased, nothing is dropped.
    Absorbed,
    /// Stopped at the bound on events, dropping `weight`.
    Truncated {
        /// The weight it still carried.
        weight: f64,
    },
    /// Its flight met no surface at all: the mesh is not closed there (or
    /// a ray slipped through an edge); `weight` is lost.
    Lost {
        /// The weight it still carried.
        weight: f64,
    },
}

/// A walk's ending and the events it took (scatterings and boundary
/// crossings or reflections, each counted once).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walked {
    /// How it ended.
    pub ending: Ending,
    /// Events taken, at most the bound.
    pub events: u32,
}

/// Walks from `start` through `medium` inside `confinement`, leaving by
/// `boundary`, for at most `max_events` events, drawing from `rng`.
pub fn walk<C: Confinement + ?Sized>(
    confinement: &C,
    medium: &ChannelMedium,
    boundary: Boundary,
    start: WalkStart,
    max_events: u32,
    rng: &mut Rng,
) -> Walked {
    let mut position = start.position;
    let mut direction = start.direction;
    let mut leaving = Some(start.triangle);
    let mut weight = 1.0f64;
    let mut events = 0u32;
    loop {
        if events >= max_events {
            return Walked {
                ending: Ending::Truncated { weight },
                events,
            };
        }
        let flight = if medium.sigma_t > 0.0 {
            -rng.uniform_open().ln() / medium.sigma_t
        } else {
            f64::INFINITY
        };
        // A flight beyond f32's range meets the surface or nothing.
        let reach = if flight < f32::MAX as f64 {
            flight as f32
        } else {
            f32::INFINITY
        };
        events += 1;
        if let Some(hit) = confinement.meet(position, direction, reach, leaving) {
            let normal = hit.normal;
            let cos_inside = direction.dot(normal).abs() as f64;
            if rng.uniform() < boundary.reflectance(cos_inside) {
                position += direction * hit.t;
                direction =
                    (direction - 2.0 * direction.dot(normal) * normal).normalize_or(-direction);
                leaving = Some(hit.triangle);
                continue;
            }
            return Walked {
                ending: Ending::Left {
                    triangle: hit.triangle,
                    barycentric: hit.barycentric,
                    weight,
                },
                events,
            };
        }
        if !reach.is_finite() {
            return Walked {
                ending: Ending::Lost { weight },
                events,
            };
        }
        position += direction * reach;
        leaving = None;
        weight *= medium.albedo;
        direction = scatter(direction, medium.g, rng);
        if weight < ROULETTE_WEIGHT {
            // Survive with probability weight / ROULETTE_WEIGHT at weight
            // ROULETTE_WEIGHT: the expected weight is unchanged.
            if rng.uniform() * ROULETTE_WEIGHT < weight {
                weight = ROULETTE_WEIGHT;
            } else {
                return Walked {
                    ending: Ending::Absorbed,
                    events,
                };
            }
        }
    }
}
