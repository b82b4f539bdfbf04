//! Lights prepared for sampling from a surface point: each returns, for a
//! sample point u ∈ [0,1)², the direction to shadow-test and the
//! irradiance that sample stands for (radiance × cos θ ÷ density).

use super::environment::EnvironmentMap;
use super::sequence::{basis, concentric_disk, cosine_hemisphere, uniform_cone};
use crate::scene::{ConeFalloff, Light, LightKind};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::Arc;

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
    /// False when nothing blocks this light.
    casts_shadow: bool,
}

/// A spot's cone: its axis, the inner and outer angles (radians) and how
/// it fades between them.
#[derive(Clone, Copy, Debug)]
struct Cone {
    facing: Vec3,
    inner: f32,
    outer: f32,
    falloff: ConeFalloff,
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
        cone: Option<Cone>,
    },
    Rectangle {
        centre: Vec3,
        x: Vec3,
        y: Vec3,
        facing: Vec3,
        spread: Spread,
    },
    Disk {
        centre: Vec3,
        radius: f32,
        facing: Vec3,
        spread: Spread,
    },
    Cylinder {
        centre: Vec3,
        /// Half the length along the axis, as a vector.
        half: Vec3,
        /// Two unit vectors across the axis.
        across: (Vec3, Vec3),
        radius: f32,
    },
    Line {
        centre: Vec3,
        half: Vec3,
    },
    Environment {
        map: Option<Arc<EnvironmentMap>>,
    },
}

