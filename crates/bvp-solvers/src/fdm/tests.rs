//! FDM against closed-form solutions: exactness on quadratics, measured orders (second
//! order on `y'' = -y`, `y'' = y`, Bratu, ...; fourth and sixth with Richardson), Newton.

use super::{BoundaryCondition as Bc, FdmOptions, FdmSolution, FdmSolver, FnBvp, SecondOrderBvp};
use crate::grid::UniformGrid;
use crate::richardson::richardson;
use crate::testing::loglog_slope;
use crate::BvpError;

fn max_err(grid: &UniformGrid, v: &[f64], exact: impl Fn(f64) -> f64) -> f64 {
    v.iter()
        .enumerate()
        .map(|(i, &y)| (y - exact(grid.x(i))).abs())
        .fold(0.0, f64::max)
}

fn solve(solver: &FdmSolver, p: &dyn SecondOrderBvp, a: f64, b: f64, n: usize) -> FdmSolution {
    let grid = UniformGrid::new(a, b, n).unwrap();
    solver.solve(p, &grid, &vec![0.0; n + 1]).unwrap()
}

/// Measures the order of y and y' errors over n = 16 .. 256; returns (slope_y, slope_yp,
/// finest error of y).
fn orders(
    solver: &FdmSolver,
    p: &dyn SecondOrderBvp,
    (a, b): (f64, f64),
    exact: impl Fn(f64) -> f64,
    exact_d: impl Fn(f64) -> f64,
) -> (f64, f64, f64) {
    let (mut hs, mut ey, mut ed) = (vec![], vec![], vec![]);
    for n in [16, 32, 64, 128, 256] {
        let s = solve(solver, p, a, b, n);
        hs.push(s.grid.h());
        ey.push(max_err(&s.grid, &s.y, &exact));
        ed.push(max_err(&s.grid, &s.yp, &exact_d));
    }
    let (oy, od) = (loglog_slope(&hs, &ey), loglog_slope(&hs, &ed));
    eprintln!(
        "orders: y {oy:.4}, y' {od:.4}; finest errors {:.3e}, {:.3e}",
        ey[4], ed[4]
    );
    (oy, od, ey[4])
}

// ---------------------------------------------------------------- Bratu problem

/// Lower-branch theta of Bratu with lambda: theta = sqrt(2 lambda) cosh(theta / 4), by
/// Newton from 1 (independent of the solver under test).
fn bratu_theta(lambda: f64) -> f64 {
    let c = (2.0 * lambda).sqrt();
    let mut t = 1.0_f64;
    for _ in 0..50 {
        let g = t - c * (t / 4.0).cosh();
        let dg = 1.0 - c * (t / 4.0).sinh() / 4.0;
        t -= g / dg;
    }
    t
}

fn bratu_exact(theta: f64) -> impl Fn(f64) -> f64 {
    move |x: f64| -2.0 * (((x - 0.5) * theta / 2.0).cosh() / (theta / 4.0).cosh()).ln()
}

fn bratu(lambda: f64) -> impl SecondOrderBvp {
    FnBvp::new(
        move |_x, y: f64, _yp| -lambda * y.exp(),
        move |_x, y: f64, _yp| -lambda * y.exp(),
        |_x, _y, _yp| 0.0,
    )
}

/// Richardson's table (orders 2, 4, ...) node by node at the coarsest grid's nodes of
/// solutions on `n, 2n, 4n, ...` intervals.
fn extrapolate_nodes(levels: &[&FdmSolution]) -> Vec<f64> {
    (0..levels[0].y.len())
        .map(|i| {
            let column: Vec<f64> = (0..levels.len()).map(|j| levels[j].y[i << j]).collect();
            richardson(&column, 2, 2).unwrap().value
        })
        .collect()
}

fn dirichlet00() -> FdmSolver {
    FdmSolver::new(Bc::Dirichlet(0.0), Bc::Dirichlet(0.0))
}

#[test]
fn bratu_theta_matches_literature() {
    assert!((bratu_theta(1.0) - 1.517_164_599_050_754_3).abs() < 1e-14);
}

