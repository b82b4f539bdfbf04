//! Progress and cancellation shared between a long computation and whoever
//! started it (the command line's progress bar, the Blender add-on's modal
//! operator, the C ABI's callback).

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// A computation stopped because its caller asked it to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("cancelled")]
pub struct Cancelled;

/// Counts work done against work planned, and carries a cancel flag that
/// every long loop checks. Shared by reference across threads.
///
/// A whole bake runs in stages (each object's lighting, then its
/// scattering); [`Control::fraction`] counts the stages done and the share
/// of the current one, so it only rises. A stage whose work comes in
/// several steps, each planning its own work as it starts (the scattering's
/// pilot, map and checks), gives each its share of the stage
/// ([`Control::part`]), so the fraction does not reach the stage's end
/// with its first step.
#[derive(Debug, Default)]
pub struct Control {
    done: AtomicU64,
    total: AtomicU64,
    cancel: AtomicBool,
    /// (stage index, stage count, label) of the current stage.
    stage: Mutex<(usize, usize, String)>,
    /// The current part of the stage: its span of the stage (from, to, as
    /// shares of it) and its label.
    part: Mutex<Part>,
    /// The largest fraction reported so far (f64 bits): work planned late
    /// in a stage (a check after the integration) does not move it back.
    shown: AtomicU64,
}

/// A span of the current stage that one step of its work fills.
#[derive(Clone, Debug)]
struct Part {
    from: f64,
    to: f64,
    label: String,
}

impl Default for Part {
    fn default() -> Self {
        Part {
            from: 0.0,
            to: 1.0,
            label: String::new(),
        }
    }
}

impl Control {
    /// A fresh control: nothing planned, not cancelled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `units` of work to the plan (work announces itself as it
    /// starts; the fraction reported holds still until it passes the
    /// largest shown before).
    pub fn plan(&self, units: u64) {
        self.total.fetch_add(units, Ordering::Relaxed);
    }

    /// Records `units` of work as done; fails once cancellation is asked.
    pub fn advance(&self, units: u64) -> Result<(), Cancelled> {
        self.done.fetch_add(units, Ordering::Relaxed);
        self.check()
    }

    /// Fails once cancellation is asked.
    pub fn check(&self) -> Result<(), Cancelled> {
        if self.cancel.load(Ordering::Relaxed) {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }

    /// Asks the computation to stop at its next check.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// True once cancellation was asked.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// Starts stage `index` of `count`, named `label` for progress reports;
    /// the work planned and done so far belongs to the stages before.
    pub fn begin_stage(&self, index: usize, count: usize, label: &str) {
        if let Ok(mut stage) = self.stage.lock() {
            *stage = (index, count.max(1), label.to_string());
        }
        if let Ok(mut part) = self.part.lock() {
            *part = Part::default();
        }
        self.total.store(0, Ordering::Relaxed);
        self.done.store(0, Ordering::Relaxed);
        if index == 0 {
            // A new run of stages (a control may serve several parts).
            self.shown.store(0, Ordering::Relaxed);
        }
    }

    /// Runs `work` as the span `from..to` (shares, 0 to 1) of the current
    /// part of the stage (of the whole stage outside any part), labelled
    /// `label`: the work it plans and does fills that span alone, and once
    /// it returns the fraction stands at least at the span's end. Parts
    /// nest: a part within a part takes its span of the outer one.
    pub fn part<T>(&self, from: f64, to: f64, label: &str, work: impl FnOnce() -> T) -> T {
        let outer = self.part.lock().map(|p| p.clone()).unwrap_or_default();
        let width = outer.to - outer.from;
        let inner = Part {
            from: outer.from + width * from.clamp(0.0, 1.0),
            to: outer.from + width * to.clamp(from.clamp(0.0, 1.0), 1.0),
            label: label.to_string(),
        };
        let end = inner.to;
        let counted = (
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        );
        self.set_part(inner, (0, 0));
        let result = work();
        self.set_part(outer, counted);
        let (index, count) = self.stage_place();
        let reached = (index as f64 + end) / count as f64;
        self.shown
            .fetch_max(reached.min(1.0).to_bits(), Ordering::Relaxed);
        result
    }

    /// Makes `part` the current one, with the work `(done, total)` counted
    /// in it.
    fn set_part(&self, part: Part, (done, total): (u64, u64)) {
        if let Ok(mut current) = self.part.lock() {
            *current = part;
        }
        self.total.store(total, Ordering::Relaxed);
        self.done.store(done, Ordering::Relaxed);
    }

    /// The current stage's index and the count of stages (at least 1).
    fn stage_place(&self) -> (usize, usize) {
        let (index, count) = self.stage.lock().map(|s| (s.0, s.1)).unwrap_or((0, 1));
        (index, count.max(1))
    }

    /// The current stage's label, with the current part's after a colon
    /// (empty before any stage).
    pub fn stage_label(&self) -> String {
        let stage = self.stage.lock().map(|s| s.2.clone()).unwrap_or_default();
        let part = self
            .part
            .lock()
            .map(|p| p.label.clone())
            .unwrap_or_default();
        match (stage.is_empty(), part.is_empty()) {
            (_, true) => stage,
            (true, false) => part,
            (false, false) => format!("{stage}: {part}"),
        }
    }

    /// Fraction of the planned work done, in [0, 1]: stages done plus the
    /// share of the current one, through its parts (0 before any plan).
    pub fn fraction(&self) -> f64 {
        let total = self.total.load(Ordering::Relaxed);
        let counted = if total == 0 {
            0.0
        } else {
            (self.done.load(Ordering::Relaxed) as f64 / total as f64).min(1.0)
        };
        let part = self.part.lock().map(|p| p.clone()).unwrap_or_default();
        let within = part.from + (part.to - part.from) * counted;
        let (index, count) = self.stage_place();
        let now = ((index as f64 + within) / count as f64).min(1.0);
        let before = self.shown.fetch_max(now.to_bits(), Ordering::Relaxed);
        // Non-negative f64s order as their bits do.
        now.max(f64::from_bits(before))
    }
}

/// The least number of chunks per thread [`parallel_fill`] splits its
/// items into, so threads that finish early take the rest.
const CHUNKS_PER_THREAD: usize = 4;

/// Fills `out[i] = item(i)` in parallel chunks of at most `chunk` items,
/// advancing `control` after each chunk and stopping at the first
/// cancellation.
pub fn parallel_fill<T: Send>(
    out: &mut [T],
    chunk: usize,
    control: &Control,
    item: impl Fn(usize) -> T + Sync,
) -> Result<(), Cancelled> {
    use rayon::prelude::*;
    let chunk = chunk_for(out.len(), chunk, rayon::current_num_threads());
    control.plan(out.len() as u64);
    out.par_chunks_mut(chunk)
        .enumerate()
        .try_for_each(|(c, slot)| {
            control.check()?;
            for (k, value) in slot.iter_mut().enumerate() {
                *value = item(c * chunk + k);
            }
            control.advance(slot.len() as u64)
        })
}

/// The chunk [`parallel_fill`] takes for `items` items, at most `chunk`,
/// on `threads` threads. Few items are split so every thread has some:
/// the exact sums at the 64 texels of a check (0.3 s each on the head at
/// 4096²) were one chunk of 256, summed on one core and deaf to a cancel
/// until the last.
fn chunk_for(items: usize, chunk: usize, threads: usize) -> usize {
    let shares = CHUNKS_PER_THREAD * threads.max(1);
    chunk.min(items.div_ceil(shares)).max(1)
}

/// Runs `work` on this thread while a watcher thread calls `tick` every
/// `period` until `work` is done (progress reports, a host's cancel flag);
/// returns what `work` returns.
pub fn watch_while<T>(
    period: std::time::Duration,
    mut tick: impl FnMut() + Send,
    work: impl FnOnce() -> T,
) -> T {
    let done = AtomicBool::new(false);
    std::thread::scope(|scope| {
        scope.spawn(|| {
            while !done.load(Ordering::Acquire) {
                tick();
                std::thread::sleep(period);
            }
        });
        let result = work();
        done.store(true, Ordering::Release);
        result
    })
}

#[cfg(test)]
mod tests {
    use super::{Control, chunk_for, parallel_fill};

