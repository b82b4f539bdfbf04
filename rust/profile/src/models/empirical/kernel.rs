//! The empirical model's exitance kernel at oblique incidence, in mm, for
//! a bake: per channel and incidence node, the azimuthal harmonics
//! m₀(r) … m₄(r) of E(r, θ_s; θ_i) = m₀ + Σ_k m_k cos kθ_s, constant over
//! each tallied annulus and scaled by σt (eq. 12).
//!
//! Normal incidence is the normal-incidence profile itself (its lobes'
//! exitance, [`crate::models::empirical::EmpiricalProfile`]), with no harmonic
//! (radial symmetry). Between nodes the kernel is linear in sin θ_i
//! outside ([`crate::models::empirical::oblique`] says why), so a light's
//! contribution splits over its two nearest nodes with weights summing to
//! 1, and the kernel of a sum of lights is the sum over nodes of each
//! node's harmonics times the lights' summed weights (a weight and, per
//! harmonic k, the weights times (cos kα, sin kα) of each light's azimuth
//! α): exact per light, at a cost set by nodes × harmonics, not by the
//! lights.
//!
//! Harmonics past [`HARMONICS_KEPT`] are dropped: over the plane they hold
//! [`ObliqueKernel::truncation_error`] of the kernel (relative L2); they
//! add nothing to the total or the centroid, and a truncated series can
//! dip below zero behind the entry point, so a sum of them is clamped at
//! zero where it is read.

use crate::material::Material;
use crate::models::empirical::EmpiricalProfile;
use crate::models::empirical::oblique::{HARMONICS_KEPT, INCIDENCE_NODES, ObliqueSlice};
use crate::profile::Profile;
use std::f64::consts::PI;

/// One annulus's harmonics m₀ … m₄, 1/mm² per unit flux entering.
pub type Harmonics = [f64; HARMONICS_KEPT];

/// One channel's tables, mm.
#[derive(Clone, Debug)]
struct Channel {
    /// Annulus edges, mm, from 0.
    edges_mm: Vec<f64>,
    /// `harmonics[node][b]`.
    harmonics: Vec<Vec<Harmonics>>,
    /// `enclosed[node][b]`: ∫ m₀ dA inside the outer edge of annulus b.
    enclosed: Vec<Vec<f64>>,
}

/// The oblique exitance kernel of a material (see the module doc).
#[derive(Clone, Debug)]
pub struct ObliqueKernel {
    channels: [Channel; 3],
    truncation: [f64; 3],
}

/// A light's share of each node: (node, weight), two entries.
pub type NodeWeights = [(usize, f64); 2];

impl ObliqueKernel {
    /// The kernel of `material` from its normal-incidence `profile` and
    /// its channels' oblique tallies; `Err` when they do not belong
    /// together.
    pub fn new(
        material: &Material,
        profile: &EmpiricalProfile,
        oblique: &[ObliqueSlice; 3],
    ) -> Result<Self, String> {
        let top = material
            .layers()
            .and_then(|l| l.first())
            .ok_or("a measured sum of Gaussians has no optical coefficients")?;
        for (c, slice) in oblique.iter().enumerate() {
            if slice.edges_mfp != profile.slices()[c].edges_mfp
                || slice.nodes.len() + 1 != INCIDENCE_NODES.len()
            {
                return Err(format!(
                    "the oblique tallies of channel {c} are on other annuli or nodes"
                ));
            }
        }
        let channels = [0, 1, 2].map(|c| {
            let slice = &profile.slices()[c];
            let sigma_t = top.sigma_a[c] + top.sigma_s[c];
            let usable = sigma_t.is_finite() && sigma_t > 0.0;
            let scale = if usable { sigma_t * sigma_t } else { 0.0 };
            let edges_mm: Vec<f64> = if usable {
                slice.edges_mfp.iter().map(|e| e / sigma_t).collect()
            } else {
                vec![0.0]
            };
            let bins = edges_mm.len().saturating_sub(1);
            // The profile is constant over each annulus: read its middle.
            let normal: Vec<Harmonics> = (0..bins)
                .map(|b| {
                    let mut h = [0.0; HARMONICS_KEPT];
                    h[0] = profile.reflectance(0.5 * (edges_mm[b] + edges_mm[b + 1]))[c];
                    h
                })
                .collect();
            let mut harmonics = vec![normal];
            for node in &oblique[c].nodes {
                harmonics.push(
                    (0..bins)
                        .map(|b| {
                            let mut h = [0.0; HARMONICS_KEPT];
                            if let Some(m) = node.harmonics.get(b) {
                                for (h, m) in h.iter_mut().zip(m) {
                                    *h = if m.is_finite() { m * scale } else { 0.0 };
                                }
                            }
                            h[0] = h[0].max(0.0);
                            h
                        })
                        .collect(),
                );
            }
            let enclosed = harmonics
                .iter()
                .map(|node| {
                    let mut sum = 0.0;
                    node.iter()
                        .zip(edges_mm.windows(2))
                        .map(|(h, e)| {
                            sum += h[0] * PI * (e[1] * e[1] - e[0] * e[0]);
                            sum
                        })
                        .collect()
                })
                .collect();
            Channel {
                edges_mm,
                harmonics,
                enclosed,
            }
        });
        let truncation = [0, 1, 2].map(|c| oblique[c].truncation_error(HARMONICS_KEPT));
        Ok(Self {
            channels,
            truncation,
        })
    }

