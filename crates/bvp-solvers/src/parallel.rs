//! Two pieces of work at once on rayon's thread pool, for the computations that split
//! (a sweep's rows, a figure's PNG beside its SVG).
//!
//! [`both`] spawns the second piece on rayon's global pool and runs the first on the
//! calling thread ([`rayon::in_place_scope`], so that the first piece need not be `Send`).
//! Nested in a parallel study (the caller a worker of the pool) the second piece waits in
//! the worker's own queue, stolen by an idle worker or run by the caller after the first:
//! the pool's size bounds the threads, whatever the nesting (this replaced a hand-made
//! count of "claims" on the cores). Only the speed depends on where the pieces run: the
//! callers split their work into fixed pieces, so the numbers do not depend on the number
//! of threads.

/// `(a(), b())`: `b` spawned on rayon's pool, `a` on the calling thread meanwhile. A panic
/// in `b` resumes in the caller once `a` is done.
pub fn both<RA, RB>(a: impl FnOnce() -> RA, b: impl FnOnce() -> RB + Send) -> (RA, RB)
where
    RB: Send,
{
    let mut rb = None;
    let ra = rayon::in_place_scope(|scope| {
        scope.spawn(|_| rb = Some(b()));
        a()
    });
    (ra, rb.expect("the scope ends after b has run"))
}

/// Whether another thread of rayon's pool may take a long-running piece of work beside the
/// caller: the pool has more than one thread and the caller is not one of them (a caller
/// inside the pool is one of many computations sharing it, as in a parallel study).
pub fn pool_beside_caller() -> bool {
    rayon::current_thread_index().is_none() && rayon::current_num_threads() > 1
}

/// Starts rayon's global pool (a program calls it first, before any parallel work): the
/// default pool, or, where no thread can be started (every stack refused), a pool of the
/// calling thread alone, so that the work runs in line instead of rayon panicking on its
/// first use. Returns the pool's number of threads. A pool already started is kept.
pub fn start_pool() -> usize {
    let can_spawn = std::thread::Builder::new()
        .spawn(|| {})
        .map(|h| h.join().is_ok())
        .unwrap_or(false);
    let builder = rayon::ThreadPoolBuilder::new();
    let builder = if can_spawn {
        builder
    } else {
        builder.num_threads(1).use_current_thread()
    };
    // (an error here is a pool already started, which is kept)
    let _ = builder.build_global();
    rayon::current_num_threads()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both halves run, once each; the second on the pool, also when nested in it; a panic
    /// of the second reaches the caller.
    #[test]
    fn both_halves_run_once() {
        let (x, y) = both(
            || (0..1000u64).sum::<u64>(),
            || (1000..2000u64).sum::<u64>(),
        );
        assert_eq!(x + y, (0..2000u64).sum::<u64>());
        use rayon::prelude::*;
        let sums: Vec<u64> = (0..64u64)
            .into_par_iter()
            .map(|i| {
                assert!(!pool_beside_caller());
                let (a, b) = both(|| i, || 2 * i);
                a + b
            })
            .collect();
        assert_eq!(sums, (0..64u64).map(|i| 3 * i).collect::<Vec<_>>());
        assert_eq!(
            pool_beside_caller(),
            rayon::current_num_threads() > 1,
            "the test thread is not in the pool"
        );
        let caught = std::panic::catch_unwind(|| both(|| 1, || -> u32 { panic!("b failed") }));
        assert!(caught.is_err());
    }
}
