//! The peak resident memory of this process: `VmHWM` of /proc/self/status (Linux). It is
//! a high-water mark over the whole process, so `musclefem bench --problem scaling` runs
//! every case in a child process of its own.

/// The peak resident set size of this process so far [bytes], or `None` where
/// /proc/self/status is not available.
pub fn peak_resident_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    vm_hwm_bytes(&status)
}

/// The `VmHWM:` line of a /proc/PID/status text [bytes] (the kernel writes it in kB,
/// meaning KiB).
pub fn vm_hwm_bytes(status: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line
        .trim_start_matches("VmHWM:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_high_water_mark_is_read_in_kibibytes() {
        let status = "Name:\tmusclefem\nVmPeak:\t  20000 kB\nVmHWM:\t    3456 kB\nVmRSS:\t 1 kB\n";
        assert_eq!(vm_hwm_bytes(status), Some(3456 * 1024));
        assert_eq!(vm_hwm_bytes("Name:\tx\n"), None);
    }
}
