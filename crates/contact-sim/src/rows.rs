//! The log's contact rows: `points` rows evenly spaced in the base position x0 from the first
//! contact to the separation, each predicted from the bracketing nodes of the traced branch
//! (cubic Hermite in x0 within a phase, Lagrange extrapolation across a switch) and
//! corrected at its base position (Broyden from the prediction, Newton as the fallback);
//! with an accuracy asked for, each row with its error estimate ([`crate::accuracy`]).

use crate::accuracy::{estimate, Estimator, Hold};
use crate::branch::{hermite, Branch, Constraint, Node, Rescue};
use crate::error::{ContactError, Result};
use crate::phase::{ContactState, Phase};

/// The log's contact rows: `points` rows evenly spaced in x0 from the first node to `last`
/// (both included), each solved at its base position from the bracketing nodes of the traced
/// branch, plus the switch nodes; in the order of the motion. `progress(done, total)` is
/// told of every row. Each row comes with its error estimate from the branch equations at
/// the estimate's integration `loose` (NaN without); `last` with the hold of its own
/// estimate (a release at zero force, any other end at its contour point).
pub(crate) fn rows(
    (branch, loose): (&Branch, Option<&Estimator>),
    nodes: &[Node],
    switches: &[Node],
    (last, last_hold): (&Node, Hold),
    points: usize,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<(ContactState, f64)>> {
    let first = nodes[0];
    let (x_start, x_end) = (first.x0(), last.x0());
    let span = x_start - x_end;
    let targets: Vec<f64> = (1..points.saturating_sub(1))
        .map(|k| x_start - span * k as f64 / (points - 1) as f64)
        .collect();
    let last = (span > 0.0).then_some((last, last_hold));
    rows_at(
        (branch, loose),
        (nodes, switches),
        last,
        &targets,
        points,
        progress,
    )
}

/// The rows of [`rows`] at the coordinates `targets` (falling, strictly between the first
/// node and the end), with the first node, the switch nodes and `last` where given: the
/// rows of one segment of a path, whose targets are the whole path's grid.
pub(crate) fn rows_at(
    (branch, loose): (&Branch, Option<&Estimator>),
    (nodes, switches): (&[Node], &[Node]),
    last: Option<(&Node, Hold)>,
    targets: &[f64],
    points: usize,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<(ContactState, f64)>> {
    let first = nodes[0];
    // two fixed halves, each its own chain of predictions: the numbers do not depend on
    // whether the second half runs on another thread of rayon's pool
    let (near, far) = targets.split_at(targets.len() / 2);
    let (a, b) = if far.is_empty() {
        let near_half = chain((branch, loose), nodes, &[first], near, &mut |k| {
            progress(k, points)
        });
        (near_half, Ok(Vec::new()))
    } else {
        bvp_solvers::parallel::both(
            || {
                chain((branch, loose), nodes, &[first], near, &mut |k| {
                    progress(k, points)
                })
            },
            || chain((branch, loose), nodes, &[], far, &mut |_| {}),
        )
    };
    // the traced nodes held at their contour points (x0 may turn there)
    let node_row = |n: &Node| (n.state, row_estimate(loose, n, Hold::ContourPoint));
    let mut out: Vec<(ContactState, f64)> = Vec::with_capacity(points + switches.len());
    out.push(node_row(&first));
    out.extend(a?);
    out.extend(b?);
    if let Some((last, last_hold)) = last {
        out.push((last.state, row_estimate(loose, last, last_hold)));
    }
    out.extend(switches.iter().map(node_row));
    out.sort_by(|a, b| b.0.x0.total_cmp(&a.0.x0));
    out.dedup_by(|a, b| a.0.x0 == b.0.x0);
    progress(points, points);
    Ok(out)
}

/// The rows at the base positions `targets` (falling), each predicted from the bracketing
/// nodes and the rows of this chain before it (after `start`), then solved; stops at the
/// end of the traced nodes. `done(k)` is told of the `k`-th row.
fn chain(
    (branch, loose): (&Branch, Option<&Estimator>),
    nodes: &[Node],
    start: &[Node],
    targets: &[f64],
    done: &mut dyn FnMut(usize),
) -> Result<Vec<(ContactState, f64)>> {
    let mut out = Vec::with_capacity(targets.len());
    let mut seg = 0;
    let mut recent: Vec<Node> = start.to_vec();
    for (k, &target) in targets.iter().enumerate() {
        done(k + 1);
        while seg + 1 < nodes.len() && nodes[seg + 1].x0() > target {
            seg += 1;
        }
        if seg + 1 >= nodes.len() {
            break;
        }
        let (a, b) = (&nodes[seg], &nodes[seg + 1]);
        let pred = predict(a, b, &recent, target);
        let node = solve_row(branch, &pred, target, a.state.point.xc)?;
        recent.push(node);
        out.push((
            node.state,
            row_estimate(loose, &node, Hold::BasePosition(target)),
        ));
    }
    Ok(out)
}

/// The error estimate of a row ([`estimate`]; infinite where its shots fail), NaN without
/// the estimate's branch equations `loose`.
fn row_estimate(loose: Option<&Estimator>, node: &Node, hold: Hold) -> f64 {
    match loose {
        Some(l) => estimate(l, node, hold).unwrap_or(f64::INFINITY),
        None => f64::NAN,
    }
}

/// The prediction of a row at base position `target` between the traced nodes `a`, `b`.
struct RowPrediction {
    phase: Phase,
    /// The best prediction.
    guess: [f64; 3],
    /// Linear interpolation between the bracketing nodes.
    lin: [f64; 3],
    /// The nearer bracketing node.
    near: [f64; 3],
    /// The Jacobian for Broyden's method.
    jac: [[f64; 3]; 3],
}

/// Predicts the row at `target` between `a` and `b` (`recent`: the rows solved so far).
///
/// Between two nodes of the traced branch in one phase (their Jacobians exact): the cubic
/// Hermite interpolant in x0 through their states and slopes du/dx0, and their Jacobians
/// interpolated linearly (Broyden's first step then contracts the residual ~1000x). Across a
/// phase switch: Lagrange extrapolation in x0 through the last rows of this phase (cubic
/// from four, quadratic from three) when they exist, else interpolation between the
/// bracketing nodes.
fn predict(a: &Node, b: &Node, recent: &[Node], target: f64) -> RowPrediction {
    let (phase, ua, ub) = if a.phase == b.phase {
        (a.phase, a.u, b.u)
    } else {
        (b.phase, b.u, b.u)
    };
    let w = (a.x0() - target) / (a.x0() - b.x0());
    let lin = crate::branch::lerp(&ua, &ub, w);
    let mut guess = lin;
    let mut jac = if w < 0.5 { a.jac } else { b.jac };
    let same: Vec<&Node> = recent
        .iter()
        .rev()
        .take(4)
        .take_while(|r| r.phase == phase)
        .collect();
    if a.phase == b.phase {
        for (r, (ra, rb)) in jac.iter_mut().zip(a.jac.iter().zip(&b.jac)) {
            *r = crate::branch::lerp(ra, rb, w);
        }
        guess = hermite(
            (a.x0(), &a.u, &a.slope()),
            (b.x0(), &b.u, &b.slope()),
            target,
        );
        if let Some(r) = recent.last().filter(|r| r.phase == phase) {
            // and the row before it, where it is of this phase too
            let before = recent.len().checked_sub(2).map(|i| &recent[i]);
            bubble_correction(
                &mut guess,
                (a, b),
                (r, before.filter(|q| q.phase == phase)),
                target,
            );
            // the Jacobian learnt at the last row, carried over by the interpolation's drift
            let wr = (a.x0() - r.x0()) / (a.x0() - b.x0());
            if (-0.5..=1.5).contains(&wr) {
                for (i, row) in jac.iter_mut().enumerate() {
                    let at_r = crate::branch::lerp(&a.jac[i], &b.jac[i], wr);
                    let at_t = crate::branch::lerp(&a.jac[i], &b.jac[i], w);
                    for k in 0..3 {
                        row[k] = at_t[k] + (r.jac[i][k] - at_r[k]);
                    }
                }
            }
        }
    } else if same.len() >= 3 {
        let xs: Vec<f64> = same.iter().map(|r| r.x0()).collect();
        for (i, g) in guess.iter_mut().enumerate() {
            *g = same
                .iter()
                .enumerate()
                .map(|(k, r)| {
                    let l: f64 = (0..xs.len())
                        .filter(|&m| m != k)
                        .map(|m| (target - xs[m]) / (xs[k] - xs[m]))
                        .product();
                    l * r.u[i]
                })
                .sum();
        }
        jac = same[0].jac;
    }
    if !guess.iter().all(|g| g.is_finite()) {
        guess = lin;
    }
    RowPrediction {
        phase,
        guess,
        lin,
        near: if w < 0.5 { ua } else { ub },
        jac,
    }
}

/// The least height of the bubble, relative to its top `span^4 / 16`, at both rows for the
/// correction through two rows ([`bubble_correction`]).
const BUBBLE_FOR_TWO_ROWS: f64 = 0.05;

/// Raises the cubic Hermite prediction `guess` at `target` between the nodes `a`, `b` by the
/// form of the cubic's own leading error term, the bubble `B(x) = (x - xa)^2 (x - xb)^2`,
/// times the polynomial `p` that makes it pass through the solved rows `(r, before)` (the
/// most recent row and the one before it): `guess + B(target) p(target)`, `p` interpolating
/// the cubic's misses divided by `B` at the rows. Through both rows (quintic, `p` linear)
/// where both sit where the bubble is at least [`BUBBLE_FOR_TWO_ROWS`] of its top (the line
/// through the divided misses carries the rows' own errors over, amplified by the ratio of
/// the bubble at the target to that at the rows: 20x at most), else through `r` alone
/// (quartic, `p` constant) where it is usable: within one segment length of the pair and
/// away from both nodes (where its miss determines `p`).
///
/// Measured on the 200-point g1 sweep (q = 5): rows corrected after one Broyden step 121
/// of 198 with two rows, 58 with one; the sweep 51.9 M instructions against 55.2 M (the
/// CLI's g2, circle sweeps 7-8 % fewer too; rows within 3e-10 of before). Three rows did
/// worse (116 after one step): their divided misses are noisier.
fn bubble_correction(
    guess: &mut [f64; 3],
    (a, b): (&Node, &Node),
    (r, before): (&Node, Option<&Node>),
    target: f64,
) {
    let (xa, xb) = (a.x0(), b.x0());
    let span = (xa - xb).abs();
    let bubble = |x: f64| ((x - xa) * (x - xb)).powi(2);
    let usable =
        |x: f64| bubble(x) > 1e-6 * span.powi(4) && (x - 0.5 * (xa + xb)).abs() < 1.5 * span;
    if !usable(r.x0()) {
        return;
    }
    // the cubic's misses at a row, divided by the bubble there
    let divided = |n: &Node| -> (f64, [f64; 3]) {
        let x = n.x0();
        let cubic = hermite((xa, &a.u, &a.slope()), (xb, &b.u, &b.slope()), x);
        (x, std::array::from_fn(|i| (n.u[i] - cubic[i]) / bubble(x)))
    };
    // the line through two divided misses carries their errors over: only from rows well
    // inside the bubble (a twentieth of its height at least: errors amplified 20x at most)
    let inside = |x: f64| bubble(x) >= BUBBLE_FOR_TWO_ROWS * span.powi(4) / 16.0;
    let (x1, d1) = divided(r);
    let second = before
        .filter(|q| inside(x1) && inside(q.x0()) && (q.x0() - x1).abs() > 1e-3 * span)
        .map(divided);
    let w = bubble(target);
    for (i, g) in guess.iter_mut().enumerate() {
        let p = match second {
            Some((x2, d2)) => d1[i] + (d2[i] - d1[i]) / (x2 - x1) * (target - x1),
            None => d1[i],
        };
        *g += w * p;
    }
}

/// Solves the row at `target` from its prediction: Broyden's method from the prediction;
/// Newton from it, from the interpolation between the bracketing nodes, and from the nearer
/// node as fallbacks (`xc` the contact point reported if all fail). Only the last start, a
/// node on the branch, goes on to the trust region where Newton fails
/// ([`Rescue::TrustRegion`]): the earlier ones are attempts with a follow-up
/// ([`Rescue::NewtonOnly`]), and a failing row fails the sweep.
fn solve_row(branch: &Branch, pred: &RowPrediction, target: f64, xc: f64) -> Result<Node> {
    let phase = pred.phase;
    if let Some(n) = branch.broyden_at_base(phase, pred.guess, target, &pred.jac) {
        return Ok(n);
    }
    let mut last_err = None;
    let starts = [
        (pred.guess, Rescue::NewtonOnly),
        (pred.lin, Rescue::NewtonOnly),
        (pred.near, Rescue::TrustRegion),
    ];
    for (start, rescue) in starts {
        match branch.correct(phase, start, Constraint::BasePosition(target), rescue) {
            Ok(n) if (n.x0() - target).abs() <= 1e-9 => return Ok(n),
            Ok(_) => {}
            Err(e) => last_err = Some(e),
        }
    }
    Err(last_err.unwrap_or_else(|| ContactError::BranchStalled {
        phase,
        x0: target,
        xc,
        step: 0.0,
        reason: "no row solution at this base position".into(),
    }))
}

#[cfg(test)]
mod tests {
    use super::bubble_correction;
    use crate::branch::{hermite, Node};
    use crate::phase::{ContactState, ContourPoint, Phase};

    /// A node at base position `x` with unknowns `u` and slope `du/dx0 = s`: a Jacobian whose
    /// first two rows have `s` as their null vector and whose third gives `dx0/du . s = 1`.
    fn node_at(x: f64, u: [f64; 3], s: [f64; 3]) -> Node {
        let ss: f64 = s.iter().map(|v| v * v).sum();
        // a vector off s, made orthogonal to it; then the third of the triple
        let e = if s[0].abs() < s[1].abs() {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let k = (e[0] * s[0] + e[1] * s[1] + e[2] * s[2]) / ss;
        let j0: [f64; 3] = std::array::from_fn(|i| e[i] - k * s[i]);
        let j1 = [
            s[1] * j0[2] - s[2] * j0[1],
            s[2] * j0[0] - s[0] * j0[2],
            s[0] * j0[1] - s[1] * j0[0],
        ];
        let state = ContactState {
            phase: Phase::A,
            point: ContourPoint {
                xc: 0.0,
                yc: 1.0,
                psi: 0.0,
            },
            f: u[1],
            s1: 1.0,
            phi1: u[0],
            x0: x,
            phi0: 0.0,
            m0: 0.0,
            iterations: 0,
            residual: 0.0,
            tilt: crate::contact_law::Tilt::NONE,
        };
        Node {
            phase: Phase::A,
            u,
            state,
            jac: [j0, j1, std::array::from_fn(|i| s[i] / ss)],
        }
    }

    /// The cubic Hermite prediction raised by the bubble through the solved rows is exact
    /// for quintics through two rows and for quartics through one (the rows on either side
    /// of the target, inside the segment or just past its end), and leaves the cubic where
    /// the only row sits on a node.
    #[test]
    fn the_bubble_correction_is_exact_for_quintics_through_two_rows() {
        let quintic = |x: f64| {
            [
                0.3 * x.powi(5) - x.powi(4) + 2.0 * x,
                -0.7 * x.powi(5) + 0.2 * x * x + 1.0,
                x.powi(5) + 0.5 * x.powi(4) - x.powi(3),
            ]
        };
        let d_quintic = |x: f64| {
            [
                1.5 * x.powi(4) - 4.0 * x.powi(3) + 2.0,
                -3.5 * x.powi(4) + 0.4 * x,
                5.0 * x.powi(4) + 2.0 * x.powi(3) - 3.0 * x * x,
            ]
        };
        let quartic = |x: f64| [x.powi(4) - x, 0.5 * x.powi(4) + x * x, -2.0 * x.powi(4)];
        let d_quartic = |x: f64| {
            [
                4.0 * x.powi(3) - 1.0,
                2.0 * x.powi(3) + 2.0 * x,
                -8.0 * x.powi(3),
            ]
        };
        let (xa, xb) = (0.9, 0.4);
        let at =
            |f: &dyn Fn(f64) -> [f64; 3], df: &dyn Fn(f64) -> [f64; 3], x| node_at(x, f(x), df(x));
        let check = |got: [f64; 3], want: [f64; 3], what: &str| {
            for (g, w) in got.iter().zip(want) {
                assert!((g - w).abs() < 1e-12, "{what}: {g} vs {w}");
            }
        };
        for (x1, x2, target) in [(0.8, 0.75, 0.6), (0.5, 0.45, 0.7), (0.95, 0.85, 0.55)] {
            let (a, b) = (at(&quintic, &d_quintic, xa), at(&quintic, &d_quintic, xb));
            let (r, q) = (at(&quintic, &d_quintic, x1), at(&quintic, &d_quintic, x2));
            let mut guess = hermite((xa, &a.u, &a.slope()), (xb, &b.u, &b.slope()), target);
            bubble_correction(&mut guess, (&a, &b), (&r, Some(&q)), target);
            check(guess, quintic(target), &format!("quintic, rows {x1} {x2}"));

            let (a, b) = (at(&quartic, &d_quartic, xa), at(&quartic, &d_quartic, xb));
            let r = at(&quartic, &d_quartic, x1);
            let mut guess = hermite((xa, &a.u, &a.slope()), (xb, &b.u, &b.slope()), target);
            bubble_correction(&mut guess, (&a, &b), (&r, None), target);
            check(guess, quartic(target), &format!("quartic, row {x1}"));
        }
        // a row on a node determines nothing: the cubic stays
        let (a, b) = (at(&quintic, &d_quintic, xa), at(&quintic, &d_quintic, xb));
        let cubic = hermite((xa, &a.u, &a.slope()), (xb, &b.u, &b.slope()), 0.6);
        let mut guess = cubic;
        bubble_correction(&mut guess, (&a, &b), (&a, Some(&b)), 0.6);
        assert_eq!(guess, cubic);
    }

    /// The Hermite interpolant reproduces cubics exactly, also between nodes listed from
    /// high to low x (the sweep's direction).
    #[test]
    fn hermite_is_exact_for_cubics() {
        let p = |x: f64| [x * x * x - 2.0 * x, 0.5 * x * x + 1.0, -3.0 * x * x * x];
        let dp = |x: f64| [3.0 * x * x - 2.0, x, -9.0 * x * x];
        let (xa, xb) = (1.3, -0.4);
        for x in [1.3, 1.0, 0.2, -0.4, -0.7] {
            let got = hermite((xa, &p(xa), &dp(xa)), (xb, &p(xb), &dp(xb)), x);
            for (g, e) in got.iter().zip(p(x)) {
                assert!((g - e).abs() < 1e-12, "x = {x}: {g} vs {e}");
            }
        }
    }
}
