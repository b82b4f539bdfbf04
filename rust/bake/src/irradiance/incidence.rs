//! Where the light entering each receiver comes from, as an oblique
//! kernel needs it ([`sssbake_profile::models::empirical::kernel`]): per incidence
//! node, the transmitted irradiance of the light samples assigned to it
//! and, per azimuthal harmonic k, that irradiance times (cos kα, sin kα),
//! α being the azimuth of the light's travel direction on the tangent
//! plane in the receiver's frame ([`frame`]).
//!
//! Every light sample keeps its own incidence: a directional, point or
//! spot light is one direction per receiver, an area light or the
//! environment as many as it has samples. The environment therefore needs
//! no azimuthal-mean stand-in; its samples' azimuths average out where the
//! sky is even. Incidence is the outside angle to the receiver's normal;
//! the kernel's nodes say how it refracts inside.

use super::sequence::basis;
use super::{IrradianceSettings, Receivers, light_samples, lit, sample_count};
use crate::control::{Cancelled, Control, parallel_fill};
use crate::irradiance::emitters::Emitter;
use crate::irradiance::entry::EntryTransmittance;
use crate::rays::RayScene;
use glam::Vec3;
use sssbake_profile::models::empirical::kernel::ObliqueKernel;
use sssbake_profile::models::empirical::oblique::{HARMONICS_KEPT, INCIDENCE_NODES};

/// Components per node: the irradiance, then cos kα and sin kα weights for
/// k = 1 … [`HARMONICS_KEPT`] − 1.
pub const COMPONENTS: usize = 2 * HARMONICS_KEPT - 1;
/// Incidence nodes.
pub const NODES: usize = INCIDENCE_NODES.len();

/// One receiver's incident light by node and component, W/m² per channel:
/// `[node][component][channel]`.
pub type IncidentHarmonics = [[[f32; 3]; COMPONENTS]; NODES];

/// The tangent frame (u, v) azimuths are measured in at a point of unit
/// normal `n`: the same at a source and wherever its kernel is read.
pub fn frame(n: Vec3) -> (Vec3, Vec3) {
    basis(n)
}

/// The incident harmonics of every receiver (the irradiance as
/// [`super::transmitted_irradiance`] gathers it, split by incidence).
pub fn incident_harmonics(
    receivers: Receivers,
    emitters: &[Emitter],
    rays: &RayScene,
    entry: &EntryTransmittance,
    settings: &IrradianceSettings,
    control: &Control,
) -> Result<Vec<IncidentHarmonics>, Cancelled> {
    let zero = [[[0.0f32; 3]; COMPONENTS]; NODES];
    let mut out = vec![zero; receivers.position.len()];
    let lit = lit(emitters);
    parallel_fill(&mut out, 256, control, |i| {
        let n = receivers.normal[i];
        let (u, v) = frame(n);
        let mut h = zero;
        for (l, emitter) in lit.iter().enumerate() {
            let scale = 1.0 / sample_count(emitter, settings) as f32;
            let mut light = zero;
            light_samples(
                &receivers,
                i,
                l,
                emitter,
                rays,
                entry,
                settings,
                |d, cos, e| {
                    // The light travels along −d; its part along the surface.
                    let travel = -(d - n * cos);
                    let alpha = travel.dot(v).atan2(travel.dot(u));
                    for (node, w) in ObliqueKernel::node_weights(cos as f64) {
                        let w = w as f32 * scale;
                        if w == 0.0 {
                            continue;
                        }
                        let slot = &mut light[node];
                        for c in 0..3 {
                            slot[0][c] += w * e[c];
                        }
                        for k in 1..HARMONICS_KEPT {
                            let (s, co) = (k as f32 * alpha).sin_cos();
                            for c in 0..3 {
                                slot[2 * k - 1][c] += w * e[c] * co;
                                slot[2 * k][c] += w * e[c] * s;
                            }
                        }
                    }
                },
            );
            // A light whose samples are not finite adds nothing, as in
            // the irradiance.
            if light.iter().flatten().flatten().all(|x| x.is_finite()) {
                for (a, b) in h
                    .iter_mut()
                    .flatten()
                    .flatten()
                    .zip(light.iter().flatten().flatten())
                {
                    *a += b;
                }
            }
        }
        h
    })?;
    Ok(out)
}
