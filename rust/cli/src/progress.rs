//! Progress of a long computation on stderr: a bar with the time left on a
//! terminal, a plain line every tenth of the way in a log.

use sssbake::control::{Control, watch_while};
use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Watches `control` from a thread while `work` runs, labelling the output
/// `label`; returns what `work` returns.
pub fn watch<T>(label: &str, control: &Control, quiet: bool, work: impl FnOnce() -> T) -> T {
    if quiet {
        return work();
    }
    let terminal = std::io::stderr().is_terminal();
    let start = Instant::now();
    let mut reported = 0;
    let tick = || {
        let fraction = control.fraction();
        let elapsed = start.elapsed().as_secs_f64();
        if terminal {
            let filled = (fraction * 30.0) as usize;
            let left = if fraction > 0.02 {
                format!("{:.0} s left", elapsed * (1.0 - fraction) / fraction)
            } else {
                String::new()
            };
            let _ = write!(
                std::io::stderr(),
                "\r{label} [{}{}] {:3.0}% {left:<14}",
                "#".repeat(filled),
                " ".repeat(30 - filled),
                100.0 * fraction
            );
        } else if (fraction * 10.0) as i32 > reported {
            reported = (fraction * 10.0) as i32;
            eprintln!("{label}: {}% after {elapsed:.1} s", reported * 10);
        }
    };
    let result = watch_while(Duration::from_millis(200), tick, work);
    if terminal {
        let _ = write!(std::io::stderr(), "\r{}\r", " ".repeat(label.len() + 60));
    }
    result
}
