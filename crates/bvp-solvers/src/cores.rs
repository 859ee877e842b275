//! Whether a second core is there to share work with.
//!
//! [`std::thread::available_parallelism`] is read once per process (each call reads the
//! cgroup files again: measured 23 us a call on the 2-core VM, more than a small solve).
//! A computation that splits its work over two cores (a sweep, a reconstruction) holds a
//! [`Claim`] while it runs; a second core is offered only while the claims leave one free
//! for each of them (`2 x claims <= cores`), so that a study running one computation per
//! core on threads of its own does not also start a helper thread per computation. Only
//! the speed depends on it: the computations' numbers do not depend on whether they split.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// The computations in progress that may split over two cores.
static CLAIMS: AtomicUsize = AtomicUsize::new(0);

/// The cores this process may use (at least 1), read on the first call.
pub fn available() -> usize {
    static CORES: OnceLock<usize> = OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// A computation in progress that may split its work over two cores: counted from
/// [`Claim::new`] until dropped.
#[derive(Debug)]
pub struct Claim(());

impl Claim {
    /// Counts one more computation in progress.
    pub fn new() -> Self {
        CLAIMS.fetch_add(1, Ordering::Relaxed);
        Claim(())
    }
}

impl Default for Claim {
    fn default() -> Self {
        Self::new()
    }
}

impl Drop for Claim {
    fn drop(&mut self) {
        CLAIMS.fetch_sub(1, Ordering::Relaxed);
    }
}

/// Whether work can be split over two cores now: a second core exists and the
/// computations in progress ([`Claim`]) leave one for each (`2 x claims <= cores`; a caller
/// that holds no claim counts as one).
pub fn second_core() -> bool {
    let claims = CLAIMS.load(Ordering::Relaxed).max(1);
    available() > 1 && 2 * claims <= available()
}

/// `(a(), b())`: `b` on a scoped thread of its own where [`second_core`] offers one and a
/// thread can be started, in line after `a` otherwise (a thread that cannot be started is no
/// error: the work is the same, only slower). A panic in `b` resumes in the caller.
pub fn both<RA, RB>(a: impl FnOnce() -> RA, b: impl FnOnce() -> RB + Send) -> (RA, RB)
where
    RB: Send,
{
    if !second_core() {
        let ra = a();
        return (ra, b());
    }
    // `b` waits in a slot: taken by the thread, or back by the caller if none starts
    let slot = std::sync::Mutex::new(Some(b));
    let take = || slot.lock().map_or(None, |mut s| s.take());
    std::thread::scope(|scope| {
        let started = std::thread::Builder::new().spawn_scoped(scope, || take().map(|b| b()));
        let ra = a();
        let rb = match started {
            Ok(h) => h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)),
            Err(_) => take().map(|b| b()),
        };
        (ra, rb.expect("b runs once, on the thread or in line"))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cached count is the library's own; a second core is offered to one computation
    /// of a two-core machine, not to two at once. (The only test of the crate that takes
    /// claims, so the count is its own.)
    #[test]
    fn counts_the_cores_once_and_shares_them_out() {
        let n = available();
        assert!(n >= 1);
        assert_eq!(
            n,
            std::thread::available_parallelism().map_or(1, |n| n.get())
        );
        let one = Claim::new();
        assert_eq!(second_core(), n >= 2);
        let others: Vec<Claim> = (0..n).map(|_| Claim::new()).collect();
        assert!(!second_core(), "{} claims on {n} cores", n + 1);
        drop(others);
        assert_eq!(second_core(), n >= 2);
        drop(one);
        assert_eq!(CLAIMS.load(Ordering::Relaxed), 0);
        // both halves run, once each, whether on two threads or in line
        let (x, y) = both(
            || (0..1000u64).sum::<u64>(),
            || (1000..2000u64).sum::<u64>(),
        );
        assert_eq!(x + y, (0..2000u64).sum::<u64>());
    }
}
