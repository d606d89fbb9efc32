//! How a run's progress over simulated time is shown: the bar of `musclefem run` on a
//! terminal, and the plain line written instead where there is none (a pipe, a log, a
//! notebook). Shared by the command and the Python module.

use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

/// A bar over a run of `duration` [s] of simulated time, drawn on stderr: position in
/// millionths of the duration, the message "t / duration s" (set it as the run goes).
pub fn simulated_time_bar(duration: f64) -> ProgressBar {
    let bar = ProgressBar::new(1_000_000);
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40} {percent:>3}% t = {msg} [{elapsed_precise}, ETA {eta_precise}]",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message(format!("0 / {duration} s"));
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}

/// Move `bar` to simulated time `time` [s] of `duration` [s].
pub fn show_time(bar: &ProgressBar, time: f64, duration: f64) {
    bar.set_position((1e6 * time / duration) as u64);
    bar.set_message(format!("{time:.4e} / {duration} s"));
}

/// The plain progress line at `time` [s] of `duration` [s], `elapsed` after the start.
pub fn progress_line(time: f64, duration: f64, elapsed: Duration) -> String {
    format!(
        "t = {time:.6e} s of {duration} s ({:.0} %), {elapsed:.2?} elapsed",
        100.0 * time / duration
    )
}

/// Plain lines are written every this fraction of the duration, and at the end.
pub const LINE_EVERY: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_gives_the_time_its_share_and_the_elapsed_time() {
        let line = progress_line(0.25, 1.0, Duration::from_millis(1500));
        assert_eq!(line, "t = 2.500000e-1 s of 1 s (25 %), 1.50s elapsed");
    }
}
