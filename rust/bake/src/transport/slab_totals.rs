//! How much light a slab of a material returns and sends through, by
//! thickness, simulated by the Monte Carlo ([`sssbake_profile::models::monte_carlo`])
//! and kept on disk like the Monte Carlo profile's tallies.
//!
//! Totals by the Monte Carlo, not by diffusion: through a few mean free
//! paths at low albedo, diffusion's decay σtr is too steep and sends too
//! little light across (skin1's blue through 3 mm: half of it). Light
//! enters as the profiles have it, a pencil beam at normal incidence, per
//! unit flux entering: by reciprocity the same as light entering as
//! irradiance and leaving along the normal, which is what Cycles' DIFFUSE
//! bake of a Random Walk material sees and what the walk of this crate
//! scores.

use crate::monte_carlo_cache::{cache_dir, cached};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sssbake_profile::material::Layer;
use sssbake_profile::models::monte_carlo::{Settings, simulate};

/// Photons per thickness and channel: totals to about 1% where light
/// crosses.
const PHOTONS: u64 = 16_384;
/// One seed for every thickness, so the ladder's noise is smooth in t.
const SEED: u64 = 0x736c_6162;
/// Changes whenever the totals change meaning without the crate's version
/// changing.
const FORMAT: u32 = 2;

/// A layer's totals for a pencil beam entering one face at normal
/// incidence, per unit flux entering, per channel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlabTotals {
    /// The layer made semi-infinite: the light it returns, R_∞.
    pub semi_infinite: [f64; 3],
    /// Thicknesses, mm, as asked.
    pub thickness: Vec<f64>,
    /// At each thickness, the light returned through the entry face, R_t.
    pub reflectance: Vec<[f64; 3]>,
    /// At each thickness, the light sent out of the far face, T_t.
    pub transmittance: Vec<[f64; 3]>,
}

impl SlabTotals {
    /// True when every total is finite, within [0, 1] and one per thickness.
    fn is_sound(&self) -> bool {
        let fine = |v: &[f64; 3]| v.iter().all(|x| x.is_finite() && (0.0..=1.0).contains(x));
        self.reflectance.len() == self.thickness.len()
            && self.transmittance.len() == self.thickness.len()
            && fine(&self.semi_infinite)
            && self.reflectance.iter().all(fine)
            && self.transmittance.iter().all(fine)
    }
}

/// The totals of `layer` (its own thickness ignored) at each of
/// `thickness` (mm) and semi-infinite, read from the cache folder when
/// simulated before.
pub fn slab_totals(layer: &Layer, thickness: &[f64]) -> SlabTotals {
    let key = format!(
        "sssbake {} slab totals format {FORMAT}\nlayer {:?}\nphotons {PHOTONS} seed {SEED}\nthickness {thickness:?}",
        env!("CARGO_PKG_VERSION"),
        Layer {
            thickness_mm: None,
            ..layer.clone()
        },
    );
    cached(
        cache_dir().as_deref(),
        "slab",
        key,
        SlabTotals::is_sound,
        || simulate_totals(layer, thickness),
    )
}

fn simulate_totals(layer: &Layer, thickness: &[f64]) -> SlabTotals {
    let simulated = |thickness_mm: Option<f64>| {
        let slab = Layer {
            thickness_mm,
            ..layer.clone()
        };
        let tallies = simulate(
            std::slice::from_ref(&slab),
            &Settings::new(PHOTONS, SEED, vec![0.0, f64::MAX]),
        );
        let reflectance =
            [0, 1, 2].map(|c| tallies.total_reflectance[c] + tallies.unscattered_reflectance[c]);
        let transmittance = [0, 1, 2]
            .map(|c| tallies.total_transmittance[c] + tallies.unscattered_transmittance[c]);
        (reflectance, transmittance)
    };
    let semi_infinite = simulated(None).0;
    let (reflectance, transmittance) = thickness.par_iter().map(|&t| simulated(Some(t))).unzip();
    SlabTotals {
        semi_infinite,
        thickness: thickness.to_vec(),
        reflectance,
        transmittance,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_thicker_slab_returns_more_and_sends_less() {
        let layer = Layer::semi_infinite([0.05; 3], [1.0; 3], 1.3);
        let totals = simulate_totals(&layer, &[0.5, 2.0, 8.0]);
        assert!(totals.is_sound());
        for c in 0..3 {
            let r: Vec<f64> = totals.reflectance.iter().map(|v| v[c]).collect();
            let t: Vec<f64> = totals.transmittance.iter().map(|v| v[c]).collect();
            assert!(
                r[0] < r[1] && r[1] < r[2] && r[2] <= totals.semi_infinite[c] * 1.02,
                "{r:?}"
            );
            assert!(t[0] > t[1] && t[1] > t[2], "{t:?}");
            // Nothing made: what returns and what crosses is at most all.
            assert!(r[0] + t[0] <= 1.0);
        }
    }
}
