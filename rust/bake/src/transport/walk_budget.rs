//! How many walks the totals a bake simulates for itself (the slab's, the
//! balls') can afford, so their work is bounded up front.
//!
//! A walk in a medium that hardly absorbs and scatters nearly straight
//! ahead takes thousands of events, and its tail far more: the sweep of
//! extreme inputs found one (albedo 0.999999, g 0.99) whose slab totals
//! ran for hours at the usual count. A pilot measures the mean events of a
//! walk; while the usual count fits within [`EVENT_BUDGET`] it is kept
//! unchanged, past it fewer walks are taken, each stopped when its share
//! of the budget is spent.

/// Scattering and absorption events one set of totals may take, all its
/// walks together, counted at the pilot's mean (that of the half-space,
/// whose walks are longest): the slab's and the balls' totals of the
/// medium above, each within it, took 47 s together on two cores. The most costly
/// preset, spectralon, takes 2.4·10⁹ for the slab's totals at the usual
/// count, skin1 5·10⁷.
pub const EVENT_BUDGET: f64 = 2.5e9;

/// Walks per channel a pilot takes in the half-space to learn a walk's
/// mean events.
pub const PILOT_WALKS: u64 = 256;

/// The most events a pilot's walk takes: the pilot costs at most
/// 3 × [`PILOT_WALKS`] × this, 8·10⁷ events.
pub const PILOT_EVENTS: u64 = 100_000;

/// The walks a set of totals takes per run and channel, and the most
/// events each may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Walks {
    /// Walks per run and channel.
    pub count: u64,
    /// Events after which a walk is stopped and its light dropped.
    pub max_events: u64,
}

/// What `runs` runs of three channels can afford within `budget` events,
/// a walk taking `mean_events` on average (the pilot's): `wanted`
/// unchanged while it fits, else walks enough to take 16 times the mean
/// each (at least `fewest`), each stopped when its share of the budget is
/// spent, so the runs take at most `budget` events however long a walk's
/// tail. A stopped walk's light is dropped: a bias only where the budget
/// binds, and never light made.
pub fn afford(mean_events: f64, runs: usize, wanted: Walks, fewest: u64, budget: f64) -> Walks {
    let walks_per_count = (3 * runs.max(1)) as f64;
    let mean = mean_events.max(1.0);
    if mean * wanted.count as f64 * walks_per_count <= budget {
        return wanted;
    }
    let count =
        ((budget / (16.0 * mean * walks_per_count)) as u64).clamp(fewest.max(1), wanted.count);
    Walks {
        count,
        max_events: ((budget / (count as f64 * walks_per_count)) as u64)
            .clamp(1, wanted.max_events),
    }
}

/// The medium the sweep of extreme inputs found walking for ever (seed 7,
/// case 1): albedo 0.999999, σt 23340 /mm, g 0.99, η 2.1, semi-infinite.
#[cfg(test)]
pub(crate) fn walking_for_ever() -> sssbake_profile::material::Layer {
    let (albedo, sigma_t) = (0.999999, 23339.5);
    sssbake_profile::material::Layer {
        g: 0.99,
        ..sssbake_profile::material::Layer::semi_infinite(
            [sigma_t * (1.0 - albedo); 3],
            [sigma_t * albedo; 3],
            2.1,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WANTED: Walks = Walks {
        count: 16_384,
        max_events: 1_000_000,
    };

    #[test]
    fn walks_that_fit_are_kept_as_asked() {
        assert_eq!(afford(100.0, 33, WANTED, 512, EVENT_BUDGET), WANTED);
    }

    #[test]
    fn walks_past_the_budget_are_fewer_and_bounded() {
        for mean in [2e3, 1e5, 1e9] {
            let walks = afford(mean, 33, WANTED, 512, EVENT_BUDGET);
            assert!(
                walks.count < WANTED.count && walks.count >= 512,
                "{walks:?}"
            );
            let most = walks.count as f64 * 99.0 * walks.max_events as f64;
            assert!(most <= EVENT_BUDGET, "{mean}: {walks:?}");
        }
        // Just past the budget, a walk may still take 16 times the mean.
        let walks = afford(2e3, 33, WANTED, 512, EVENT_BUDGET);
        assert!(walks.max_events >= 32_000, "{walks:?}");
    }
}
