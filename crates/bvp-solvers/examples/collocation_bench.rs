//! The Rust half of the work-precision comparison with scipy's `solve_bvp`
//! (`crates/bvp-solvers/bench/compare_scipy.py` runs both): every problem of
//! [`problems`] at tol 1e-3 and 1e-6, one JSON line each with the nodes, the error against
//! the closed form / published value, and the best time of repeated solves.
//!
//! `cargo run --release --example collocation_bench -p bvp-solvers`

use bvp_solvers::collocation::{solve_bvp, BvpOptions, BvpSolution};
use std::f64::consts::PI;
use std::time::Instant;

type F = fn(f64, &[f64], &[f64], &mut [f64]);
type B = fn(&[f64], &[f64], &[f64], &mut [f64]);

/// One benchmark problem: same mesh, guess, parameters and options as the Python side.
struct Problem {
    name: &'static str,
    f: F,
    bc: B,
    x: Vec<f64>,
    y: Vec<Vec<f64>>,
    p: Vec<f64>,
    singular: Option<Vec<f64>>,
    /// The error of a solution: max over a grid against the closed form, or the distance of
    /// the published value.
    error: fn(&BvpSolution) -> f64,
}

fn linspace(a: f64, b: f64, m: usize) -> Vec<f64> {
    (0..m)
        .map(|i| a + (b - a) * i as f64 / (m - 1) as f64)
        .collect()
}

fn grid_err(sol: &BvpSolution, a: f64, b: f64, exact: impl Fn(f64) -> f64) -> f64 {
    linspace(a, b, 1001)
        .into_iter()
        .map(|t| (sol.eval(t)[0] - exact(t)).abs())
        .fold(0.0, f64::max)
}

fn erf(z: f64) -> f64 {
    if z < 0.0 {
        return -erf(-z);
    }
    if z <= 3.0 {
        let (mut term, mut sum) = (z, z);
        for n in 1..200 {
            term *= -z * z / n as f64;
            let add = term / (2 * n + 1) as f64;
            sum += add;
            if add.abs() < 1e-17 * sum.abs() {
                break;
            }
        }
        return 2.0 / PI.sqrt() * sum;
    }
    let mut f = z;
    for k in (1..80).rev() {
        f = z + (k as f64 / 2.0) / f;
    }
    1.0 - (-z * z).exp() / PI.sqrt() / f
}

fn bratu_theta() -> f64 {
    let mut th = 1.0f64;
    for _ in 0..200 {
        th = 2.0f64.sqrt() * (th / 4.0).cosh();
    }
    th
}

fn winkler_exact(l: f64) -> impl Fn(f64) -> f64 {
    // EI = 1, k = 4 (beta = 1), q = 1, simply supported; the end terms' coupling is e^-L.
    move |x: f64| 0.25 * (1.0 - (-x).exp() * x.cos() - (-(l - x)).exp() * (l - x).cos())
}

fn winkler(l: f64) -> Problem {
    Problem {
        name: if l == 30.0 {
            "winkler_L30"
        } else {
            "winkler_L50"
        },
        f: |_, y, _, d| {
            d[0] = y[1];
            d[1] = y[2];
            d[2] = y[3];
            d[3] = 1.0 - 4.0 * y[0];
        },
        bc: |ya, yb, _, r| {
            r[0] = ya[0];
            r[1] = ya[2];
            r[2] = yb[0];
            r[3] = yb[2];
        },
        x: linspace(0.0, l, 5),
        y: vec![vec![0.0; 4]; 5],
        p: vec![],
        singular: None,
        error: if l == 30.0 {
            |s| grid_err(s, 0.0, 30.0, winkler_exact(30.0))
        } else {
            |s| grid_err(s, 0.0, 50.0, winkler_exact(50.0))
        },
    }
}