#[test]
fn bratu_second_order() {
    let theta = bratu_theta(1.0);
    let exact = bratu_exact(theta);
    let p = bratu(1.0);
    let (mut hs, mut es) = (vec![], vec![]);
    for n in [8, 16, 32, 64, 128, 256] {
        let s = solve(&dirichlet00(), &p, 0.0, 1.0, n);
        hs.push(s.grid.h());
        es.push(max_err(&s.grid, &s.y, &exact));
    }
    let slope = loglog_slope(&hs, &es);
    eprintln!("bratu FDM order {slope:.4}, errors {es:?}");
    assert!((1.9..=2.1).contains(&slope), "order {slope}");
    // Error constant: measured 2.17e-7 at n = 256.
    assert!(es[5] < 3e-7, "error at n=256: {:e}", es[5]);
}

#[test]
fn bratu_richardson_one_level_fourth_order() {
    let exact = bratu_exact(bratu_theta(1.0));
    let p = bratu(1.0);
    let (mut hs, mut es) = (vec![], vec![]);
    for n in [8, 16, 32, 64] {
        let c = solve(&dirichlet00(), &p, 0.0, 1.0, n);
        let f = solve(&dirichlet00(), &p, 0.0, 1.0, 2 * n);
        let r = extrapolate_nodes(&[&c, &f]);
        hs.push(c.grid.h());
        es.push(max_err(&c.grid, &r, &exact));
    }
    let slope = loglog_slope(&hs, &es);
    eprintln!("bratu FDM + 1 Richardson level: order {slope:.4}, errors {es:?}");
    assert!((3.7..=4.3).contains(&slope), "order {slope}, errors {es:?}");
}

#[test]
fn bratu_richardson_two_levels_sixth_order() {
    let exact = bratu_exact(bratu_theta(1.0));
    let p = bratu(1.0);
    let (mut hs, mut es, mut es_mid) = (vec![], vec![], vec![]);
    for n in [4, 8, 16, 32] {
        let s: Vec<FdmSolution> = [n, 2 * n, 4 * n]
            .iter()
            .map(|&m| solve(&dirichlet00(), &p, 0.0, 1.0, m))
            .collect();
        let r = extrapolate_nodes(&[&s[0], &s[1], &s[2]]);
        hs.push(s[0].grid.h());
        es.push(max_err(&s[0].grid, &r, &exact));
        let mids: Vec<f64> = s.iter().map(|v| v.y[v.y.len() / 2]).collect();
        let ex = richardson(&mids, 2, 2).unwrap();
        es_mid.push((ex.value - exact(0.5)).abs());
        // The error estimate is conservative (bounds the true error).
        assert!(ex.error_estimate >= es_mid[es_mid.len() - 1]);
    }
    let slope = loglog_slope(&hs, &es);
    assert!((5.6..=6.4).contains(&slope), "order {slope}, errors {es:?}");
    let slope_mid = loglog_slope(&hs, &es_mid);
    eprintln!(
        "bratu FDM + 2 levels: order {slope:.4} (max-norm), {slope_mid:.4} (y(1/2)), errors {es:?}"
    );
    assert!((5.6..=6.4).contains(&slope_mid), "order {slope_mid}");
}

#[test]
fn newton_converges_quadratically() {
    let p = bratu(3.0);
    let grid = UniformGrid::new(0.0, 1.0, 64).unwrap();
    let guess = vec![0.0; 65];
    let s = dirichlet00().solve(&p, &grid, &guess).unwrap();
    // 5 iterations to 1e-16 plus one confirming step (measured: 6).
    assert!(s.stats.iterations <= 7, "{} iterations", s.stats.iterations);
    assert!(s.stats.residual <= 1e-12 && s.stats.step_norm <= 1e-12);
    // Residuals after k = 2, 3, 4 iterations, read from the NoConvergence errors.
    let res: Vec<f64> = (2..=4)
        .map(|k| {
            let solver = dirichlet00().with_options(FdmOptions {
                max_iter: k,
                ..FdmOptions::default()
            });
            match solver.solve(&p, &grid, &guess) {
                Err(BvpError::NoConvergence {
                    method,
                    iterations,
                    residual,
                }) => {
                    assert_eq!(method, "fdm-newton");
                    assert_eq!(iterations, k);
                    residual
                }
                other => panic!("expected NoConvergence, got {other:?}"),
            }
        })
        .collect();
    // Convergence order q = ln(r4/r3) / ln(r3/r2) (measured 2.00) and a stable constant
    // C = r_{k+1} / r_k^2 (measured 345 and 338); linear convergence would give q ~ 1.
    let q = (res[2] / res[1]).ln() / (res[1] / res[0]).ln();
    assert!((1.8..=2.2).contains(&q), "order {q}, residuals {res:?}");
    let c1 = res[1] / (res[0] * res[0]);
    let c2 = res[2] / (res[1] * res[1]);
    assert!(c2 / c1 > 0.33 && c2 / c1 < 3.0, "C: {c1} {c2}");
}

