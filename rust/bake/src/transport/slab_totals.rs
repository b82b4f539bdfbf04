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
use crate::transport::shares::{is_share, most_per_channel};
use crate::transport::walk_budget::{EVENT_BUDGET, PILOT_EVENTS, PILOT_WALKS, Walks, afford};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sssbake_profile::material::Layer;
use sssbake_profile::models::monte_carlo::{Settings, simulate};

/// Photons per thickness and channel: totals to about 1% where light
/// crosses.
const PHOTONS: u64 = 16_384;
/// The fewest photons per thickness and channel when the work's budget
/// cannot afford [`PHOTONS`] ([`crate::transport::walk_budget`]): totals
/// to a few per cent.
const FEWEST_PHOTONS: u64 = 512;
/// One seed for every thickness, so the ladder's noise is smooth in t.
const SEED: u64 = 0x736c_6162;
/// Changes whenever the totals change meaning without the crate's version
/// changing.
const FORMAT: u32 = 3;

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
    /// Per channel, the most light any of the runs stopped before it left
    /// (photons that met the limit on their events, [`affordable`]), as a
    /// share of the flux entering: by at most this much each total is low.
    /// 0 where every photon finished.
    pub unfinished: [f64; 3],
}

impl SlabTotals {
    /// True when every total is finite, within [0, 1] and one per thickness.
    fn is_sound(&self) -> bool {
        self.reflectance.len() == self.thickness.len()
            && self.transmittance.len() == self.thickness.len()
            && is_share(&self.semi_infinite)
            && is_share(&self.unfinished)
            && self.reflectance.iter().all(is_share)
            && self.transmittance.iter().all(is_share)
    }
}