fn problems() -> Vec<Problem> {
    let mut v = vec![
        Problem {
            name: "exp",
            f: |_, y, _, d| {
                d[0] = y[1];
                d[1] = y[0];
            },
            bc: |ya, yb, _, r| {
                r[0] = ya[0] - 1.0;
                r[1] = yb[0];
            },
            x: linspace(0.0, 1.0, 5),
            y: vec![vec![0.0; 2]; 5],
            p: vec![],
            singular: None,
            error: |s| {
                grid_err(s, 0.0, 1.0, |x| {
                    ((-x).exp() - (x - 2.0).exp()) / (1.0 - (-2.0f64).exp())
                })
            },
        },
        Problem {
            name: "sturm_liouville",
            f: |_, y, p, d| {
                d[0] = y[1];
                d[1] = -p[0] * p[0] * y[0];
            },
            bc: |ya, yb, p, r| {
                r[0] = ya[0];
                r[1] = yb[0];
                r[2] = ya[1] - p[0];
            },
            x: linspace(0.0, PI, 5),
            y: vec![vec![1.0; 2]; 5],
            p: vec![0.5],
            singular: None,
            error: |s| grid_err(s, 0.0, PI, f64::sin).max((s.p[0] - 1.0).abs()),
        },
        Problem {
            name: "emden",
            f: |_, y, _, d| {
                d[0] = y[1];
                d[1] = -y[0].powi(5);
            },
            bc: |ya, yb, _, r| {
                r[0] = ya[1];
                r[1] = yb[0] - 0.75f64.sqrt();
            },
            x: linspace(0.0, 1.0, 10),
            y: vec![vec![0.75f64.sqrt(), 1e-4]; 10],
            p: vec![],
            singular: Some(vec![0.0, 0.0, 0.0, -2.0]),
            error: |s| grid_err(s, 0.0, 1.0, |x| (1.0 + x * x / 3.0).powf(-0.5)),
        },
        Problem {
            name: "big_n60",
            f: |_, y, _, d| {
                for i in 0..30 {
                    d[2 * i] = y[2 * i + 1];
                    d[2 * i + 1] = 0.0;
                }
            },
            bc: |ya, yb, _, r| {
                for i in 0..30 {
                    r[i] = ya[2 * i];
                    r[30 + i] = yb[2 * i] - 1.0;
                }
            },
            x: linspace(0.0, 1.0, 5),
            y: vec![vec![0.0; 60]; 5],
            p: vec![],
            singular: None,
            error: |s| grid_err(s, 0.0, 1.0, |x| x),
        },
        Problem {
            name: "shock",
            f: |x, y, _, d| {
                let eps = 1e-3;
                d[0] = y[1];
                d[1] = -(x * y[1] + eps * PI * PI * (PI * x).cos() + PI * x * (PI * x).sin()) / eps;
            },
            bc: |ya, yb, _, r| {
                r[0] = ya[0] + 2.0;
                r[1] = yb[0];
            },
            x: linspace(-1.0, 1.0, 5),
            y: vec![vec![0.0; 2]; 5],
            p: vec![],
            singular: None,
            error: |s| {
                let k = (2.0f64 * 1e-3).sqrt();
                grid_err(s, -1.0, 1.0, |x| (PI * x).cos() + erf(x / k) / erf(1.0 / k))
            },
        },
        Problem {
            name: "nonlin_bc",
            f: |_, y, _, d| {
                d[0] = y[1];
                d[1] = 0.0;
            },
            bc: |ya, yb, _, r| {
                let (kappa, ioa, ioc, v, f) = (1.64, 0.01, 1.0e-4, 0.5, 38.9);
                let ha = -ya[0];
                r[0] = ioa * ((f * ha).exp() - (-f * ha).exp()) + kappa * ya[1];
                let hc = v - yb[0] - 1.0;
                r[1] = ioc * ((f * hc).exp() - (-f * hc).exp()) - kappa * yb[1];
            },
            x: linspace(0.0, 0.1, 5),
            y: vec![vec![0.0; 2]; 5],
            p: vec![],
            singular: None,
            // the published slope has 8 digits: compare y(0) and y(0.1) through it
            error: |s| grid_err(s, 0.0, 0.1, |x| -0.13426436116763119 - 1.1308709 * x),
        },
        Problem {
            name: "periodic",
            f: |x, y, _, d| {
                d[0] = y[1];
                d[1] = x.cos() - 2.0 * y[0];
            },
            bc: |ya, yb, _, r| {
                r[0] = ya[0] - yb[0];
                r[1] = ya[1] - yb[1];
            },
            x: linspace(0.0, 2.0 * PI, 7),
            y: vec![vec![0.0; 2]; 7],
            p: vec![],
            singular: None,
            error: |s| grid_err(s, 0.0, 2.0 * PI, f64::cos),
        },
        Problem {
            name: "mathieu",
            f: |x, y, p, d| {
                d[0] = y[1];
                d[1] = -(p[0] - 10.0 * (2.0 * x).cos()) * y[0];
            },
            bc: |ya, yb, _, r| {
                r[0] = ya[1];
                r[1] = yb[1];
                r[2] = ya[0] - 1.0;
            },
            x: linspace(0.0, PI, 10),
            y: linspace(0.0, PI, 10)
                .iter()
                .map(|&t| vec![(4.0 * t).cos(), -4.0 * (4.0 * t).sin()])
                .collect(),
            p: vec![15.0],
            singular: None,
            error: |s| (s.p[0] - 17.096_581_684_366_047).abs(),
        },
        Problem {
            name: "twobvp",
            f: |_, y, _, d| {
                d[0] = y[1];
                d[1] = -y[0].abs();
            },
            bc: |ya, yb, _, r| {
                r[0] = ya[0];
                r[1] = yb[0] + 2.0;
            },
            x: linspace(0.0, 4.0, 5),
            y: vec![vec![1.0, 0.0]; 5],
            p: vec![],
            singular: None,
            error: |s| {
                let a = 2.0 / (4.0 - PI).sinh();
                grid_err(s, 0.0, 4.0, |x| {
                    if x <= PI {
                        a * x.sin()
                    } else {
                        -a * (x - PI).sinh()
                    }
                })
            },
        },
        Problem {
            name: "falkner_skan",
            f: |_, y, _, d| {
                d[0] = y[1];
                d[1] = y[2];
                d[2] = -y[0] * y[2] - 0.5 * (1.0 - y[1] * y[1]);
            },
            bc: |ya, yb, _, r| {
                r[0] = ya[0];
                r[1] = ya[1];
                r[2] = yb[1] - 1.0;
            },
            x: linspace(0.0, 6.0, 10),
            y: vec![vec![0.0, 0.0, 1.0]; 10],
            p: vec![],
            singular: None,
            error: |s| (s.y[0][2] - 0.92768).abs(),
        },
        Problem {
            name: "bratu",
            f: |_, y, _, d| {
                d[0] = y[1];
                d[1] = -y[0].exp();
            },
            bc: |ya, yb, _, r| {
                r[0] = ya[0];
                r[1] = yb[0];
            },
            x: linspace(0.0, 1.0, 5),
            y: vec![vec![0.0; 2]; 5],
            p: vec![],
            singular: None,
            error: |s| {
                let th = bratu_theta();
                grid_err(s, 0.0, 1.0, |x| {
                    -2.0 * ((th * (x - 0.5) / 2.0).cosh() / (th / 4.0).cosh()).ln()
                })
            },
        },
        Problem {
            name: "layer_k100",
            f: |_, y, _, d| {
                d[0] = y[1];
                d[1] = 1e4 * y[0];
            },
            bc: |ya, yb, _, r| {
                r[0] = ya[0] - 1.0;
                r[1] = yb[0];
            },
            x: linspace(0.0, 1.0, 5),
            y: vec![vec![0.0; 2]; 5],
            p: vec![],
            singular: None,
            error: |s| {
                grid_err(s, 0.0, 1.0, |x| {
                    (-100.0 * x).exp() * (1.0 - (-200.0 * (1.0 - x)).exp())
                        / (1.0 - (-200.0f64).exp())
                })
            },
        },
        Problem {
            name: "euler_buckling",
            f: |_, y, p, d| {
                d[0] = y[1];
                d[1] = -p[0] * y[0];
            },
            bc: |ya, yb, _, r| {
                r[0] = ya[0];
                r[1] = yb[0];
                r[2] = ya[1] - 1.0;
            },
            x: linspace(0.0, 1.0, 5),
            y: linspace(0.0, 1.0, 5)
                .iter()
                .map(|&t| vec![(PI * t).sin() / PI, (PI * t).cos()])
                .collect(),
            p: vec![8.0],
            singular: None,
            error: |s| (s.p[0] - PI * PI).abs() / (PI * PI),
        },
    ];
    v.push(winkler(30.0));
    v.push(winkler(50.0));
    v
}