#[test]
fn max_iter_one_reports_no_convergence_with_residual() {
    // Bratu with lambda = 3 from a zero guess is far from converged after one step.
    let solver = FdmSolver::new(Bc::Dirichlet(0.0), Bc::Dirichlet(0.0)).with_options(FdmOptions {
        max_iter: 1,
        ..FdmOptions::default()
    });
    let grid = UniformGrid::new(0.0, 1.0, 32).unwrap();
    match solver.solve(&bratu(3.0), &grid, &[0.0; 33]) {
        Err(BvpError::NoConvergence {
            method: "fdm-newton",
            iterations: 1,
            residual,
        }) => assert!(residual.is_finite() && residual > 1e-5, "{residual:e}"),
        other => panic!("expected NoConvergence, got {other:?}"),
    }
}

#[test]
fn damping_converges_linearly_to_same_solution() {
    let p = bratu(1.0);
    let grid = UniformGrid::new(0.0, 1.0, 32).unwrap();
    let full = dirichlet00().solve(&p, &grid, &[0.0; 33]).unwrap();
    let damped = dirichlet00()
        .with_options(FdmOptions {
            damping: 0.5,
            ..FdmOptions::default()
        })
        .solve(&p, &grid, &[0.0; 33])
        .unwrap();
    // Step shrinks by ~(1 - 0.5) per iteration: from ~0.14 to 1e-12 takes ~37 iterations.
    assert!(
        (30..=60).contains(&damped.stats.iterations),
        "{} iterations",
        damped.stats.iterations
    );
    assert!(full.stats.iterations < damped.stats.iterations);
    let diff = full
        .y
        .iter()
        .zip(&damped.y)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-11, "{diff:e}");
}

// ---------------------------------------------------------------- linear closed forms

#[test]
fn dirichlet_both_ends_sinh() {
    // y'' = y, y(0) = 0, y(1) = 1: y = sinh x / sinh 1. Linear: Newton takes 2 iterations.
    let p = FnBvp::new(|_x, y, _yp| y, |_x, _y, _yp| 1.0, |_x, _y, _yp| 0.0);
    let solver = FdmSolver::new(Bc::Dirichlet(0.0), Bc::Dirichlet(1.0));
    let s1 = 1f64.sinh();
    let (oy, oyp, e) = orders(
        &solver,
        &p,
        (0.0, 1.0),
        |x| x.sinh() / s1,
        |x| x.cosh() / s1,
    );
    assert!((1.9..=2.1).contains(&oy), "order y {oy}");
    assert!((1.9..=2.1).contains(&oyp), "order y' {oyp}");
    assert!(e < 1e-6, "{e:e}");
    assert_eq!(solve(&solver, &p, 0.0, 1.0, 10).stats.iterations, 2);
}

#[test]
fn neumann_left_sin() {
    // y'' = -y, y'(0) = 1, y(1) = sin 1: y = sin x.
    let p = FnBvp::new(|_x, y: f64, _yp| -y, |_x, _y, _yp| -1.0, |_x, _y, _yp| 0.0);
    let solver = FdmSolver::new(Bc::Neumann(1.0), Bc::Dirichlet(1f64.sin()));
    let (oy, oyp, e) = orders(&solver, &p, (0.0, 1.0), f64::sin, f64::cos);
    assert!((1.9..=2.1).contains(&oy), "order y {oy}");
    assert!((1.9..=2.1).contains(&oyp), "order y' {oyp}");
    assert!(e < 1e-5, "{e:e}");
}

