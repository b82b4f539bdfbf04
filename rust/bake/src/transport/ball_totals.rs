//! How much light a ball of a material returns, by radius, against a
//! half-space of it: the walk of [`crate::walk`] confined to the exact
//! shapes, kept on disk like the slab's totals.
//!
//! A profile of a semi-infinite medium takes the light that goes deep to
//! be absorbed, or to come out far away; in a small convex body much of it
//! meets the surface sooner and comes out (Vicini et al. 2019 show
//! planar profiles failing so). A uniformly lit ball says by how much:
//! every point of it is alike, so the share of a pencil beam's flux that
//! leaves it anywhere is what each point returns under uniform light.
//!
//! Light enters as the slab's totals have it, a pencil beam at normal
//! incidence, per unit flux entering, and each radius walks the same
//! random streams as the half-space, so their ratio is far quieter than
//! either.

use crate::monte_carlo_cache::{cache_dir, cached};
use crate::transport::shares::{is_share, most_per_channel, share_of};
use crate::transport::walk_budget::{EVENT_BUDGET, PILOT_EVENTS, PILOT_WALKS, Walks, afford};
use crate::walk::path::{Confinement, Ending, WalkStart, walk};
use crate::walk::shapes::{Ball, HalfSpace};
use crate::walk::{ChannelMedium, WalkMedium};
use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sssbake_profile::material::{Layer, Material, Optics};
use sssbake_profile::numerics::rng::Rng;

/// Walks per radius and channel: a ball's return over the half-space's to
/// well under 1% (their streams are shared).
const WALKS: u64 = 8192;
/// The fewest walks per radius and channel when the work's budget cannot
/// afford [`WALKS`] ([`crate::transport::walk_budget`]).
const FEWEST_WALKS: u64 = 256;
/// The bound on events per walk: far past where Russian roulette ends the
/// walks of any albedo short of 1.
const MAX_EVENTS: u32 = 100_000;
/// One seed for every radius, so the ladder's noise is smooth in r.
const SEED: u64 = 0x6261_6c6c;
/// Changes whenever the totals change meaning without the crate's version
/// changing.
const FORMAT: u32 = 2;

/// The light balls of one material return, per channel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BallTotals {
    /// The half-space's return, R_∞ by the walk.
    pub half_space: [f64; 3],
    /// Radii, mm, as asked.
    pub radius: Vec<f64>,
    /// At each radius, the share of the flux entering that leaves the ball.
    pub returned: Vec<[f64; 3]>,
    /// Per channel, the most light of the flux entering that any run's
    /// walks carried when the bound on their events stopped them (0 where
    /// every walk ended): a total may be low by as much.
    #[serde(default)]
    pub unfinished: [f64; 3],
}

impl BallTotals {
    /// True when every total is finite, within [0, 1] and one per radius.
    fn is_sound(&self) -> bool {
        self.returned.len() == self.radius.len()
            && is_share(&self.half_space)
            && is_share(&self.unfinished)
            && self.returned.iter().all(is_share)
    }

    /// Per radius and channel, the ball's return over the half-space's
    /// (1 for a channel the half-space returns nothing of).
    pub fn over_half_space(&self) -> Vec<[f64; 3]> {
        self.returned
            .iter()
            .map(|r| {
                [0, 1, 2].map(|c| {
                    let ratio = r[c] / self.half_space[c];
                    if ratio.is_finite() { ratio } else { 1.0 }
                })
            })
            .collect()
    }

    /// Per channel, the most a ball's return over the half-space's may be
    /// off by where the bound on the walks' events binds, as a share of
    /// the half-space's return (0 where every walk ended).
    pub fn unfinished_share(&self) -> [f64; 3] {
        share_of(self.unfinished, self.half_space)
    }
}

/// The totals of `layer` (its own thickness ignored) for balls of each of
/// `radius` (mm) and for the half-space, read from the cache folder when
/// walked before.
pub fn ball_totals(layer: &Layer, radius: &[f64]) -> BallTotals {
    let layer = Layer {
        thickness_mm: None,
        ..layer.clone()
    };
    let key = format!(
        "sssbake {} ball totals format {FORMAT}\nlayer {layer:?}\nwalks {WALKS} seed {SEED} \
         max_events {MAX_EVENTS} budget {EVENT_BUDGET}\nradius {radius:?}",
        env!("CARGO_PKG_VERSION"),
    );
    cached(
        cache_dir().as_deref(),
        "ball",
        key,
        BallTotals::is_sound,
        || walk_totals(&layer, radius),
    )
}