    #[test]
    fn few_items_are_split_over_the_threads_and_many_keep_their_chunk() {
        // 64 costly texels on 2 threads: 8 chunks of 8, not one of 64.
        assert_eq!(chunk_for(64, 256, 2), 8);
        assert_eq!(chunk_for(3, 256, 2), 1);
        assert_eq!(chunk_for(0, 256, 2), 1);
        assert_eq!(chunk_for(1_000_000, 256, 2), 256);
        assert_eq!(chunk_for(10, 0, 0), 1);
        // Whatever the chunk, every item is filled, once, in its place.
        let mut out = vec![0usize; 37];
        parallel_fill(&mut out, 256, &Control::new(), |i| i * i).unwrap();
        assert!(out.iter().enumerate().all(|(i, &v)| v == i * i));
    }

    #[test]
    fn work_planned_late_in_a_stage_does_not_move_the_fraction_back() {
        let control = Control::new();
        control.begin_stage(1, 2, "scattering");
        control.plan(100);
        control.advance(100).unwrap();
        assert_eq!(control.fraction(), 1.0);
        // A check after the integration plans more work in the same stage.
        control.plan(300);
        assert_eq!(control.fraction(), 1.0);
        control.advance(300).unwrap();
        assert_eq!(control.fraction(), 1.0);
        // A new run of stages starts from zero again.
        control.begin_stage(0, 2, "lighting");
        assert_eq!(control.fraction(), 0.0);
    }

    #[test]
    fn each_part_of_a_stage_fills_its_own_span() {
        let control = Control::new();
        control.begin_stage(1, 2, "Head: scattering");
        // A first step that plans and finishes its work takes the stage to
        // its span's end, not to the stage's.
        control.part(0.0, 0.2, "pilot", || {
            assert_eq!(control.stage_label(), "Head: scattering: pilot");
            control.plan(10);
            control.advance(5).unwrap();
            assert!((control.fraction() - 0.55).abs() < 1e-12);
            control.advance(5).unwrap();
        });
        assert!((control.fraction() - 0.6).abs() < 1e-12);
        assert_eq!(control.stage_label(), "Head: scattering");
        // Parts nest: half of the span 0.2..0.8 is 0.2..0.5 of the stage.
        control.part(0.2, 0.8, "", || {
            control.part(0.0, 0.5, "the map", || {
                assert_eq!(control.stage_label(), "Head: scattering: the map");
                control.plan(4);
                control.advance(2).unwrap();
                assert!((control.fraction() - 0.675).abs() < 1e-12);
            });
            // Left unfinished, a part still ends at its span's end.
            assert!((control.fraction() - 0.75).abs() < 1e-12);
        });
        assert!((control.fraction() - 0.9).abs() < 1e-12);
        // A span left between parts is passed over.
        control.part(0.9, 1.0, "check", || {
            control.plan(1);
            assert!((control.fraction() - 0.95).abs() < 1e-12);
            control.advance(1).unwrap();
        });
        assert!((control.fraction() - 1.0).abs() < 1e-12);
    }
}