#[test]
fn robin_both_ends_exp_with_first_derivative_term() {
    // y'' = y' on [0, 1], y = e^x: y(0) + 2 y'(0) = 3, 2 y(1) + y'(1) = 3e (F_{y'} used).
    let p = FnBvp::new(|_x, _y, yp| yp, |_x, _y, _yp| 0.0, |_x, _y, _yp| 1.0);
    let e1 = 1f64.exp();
    let solver = FdmSolver::new(
        Bc::Robin {
            alpha: 1.0,
            beta: 2.0,
            gamma: 3.0,
        },
        Bc::Robin {
            alpha: 2.0,
            beta: 1.0,
            gamma: 3.0 * e1,
        },
    );
    let (oy, oyp, e) = orders(&solver, &p, (0.0, 1.0), f64::exp, f64::exp);
    assert!((1.9..=2.1).contains(&oy), "order y {oy}");
    assert!((1.9..=2.1).contains(&oyp), "order y' {oyp}");
    assert!(e < 2e-5, "{e:e}");
}

#[test]
fn neumann_right_nonlinear_log() {
    // y'' = -(y')^2 on [0, 1] with y(0) = 0, y'(1) = 1/2: y = ln(1 + x). Non-linear in y'.
    let p = FnBvp::new(
        |_x, _y, yp: f64| -yp * yp,
        |_x, _y, _yp| 0.0,
        |_x, _y, yp: f64| -2.0 * yp,
    );
    let solver = FdmSolver::new(Bc::Dirichlet(0.0), Bc::Neumann(0.5));
    let (oy, oyp, e) = orders(
        &solver,
        &p,
        (0.0, 1.0),
        |x| (1.0 + x).ln(),
        |x| 1.0 / (1.0 + x),
    );
    assert!((1.9..=2.1).contains(&oy), "order y {oy}");
    assert!((1.9..=2.1).contains(&oyp), "order y' {oyp}");
    assert!(e < 1e-5, "{e:e}");
}

#[test]
fn quadratics_reproduced_exactly() {
    // y = x^2 + x solves y'' = y - x^2 - x + 2 + 3 (y' - 2x - 1) for any conditions that
    // y satisfies; the central scheme with ghost points is exact on quadratics.
    let exact = |x: f64| x * x + x;
    let d_exact = |x: f64| 2.0 * x + 1.0;
    let p = FnBvp::new(
        |x: f64, y: f64, yp: f64| y - x * x - x + 2.0 + 3.0 * (yp - 2.0 * x - 1.0),
        |_x, _y, _yp| 1.0,
        |_x, _y, _yp| 3.0,
    );
    let (a, b) = (-0.5, 2.0);
    let robin = |x: f64, alpha: f64, beta: f64| Bc::Robin {
        alpha,
        beta,
        gamma: alpha * exact(x) + beta * d_exact(x),
    };
    let cases = [
        (robin(a, 2.0, -1.0), Bc::Neumann(d_exact(b))),
        (Bc::Dirichlet(exact(a)), robin(b, 0.5, 3.0)),
        (Bc::Neumann(d_exact(a)), Bc::Dirichlet(exact(b))),
        (robin(a, 1.0, 1.0), robin(b, -1.0, 2.0)),
    ];
    for (left, right) in cases {
        for n in [2, 7, 40] {
            let s = solve(&FdmSolver::new(left, right), &p, a, b, n);
            let ey = max_err(&s.grid, &s.y, exact);
            let ed = max_err(&s.grid, &s.yp, d_exact);
            assert!(ey < 1e-12, "{left:?} {right:?} n={n}: y error {ey:e}");
            assert!(ed < 1e-11, "{left:?} {right:?} n={n}: y' error {ed:e}");
        }
    }
}

#[test]
fn fine_grid_terminates_at_rounding_floor() {
    // n = 20000: |J^{-1}| ~ 5e7, so a 1e-12 absolute step is below what f64 resolves; the
    // floored test must still converge, and the O(h^2) error (~1e-10) must be intact.
    let p = FnBvp::new(|_x, y, _yp| y, |_x, _y, _yp| 1.0, |_x, _y, _yp| 0.0);
    let solver = FdmSolver::new(Bc::Neumann(1.0 / 1f64.sinh()), Bc::Dirichlet(1.0));
    let s = solve(&solver, &p, 0.0, 1.0, 20_000);
    eprintln!("n = 20000: {:?}", s.stats);
    assert!(s.stats.iterations <= 3, "{}", s.stats.iterations);
    let s1 = 1f64.sinh();
    let e = max_err(&s.grid, &s.y, |x| x.sinh() / s1);
    assert!(e < 1e-9, "{e:e}");
}

