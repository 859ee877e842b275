//! Checks run ahead on another thread of rayon's pool: a sequence of items (the trace's
//! accepted nodes) is checked on another thread while the caller goes on as if every check
//! passed. Each item is submitted with the caller's state from before it was accepted; the
//! results are collected in order, without waiting as a rule, and the first item that fails
//! its check comes back with that state, so that the caller can return to it and go on as
//! if the check had been made before the item was accepted. Nothing else depends on the thread:
//! the caller's result is the same with the checks run ahead or in line.
//!
//! The caller waits only where it must decide (an event, an error, the end): then every
//! check still out is collected first.
//!
//! The checking loop is one job spawned on rayon's pool for the length of the trace (it
//! waits on a channel between items). It is spawned only where the caller is not itself a
//! worker of the pool ([`bvp_solvers::parallel::pool_beside_caller`]): a worker that waited
//! on a job queued behind it could wait for ever, and a computation inside the pool is one
//! of many sharing it (a parallel study), where checking in line costs nothing.

use crate::error::Result;
use std::collections::VecDeque;
use std::sync::mpsc::{channel, Receiver, RecvError, Sender, TryRecvError};
use std::time::{Duration, Instant};

/// How long a waiting thread polls before it blocks. A blocked thread is woken late (tens
/// of microseconds, where an idle virtual CPU must be woken), later than a check takes; a
/// longer poll keeps a virtual CPU busy that its sibling may need (measured on the 2-core
/// VM, CLI sweeps: 500 us polls made the median 14.6 ms, 100 us 8.3 ms, no poll 10.6 ms).
const POLL: Duration = Duration::from_micros(100);

/// The checks of submitted items, run on another thread: results in the order submitted.
pub(crate) struct Ahead<T, S> {
    to_check: Sender<T>,
    results: Receiver<Result<bool>>,
    /// The items submitted and not yet collected, each with the caller's state before it.
    pending: VecDeque<(T, S)>,
}

/// Runs `body` with checks by `check` (`true`: the item fails) on another thread of rayon's
/// pool where [`bvp_solvers::parallel::pool_beside_caller`] (`Some`), in line otherwise
/// (`None`: the caller checks).
pub(crate) fn with_checks<T, S, R>(
    check: impl Fn(&T) -> Result<bool> + Send,
    body: impl FnOnce(Option<Ahead<T, S>>) -> R,
) -> R
where
    T: Copy + Send,
{
    if !bvp_solvers::parallel::pool_beside_caller() {
        return body(None);
    }
    let (to_check, items) = channel::<T>();
    let (found, results) = channel();
    rayon::in_place_scope(|scope| {
        // ends when `body` is done with its `Ahead` (the channel closed)
        scope.spawn(move |_| {
            while let Ok(item) = receive(&items) {
                if found.send(check(&item)).is_err() {
                    break;
                }
            }
        });
        body(Some(Ahead {
            to_check,
            results,
            pending: VecDeque::new(),
        }))
    })
}

impl<T: Copy, S> Ahead<T, S> {
    /// Submits `item` for its check, with the caller's `state` from before it.
    pub fn submit(&mut self, item: T, state: S) {
        self.pending.push_back((item, state));
        // a closed channel (the thread gone) shows when the result is collected
        let _ = self.to_check.send(item);
    }

    /// Collects the results in order: those that have come (`wait` false) or all still out
    /// (`wait` true). The first item that fails comes back with its state, the checks after
    /// it discarded.
    ///
    /// # Errors
    /// The first check's error (in order), or [`crate::ContactError::NoContact`] if the
    /// checking thread is gone.
    pub fn collect(&mut self, wait: bool) -> Result<Option<(T, S)>> {
        while !self.pending.is_empty() {
            let got = if wait {
                receive(&self.results).map_err(|_| TryRecvError::Disconnected)
            } else {
                self.results.try_recv()
            };
            let failed = match got {
                Ok(r) => r?,
                Err(TryRecvError::Empty) => return Ok(None),
                Err(TryRecvError::Disconnected) => {
                    return Err(crate::ContactError::NoContact {
                        reason: "the second-contact checks ended early".into(),
                    })
                }
            };
            let (item, state) = self.pending.pop_front().expect("one pending per result");
            if failed {
                // the checks of the items after it are moot: drained and dropped
                for _ in self.pending.drain(..) {
                    let _ = receive(&self.results);
                }
                return Ok(Some((item, state)));
            }
        }
        Ok(None)
    }
}

/// The next message of `rx`: polled for up to [`POLL`], then waited for.
fn receive<T>(rx: &Receiver<T>) -> std::result::Result<T, RecvError> {
    let start = Instant::now();
    loop {
        match rx.try_recv() {
            Ok(v) => return Ok(v),
            Err(TryRecvError::Disconnected) => return Err(RecvError),
            Err(TryRecvError::Empty) if start.elapsed() > POLL => return rx.recv(),
            Err(TryRecvError::Empty) => std::hint::spin_loop(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Items checked ahead come back in order: the first that fails, with its state,
    /// whatever the timing; nothing when all pass.
    #[test]
    fn the_first_failing_item_comes_back_with_its_state() {
        for _ in 0..20 {
            let got = with_checks(
                |&i: &u32| Ok(i == 7 || i == 9),
                |ahead| {
                    let mut ahead = ahead?;
                    for i in 0..12u32 {
                        ahead.submit(i, i * 10);
                        if let Some(hit) = ahead.collect(false).unwrap() {
                            return Some(hit);
                        }
                    }
                    ahead.collect(true).unwrap()
                },
            );
            if bvp_solvers::parallel::pool_beside_caller() {
                assert_eq!(got, Some((7, 70)));
            }
            let none = with_checks(
                |_: &u32| Ok(false),
                |ahead: Option<Ahead<u32, ()>>| {
                    let mut ahead = ahead?;
                    (0..5).for_each(|i| ahead.submit(i, ()));
                    ahead.collect(true).unwrap()
                },
            );
            assert_eq!(none, None);
        }
    }
}
