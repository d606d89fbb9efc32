//! The `--frame-interval` option of the commands that write frames (`elongate`, `knee`).

use anyhow::{Result, bail};

/// `--frame-interval` is 0 (no frames) or a positive, finite time [s]; a negative one was
/// accepted silently (and meant no frames).
pub fn check_frame_interval(interval: f64) -> Result<()> {
    if !(interval.is_finite() && interval >= 0.0) {
        bail!("--frame-interval {interval} s must be 0 (no frames) or a positive time");
    }
    Ok(())
}
