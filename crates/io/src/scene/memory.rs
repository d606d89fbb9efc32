//! A model's memory, estimated before its mesh is allocated and checked against the
//! machine, so that a mistyped `divisions = [700, 700, 700]` is refused with its line
//! instead of aborting on a failed allocation.
//!
//! The estimate is a lower bound: [`BYTES_PER_ELEMENT`] per element, below what runs
//! take (measured with `/usr/bin/time` on this project's 2-core machine, 2026-11-26: an
//! explicit Hill block of 64 000 one-point hex8, 3.9 KB per element; an implicit
//! neo-Hookean cube of 27 000 F-bar hex8, 49 KB per element with its sparse factor).

/// The least memory a run needs per element [bytes] (see the module documentation).
pub const BYTES_PER_ELEMENT: u64 = 2048;

/// The memory this machine has available [bytes] (`MemAvailable` of `/proc/meminfo`), or
/// `None` where that cannot be read.
pub fn available_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kilobytes: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kilobytes * 1024)
}

/// An error message if `elements` need more memory than `available` [bytes].
pub fn too_large(elements: u64, available: Option<u64>) -> Option<String> {
    let needed = elements.saturating_mul(BYTES_PER_ELEMENT);
    let available = available?;
    (needed > available).then(|| {
        format!(
            "{elements} elements need at least {:.1} GB to run (≥ {} KB each), more than the \
             {:.1} GB this machine has available",
            needed as f64 / 1e9,
            BYTES_PER_ELEMENT / 1024,
            available as f64 / 1e9
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mesh_larger_than_the_memory_is_named_and_a_small_one_passes() {
        let gigabytes_16 = Some(16u64 << 30);
        let message = too_large(343_000_000, gigabytes_16).unwrap();
        assert!(message.contains("343000000 elements"), "{message}");
        assert!(message.contains("702.5 GB"), "{message}");
        assert!(too_large(64_000, gigabytes_16).is_none());
        // Where the machine's memory is unknown, nothing is refused.
        assert!(too_large(u64::MAX, None).is_none());
        assert!(available_bytes().is_none_or(|b| b > 0));
    }
}