impl Emitter {
    /// Prepares `light`; `environment` is the image an environment light's
    /// texture names, already read (shared by every object's bake).
    pub fn new(light: &Light, environment: Option<Arc<EnvironmentMap>>) -> Self {
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
                falloff,
            } => {
                let outer = outer_cone.clamp(0.0, PI);
                let inner = inner_cone.clamp(0.0, outer);
                Shape::Sphere {
                    centre: light.position,
                    radius: radius_mm.max(0.0),
                    cone: Some(Cone {
                        facing,
                        inner,
                        outer,
                        falloff: *falloff,
                    }),
                }
            }
            LightKind::Rectangle {
                width_mm,
                height_mm,
                spread,
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
                    spread: Spread::new(*spread),
                }
            }
            LightKind::Disk { radius_mm, spread } => Shape::Disk {
                centre: light.position,
                radius: radius_mm.max(0.0),
                facing,
                spread: Spread::new(*spread),
            },
            LightKind::Cylinder {
                length_mm,
                radius_mm,
            } => {
                let axis = light.tangent.normalize_or(Vec3::X);
                Shape::Cylinder {
                    centre: light.position,
                    half: axis * 0.5 * length_mm.max(0.0),
                    across: basis(axis),
                    radius: radius_mm.max(0.0),
                }
            }
            LightKind::Line { length_mm } => Shape::Line {
                centre: light.position,
                half: light.tangent.normalize_or(Vec3::X) * 0.5 * length_mm.max(0.0),
            },
            LightKind::Environment { .. } => Shape::Environment {
                map: environment.filter(|m| !m.is_constant()),
            },
        };
        Emitter {
            name: light.name.clone(),
            shape,
            power,
            casts_shadow: light.casts_shadow,
        }
    }

    /// True when objects block this light.
    pub fn casts_shadow(&self) -> bool {
        self.casts_shadow
    }

    /// True when one sample gives the exact answer (no area, no angle).
    pub fn is_delta(&self) -> bool {
        match self.shape {
            Shape::Distant { cos_half, .. } => cos_half >= 1.0,
            Shape::Sphere { radius, .. } => radius <= 0.0,
            Shape::Rectangle { x, y, .. } => x.cross(y).length_squared() <= 0.0,
            Shape::Disk { radius, .. } => radius <= 0.0,
            Shape::Cylinder { half, radius, .. } => half.length() <= 0.0 || radius <= 0.0,
            Shape::Line { half, .. } => half.length() <= 0.0,
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
                let falloff = cone.map_or(1.0, |c| {
                    let angle = c.facing.dot(-axis).clamp(-1.0, 1.0).acos();
                    c.falloff.at(angle, c.inner, c.outer)
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
                spread,
            } => {
                let q = *centre + *x * (u.x - 0.5) + *y * (u.y - 0.5);
                area_sample(p, q, *facing, x.cross(*y).length(), *spread, self.power)
            }
            Shape::Disk {
                centre,
                radius,
                facing,
                spread,
            } => {
                let (t, b) = basis(*facing);
                let d = concentric_disk(u) * *radius;
                let q = *centre + t * d.x + b * d.y;
                area_sample(p, q, *facing, PI * radius * radius, *spread, self.power)
            }
            Shape::Cylinder {
                centre,
                half,
                across,
                radius,
            } => {
                // Uniform over the side: u.x along the axis, u.y round it.
                let phi = 2.0 * PI * u.y;
                let normal = across.0 * phi.cos() + across.1 * phi.sin();
                let q = *centre + *half * (2.0 * u.x - 1.0) + normal * *radius;
                let area = 2.0 * PI * radius * 2.0 * half.length();
                area_sample(p, q, normal, area, Spread::LAMBERTIAN, self.power)
            }
            Shape::Line { centre, half } => {
                // Uniform along the line; each metre gives I·sin ψ / d².
                let q = *centre + *half * (2.0 * u.x - 1.0);
                let to = q - p;
                let d2 = to.length_squared();
                if d2 <= 0.0 {
                    return None;
                }
                let d = d2.sqrt();
                let direction = to / d;
                let axis = half.normalize_or_zero();
                let sin = axis.cross(direction).length();
                let length_m = 2.0 * half.length() * 1e-3;
                Some(LightSample {
                    direction,
                    distance: d,
                    weight: scaled(sin * length_m / (d2 * 1e-6)),
                })
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

/// How an area light's emission narrows with Cycles' `spread`: radiance
/// at angle θ from the normal scaled by max(tan a − tan θ, 0)/(tan a − a),
/// a = spread/2, which keeps the emitted power (Cycles' `area.h` and
/// `light.cpp`); a spread of π is Lambertian.
#[derive(Clone, Copy, Debug)]
struct Spread {
    /// tan a, or infinite for a Lambertian emitter.
    tan_half: f64,
    /// 1/(tan a − a).
    scale: f64,
}

impl Spread {
    const LAMBERTIAN: Spread = Spread {
        tan_half: f64::INFINITY,
        scale: 0.0,
    };

    fn new(spread: f32) -> Self {
        let half = 0.5 * f64::from(spread).clamp(0.0, std::f64::consts::PI);
        if half >= 0.5 * std::f64::consts::PI - 1e-6 {
            return Spread::LAMBERTIAN;
        }
        let tan_half = half.tan();
        // tan a − a ≈ a³/3 for small a.
        let rest = if half > 0.05 {
            tan_half - half
        } else {
            half.powi(3) / 3.0
        };
        Spread {
            tan_half,
            scale: if rest > 0.0 { 1.0 / rest } else { 0.0 },
        }
    }

    /// The factor on the radiance leaving at cos θ from the normal.
    fn at(self, cos: f32) -> f32 {
        if self.tan_half.is_infinite() {
            return 1.0;
        }
        let cos = f64::from(cos).clamp(1e-9, 1.0);
        let tan = (1.0 - cos * cos).max(0.0).sqrt() / cos;
        ((self.tan_half - tan).max(0.0) * self.scale) as f32
    }
}

/// A point `q` sampled uniformly on an emitter of `area` (mm²) with front
/// normal `facing`, seen from `p`: density 1/A in area is d²/(A cos θl) in
/// solid angle.
fn area_sample(
    p: Vec3,
    q: Vec3,
    facing: Vec3,
    area: f32,
    spread: Spread,
    power: [f32; 3],
) -> Option<LightSample> {
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
    let w = area * cos_light * spread.at(cos_light) / d2;
    if w <= 0.0 {
        return None;
    }
    Some(LightSample {
        direction,
        distance: d,
        weight: power.map(|c| c * w),
    })
}