fn main() {
    let only: Option<String> = std::env::args().nth(1);
    for pr in problems() {
        if only.as_deref().is_some_and(|o| o != pr.name) {
            continue;
        }
        for tol in [1e-3, 1e-6] {
            let opts = BvpOptions {
                tol,
                max_nodes: 100_000,
                singular: pr.singular.clone(),
                ..Default::default()
            };
            let run = || solve_bvp(pr.f, pr.bc, &pr.x, &pr.y, &pr.p, &opts);
            let sol = match run() {
                Ok(s) => s,
                Err(e) => {
                    println!(
                        "{{\"problem\":\"{}\",\"tol\":{tol:e},\"error_msg\":\"{e}\"}}",
                        pr.name
                    );
                    continue;
                }
            };
            let err = (pr.error)(&sol);
            // best of repeated batches, at least 0.2 s of solving
            let mut best = f64::INFINITY;
            let start = Instant::now();
            let mut reps = 0;
            while start.elapsed().as_secs_f64() < 0.2 || reps < 5 {
                let t0 = Instant::now();
                let s = run().unwrap();
                best = best.min(t0.elapsed().as_secs_f64());
                std::hint::black_box(s);
                reps += 1;
            }
            println!(
                "{{\"problem\":\"{}\",\"tol\":{tol:e},\"nodes\":{},\"error\":{err:e},\"max_rms_residual\":{:e},\"time_s\":{best:e},\"newton\":{},\"rhs_evals\":{}}}",
                pr.name,
                sol.x.len(),
                sol.max_rms_residual,
                sol.stats.newton_iterations,
                sol.stats.rhs_evaluations
            );
        }
    }
}
