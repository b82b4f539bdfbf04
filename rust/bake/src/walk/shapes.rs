//! Exact shapes a walk can be confined to, where it measures a law of
//! light rather than an object: how much a ball of a material returns
//! against a half-space of it ([`crate::transport::ball_totals`]). Each is
//! one surface element (triangle 0) with its normal at the point met.

use super::path::{Confinement, Meeting};
use glam::{DVec3, Vec2, Vec3};

/// The medium below the plane z = 0 (outward normal +z).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HalfSpace;

impl Confinement for HalfSpace {
    fn meet(&self, origin: Vec3, direction: Vec3, t_max: f32, _: Option<u32>) -> Option<Meeting> {
        // Only a flight heading up leaves; from the plane itself (a start
        // or a reflection) the flight heads down and meets nothing.
        if direction.z <= 0.0 {
            return None;
        }
        let t = (-origin.z).max(0.0) / direction.z;
        (t <= t_max).then_some(Meeting {
            t,
            triangle: 0,
            barycentric: Vec2::ZERO,
            normal: Vec3::Z,
        })
    }
}

/// The medium inside a ball about the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    /// Radius, mm.
    pub radius: f64,
}

impl Confinement for Ball {
    fn meet(&self, origin: Vec3, direction: Vec3, t_max: f32, _: Option<u32>) -> Option<Meeting> {
        // The far root of |o + t d| = r: from inside, or from the surface
        // heading in, the near root is at or behind the origin. In f64, so
        // a point rounded just outside the surface still finds the far side.
        let (o, d) = (origin.as_dvec3(), direction.as_dvec3());
        let b = o.dot(d);
        let c = o.length_squared() - self.radius * self.radius;
        let t = -b + (b * b - c).max(0.0).sqrt();
        if !(t.is_finite() && t <= f64::from(t_max)) {
            return None;
        }
        let normal = (o + d * t).normalize_or(DVec3::Z).as_vec3();
        Some(Meeting {
            t: t.max(0.0) as f32,
            triangle: 0,
            barycentric: Vec2::ZERO,
            normal,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chord_from_the_pole_meets_the_ball_on_its_far_side() {
        let ball = Ball { radius: 2.0 };
        let start = Vec3::new(0.0, 0.0, 2.0);
        // Straight down: the antipode, 4 mm on.
        let hit = ball.meet(start, -Vec3::Z, 10.0, Some(0)).unwrap();
        assert!((hit.t - 4.0).abs() < 1e-5, "{}", hit.t);
        assert!((hit.normal + Vec3::Z).length() < 1e-5);
        // At 60° from the normal: a chord of 2r cos 60° = 2 mm.
        let d = Vec3::new(60f32.to_radians().sin(), 0.0, -60f32.to_radians().cos());
        let hit = ball.meet(start, d, 10.0, Some(0)).unwrap();
        assert!((hit.t - 2.0).abs() < 1e-5, "{}", hit.t);
        // Shorter than the flight: no meeting.
        assert!(ball.meet(start, -Vec3::Z, 3.9, Some(0)).is_none());
    }

    #[test]
    fn the_half_space_is_left_only_upwards() {
        let origin = Vec3::new(0.5, 0.0, -1.0);
        let up = Vec3::new(0.6, 0.0, 0.8);
        let hit = HalfSpace.meet(origin, up, 5.0, None).unwrap();
        assert!((hit.t - 1.25).abs() < 1e-6);
        assert!(HalfSpace.meet(origin, -up, 5.0, None).is_none());
        assert!(HalfSpace.meet(origin, up, 1.0, None).is_none());
    }
}
