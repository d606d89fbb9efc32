//! How many worker threads a run may use (`musclefem run --threads N`, and `threads=N`
//! in Python): at least one, at most one per core.

use anyhow::{Result, bail};

/// The worker threads for a request of `requested`: an error for 0, the number of cores
/// for more than that (more only add switching; 100 000 of them never started), with a
/// warning saying so.
pub fn worker_threads(requested: usize, option: &str) -> Result<(usize, Option<String>)> {
    if requested == 0 {
        bail!("{option} 0: at least one thread must run");
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if requested > cores {
        let warning = format!("{option} {requested} is more than the {cores} cores; using {cores}");
        return Ok((cores, Some(warning)));
    }
    Ok((requested, None))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_is_refused_and_too_many_are_capped_with_a_warning() {
        let error = worker_threads(0, "--threads").unwrap_err().to_string();
        assert!(error.contains("--threads 0"), "{error}");
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        assert_eq!(worker_threads(1, "--threads").unwrap(), (1, None));
        let (threads, warning) = worker_threads(cores + 1, "threads=").unwrap();
        assert_eq!(threads, cores);
        assert!(warning.unwrap().contains(&format!("{}", cores + 1)));
    }
}
