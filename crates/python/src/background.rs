//! Long calls run on a thread of their own while the calling thread, without the GIL,
//! watches for Python's signals: Python runs its signal handlers (Ctrl-C raising
//! KeyboardInterrupt) only in the main thread, so the solver's thread cannot see them
//! itself, least of all in a pool of worker threads (`threads=N`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use pyo3::prelude::*;

use crate::MusclefemError;

/// How often the calling thread checks for signals.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// The solver's thread's stack [bytes]: the main thread's usual 8 MB, not the 2 MB of a
/// spawned thread.
const STACK_BYTES: usize = 8 << 20;

/// A pool of `threads` rayon threads for one call, or `None` for the global pool (one
/// thread per core). `threads` is checked as `musclefem run --threads` checks it; more
/// than the cores warn (Python's `warnings`) and use the cores.
pub(crate) fn thread_pool(
    py: Python<'_>,
    threads: Option<usize>,
) -> PyResult<Option<rayon::ThreadPool>> {
    let Some(requested) = threads else {
        return Ok(None);
    };
    let (threads, warning) = musclefem_studies::threads::worker_threads(requested, "threads=")
        .map_err(crate::python_error)?;
    if let Some(warning) = warning {
        let warnings = py.import("warnings")?;
        warnings.call_method1("warn", (warning,))?;
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map(Some)
        .map_err(|e| MusclefemError::new_err(format!("cannot start {threads} threads: {e}")))
}

/// Run `work` on its own thread (inside `pool` if given) while this thread releases the
/// GIL and checks Python's signals every [`SIGNAL_POLL`]. A signal handler's exception
/// (KeyboardInterrupt for Ctrl-C) sets `stop`, which `work` is to honour by stopping
/// soon, and is returned beside what `work` returned.
pub(crate) fn run_watched<T: Send>(
    py: Python<'_>,
    pool: Option<&rayon::ThreadPool>,
    stop: &AtomicBool,
    work: impl FnOnce() -> T + Send,
) -> PyResult<(T, Option<PyErr>)> {
    py.detach(|| {
        std::thread::scope(|scope| {
            let (done, finished) = mpsc::channel::<()>();
            let worker = std::thread::Builder::new()
                .name("musclefem".into())
                .stack_size(STACK_BYTES)
                .spawn_scoped(scope, move || {
                    let value = match pool {
                        Some(pool) => pool.install(work),
                        None => work(),
                    };
                    // The receiver waits for this, or for the sender's drop on a panic.
                    let _ = done.send(());
                    value
                })
                .map_err(|e| MusclefemError::new_err(format!("cannot start a thread: {e}")))?;
            let mut signal = None;
            while let Err(mpsc::RecvTimeoutError::Timeout) = finished.recv_timeout(SIGNAL_POLL) {
                if signal.is_none()
                    && let Err(error) = Python::attach(|py| py.check_signals())
                {
                    signal = Some(error);
                    stop.store(true, Ordering::SeqCst);
                }
            }
            let value = worker.join().map_err(|panic| {
                let message = panic
                    .downcast_ref::<String>()
                    .map(String::as_str)
                    .or_else(|| panic.downcast_ref::<&str>().copied())
                    .unwrap_or("(no message)");
                MusclefemError::new_err(format!("the run's thread panicked: {message}"))
            })?;
            Ok((value, signal))
        })
    })
}