fn walk_totals(layer: &Layer, radius: &[f64]) -> BallTotals {
    walk_within(layer, radius, EVENT_BUDGET).0
}

/// [`walk_totals`] within `budget` events ([`affordable`]), with the
/// events the walks took.
fn walk_within(layer: &Layer, radius: &[f64], budget: f64) -> (BallTotals, u64) {
    let material = Material {
        name: String::new(),
        optics: Optics::Layers(vec![layer.clone()]),
        coat_ior: None,
        roughness: 0.0,
        top_layer: Default::default(),
    };
    // One layer with coefficients always makes a medium.
    let Ok(medium) = WalkMedium::of_material(&material) else {
        let none = BallTotals {
            half_space: [0.0; 3],
            radius: radius.to_vec(),
            returned: vec![[0.0; 3]; radius.len()],
            unfinished: [0.0; 3],
        };
        return (none, 0);
    };
    let walks = affordable(&medium, radius.len() + 1, budget);
    let half_space = shares(&HalfSpace, Vec3::ZERO, &medium, walks);
    let balls: Vec<Walked> = radius
        .par_iter()
        .map(|&r| {
            shares(
                &Ball { radius: r },
                Vec3::new(0.0, 0.0, r as f32),
                &medium,
                walks,
            )
        })
        .collect();
    let events = half_space.events + balls.iter().map(|b| b.events).sum::<u64>();
    let unfinished = most_per_channel(half_space.unfinished, balls.iter().map(|b| b.unfinished));
    let totals = BallTotals {
        half_space: half_space.returned,
        radius: radius.to_vec(),
        returned: balls.iter().map(|b| b.returned).collect(),
        unfinished,
    };
    (totals, events)
}

/// What one shape's walks found, per channel: the share of the flux
/// entering that left it, and that they carried when stopped; with the
/// events they took in all.
struct Walked {
    returned: [f64; 3],
    unfinished: [f64; 3],
    events: u64,
}

/// [`returned`] in every channel.
fn shares<C: Confinement + Sync>(
    shape: &C,
    top: Vec3,
    medium: &WalkMedium,
    walks: Walks,
) -> Walked {
    let each = [0, 1, 2].map(|c| returned(shape, top, medium, c, walks));
    Walked {
        returned: each.map(|e| e.left),
        unfinished: each.map(|e| e.stopped),
        events: each.iter().map(|e| e.events).sum(),
    }
}

/// The walks `runs` runs of `medium` (the half-space's among them) can
/// afford within `budget` events: [`WALKS`] of at most [`MAX_EVENTS`]
/// unless a pilot in the half-space, whose walks are longest, finds them
/// too costly ([`afford`]).
fn affordable(medium: &WalkMedium, runs: usize, budget: f64) -> Walks {
    let pilot = Walks {
        count: PILOT_WALKS,
        max_events: PILOT_EVENTS,
    };
    let events = shares(&HalfSpace, Vec3::ZERO, medium, pilot).events;
    let mean = events as f64 / (3 * PILOT_WALKS) as f64;
    let wanted = Walks {
        count: WALKS,
        max_events: u64::from(MAX_EVENTS),
    };
    afford(mean, runs, wanted, FEWEST_WALKS, budget)
}

/// What one channel's walks found: the share of the flux entering that
/// left, and that they carried when stopped; with the events they took.
#[derive(Clone, Copy)]
struct ChannelWalked {
    left: f64,
    stopped: f64,
    events: u64,
}

