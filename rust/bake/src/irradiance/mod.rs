//! The irradiance transmitted into the surface at texels and sample
//! points: every light, shadowed by the whole scene, times the entry
//! Fresnel transmittance (docs/physics.md: the `irradiance` output).

pub mod bounce;
pub mod emitters;
pub mod entry;
pub mod environment;
pub mod incidence;
pub mod sequence;

use crate::control::{Cancelled, Control, parallel_fill};
use crate::rays::RayScene;
use emitters::Emitter;
use entry::EntryTransmittance;
use glam::Vec3;

/// Points on one mesh to light.
#[derive(Clone, Copy, Debug)]
pub struct Receivers<'a> {
    /// Which mesh of the [`RayScene`] they lie on.
    pub mesh: u32,
    /// Positions, mm.
    pub position: &'a [Vec3],
    /// Unit normals.
    pub normal: &'a [Vec3],
    /// The triangle of the mesh each lies on.
    pub triangle: &'a [u32],
}

/// How the irradiance is gathered.
#[derive(Clone, Debug)]
pub struct IrradianceSettings {
    /// Samples per receiver for each light with a size and for the
    /// environment (lights without a size take one).
    pub samples: u32,
    /// Trace shadow rays (the plan turns them off when nothing can occlude).
    pub shadows: bool,
}

impl Default for IrradianceSettings {
    fn default() -> Self {
        IrradianceSettings {
            samples: 16,
            shadows: true,
        }
    }
}

/// Transmitted irradiance E_t (W/m², linear RGB) at each receiver:
/// Σ over lights of ∫ ρt(θ) L(ω) cos θ dω with visibility through `rays`,
/// ρt per channel from `entry`.
pub fn transmitted_irradiance(
    receivers: Receivers,
    emitters: &[Emitter],
    rays: &RayScene,
    entry: &EntryTransmittance,
    settings: &IrradianceSettings,
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let mut out = vec![[0.0f32; 3]; receivers.position.len()];
    let lit = lit(emitters);
    parallel_fill(&mut out, 1024, control, |i| {
        let mut e = [0.0f32; 3];
        for (l, emitter) in lit.iter().enumerate() {
            let mut sum = [0.0f32; 3];
            light_samples(
                &receivers,
                i,
                l,
                emitter,
                rays,
                entry,
                settings,
                |_, _, v| {
                    for (s, v) in sum.iter_mut().zip(v) {
                        *s += v;
                    }
                },
            );
            let count = sample_count(emitter, settings) as f32;
            for c in 0..3 {
                let v = sum[c] / count;
                if v.is_finite() {
                    e[c] += v;
                }
            }
        }
        e
    })?;
    Ok(out)
}

/// Samples per receiver of `emitter`: one for a light without a size.
pub(crate) fn sample_count(emitter: &Emitter, settings: &IrradianceSettings) -> u32 {
    if emitter.is_delta() {
        1
    } else {
        settings.samples.max(1)
    }
}

/// Lit emitters (those that send any light).
pub(crate) fn lit(emitters: &[Emitter]) -> Vec<&Emitter> {
    emitters.iter().filter(|e| !e.is_dark()).collect()
}

/// Calls `visit(direction, cos θ, share)` for every sample of emitter `l`
/// seen from receiver `i` that is unoccluded and above its horizon:
/// `direction` towards the light, `share` its transmitted irradiance
/// times the light's [`sample_count`], W/m² per channel.
#[allow(clippy::too_many_arguments)]
pub(crate) fn light_samples(
    receivers: &Receivers,
    i: usize,
    l: usize,
    emitter: &Emitter,
    rays: &RayScene,
    entry: &EntryTransmittance,
    settings: &IrradianceSettings,
    mut visit: impl FnMut(Vec3, f32, [f32; 3]),
) {
    let p = receivers.position[i];
    let n = receivers.normal[i];
    let skip = rays.scene_triangle(receivers.mesh, receivers.triangle[i]);
    let origin = p + n * rays.epsilon();
    let count = sample_count(emitter, settings);
    // Samples alternate between the emitter's strategies; each
    // strategy draws from its own point set, so none of them sees
    // only part of the square.
    let strategies = emitter.strategies();
    for s in 0..count {
        let (strategy, j) = (s % strategies, s / strategies);
        let own = count.div_ceil(strategies);
        let rotation = sequence::rotation(i as u64, (l as u64) << 8 | strategy as u64);
        let u = sequence::hammersley(j, own, rotation);
        let Some(sample) = emitter.sample(p, n, u, strategy) else {
            continue;
        };
        let cos = sample.direction.dot(n);
        if cos <= 0.0 {
            continue;
        }
        if settings.shadows
            && emitter.casts_shadow()
            && rays.occluded(origin, sample.direction, sample.distance, skip)
        {
            continue;
        }
        let entering = entry.at_rgb(cos);
        let share = std::array::from_fn(|c| sample.weight[c] * cos * entering[c]);
        visit(sample.direction, cos, share);
    }
}