    /// The nodes' sin θ_i outside.
    pub fn nodes() -> &'static [f64] {
        &INCIDENCE_NODES
    }

    /// The share of each node for light arriving at outside cosine
    /// `cos_outside` to the normal: linear in sin θ_i between the two
    /// nodes around it.
    pub fn node_weights(cos_outside: f64) -> NodeWeights {
        let cos = if cos_outside.is_finite() {
            cos_outside.clamp(0.0, 1.0)
        } else {
            1.0
        };
        let sin = (1.0 - cos * cos).sqrt();
        let last = INCIDENCE_NODES.len() - 1;
        let i = INCIDENCE_NODES
            .partition_point(|&s| s <= sin)
            .clamp(1, last);
        let (s0, s1) = (INCIDENCE_NODES[i - 1], INCIDENCE_NODES[i]);
        let f = ((sin - s0) / (s1 - s0)).clamp(0.0, 1.0);
        [(i - 1, 1.0 - f), (i, f)]
    }

    /// The annulus holding `r` mm in channel `c`, if any.
    pub fn annulus(&self, c: usize, r: f64) -> Option<usize> {
        let edges = &self.channels[c].edges_mm;
        let i = edges.partition_point(|&e| e <= r.max(0.0));
        (i >= 1 && i < edges.len()).then(|| i - 1)
    }

    /// Node `node`'s harmonics over annulus `b` of channel `c` (see
    /// [`Self::annulus`]), 1/mm² per unit flux entering.
    pub fn harmonics_in(&self, node: usize, c: usize, b: usize) -> &Harmonics {
        &self.channels[c].harmonics[node][b]
    }

    /// Node `node`'s harmonics at `r` mm in channel `c`, 1/mm² per unit
    /// flux entering; zero beyond the last annulus.
    pub fn harmonics(&self, node: usize, c: usize, r: f64) -> Harmonics {
        let ch = &self.channels[c];
        match self.annulus(c, r) {
            Some(b) if node < ch.harmonics.len() => ch.harmonics[node][b],
            _ => [0.0; HARMONICS_KEPT],
        }
    }

    /// ∫ m₀ dA over the disc of radius `r` mm around the entry point, node
    /// `node`, channel `c`: the share of the light entering at one point
    /// that leaves within `r` (the harmonics integrate to zero there).
    pub fn enclosed(&self, node: usize, c: usize, r: f64) -> f64 {
        let ch = &self.channels[c];
        let Some(table) = ch.enclosed.get(node) else {
            return 0.0;
        };
        let total = table.last().copied().unwrap_or(0.0);
        if r.is_nan() || r <= 0.0 {
            return 0.0;
        }
        match self.annulus(c, r) {
            None => total,
            Some(b) => {
                let inner = if b == 0 { 0.0 } else { table[b - 1] };
                let e0 = ch.edges_mm[b];
                inner + ch.harmonics[node][b][0] * PI * (r * r - e0 * e0)
            }
        }
    }

    /// E(r, θ_s) in channel `c` for light at outside cosine `cos_outside`,
    /// 1/mm² per unit flux entering, `theta_s` the angle (rad) between the
    /// offset from the entry point and the light's travel direction on the
    /// surface; clamped at zero.
    pub fn exitance(&self, c: usize, r: f64, theta_s: f64, cos_outside: f64) -> f64 {
        let v: f64 = Self::node_weights(cos_outside)
            .iter()
            .map(|&(j, w)| {
                let h = self.harmonics(j, c, r);
                let series: f64 = h
                    .iter()
                    .enumerate()
                    .map(|(k, m)| m * (k as f64 * theta_s).cos())
                    .sum();
                w * series
            })
            .sum();
        if v.is_finite() { v.max(0.0) } else { 0.0 }
    }

    /// Total diffuse reflectance at outside cosine `cos_outside`.
    pub fn total(&self, c: usize, cos_outside: f64) -> f64 {
        Self::node_weights(cos_outside)
            .iter()
            .map(|&(j, w)| w * self.enclosed(j, c, f64::INFINITY))
            .sum()
    }

    /// The exitance's mean position along the light's travel direction on
    /// the surface, mm: π ∫ m₁ r² dr over the total.
    pub fn centroid(&self, c: usize, cos_outside: f64) -> f64 {
        let ch = &self.channels[c];
        let moment: f64 = Self::node_weights(cos_outside)
            .iter()
            .map(|&(j, w)| {
                w * ch.harmonics[j]
                    .iter()
                    .zip(ch.edges_mm.windows(2))
                    .map(|(h, e)| h[1] * PI * (e[1].powi(3) - e[0].powi(3)) / 3.0)
                    .sum::<f64>()
            })
            .sum();
        let total = self.total(c, cos_outside);
        if total > 0.0 { moment / total } else { 0.0 }
    }

    /// The outermost radius with light, mm, over the channels.
    pub fn reach(&self) -> f64 {
        self.channels
            .iter()
            .filter_map(|ch| ch.edges_mm.last().copied())
            .fold(0.0, f64::max)
    }

    /// Relative L2 error per channel of dropping the harmonics past
    /// [`HARMONICS_KEPT`].
    pub fn truncation_error(&self) -> [f64; 3] {
        self.truncation
    }
}