/// The share of a pencil beam entering at `top` (a point of the surface
/// whose outward normal is +z), straight down, that leaves `shape`, in
/// channel `c`, by `walks`.
fn returned<C: Confinement>(
    shape: &C,
    top: Vec3,
    medium: &WalkMedium,
    c: usize,
    walks: Walks,
) -> ChannelWalked {
    let channel: &ChannelMedium = &medium.channels[c];
    let start = WalkStart {
        position: top,
        direction: -Vec3::Z,
        triangle: 0,
    };
    let most = walks.max_events.min(u64::from(u32::MAX)) as u32;
    let (left, stopped, events): (f64, f64, u64) = (0..walks.count)
        .into_par_iter()
        .map(|k| {
            let mut rng = Rng::new(SEED, k);
            let walked = walk(shape, channel, medium.boundary, start, most, &mut rng);
            let (left, stopped) = match walked.ending {
                Ending::Left { weight, .. } => (weight, 0.0),
                Ending::Truncated { weight } => (0.0, weight),
                _ => (0.0, 0.0),
            };
            (left, stopped, u64::from(walked.events))
        })
        .reduce(|| (0.0, 0.0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2));
    let share = |x: f64| (x / walks.count as f64).clamp(0.0, 1.0);
    ChannelWalked {
        left: share(left),
        stopped: share(stopped),
        events,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transport::slab_totals::slab_totals;

    fn skin() -> Layer {
        Layer::semi_infinite([0.032, 0.17, 0.48], [0.74, 0.88, 1.01], 1.0)
    }

    #[test]
    fn the_half_space_returns_what_the_slab_monte_carlo_does() {
        let layer = skin();
        let walked = walk_totals(&layer, &[]).half_space;
        let simulated = slab_totals(&layer, &[]).semi_infinite;
        for c in 0..3 {
            let (w, s) = (walked[c], simulated[c]);
            assert!(
                (w - s).abs() < 0.02 * s + 0.005,
                "channel {c}: walk {w}, slab {s}"
            );
        }
    }

    #[test]
    fn a_small_ball_returns_more_than_a_half_space_and_a_large_one_as_much() {
        let totals = walk_totals(&skin(), &[1.0, 4.0, 1000.0]);
        let ratio = totals.over_half_space();
        for (c, returned) in totals.returned[0].iter().enumerate() {
            let (small, mid, large) = (ratio[0][c], ratio[1][c], ratio[2][c]);
            assert!(small > mid && mid > 1.0, "channel {c}: {small} {mid}");
            assert!((large - 1.0).abs() < 0.01, "channel {c}: {large}");
            // Nothing made: a ball returns at most what entered.
            assert!(*returned <= 1.0);
        }
        // Red goes deepest, so its balls gain the most.
        assert!(ratio[1][0] > ratio[1][2], "{:?}", ratio[1]);
        // Every walk ended within the bound on its events.
        assert_eq!(totals.unfinished, [0.0; 3]);
    }

    /// The sweep's medium that walks for ever (see `slab_totals`): within
    /// a budget its walks are fewer and stopped early, the work stays
    /// within it, and every total is still a share of what entered.
    #[test]
    fn a_medium_that_walks_for_ever_is_walked_within_its_budget() {
        let layer = crate::transport::walk_budget::walking_for_ever();
        let budget = 2e7;
        let (totals, events) = walk_within(&layer, &[1e-3, 1.0, 10.0], budget);
        assert!((events as f64) <= budget, "{events} events");
        assert!(totals.is_sound(), "{totals:?}");
        // Stopped walks are counted: the totals say how far off they may be.
        assert!(
            totals.unfinished_share().iter().any(|&u| u > 0.01),
            "{totals:?}"
        );
    }

    #[test]
    fn extreme_media_keep_every_total_a_share_of_what_entered() {
        for (sigma_a, sigma_s) in [
            ([0.0; 3], [1.0; 3]),
            ([1.0; 3], [1e-9; 3]),
            ([1e-6, 1e-3, 1.0], [1e4; 3]),
            ([1e3; 3], [1e3; 3]),
        ] {
            let layer = Layer::semi_infinite(sigma_a, sigma_s, 1.4);
            let totals = walk_totals(&layer, &[1e-3, 1.0, 1e3]);
            assert!(totals.is_sound(), "{sigma_a:?} {sigma_s:?}: {totals:?}");
            for ratio in totals.over_half_space().iter().flatten() {
                assert!(ratio.is_finite() && *ratio >= 0.0, "{totals:?}");
            }
        }
    }
}