/// The totals of `layer` (its own thickness ignored) at each of
/// `thickness` (mm) and semi-infinite, read from the cache folder when
/// simulated before.
pub fn slab_totals(layer: &Layer, thickness: &[f64]) -> SlabTotals {
    let key = format!(
        "sssbake {} slab totals format {FORMAT}\nlayer {:?}\nphotons {PHOTONS} seed {SEED} budget {EVENT_BUDGET}\nthickness {thickness:?}",
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

/// The Monte Carlo's settings for the `simulations` of `layer`'s totals
/// (a semi-infinite one among them) within `budget` events: [`PHOTONS`]
/// and the Monte Carlo's own limit on a photon's events unless a pilot in
/// the semi-infinite layer, whose photons walk longest, finds them too
/// costly ([`afford`]).
fn affordable(layer: &Layer, simulations: usize, budget: f64) -> Settings {
    let all = Settings::new(PHOTONS, SEED, vec![0.0, f64::MAX]);
    let pilot = Settings {
        photons: PILOT_WALKS,
        max_interactions: PILOT_EVENTS,
        ..all.clone()
    };
    let semi_infinite = Layer {
        thickness_mm: None,
        ..layer.clone()
    };
    let walked = simulate(std::slice::from_ref(&semi_infinite), &pilot).interactions;
    let mean = walked as f64 / (3 * PILOT_WALKS) as f64;
    let wanted = Walks {
        count: all.photons,
        max_events: all.max_interactions,
    };
    let walks = afford(mean, simulations, wanted, FEWEST_PHOTONS, budget);
    Settings {
        photons: walks.count,
        max_interactions: walks.max_events,
        ..all
    }
}

fn simulate_totals(layer: &Layer, thickness: &[f64]) -> SlabTotals {
    simulate_within(layer, thickness, EVENT_BUDGET).0
}

/// [`simulate_totals`] within `budget` events ([`affordable`]), with the
/// events the simulations took.
fn simulate_within(layer: &Layer, thickness: &[f64], budget: f64) -> (SlabTotals, u64) {
    let settings = affordable(layer, thickness.len() + 1, budget);
    let simulated = |thickness_mm: Option<f64>| {
        let slab = Layer {
            thickness_mm,
            ..layer.clone()
        };
        let tallies = simulate(std::slice::from_ref(&slab), &settings);
        let reflectance =
            [0, 1, 2].map(|c| tallies.total_reflectance[c] + tallies.unscattered_reflectance[c]);
        let transmittance = [0, 1, 2]
            .map(|c| tallies.total_transmittance[c] + tallies.unscattered_transmittance[c]);
        let run = Run {
            reflectance,
            transmittance,
            unfinished: [0, 1, 2].map(|c| tallies.truncated[c]),
        };
        (run, tallies.interactions)
    };
    let (semi_infinite, mut events) = simulated(None);
    let (runs, walked): (Vec<Run>, Vec<u64>) =
        thickness.par_iter().map(|&t| simulated(Some(t))).unzip();
    events += walked.iter().sum::<u64>();
    let unfinished = most_per_channel(semi_infinite.unfinished, runs.iter().map(|r| r.unfinished));
    let totals = SlabTotals {
        semi_infinite: semi_infinite.reflectance,
        thickness: thickness.to_vec(),
        reflectance: runs.iter().map(|r| r.reflectance).collect(),
        transmittance: runs.iter().map(|r| r.transmittance).collect(),
        unfinished,
    };
    (totals, events)
}

/// One run's totals, per unit flux entering, per channel.
struct Run {
    reflectance: [f64; 3],
    transmittance: [f64; 3],
    unfinished: [f64; 3],
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every preset keeps its photons and the Monte Carlo's own limit:
    /// the budget binds only past any material in the list.
    #[test]
    fn the_presets_are_simulated_in_full() {
        let full = Settings::new(PHOTONS, SEED, vec![0.0, f64::MAX]);
        for (name, _) in sssbake_profile::presets::list() {
            let material = sssbake_profile::presets::preset(name).unwrap();
            for layer in material.layers().unwrap_or(&[]) {
                let settings = affordable(layer, 33, EVENT_BUDGET);
                assert_eq!(settings.photons, full.photons, "{name}");
                assert_eq!(settings.max_interactions, full.max_interactions, "{name}");
            }
        }
    }

    /// Found by the sweep of extreme inputs (seed 7, case 1): a medium of
    /// albedo 0.999999 scattering nearly straight ahead (g 0.99, σt
    /// 23340 /mm, η 2.1) walked so long that its totals ran for hours.
    /// Within a budget its photons are fewer and stopped early, the work
    /// stays within it, and the totals are still shares of what entered.
    #[test]
    fn a_medium_that_walks_for_ever_is_simulated_within_its_budget() {
        let layer = crate::transport::walk_budget::walking_for_ever();
        let budget = 2e7;
        let settings = affordable(&layer, 4, budget);
        assert!(settings.photons < PHOTONS, "{settings:?}");
        let (totals, events) = simulate_within(&layer, &[0.01, 0.1, 1.0], budget);
        assert!(totals.is_sound(), "{totals:?}");
        assert!((events as f64) <= budget, "{events} events");
        // Stopped photons are counted: the totals say how low they may be.
        assert!(totals.unfinished.iter().any(|&u| u > 0.01), "{totals:?}");
        // What a stopped photon carried is dropped, never made: a thicker
        // slab still returns no more than the semi-infinite layer.
        for r in &totals.reflectance[1..] {
            assert!(
                (0..3).all(|c| r[c] <= totals.semi_infinite[c] + 1e-12),
                "{totals:?}"
            );
        }
    }

    #[test]
    fn a_thicker_slab_returns_more_and_sends_less() {
        let layer = Layer::semi_infinite([0.05; 3], [1.0; 3], 1.3);
        let totals = simulate_totals(&layer, &[0.5, 2.0, 8.0]);
        assert!(totals.is_sound());
        // Every photon finished within the Monte Carlo's own limit.
        assert_eq!(totals.unfinished, [0.0; 3]);
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
