//! Lights prepared for sampling from a surface point: each returns, for a
//! sample point u ∈ [0,1)², the direction to shadow-test and the
//! irradiance that sample stands for (radiance × cos θ ÷ density).

use super::environment::EnvironmentMap;
use super::sequence::{basis, concentric_disk, cosine_hemisphere, uniform_cone};
use crate::scene::{Light, LightKind};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// One light sample as seen from a receiver.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the receiver towards the light.
    pub direction: Vec3,
    /// Distance to the emitting point, mm (infinite for distant light).
    pub distance: f32,
    /// Radiance × colour ÷ density, per steradian of direction; multiply by
    /// cos θ and ρt(θ) at the receiver to get irradiance (W/m²).
    pub weight: [f32; 3],
}

/// A light ready to be sampled.
#[derive(Clone, Debug)]
pub struct Emitter {
    /// The light's name, for reports.
    pub name: String,
    shape: Shape,
    /// Colour × intensity.
    power: [f32; 3],
}

#[derive(Clone, Debug)]
enum Shape {
    Distant {
        toward: Vec3,
        cos_half: f32,
    },
    Sphere {
        centre: Vec3,
        radius: f32,
        cone: Option<(Vec3, f32, f32)>,
    },
    Rectangle {
        centre: Vec3,
        x: Vec3,
        y: Vec3,
        facing: Vec3,
    },
    Disk {
        centre: Vec3,
        radius: f32,
        facing: Vec3,
    },
    Environment {
        map: Option<EnvironmentMap>,
    },
}

impl Emitter {
    /// Prepares `light`; `environment` is the image an environment light's
    /// texture names, already read.
    pub fn new(light: &Light, environment: Option<EnvironmentMap>) -> Self {
        let power = light.color.map(|c| {
            let p = c * light.intensity;
            if p.is_finite() { p.max(0.0) } else { 0.0 }
        });
        let facing = light.direction.normalize_or(Vec3::NEG_Z);
        let shape = match &light.kind {
            LightKind::Directional { angle } => Shape::Distant {
                toward: -facing,
                cos_half: (0.5 * angle.clamp(0.0, PI)).cos(),
            },
            LightKind::Point { radius_mm } => Shape::Sphere {
                centre: light.position,
                radius: radius_mm.max(0.0),
                cone: None,
            },
            LightKind::Spot {
                radius_mm,
                inner_cone,
                outer_cone,
            } => {
                let outer = outer_cone.clamp(0.0, PI);
                let inner = inner_cone.clamp(0.0, outer);
                Shape::Sphere {
                    centre: light.position,
                    radius: radius_mm.max(0.0),
                    cone: Some((facing, inner.cos(), outer.cos())),
                }
            }
            LightKind::Rectangle {
                width_mm,
                height_mm,
            } => {
                let x = light
                    .tangent
                    .reject_from(facing)
                    .normalize_or(basis(facing).0);
                let y = (-facing).cross(x);
                Shape::Rectangle {
                    centre: light.position,
                    x: x * width_mm.max(0.0),
                    y: y * height_mm.max(0.0),
                    facing,
                }
            }
            LightKind::Disk { radius_mm } => Shape::Disk {
                centre: light.position,
                radius: radius_mm.max(0.0),
                facing,
            },
            LightKind::Environment { .. } => Shape::Environment {
                map: environment.filter(|m| !m.is_constant()),
            },
        };
        Emitter {
            name: light.name.clone(),
            shape,
            power,
        }
    }

    /// True when one sample gives the exact answer (no area, no angle).
    pub fn is_delta(&self) -> bool {
        match self.shape {
            Shape::Distant { cos_half, .. } => cos_half >= 1.0,
            Shape::Sphere { radius, .. } => radius <= 0.0,
            Shape::Rectangle { x, y, .. } => x.cross(y).length_squared() <= 0.0,
            Shape::Disk { radius, .. } => radius <= 0.0,
            Shape::Environment { .. } => false,
        }
    }

    /// How many sampling strategies [`Emitter::sample`] alternates between
    /// (two for an environment image: the image and the cosine).
    pub fn strategies(&self) -> u32 {
        match &self.shape {
            Shape::Environment { map: Some(_) } => 2,
            _ => 1,
        }
    }

    /// True when the light casts nothing.
    pub fn is_dark(&self) -> bool {
        self.power.iter().all(|&p| p <= 0.0)
    }

    /// True for light from infinitely far (shadow rays have no end).
    pub fn is_distant(&self) -> bool {
        matches!(
            self.shape,
            Shape::Distant { .. } | Shape::Environment { .. }
        )
    }

