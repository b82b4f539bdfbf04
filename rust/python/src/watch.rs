//! Runs library work on its own thread with the GIL released, while the
//! calling thread reports progress to a Python callback, honours a cancel
//! request (a callback's exception, a cancel event, Ctrl-C) and stays
//! responsive to other Python threads.

use pyo3::prelude::*;
use sssbake::control::Control;
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// How often progress is reported and cancellation is looked for.
const PERIOD: Duration = Duration::from_millis(100);

/// What the caller gave to follow and stop the work.
pub struct Watchers<'py> {
    /// Called as `progress(fraction, stage)`: fraction in [0, 1], rising,
    /// ending at 1 when the work succeeds; stage a label. An exception it
    /// raises cancels the work and is raised again.
    pub progress: Option<Bound<'py, PyAny>>,
    /// Anything with `is_set()` (a `threading.Event`): once set, the work
    /// is cancelled.
    pub cancel: Option<Bound<'py, PyAny>>,
    /// `(part, parts)`: the work is part `part` of `parts` equal parts of
    /// the call, so the fraction reported runs from part / parts to
    /// (part + 1) / parts.
    pub part: (usize, usize),
}

impl<'py> Watchers<'py> {
    /// `progress` and `cancel` following the whole call.
    pub fn whole(progress: Option<Bound<'py, PyAny>>, cancel: Option<Bound<'py, PyAny>>) -> Self {
        Watchers {
            progress,
            cancel,
            part: (0, 1),
        }
    }
}

/// Runs `work` (which checks `control`) on a thread of its own while this
/// thread, holding the GIL only between waits, watches it. A Python error
/// from a watcher, or Ctrl-C, cancels the work and is returned once the
/// work has stopped.
pub fn run_watched<T: Send>(
    py: Python<'_>,
    control: &Control,
    watchers: &Watchers<'_>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let finished = (Mutex::new(false), Condvar::new());
    // Watched once before the work starts: a cancel already asked for, or a
    // callback that fails at once, stops it however quick it would be.
    let mut raised: Option<PyErr> = watch_once(py, control, watchers).err();
    if raised.is_some() {
        control.cancel();
    }
    let result = std::thread::scope(|scope| {
        let worker = scope.spawn(|| {
            let value = work();
            let (lock, signal) = &finished;
            if let Ok(mut done) = lock.lock() {
                *done = true;
            }
            signal.notify_all();
            value
        });
        loop {
            let done = py.detach(|| {
                let (lock, signal) = &finished;
                let Ok(guard) = lock.lock() else { return true };
                signal
                    .wait_timeout_while(guard, PERIOD, |done| !*done)
                    .map(|(done, _)| *done)
                    .unwrap_or(true)
            });
            if done {
                break;
            }
            if raised.is_none()
                && let Err(error) = watch_once(py, control, watchers)
            {
                control.cancel();
                raised = Some(error);
            }
        }
        worker.join()
    });
    let value = match result {
        Ok(value) => value,
        Err(_) => {
            return Err(pyo3::exceptions::PyRuntimeError::new_err(
                "sssbake's native work panicked; please report it with the input",
            ));
        }
    };
    match raised {
        Some(error) => Err(error),
        None => Ok(value),
    }
}

/// Reports the end of successful work: the fraction reaches 1.
pub fn finish(watchers: &Watchers<'_>, label: &str) -> PyResult<()> {
    if let Some(progress) = &watchers.progress {
        progress.call1((1.0, label))?;
    }
    Ok(())
}

fn watch_once(py: Python<'_>, control: &Control, watchers: &Watchers<'_>) -> PyResult<()> {
    py.check_signals()?;
    if let Some(cancel) = &watchers.cancel
        && cancel.call_method0("is_set")?.is_truthy()?
    {
        control.cancel();
    }
    if let Some(progress) = &watchers.progress {
        let stage = control.stage_label();
        let stage = if stage.is_empty() { "starting" } else { &stage };
        let (part, parts) = watchers.part;
        let fraction = (part as f64 + control.fraction()) / parts.max(1) as f64;
        progress.call1((fraction, stage))?;
    }
    Ok(())
}
