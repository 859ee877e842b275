//! The buffers of one solve (collocation residuals, the ABD Jacobian, its factors, Newton's
//! vectors, the Jacobian's scratch), kept per thread between solves so that repeated solves
//! (a load continuation, a parameter study, a benchmark) allocate and zero none of them
//! again: a solve of `n = 60` states on 5 nodes otherwise spends about half its time
//! mapping and clearing fresh pages (`docs/bvp20.md`).
//!
//! A solve takes the thread's workspace (a nested solve, from inside a user's `f`, finds
//! none and starts an empty one) and puts it back when it ends, unless the workspace has
//! grown beyond [`KEEP_BYTES`], which is then freed. Every buffer is resized, never cleared:
//! each entry is written before it is read (the unit tests solve on a dirty workspace).

use super::abd::AbdMatrix;
use super::newton::NewtonWork;
use super::system::{Colloc, JacWork};
use std::cell::RefCell;

/// The largest workspace kept for the next solve (bytes of its buffers); a larger one (a
/// fine mesh of a large system) is freed when its solve ends.
pub const KEEP_BYTES: usize = 8 << 20;

/// The buffers of one solve.
#[derive(Debug, Default)]
pub struct Workspace {
    /// The collocation residuals and midpoint values.
    pub col: Colloc,
    /// The ABD Jacobian.
    pub mat: AbdMatrix,
    /// Newton's vectors and the Jacobian's factors.
    pub newton: NewtonWork,
    /// The Jacobian's scratch.
    pub jac: JacWork,
}

impl Workspace {
    /// Bytes held by the buffers (their capacities).
    pub fn bytes(&self) -> usize {
        self.col.bytes() + self.mat.bytes() + self.newton.bytes() + self.jac.bytes()
    }
}

thread_local! {
    static SPARE: RefCell<Option<Workspace>> = const { RefCell::new(None) };
}

/// The thread's spare workspace (an empty one if there is none, or another solve holds it).
pub fn take() -> Workspace {
    SPARE
        .with(|s| s.try_borrow_mut().ok().and_then(|mut s| s.take()))
        .unwrap_or_default()
}

/// Keeps `ws` for the thread's next solve (freed instead if it holds more than
/// [`KEEP_BYTES`]).
pub fn give(ws: Workspace) {
    if ws.bytes() <= KEEP_BYTES {
        SPARE.with(|s| {
            if let Ok(mut s) = s.try_borrow_mut() {
                *s = Some(ws);
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::super::{solve_bvp, BvpOptions, BvpSolution};

    /// scipy's `sl_fun` (`y'' = -p^2 y`, `p` unknown; 2 states, 1 parameter) from `p = 0.5`.
    fn sturm_liouville() -> BvpSolution {
        let x: Vec<f64> = (0..5)
            .map(|i| i as f64 * std::f64::consts::PI / 4.0)
            .collect();
        let y = vec![vec![1.0, 1.0]; 5];
        let opts = BvpOptions {
            tol: 1e-6,
            ..Default::default()
        };
        solve_bvp(
            |_x, y, p, d| {
                d[0] = y[1];
                d[1] = -p[0] * p[0] * y[0];
            },
            |ya, yb, p, r| {
                r[0] = ya[0];
                r[1] = yb[0];
                r[2] = ya[1] - p[0];
            },
            &x,
            &y,
            &[0.5],
            &opts,
        )
        .unwrap()
    }

    /// A periodic problem of 3 states (the bordered elimination), fine mesh.
    fn periodic3() -> BvpSolution {
        let x: Vec<f64> = (0..40).map(|i| i as f64 / 39.0).collect();
        let y = vec![vec![0.0; 3]; 40];
        let opts = BvpOptions {
            tol: 1e-8,
            ..Default::default()
        };
        solve_bvp(
            |x, y, _p, d| {
                d[0] = y[1];
                d[1] = -y[0] + (6.0 * x).cos();
                d[2] = y[0] - y[2];
            },
            |ya, yb, _p, r| {
                r[0] = ya[0] - yb[0];
                r[1] = ya[1] - yb[1];
                r[2] = ya[2] - 1.0;
            },
            &x,
            &y,
            &[],
            &opts,
        )
        .unwrap()
    }

    /// A solve on the workspace a larger, different solve left behind (other sizes, other
    /// elimination, stale values everywhere) is bit for bit the solve on a fresh thread's
    /// empty workspace: no buffer is read before it is written.
    #[test]
    fn a_dirty_workspace_changes_no_bit() {
        let fresh = std::thread::spawn(sturm_liouville).join().unwrap();
        let fresh_p = std::thread::spawn(periodic3).join().unwrap();
        let _ = periodic3();
        let again = sturm_liouville();
        assert_eq!(again, fresh);
        let again_p = periodic3();
        assert_eq!(again_p, fresh_p);
        assert!((again.p[0] - 1.0).abs() < 1e-4, "{:?}", again.p);
    }
}