    /// A sample of the light seen from `p` with normal `n`, from `u`, by
    /// strategy `strategy` (below [`Emitter::strategies`]; the estimate
    /// weighs both by the balance heuristic, so callers alternate them
    /// evenly). `None` when the sample carries no light.
    pub fn sample(&self, p: Vec3, n: Vec3, u: Vec2, strategy: u32) -> Option<LightSample> {
        let scaled = |w: f32| self.power.map(|c| c * w);
        match &self.shape {
            Shape::Distant { toward, cos_half } => {
                if *cos_half >= 1.0 {
                    return Some(LightSample {
                        direction: *toward,
                        distance: f32::INFINITY,
                        weight: self.power,
                    });
                }
                // A disk of uniform radiance L with E⊥ = L·π sin²(α/2);
                // uniform cone sampling has density 1/Ω.
                let (t, b) = basis(*toward);
                let local = uniform_cone(u, *cos_half);
                let direction = (t * local.x + b * local.y + *toward * local.z).normalize();
                let sin2 = 1.0 - cos_half * cos_half;
                let solid_angle = 2.0 * PI * (1.0 - cos_half);
                Some(LightSample {
                    direction,
                    distance: f32::INFINITY,
                    weight: scaled(solid_angle / (PI * sin2)),
                })
            }
            Shape::Sphere {
                centre,
                radius,
                cone,
            } => {
                let to = *centre - p;
                let d2 = to.length_squared();
                if d2 <= 0.0 {
                    return None;
                }
                let d = d2.sqrt();
                let axis = to / d;
                let falloff = cone.map_or(1.0, |(facing, cos_inner, cos_outer)| {
                    spot_falloff(facing.dot(-axis), cos_inner, cos_outer)
                });
                if falloff <= 0.0 {
                    return None;
                }
                // Radiant intensity I (W/sr) over d in metres gives W/m².
                let d_m2 = d2 * 1e-6;
                if *radius <= 0.0 || *radius >= d {
                    return Some(LightSample {
                        direction: axis,
                        distance: d,
                        weight: scaled(falloff / d_m2),
                    });
                }
                // Sample the cone the sphere subtends; its radiance is
                // I / (π r²), so each sample carries L·Ω.
                let sin2_max = (radius * radius / d2).min(1.0);
                let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
                let (t, b) = basis(axis);
                let local = uniform_cone(u, cos_max);
                let direction = (t * local.x + b * local.y + axis * local.z).normalize();
                let solid_angle = 2.0 * PI * (1.0 - cos_max);
                let radiance = 1.0 / (PI * radius * radius * 1e-6);
                Some(LightSample {
                    direction,
                    distance: d - radius,
                    weight: scaled(falloff * radiance * solid_angle),
                })
            }
            Shape::Rectangle {
                centre,
                x,
                y,
                facing,
            } => {
                let q = *centre + *x * (u.x - 0.5) + *y * (u.y - 0.5);
                area_sample(p, q, *facing, x.cross(*y).length(), self.power)
            }
            Shape::Disk {
                centre,
                radius,
                facing,
            } => {
                let (t, b) = basis(*facing);
                let d = concentric_disk(u) * *radius;
                let q = *centre + t * d.x + b * d.y;
                area_sample(p, q, *facing, PI * radius * radius, self.power)
            }
            Shape::Environment { map } => {
                let (t, b) = basis(n);
                let to_world = |l: Vec3| (t * l.x + b * l.y + n * l.z).normalize();
                let Some(map) = map else {
                    // Constant radiance: cosine sampling, weight L·π/cos θ.
                    let direction = to_world(cosine_hemisphere(u));
                    let cos = direction.dot(n).max(1e-6);
                    return Some(LightSample {
                        direction,
                        distance: f32::INFINITY,
                        weight: scaled(PI / cos),
                    });
                };
                // Half the samples follow the image, half the cosine; the
                // balance heuristic weighs each by both densities.
                let direction = if strategy == 0 {
                    map.sample(u)?
                } else {
                    to_world(cosine_hemisphere(u))
                };
                let cos = direction.dot(n);
                if cos <= 0.0 {
                    return None;
                }
                let density = 0.5 * map.pdf(direction) + 0.5 * cos / PI;
                if density <= 0.0 {
                    return None;
                }
                let radiance = map.radiance(direction);
                Some(LightSample {
                    direction,
                    distance: f32::INFINITY,
                    weight: [0, 1, 2].map(|c| self.power[c] * radiance[c] / density),
                })
            }
        }
    }
}

/// glTF's spot falloff: squared linear ramp in cos θ from the outer cone
/// to the inner one.
fn spot_falloff(cos: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    if cos <= cos_outer {
        return 0.0;
    }
    let span = (cos_inner - cos_outer).max(1e-6);
    let t = ((cos - cos_outer) / span).clamp(0.0, 1.0);
    t * t
}

/// A point `q` sampled uniformly on an emitter of `area` (mm²) with front
/// normal `facing`, seen from `p`: density 1/A in area is d²/(A cos θl) in
/// solid angle.
fn area_sample(p: Vec3, q: Vec3, facing: Vec3, area: f32, power: [f32; 3]) -> Option<LightSample> {
    let to = q - p;
    let d2 = to.length_squared();
    if d2 <= 0.0 || area <= 0.0 {
        return None;
    }
    let d = d2.sqrt();
    let direction = to / d;
    let cos_light = facing.dot(-direction);
    if cos_light <= 0.0 {
        return None;
    }
    let w = area * cos_light / d2;
    Some(LightSample {
        direction,
        distance: d,
        weight: power.map(|c| c * w),
    })
}
