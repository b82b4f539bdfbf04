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
    use crate::transport::verify::THIN_REFERENCE_EPSILON;
    use glam::Vec3;
    use sssbake_profile::model::Model;
    use std::borrow::Cow;

    /// A bent sheet `n` texels of `step` mm square, of unequal texels,
    /// under a light uneven across it: the sheet under that light and
    /// under a unit light.
    fn sheet(n: usize, step: f32) -> [Sources<'static>; 2] {
        let (mut position, mut area, mut irradiance) = (Vec::new(), Vec::new(), Vec::new());
        let half = 0.5 * n as f32 * step;
        for i in 0..n {
            for j in 0..n {
                let (x, y) = (i as f32 * step - half, j as f32 * step - half);
                position.push(Vec3::new(x, y, 0.5 * x * x / half - 1.0));
                let unequal = 1.0 + 0.5 * ((i * 7 + j * 3) % 5) as f32 / 4.0;
                area.push(step * step * unequal);
                irradiance.push([1.0 + x.max(0.0), 0.5, (j % 3) as f32]);
            }
        }
        let count = position.len();
        let sources = |irradiance: Vec<[f32; 3]>| Sources {
            position: Cow::Owned(position.clone()),
            normal: Cow::Owned(vec![Vec3::Z; count]),
            area: Cow::Owned(area.clone()),
            irradiance,
            footprint: Cow::Owned(Vec::new()),
            piece: Cow::Owned(Vec::new()),
            part: Default::default(),
        };
        [sources(irradiance), sources(vec![[1.0; 3]; count])]
    }

    /// Two targets above the sheet, facing it.
    const TARGETS: [Vec3; 2] = [Vec3::new(0.0, 0.0, -0.5), Vec3::new(4.0, -3.0, 0.5)];

    /// The sums at [`TARGETS`] of `sources` through the octree at solid
    /// angle `epsilon` under skin1, every pair of the sheet placed as it
    /// lies but those beyond x = 6 mm: of their light alone, or of it and
    /// a unit light in one walk.
    fn sums(sources: &Sources, epsilon: f32, with_unit: bool) -> Vec<[[f32; 3]; 2]> {
        let material = preset("skin1").unwrap();
        let skin = Scattering::new(material, Some(Model::Dipole), 6, D_MAX_EPSILON).unwrap();
        let up = [Vec3::Z; 2];
        let targets = Targets {
            position: &TARGETS,
            normal: &up,
            own: OwnSource::None,
            piece: &[],
            part: &[],
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
        let gathering = Gathering::new(&skin.kernel, sources, epsilon);
        if with_unit {
            return gathering
                .placed_with_unit(targets, placing, epsilon, &control)
                .unwrap();
        }
        let alone = gathering.at_placed(targets, placing, epsilon, None, &control);
        alone.unwrap().into_iter().map(|m| [m, [0.0; 3]]).collect()
    }

    /// How far `got` is from `reference`, relatively, at worst.
    fn worst(got: &[[f32; 3]], reference: &[[f32; 3]]) -> f32 {
        got.iter()
            .flatten()
            .zip(reference.iter().flatten())
            .map(|(g, r)| {
                assert!(*r > 0.0, "{reference:?}");
                (g / r - 1.0).abs()
            })
            .fold(0.0, f32::max)
    }

    /// The exact sums of a light and of a unit light taken in one walk
    /// are each the sum the walk of one light gives, pair for pair.
    #[test]
    fn a_light_and_a_unit_light_in_one_walk_are_each_its_own_sum() {
        let [lit, unit] = sheet(80, 0.25);
        let both = sums(&lit, 0.0, true);
        let light: Vec<_> = both.iter().map(|b| b[0]).collect();
        let under_unit: Vec<_> = both.iter().map(|b| b[1]).collect();
        let alone = |sources| {
            sums(sources, 0.0, false)
                .iter()
                .map(|b| b[0])
                .collect::<Vec<_>>()
        };
        assert!(worst(&light, &alone(&lit)) < 1e-6);
        assert!(worst(&under_unit, &alone(&unit)) < 1e-6);
    }

    /// At the error estimate's solid angle for thin parts, the walk of a
    /// light and a unit light is within 0.2% of their exact sums, the
    /// unit light's too (its nodes taken whole are read where the light's
    /// flux centres in them): on a sheet 30 mm wide of 0.1 mm texels,
    /// whose far nodes are taken whole (at 0.05 sr, 14% off).
    #[test]
    fn a_shared_walk_at_the_estimates_solid_angle_is_near_the_exact_sums() {
        let [lit, _] = sheet(300, 0.1);
        let reference = THIN_REFERENCE_EPSILON;
        let (exact, near) = (sums(&lit, 0.0, true), sums(&lit, reference, true));
        for light in 0..2 {
            let pick = |s: &[[[f32; 3]; 2]]| s.iter().map(|b| b[light]).collect::<Vec<_>>();
            let off = worst(&pick(&near), &pick(&exact));
            assert!(off > 0.0 && off < 0.002, "light {light}: {off}");
        }
    }
}