// ---------------------------------------------------------------- errors

#[test]
fn invalid_inputs_are_rejected() {
    let p = bratu(1.0);
    let grid = UniformGrid::new(0.0, 1.0, 8).unwrap();
    let guess = [0.0; 9];
    let with = |o: FdmOptions| dirichlet00().with_options(o).solve(&p, &grid, &guess);
    let d = FdmOptions::default;
    for (o, name) in [
        (FdmOptions { tol: 0.0, ..d() }, "tol"),
        (
            FdmOptions {
                tol: f64::NAN,
                ..d()
            },
            "tol",
        ),
        (FdmOptions { max_iter: 0, ..d() }, "max_iter"),
        (
            FdmOptions {
                damping: 0.0,
                ..d()
            },
            "damping",
        ),
        (
            FdmOptions {
                damping: 1.5,
                ..d()
            },
            "damping",
        ),
        (
            FdmOptions {
                damping: f64::NAN,
                ..d()
            },
            "damping",
        ),
    ] {
        match with(o) {
            Err(BvpError::InvalidInput { name: got, .. }) => assert_eq!(got, name),
            other => panic!("expected InvalidInput({name}), got {other:?}"),
        }
    }
    assert_eq!(
        dirichlet00().solve(&p, &grid, &[0.0; 8]).unwrap_err(),
        BvpError::DimensionMismatch {
            name: "guess",
            expected: 9,
            found: 8
        }
    );
    let mut nan_guess = guess;
    nan_guess[3] = f64::NAN;
    assert!(matches!(
        dirichlet00().solve(&p, &grid, &nan_guess),
        Err(BvpError::InvalidInput { name: "guess", .. })
    ));
    let bad_bc = FdmSolver::new(Bc::Dirichlet(f64::INFINITY), Bc::Dirichlet(0.0));
    assert!(matches!(
        bad_bc.solve(&p, &grid, &guess),
        Err(BvpError::InvalidInput { .. })
    ));
}

#[test]
fn singular_and_non_finite_are_reported() {
    let grid = UniformGrid::new(0.0, 1.0, 8).unwrap();
    let guess = [0.0; 9];
    let zero = Bc::Robin {
        alpha: 0.0,
        beta: 0.0,
        gamma: 1.0,
    };
    let p = bratu(1.0);
    assert!(matches!(
        FdmSolver::new(zero, Bc::Dirichlet(0.0)).solve(&p, &grid, &guess),
        Err(BvpError::SingularJacobian { row: 0, .. })
    ));
    assert!(matches!(
        FdmSolver::new(Bc::Dirichlet(0.0), zero).solve(&p, &grid, &guess),
        Err(BvpError::SingularJacobian { row: 8, .. })
    ));
    // y'' = 1 with y'(0) = 0, y'(1) = 1: compatible but non-unique; J singular at row n.
    let flat = FnBvp::new(|_x, _y, _yp| 1.0, |_x, _y, _yp| 0.0, |_x, _y, _yp| 0.0);
    assert!(matches!(
        FdmSolver::new(Bc::Neumann(0.0), Bc::Neumann(1.0)).solve(&flat, &grid, &guess),
        Err(BvpError::SingularJacobian { row: 8, .. })
    ));
    // F blows up at y > 0.5 (log of a negative number).
    let blow = FnBvp::new(
        |_x, y: f64, _yp| (0.5 - y).ln(),
        |_x, y: f64, _yp| -1.0 / (0.5 - y),
        |_x, _y, _yp| 0.0,
    );
    let mut hot = guess;
    hot[4] = 0.7;
    assert_eq!(
        dirichlet00().solve(&blow, &grid, &hot).unwrap_err(),
        BvpError::NonFinite {
            what: "fdm residual",
            s: 0.5
        }
    );
}

// ---------------------------------------------------------------------------------------
// Right-end (bordered) dependence: y'' = F(x, y, y', y(b)).

