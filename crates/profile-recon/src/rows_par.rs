//! Independent rows on rayon's pool: the rows of a log are evaluated and judged each on its
//! own, so the numbers are the same on any number of threads (and the same as one pass in
//! order).

use rayon::prelude::*;

/// `f(i)` for `i` in `0..n`, in order, the rows shared out over rayon's pool. The first
/// error in row order is returned, as one pass in order would return it (every row is
/// evaluated; an error is the exception, not worth a cancellation).
///
/// # Errors
/// The first error of `f` in row order.
pub(crate) fn map_rows<T, E, F>(n: usize, f: F) -> Result<Vec<T>, E>
where
    T: Send,
    E: Send,
    F: Fn(usize) -> Result<T, E> + Sync,
{
    let all: Vec<Result<T, E>> = (0..n).into_par_iter().map(&f).collect();
    all.into_iter().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// In order, every row once, and the first error in row order (not the first to occur
    /// in time), on the global pool and on pools of 1 and 3 threads.
    #[test]
    fn rows_come_back_in_order_with_the_first_error() {
        let check = || {
            let squares = map_rows(101, |i| Ok::<_, usize>(i * i)).unwrap();
            assert_eq!(squares, (0..101).map(|i| i * i).collect::<Vec<_>>());
            let err = map_rows(100, |i| if i == 20 || i == 70 { Err(i) } else { Ok(i) });
            assert_eq!(err, Err(20));
            let err = map_rows(100, |i| if i == 70 { Err(i) } else { Ok(i) });
            assert_eq!(err, Err(70));
            assert_eq!(map_rows(0, Ok::<_, ()>), Ok(vec![]));
            assert_eq!(map_rows(1, Ok::<_, ()>), Ok(vec![0]));
        };
        check();
        for threads in [1, 3] {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(check);
        }
    }
}
