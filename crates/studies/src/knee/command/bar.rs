//! The progress bar of one squat of the knee study (the two squats' bars are drawn one
//! above the other); the directory runner moves it along the simulated time
//! ([`crate::progress::show_time`]).

use indicatif::{ProgressBar, ProgressStyle};

use crate::knee::simulation::Activation;

/// The bar of one squat: position in millionths of its duration, the message
/// "t / duration s".
pub(super) fn progress_bar(duration: f64, activation: Activation) -> ProgressBar {
    let bar = ProgressBar::new(1_000_000);
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{:<7} {{bar:40}} t = {{msg}} [{{elapsed_precise}}, ETA {{eta}}]",
            activation.name()
        ))
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message(format!("0 / {duration} s"));
    bar
}
