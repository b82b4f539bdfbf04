//! Stacks of slabs over an optional semi-infinite base, combined per spatial
//! frequency (Mikkelsen 2.7.2–2.7.3, after Donner & Jensen 2005) and brought
//! back to R(r), T(r) by one inverse Hankel transform.

use crate::diffusion::slab::{Face, Incidence, SideResponse, SlabChannel, SlabResponse};
use crate::diffusion::split::{Split, SplitSlab, combine};
use crate::material::Layer;
use crate::models::tabulated::Tabulated;
use crate::numerics::hankel::inverse_hankel_many;
use crate::profile::Profile;
use crate::{Rgb, rgb_map};

/// Transform values below this fraction of the largest are the transform's
/// round-off, not signal, and are set to zero.
const NOISE_FLOOR: f64 = 1e-11;

/// The slabs of a stack, per channel, with indices of their neighbours.
#[derive(Clone, Debug)]
pub struct Stack {
    channels: [Vec<SlabChannel>; 3],
}

impl Stack {
    /// Slabs for `layers` (top first) under air; a finite last layer has air below.
    pub fn new(layers: &[Layer]) -> Self {
        Self::with_roughness(layers, 0.0)
    }

    /// [`Self::new`] with the faces against air (the top, and the bottom of
    /// a finite stack) rough with RMS facet slope `roughness`; the faces
    /// between layers stay smooth.
    pub fn with_roughness(layers: &[Layer], roughness: f64) -> Self {
        let index_above = |i: usize| if i == 0 { 1.0 } else { layers[i - 1].ior };
        let index_below = |i: usize| layers.get(i + 1).map_or(1.0, |l| l.ior);
        let last = layers.len().saturating_sub(1);
        let faces: Vec<(Face, Face)> = layers
            .iter()
            .enumerate()
            .map(|(i, layer)| {
                let rough = |against_air: bool| if against_air { roughness } else { 0.0 };
                (
                    Face::new(layer.ior / index_above(i), rough(i == 0)),
                    Face::new(layer.ior / index_below(i), rough(i == last)),
                )
            })
            .collect();
        Self {
            channels: [0, 1, 2].map(|c| {
                layers
                    .iter()
                    .enumerate()
                    .map(|(i, layer)| {
                        SlabChannel::with_faces(
                            layer.medium(c),
                            layer.thickness_mm.unwrap_or(f64::INFINITY),
                            faces[i].0,
                            faces[i].1,
                            if i == 0 {
                                Incidence::Collimated
                            } else {
                                Incidence::Diffuse
                            },
                        )
                    })
                    .collect()
            }),
        }
    }

    /// The stack without its top slab: the layers below a top layer that
    /// is solved another way ([`crate::models::stam::topped`]). Each keeps the
    /// faces and incidence it had under the top layer.
    pub fn without_top(mut self) -> Self {
        for channel in &mut self.channels {
            if !channel.is_empty() {
                channel.remove(0);
            }
        }
        self
    }

    /// The slabs of channel `c`, top first.
    pub fn channel(&self, c: usize) -> &[SlabChannel] {
        &self.channels[c]
    }

    /// The whole stack's response to light from above and from below at
    /// angular frequency `k` (rad/mm) in channel `c`, kept in its
    /// unscattered and diffuse parts.
    pub fn split_response(&self, c: usize, k: f64) -> SplitSlab {
        let mut slabs = self.channels[c].iter().map(|s| s.split_response(k));
        let first = slabs.next().unwrap_or_else(SplitSlab::transparent);
        slabs.fold(first, combine)
    }

    /// The stack's whole response (unscattered and diffuse) at `k`.
    pub fn frequency_response(&self, c: usize, k: f64) -> SlabResponse {
        self.split_response(c, k).map(Split::total)
    }

    /// Light the stack reflects and transmits without scattering in channel
    /// `c` (deltas at r = 0; the same at every frequency).
    pub fn ballistic(&self, c: usize) -> SideResponse {
        self.split_response(c, 0.0).map(|s| s.ballistic).down
    }

    /// (shortest, longest) length in mm over all slabs and channels.
    pub fn length_scales(&self) -> (f64, f64) {
        let mut scales = (f64::INFINITY, 0.0f64);
        for slab in self.channels.iter().flatten() {
            let (s, l) = slab.length_scales();
            scales = (scales.0.min(s), scales.1.max(l));
        }
        scales
    }
}

/// A layered material's profiles, tabulated from the exact frequency response.
#[derive(Clone, Debug)]
pub struct Layered {
    stack: Stack,
    table: Tabulated,
}

impl Layered {
    /// Profiles of `layers` (top first; only the last may be semi-infinite).
    pub fn new(layers: &[Layer]) -> Self {
        Self::with_roughness(layers, 0.0)
    }

