//! What a walk over the octree adds up: one light's weighed flux, or a
//! light's and a unit light's side by side, so that two sums over the same
//! pairs weigh each pair once.

use glam::{DVec3, Vec4};

/// The weighed light of one pair or node, added up per node in single
/// precision and across nodes in double.
pub trait Weighed: Copy {
    /// The sums across nodes.
    type Total: Copy;
    /// The sums as a gather returns them, W/m² per channel.
    type Out: Copy + Send;
    /// Nothing weighed.
    const ZERO: Self;
    /// Nothing summed.
    const NO_TOTAL: Self::Total;
    /// A pair's `weight` (1/mm² per channel) times the source's `flux`
    /// (W per channel), and beside it, where this sums a unit light too,
    /// times its `area` (mm²).
    fn weigh(weight: Vec4, flux: Vec4, area: f32) -> Self;
    /// Each sum times `factor`.
    fn scaled(self, factor: f32) -> Self;
    /// `self` plus `other`.
    fn plus(self, other: Self) -> Self;
    /// Adds `self` to `total`.
    fn add_to(self, total: &mut Self::Total);
    /// `total` as the gather returns it.
    fn out(total: Self::Total) -> Self::Out;
}

/// One light's weighed flux.
impl Weighed for Vec4 {
    type Total = DVec3;
    type Out = [f32; 3];
    const ZERO: Self = Vec4::ZERO;
    const NO_TOTAL: DVec3 = DVec3::ZERO;

    #[inline(always)]
    fn weigh(weight: Vec4, flux: Vec4, _area: f32) -> Self {
        weight * flux
    }

    #[inline(always)]
    fn scaled(self, factor: f32) -> Self {
        self * factor
    }

    #[inline(always)]
    fn plus(self, other: Self) -> Self {
        self + other
    }

    #[inline(always)]
    fn add_to(self, total: &mut DVec3) {
        *total += self.truncate().as_dvec3();
    }

    #[inline(always)]
    fn out(total: DVec3) -> [f32; 3] {
        total.to_array().map(|v| v as f32)
    }
}

/// A light's weighed flux and a unit light's (1 W/m² on every source).
impl Weighed for [Vec4; 2] {
    type Total = [DVec3; 2];
    type Out = [[f32; 3]; 2];
    const ZERO: Self = [Vec4::ZERO; 2];
    const NO_TOTAL: [DVec3; 2] = [DVec3::ZERO; 2];

    #[inline(always)]
    fn weigh(weight: Vec4, flux: Vec4, area: f32) -> Self {
        [weight * flux, weight * area]
    }

    #[inline(always)]
    fn scaled(self, factor: f32) -> Self {
        self.map(|w| w * factor)
    }

    #[inline(always)]
    fn plus(self, other: Self) -> Self {
        [self[0] + other[0], self[1] + other[1]]
    }

    #[inline(always)]
    fn add_to(self, total: &mut [DVec3; 2]) {
        for (total, part) in total.iter_mut().zip(self) {
            *total += part.truncate().as_dvec3();
        }
    }

    #[inline(always)]
    fn out(total: [DVec3; 2]) -> [[f32; 3]; 2] {
        total.map(|t| t.to_array().map(|v| v as f32))
    }
}

#[cfg(test)]
mod tests {
    use crate::control::Control;
    use crate::materials::preset;
    use crate::scattering::{D_MAX_EPSILON, Scattering};
    use crate::transport::kernel::Separation;
    use crate::transport::octree::Gathering;
    use crate::transport::sources::{OwnSource, Sources, Targets};
    use glam::Vec3;
    use sssbake_profile::model::Model;
    use std::borrow::Cow;

    /// The exact sums of a light and of a unit light taken in one walk
    /// are each the sum the walk of one light gives, pair for pair: on a
    /// bent sheet of unequal texels under an uneven light, some of its
    /// pairs placed as exchanging nothing.
    #[test]
    fn a_light_and_a_unit_light_in_one_walk_are_each_its_own_sum() {
        let skin = Scattering::new(
            preset("skin1").unwrap(),
            Some(Model::Dipole),
            6,
            D_MAX_EPSILON,
        )
        .unwrap();
        let (mut position, mut area, mut irradiance) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..80 {
            for j in 0..80 {
                let (x, y) = (i as f32 * 0.25 - 10.0, j as f32 * 0.25 - 10.0);
                position.push(Vec3::new(x, y, 0.05 * x * x - 1.0));
                area.push(0.0625 * (1.0 + 0.5 * ((i * 7 + j * 3) % 5) as f32 / 4.0));
                irradiance.push([1.0 + x.max(0.0), 0.5, (j % 3) as f32]);
            }
        }
        let n = position.len();
        let sources = |irradiance: Vec<[f32; 3]>| Sources {
            position: Cow::Owned(position.clone()),
            normal: Cow::Owned(vec![Vec3::Z; n]),
            area: Cow::Owned(area.clone()),
            irradiance,
            footprint: Cow::Owned(Vec::new()),
            piece: Cow::Owned(Vec::new()),
        };
        let (lit, unit) = (sources(irradiance), sources(vec![[1.0; 3]; n]));
        let (p, up) = (
            [Vec3::new(0.0, 0.0, -0.5), Vec3::new(4.0, -3.0, 0.5)],
            [Vec3::Z; 2],
        );
        let targets = Targets {
            position: &p,
            normal: &up,
            own: OwnSource::None,
            piece: &[],
        };
        let placing = |_| {
            ([(0, 1.0), (0, 0.0)], |q: Vec3, _m: Vec3| {
                let distance = q.length();
                (q.x < 6.0).then_some(Separation {
                    distance,
                    across: distance,
                    t: 0.0,
                })
            })
        };
        let control = Control::default();
        let one = |sources: &Sources| {
            let gathering = Gathering::new(&skin.kernel, sources, 0.0);
            gathering
                .at_placed(targets, placing, 0.0, None, &control)
                .unwrap()
        };
        let both = Gathering::new(&skin.kernel, &lit, 0.0)
            .exact_placed_with_unit(targets, placing, &control)
            .unwrap();
        for (k, [light, under_unit]) in both.iter().enumerate() {
            for (got, alone) in [(light, one(&lit)[k]), (under_unit, one(&unit)[k])] {
                for c in 0..3 {
                    assert!(alone[c] > 0.0, "{alone:?}");
                    let off = (got[c] / alone[c] - 1.0).abs();
                    assert!(off < 1e-6, "target {k}: {got:?} against {alone:?}");
                }
            }
        }
    }
}
