//! Progress of a bake on stderr: an indicatif bar with the stage and the
//! time left on a terminal, a plain line every tenth of the way in a log.

use indicatif::{ProgressBar, ProgressStyle};
use sssbake::control::{Control, watch_while};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Steps of the bar.
const STEPS: u64 = 1000;

/// Watches `control` from a thread while `work` runs; returns what `work`
/// returns. `quiet` shows nothing (for `--json`).
pub fn watch<T>(control: &Control, quiet: bool, work: impl FnOnce() -> T) -> T {
    if quiet {
        return work();
    }
    if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(STEPS);
        bar.set_style(
            ProgressStyle::with_template("{msg:32} [{bar:30}] {percent:>3}% {eta} left")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("#>-"),
        );
        let tick = || {
            bar.set_message(control.stage_label());
            bar.set_position((control.fraction() * STEPS as f64) as u64);
        };
        let result = watch_while(Duration::from_millis(100), tick, work);
        bar.finish_and_clear();
        result
    } else {
        let start = Instant::now();
        let mut reported = 0;
        let tick = || {
            let tenths = (control.fraction() * 10.0) as i32;
            if tenths > reported {
                reported = tenths;
                eprintln!(
                    "{}: {}% after {:.1} s",
                    control.stage_label(),
                    tenths * 10,
                    start.elapsed().as_secs_f64()
                );
            }
        };
        watch_while(Duration::from_millis(200), tick, work)
    }
}