    /// [`Self::new`] under a rough surface of RMS facet slope `roughness`
    /// ([`Stack::with_roughness`]).
    pub fn with_roughness(layers: &[Layer], roughness: f64) -> Self {
        let stack = Stack::with_roughness(layers, roughness);
        let table = tabulate("layered", stack.length_scales(), |c, k| {
            stack.split_response(c, k).map(|s| s.diffuse).down
        });
        Self { stack, table }
    }

    /// The underlying stack.
    pub fn stack(&self) -> &Stack {
        &self.stack
    }
}

/// Tabulates R(r) and T(r) from `diffuse(channel, k)`, the diffuse response
/// to light from above, on a log grid wide enough for lengths `scales` =
/// (shortest, longest) in mm that the transform neither wraps nor misses
/// the peak.
pub fn tabulate(
    model: &'static str,
    scales: (f64, f64),
    diffuse: impl Fn(usize, f64) -> SideResponse,
) -> Tabulated {
    let (shortest, longest) = scales;
    let r_min = 1e-3 * shortest;
    let r_max = 1e5 * longest;
    let (radii, values) = inverse_hankel_many(
        6,
        |k, out: &mut [f64]| {
            for c in 0..3 {
                let down = diffuse(c, k);
                out[2 * c] = down.reflectance;
                out[2 * c + 1] = down.transmittance;
            }
        },
        r_min,
        r_max,
    );
    let clean = |v: &Vec<f64>| {
        let peak = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        v.iter()
            .map(|&x| if x.abs() > NOISE_FLOOR * peak { x } else { 0.0 })
            .collect::<Vec<_>>()
    };
    let totals = [0, 1, 2].map(|c| diffuse(c, 0.0));
    let mut values: Vec<Vec<f64>> = values.iter().map(clean).collect();
    for (i, series) in values.iter_mut().enumerate() {
        let total = if i % 2 == 0 {
            totals[i / 2].reflectance
        } else {
            totals[i / 2].transmittance
        };
        end_where_complete(&radii, series, total);
    }
    // Drop the far tail where every channel is zero.
    let last = (0..radii.len())
        .rev()
        .find(|&i| values.iter().any(|v| v[i] != 0.0))
        .map_or(1, |i| (i + 2).min(radii.len()));
    let at = |i: usize, offset: usize| rgb_map(|c| values[2 * c + offset][i]);
    Tabulated::new(
        model,
        radii[..last].to_vec(),
        (0..last).map(|i| at(i, 0)).collect(),
        (0..last).map(|i| at(i, 1)).collect(),
        totals.map(|t| t.reflectance),
        totals.map(|t| t.transmittance),
    )
}

/// Ends `values` (f(r) on the log grid `radii`) where its enclosed integral
/// ∫ 2πr f dr comes closest to `total`, the spectrum at k = 0: what follows
/// only takes it away again, the transform's round-off, tiny against the
/// peak but spread over a window that reaches 10⁵ times the longest scale,
/// where a floor of 10⁻⁹ of the peak would otherwise add many times the
/// total (a slab 6·10⁻⁵ mm thick: 35 times).
fn end_where_complete(radii: &[f64], values: &mut [f64], total: f64) {
    if total.is_nan() || total <= 0.0 || values.len() < 2 {
        return;
    }
    let ring = |j: usize| 2.0 * std::f64::consts::PI * radii[j] * values[j];
    let (mut enclosed, mut best, mut best_gap) = (0.0, values.len() - 1, f64::INFINITY);
    for i in 1..values.len() {
        enclosed += 0.5 * (ring(i - 1) + ring(i)) * (radii[i] - radii[i - 1]);
        let gap = (enclosed - total).abs();
        if gap < best_gap {
            (best, best_gap) = (i, gap);
        }
    }
    values[best + 1..].fill(0.0);
}

impl Profile for Layered {
    fn model(&self) -> &'static str {
        "layered"
    }
    fn reflectance(&self, r: f64) -> Rgb {
        self.table.reflectance(r)
    }
    fn transmittance(&self, r: f64) -> Rgb {
        self.table.transmittance(r)
    }
    fn total_reflectance(&self) -> Rgb {
        self.table.total_reflectance()
    }
    fn total_transmittance(&self) -> Rgb {
        self.table.total_transmittance()
    }
    fn ballistic_reflectance(&self) -> Rgb {
        rgb_map(|c| self.stack.ballistic(c).reflectance)
    }
    fn reflectance_spectrum(&self, k: f64) -> Option<Rgb> {
        Some(rgb_map(|c| {
            self.stack.split_response(c, k).down.reflectance.diffuse
        }))
    }
    fn ballistic_transmittance(&self) -> Rgb {
        rgb_map(|c| self.stack.ballistic(c).transmittance)
    }
    fn enclosed_reflectance(&self, r: f64) -> Rgb {
        self.table.enclosed_reflectance(r)
    }
    fn length_scale(&self) -> Rgb {
        self.table.length_scale()
    }
}