/// `y'' = k y(1) + e^x` (linear, non-local), the constant `k` and the closures below give
/// closed forms `y = K x^2 / 2 + e^x + A x + B` with `K = k y(1)`.
struct NonLocalLinear {
    k: f64,
}

impl SecondOrderBvp for NonLocalLinear {
    fn f(&self, x: f64, _y: f64, _yp: f64) -> f64 {
        x.exp()
    }
    fn f_y(&self, _x: f64, _y: f64, _yp: f64) -> f64 {
        0.0
    }
    fn f_yp(&self, _x: f64, _y: f64, _yp: f64) -> f64 {
        0.0
    }
    fn depends_on_right_end(&self) -> bool {
        true
    }
    fn eval_with_right_end(&self, x: f64, _y: f64, _yp: f64, yb: f64) -> (f64, f64, f64, f64) {
        (self.k * yb + x.exp(), 0.0, 0.0, self.k)
    }
}

/// Manufactured non-linear problem with exact solution `y = sin x` on `[0, 1]`:
/// `y'' = -e^y + e^{sin x} - sin x + y(1)^2 - sin^2 1`.
struct NonLocalNonlinear;

impl SecondOrderBvp for NonLocalNonlinear {
    fn f(&self, x: f64, y: f64, _yp: f64) -> f64 {
        -y.exp() + x.sin().exp() - x.sin()
    }
    fn f_y(&self, _x: f64, y: f64, _yp: f64) -> f64 {
        -y.exp()
    }
    fn f_yp(&self, _x: f64, _y: f64, _yp: f64) -> f64 {
        0.0
    }
    fn depends_on_right_end(&self) -> bool {
        true
    }
    fn eval_with_right_end(&self, x: f64, y: f64, _yp: f64, yb: f64) -> (f64, f64, f64, f64) {
        let s1 = 1.0_f64.sin();
        (
            -y.exp() + x.sin().exp() - x.sin() + yb * yb - s1 * s1,
            -y.exp(),
            0.0,
            2.0 * yb,
        )
    }
}

#[test]
fn right_end_linear_dirichlet_neumann_closed_form_second_order() {
    // y'' = y(1) + e^x, y(0) = 0, y'(1) = 0: K = y(1) = -2/3,
    // y = -x^2/3 + e^x + (2/3 - e) x - 1.
    let e = std::f64::consts::E;
    let exact = move |x: f64| -x * x / 3.0 + x.exp() + (2.0 / 3.0 - e) * x - 1.0;
    let dexact = move |x: f64| -2.0 * x / 3.0 + x.exp() + 2.0 / 3.0 - e;
    let solver = FdmSolver::new(Bc::Dirichlet(0.0), Bc::Neumann(0.0));
    let p = NonLocalLinear { k: 1.0 };
    let (sy, syp, fine) = orders(&solver, &p, (0.0, 1.0), exact, dexact);
    // measured: 2.00, 2.00, 2.9e-6 at n = 256
    assert!((1.95..=2.05).contains(&sy), "order of y {sy}");
    assert!((1.9..=2.1).contains(&syp), "order of y' {syp}");
    assert!(fine < 1e-5, "{fine:e}");
    // Linear: one step solves it, one confirms.
    let s = solve(&solver, &p, 0.0, 1.0, 64);
    assert!(s.stats.iterations <= 2, "{}", s.stats.iterations);
}

#[test]
fn right_end_linear_robin_left_closed_form() {
    // y'' = y(1) + e^x, y'(0) - y(0) = 0, y'(1) = 0: A = B = -K - e, K = y(1) = -2e/5.
    let e = std::f64::consts::E;
    let k = -2.0 * e / 5.0;
    let exact = move |x: f64| 0.5 * k * x * x + x.exp() + (-k - e) * (x + 1.0);
    let dexact = move |x: f64| k * x + x.exp() - k - e;
    let solver = FdmSolver::new(
        Bc::Robin {
            alpha: -1.0,
            beta: 1.0,
            gamma: 0.0,
        },
        Bc::Neumann(0.0),
    );
    let p = NonLocalLinear { k: 1.0 };
    let (sy, syp, fine) = orders(&solver, &p, (0.0, 1.0), exact, dexact);
    assert!((1.95..=2.05).contains(&sy), "order of y {sy}");
    assert!((1.9..=2.1).contains(&syp), "order of y' {syp}");
    assert!(fine < 1e-4, "{fine:e}");
}

