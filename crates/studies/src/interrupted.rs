//! A run stopped on request (Ctrl-C) after writing its outputs up to there: the command
//! exits with 130 (128 + SIGINT, as shells report an interrupted program) and this
//! message, which says how to go on.

/// The error of a command stopped by Ctrl-C (see the module documentation).
#[derive(Debug)]
pub struct Interrupted(pub String);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Interrupted {}
