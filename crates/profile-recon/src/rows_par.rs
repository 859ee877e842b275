//! Independent rows in two fixed halves, the second on a thread of its own where a second
//! core exists: the rows of a log are evaluated and judged each on its own, so the numbers
//! are the same either way (and the same as one pass in order).

use std::ops::Range;

/// `f(i)` for `i` in `0..n`, in order: the halves `0..n/2` and `n/2..n` (the second on a
/// scoped thread where [`bvp_solvers::cores::second_core`] says so). The first error
/// in row order is returned, as one pass in order would return it.
///
/// # Errors
/// The first error of `f` in row order.
pub(crate) fn in_halves<T, E, F>(n: usize, f: F) -> Result<Vec<T>, E>
where
    T: Send,
    E: Send,
    F: Fn(usize) -> Result<T, E> + Sync,
{
    let run = |range: Range<usize>| range.map(&f).collect::<Result<Vec<T>, E>>();
    let mid = n / 2;
    let (first, second) = if mid > 0 {
        bvp_solvers::cores::both(|| run(0..mid), || run(mid..n))
    } else {
        (run(0..mid), run(mid..n))
    };
    let mut out = first?;
    out.extend(second?);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// In order, every row once, and the first error in row order (not the first to occur
    /// in time).
    #[test]
    fn rows_come_back_in_order_with_the_first_error() {
        let squares = in_halves(101, |i| Ok::<_, usize>(i * i)).unwrap();
        assert_eq!(squares, (0..101).map(|i| i * i).collect::<Vec<_>>());
        let err = in_halves(100, |i| if i == 20 || i == 70 { Err(i) } else { Ok(i) });
        assert_eq!(err, Err(20));
        let err = in_halves(100, |i| if i == 70 { Err(i) } else { Ok(i) });
        assert_eq!(err, Err(70));
        assert_eq!(in_halves(0, Ok::<_, ()>), Ok(vec![]));
        assert_eq!(in_halves(1, Ok::<_, ()>), Ok(vec![0]));
    }
}
