//! A run's progress as `progress=True` shows it, and its stop when Python asks (Ctrl-C:
//! the flag [`crate::background::run_watched`] sets).
//!
//! Shown as a `tqdm.auto` bar when tqdm is installed (a widget in a notebook), else as
//! `musclefem run`'s bar when stderr is a terminal, else as its plain lines (every tenth
//! of the duration) on Python's `sys.stderr`, so that a notebook shows them.

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use indicatif::ProgressBar;
use pyo3::prelude::*;

use musclefem_io::output::RunProgress;
use musclefem_studies::progress::{LINE_EVERY, progress_line, show_time, simulated_time_bar};

/// How the progress is shown.
enum Display {
    Hidden,
    Bar(ProgressBar),
    /// A `tqdm.auto.tqdm` over the duration [s], and the time it shows.
    Tqdm(Py<PyAny>, f64),
    Lines,
}

/// The progress of one run over `duration` [s] of simulated time.
pub(crate) struct Progress<'a> {
    stop: &'a AtomicBool,
    duration: f64,
    display: Display,
    next_line: f64,
    started: Instant,
}

impl<'a> Progress<'a> {
    /// Shown if `show`, stopping when `stop` is set.
    pub fn new(py: Python<'_>, show: bool, duration: f64, stop: &'a AtomicBool) -> PyResult<Self> {
        let display = if !show {
            Display::Hidden
        } else if let Ok(tqdm) = py.import("tqdm.auto") {
            let kwargs = pyo3::types::PyDict::new(py);
            kwargs.set_item("total", duration)?;
            kwargs.set_item("unit", "s")?;
            kwargs.set_item("desc", "musclefem")?;
            let bar = tqdm.getattr("tqdm")?.call((), Some(&kwargs))?;
            Display::Tqdm(bar.unbind(), 0.0)
        } else if py
            .import("sys")?
            .getattr("stderr")?
            .call_method0("isatty")?
            .extract::<bool>()
            .unwrap_or(false)
        {
            Display::Bar(simulated_time_bar(duration))
        } else {
            Display::Lines
        };
        Ok(Progress {
            stop,
            duration,
            display,
            next_line: 0.0,
            started: Instant::now(),
        })
    }

    /// Simulated time `time` [s] reached: show it; stop if asked to.
    pub fn at(&mut self, time: f64) -> ControlFlow<()> {
        let duration = self.duration;
        match &mut self.display {
            Display::Hidden => {}
            Display::Bar(bar) => show_time(bar, time, duration),
            Display::Tqdm(bar, shown) => {
                let step = time - *shown;
                *shown = time;
                // A bar that cannot be drawn does not stop the run.
                Python::attach(|py| bar.bind(py).call_method1("update", (step,)).map(drop)).ok();
            }
            Display::Lines => {
                let at_end = time >= duration * (1.0 - 1e-12);
                if time >= self.next_line || at_end {
                    let line = progress_line(time, duration, self.started.elapsed()) + "\n";
                    Python::attach(|py| {
                        let stderr = py.import("sys")?.getattr("stderr")?;
                        stderr.call_method1("write", (line,))?;
                        stderr.call_method0("flush").map(drop)
                    })
                    .ok();
                    self.next_line = time + LINE_EVERY * duration;
                }
            }
        }
        if self.stop.load(Ordering::SeqCst) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

impl Drop for Progress<'_> {
    /// The bar is taken down when the run ends, however it ends.
    fn drop(&mut self) {
        match &self.display {
            Display::Bar(bar) => bar.finish_and_clear(),
            Display::Tqdm(bar, _) => {
                Python::attach(|py| bar.bind(py).call_method0("close").map(drop)).ok();
            }
            Display::Hidden | Display::Lines => {}
        }
    }
}

impl RunProgress for Progress<'_> {
    fn reached(&mut self, time: f64) -> ControlFlow<()> {
        self.at(time)
    }
}
