//! Whether a second core is there to share work with: [`std::thread::available_parallelism`]
//! read once per process (each call reads the cgroup files again: measured 23 us a call
//! on the 2-core VM, more than a small solve).

use std::sync::OnceLock;

/// The cores this process may use (at least 1), read on the first call.
pub fn available() -> usize {
    static CORES: OnceLock<usize> = OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// Whether work can be split over two cores.
pub fn second_core() -> bool {
    available() > 1
}

#[cfg(test)]
mod tests {
    /// The cached count is the library's own, and at least one.
    #[test]
    fn counts_the_cores_once() {
        let n = super::available();
        assert!(n >= 1);
        assert_eq!(
            n,
            std::thread::available_parallelism().map_or(1, |n| n.get())
        );
        assert_eq!(super::second_core(), n > 1);
    }
}