#[test]
fn right_end_nonlinear_second_order_and_quadratic_newton() {
    let solver = FdmSolver::new(Bc::Dirichlet(0.0), Bc::Neumann(1.0_f64.cos()));
    let (sy, syp, fine) = orders(&solver, &NonLocalNonlinear, (0.0, 1.0), f64::sin, f64::cos);
    assert!((1.95..=2.05).contains(&sy), "order of y {sy}");
    assert!((1.9..=2.1).contains(&syp), "order of y' {syp}");
    assert!(fine < 1e-5, "{fine:e}");

    let grid = UniformGrid::new(0.0, 1.0, 64).unwrap();
    let guess = vec![0.0; 65];
    let res: Vec<f64> = (1..=5)
        .map(|k| {
            let s = solver.clone().with_options(FdmOptions {
                max_iter: k,
                ..FdmOptions::default()
            });
            match s.solve(&NonLocalNonlinear, &grid, &guess) {
                Err(BvpError::NoConvergence { residual, .. }) => residual,
                other => panic!("expected NoConvergence, got {other:?}"),
            }
        })
        .collect();
    // Residuals after k = 1..5 iterations (measured 3.7e-4, 3.6e-5, 1.3e-8, 3.8e-14,
    // 1.6e-16): r_{k+1} <= C r_k^2 with one constant (measured C = 261, 10, 223) down to
    // the rounding floor; linear convergence would give r_{k+1} / r_k ~ const.
    for k in 0..3 {
        let c = res[k + 1] / (res[k] * res[k]);
        assert!(c < 1e3, "C_{k} = {c}, residuals {res:?}");
    }
    assert!(res[3] < 1e-13 && res[3] / res[2] < 1e-4, "{res:?}");
    let s = solver.solve(&NonLocalNonlinear, &grid, &guess).unwrap();
    assert!(s.stats.iterations <= 6, "{}", s.stats.iterations);
}

#[test]
fn right_end_without_dependence_matches_plain_path() {
    // The bordered (pivoted) path with F_{y(b)} = 0 equals the Thomas path.
    let p = NonLocalLinear { k: 0.0 };
    let plain = FnBvp::new(|x: f64, _, _| x.exp(), |_, _, _| 0.0, |_, _, _| 0.0);
    let solver = FdmSolver::new(Bc::Dirichlet(1.0), Bc::Neumann(2.0));
    let a = solve(&solver, &p, 0.0, 1.0, 50);
    let b = solve(&solver, &plain, 0.0, 1.0, 50);
    let d =
        a.y.iter()
            .zip(&b.y)
            .map(|(u, v)| (u - v).abs())
            .fold(0.0, f64::max);
    assert!(d < 1e-13, "{d:e}");
}

#[test]
fn right_end_singular_bordered_system_is_reported() {
    // y'' = y(1) - y with y'(0) = y'(1) = 0: every constant solves it, and also the discrete
    // system (the constant vector is in the kernel of T + c e_n^T).
    struct Kernel;
    impl SecondOrderBvp for Kernel {
        fn f(&self, _x: f64, y: f64, _yp: f64) -> f64 {
            -y
        }
        fn f_y(&self, _x: f64, _y: f64, _yp: f64) -> f64 {
            -1.0
        }
        fn f_yp(&self, _x: f64, _y: f64, _yp: f64) -> f64 {
            0.0
        }
        fn depends_on_right_end(&self) -> bool {
            true
        }
        fn eval_with_right_end(&self, _x: f64, y: f64, _yp: f64, yb: f64) -> (f64, f64, f64, f64) {
            (yb - y, -1.0, 0.0, 1.0)
        }
    }
    let grid = UniformGrid::new(0.0, 1.0, 32).unwrap();
    let r = FdmSolver::new(Bc::Neumann(0.0), Bc::Neumann(0.0)).solve(&Kernel, &grid, &[0.0; 33]);
    assert!(matches!(r, Err(BvpError::SingularJacobian { .. })), "{r:?}");
}
