//! Peak memory of this process, for `render --json` and `bench --large`.
//!
//! Linux reports the resident-set high-water mark as `VmHWM` in `/proc/self/status`; elsewhere
//! (or if the file cannot be read) the peak is unknown and reported as `None` (JSON null).

/// Peak resident set size of this process in bytes (`VmHWM`), if the system reports it.
pub fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_status_kib(&status, "VmHWM")
}

/// Reset the peak resident set size to the current one, so that [`peak_rss_bytes`] measures
/// from here (Linux: `5` written to `/proc/self/clear_refs`); `false` where the system does not
/// allow it.
pub fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Current resident set size in bytes (`VmRSS`), if the system reports it.
pub fn rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_status_kib(&status, "VmRSS")
}

/// The value of a `Key:   1234 kB` line of `/proc/<pid>/status`, in bytes.
pub fn parse_status_kib(status: &str, key: &str) -> Option<u64> {
    status.lines().find_map(|line| {
        let (k, rest) = line.split_once(':')?;
        if k.trim() != key {
            return None;
        }
        let mut parts = rest.split_whitespace();
        let value: u64 = parts.next()?.parse().ok()?;
        match parts.next() {
            Some(unit) if unit.eq_ignore_ascii_case("kb") => value.checked_mul(1024),
            None => Some(value),
            Some(_) => None,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = "Name:\ttensorglyph\nUmask:\t0022\nState:\tR (running)\n\
        VmPeak:\t 5012344 kB\nVmSize:\t 4990000 kB\nVmHWM:\t  3145728 kB\nVmRSS:\t  1048576 kB\n\
        Threads:\t3\n";

    #[test]
    fn parses_vmhwm_and_vmrss_in_bytes() {
        assert_eq!(
            parse_status_kib(SAMPLE, "VmHWM"),
            Some(3 * 1024 * 1024 * 1024)
        );
        assert_eq!(parse_status_kib(SAMPLE, "VmRSS"), Some(1024 * 1024 * 1024));
        assert_eq!(parse_status_kib(SAMPLE, "Threads"), Some(3));
        // VmHWMx is another key; a missing key or a malformed value is None.
        assert_eq!(parse_status_kib("VmHWMx:\t1 kB\n", "VmHWM"), None);
        assert_eq!(parse_status_kib(SAMPLE, "VmSwap"), None);
        assert_eq!(parse_status_kib("VmHWM:\tlots kB\n", "VmHWM"), None);
        assert_eq!(parse_status_kib("VmHWM:\t12 MB\n", "VmHWM"), None);
        assert_eq!(parse_status_kib("", "VmHWM"), None);
    }

    #[test]
    #[cfg(target_os = "linux")]
    fn this_process_has_a_peak() {
        let peak = peak_rss_bytes().expect("Linux reports VmHWM");
        assert!(peak > 0);
        assert!(rss_bytes().unwrap() > 0);
    }
}
