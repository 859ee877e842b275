//! The numerical studies behind the chapter-4 charts: accuracy against cost of the three
//! methods (work-precision), where each method converges over a load x conicity grid
//! (stability maps, thesis §4.2.2 and §4.3.3), and the comparison with the finite-element
//! results of thesis §4.5 (Tables 4.2 and 4.3). This module only computes; plotting is done
//! elsewhere.
//!
//! ```no_run
//! use beam_model::scenarios;
//! use xtask::study;
//! for (name, scene) in scenarios::reference_scenes() {
//!     let points = study::work_precision(&scene, name).unwrap();
//!     println!("{}", study::to_csv(&points));
//! }
//! ```

use beam_model::error::finite;
use beam_model::methods::{solve, Method, DEFAULT_INTERVALS};
use beam_model::{Loads, ModelError, Preset, Result, Scene, Solution, Support, TipForce, Whisker};

use rayon::prelude::*;
use std::fmt::Write as _;
use std::time::{Duration, Instant};

// ---------------------------------------------------------------------------------------
// Work-precision
// ---------------------------------------------------------------------------------------

/// Grid intervals of the `fdm` points: 25, 50, ..., 3200.
pub const FDM_INTERVALS: [usize; 8] = [25, 50, 100, 200, 400, 800, 1600, 3200];
/// Steps of the `rk4` points: 10, 20, ..., 1280.
pub const RK4_STEPS: [usize; 8] = [10, 20, 40, 80, 160, 320, 640, 1280];
/// Coarsest-grid intervals of the fdm-richardson points (grids n, 2n, 4n).
pub const FDM_RICHARDSON_INTERVALS: [usize; 6] = [10, 20, 40, 80, 160, 320];
/// Integrator tolerances of the `accurate` points: 1e-4, 1e-5, ..., 1e-13.
pub const ACCURATE_TOLS: [f64; 10] = [
    1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13,
];
/// Integrator tolerance of the reference solve the errors are measured against: one decade
/// below the tightest `accurate` setting (at the issue's 1e-13 that point would measure
/// itself, error 0). Its tips differ from those at 1e-15 by about 1e-14.
pub const REFERENCE_TOL: f64 = 1e-14;
/// Wall time over which one setting's solves are repeated (at least [`MIN_REPEATS`] times).
pub const TIMING_BUDGET: Duration = Duration::from_millis(5);
/// Minimum number of timed solves per setting.
pub const MIN_REPEATS: usize = 3;
const MAX_REPEATS: usize = 10_000;

/// One point of a work-precision chart: a method at one setting on one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkPoint {
    /// The scene's name, as passed to [`work_precision`].
    pub scene: String,
    /// `fdm`, `rk4` or `accurate`.
    pub method: &'static str,
    /// Grid intervals n (`fdm`, `rk4`) or integrator tolerance (`accurate`).
    pub setting: f64,
    /// Error in the norm the accuracy is asked in (`--tol`, `Method::Auto`:
    /// [`Solution::difference`], the largest difference of the tip, the loaded end and the
    /// base observables) against the reference solve at [`REFERENCE_TOL`]; `+inf` when the
    /// solve failed.
    pub error: f64,
    /// Tip error `max(|x1 - x1_ref|, |y1 - y1_ref|)` against the same reference (the
    /// thesis's measure, Table 4.2); `+inf` when the solve failed.
    pub tip_error: f64,
    /// Median wall time of one solve (s); `+inf` when the solve failed.
    pub seconds: f64,
    /// Right-hand-side evaluations or FDM sweeps of one solve (machine-independent cost);
    /// 0 when the solve failed.
    pub evaluations: usize,
}

/// The methods and settings of a work-precision study, in chart order.
pub fn work_precision_methods() -> Vec<Method> {
    let mut m: Vec<Method> = FDM_INTERVALS.iter().map(|&n| Method::Fdm { n }).collect();
    m.extend(RK4_STEPS.iter().map(|&n| Method::Rk4 { n }));
    m.extend(
        FDM_RICHARDSON_INTERVALS
            .iter()
            .map(|&n| Method::FdmRichardson { n }),
    );
    m.extend(ACCURATE_TOLS.iter().map(|&tol| Method::Accurate {
        tol,
        samples: DEFAULT_INTERVALS,
    }));
    m.extend(AUTO_TOLS.iter().map(|&tol| Method::Auto {
        tol,
        samples: DEFAULT_INTERVALS,
    }));
    m
}

/// The accuracies asked of `auto` (the automatic choice) on the work-precision chart.
const AUTO_TOLS: [f64; 5] = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12];

fn setting(method: &Method) -> f64 {
    match *method {
        Method::Accurate { tol, .. }
        | Method::Auto { tol, .. }
        | Method::MultipleShooting { tol, .. }
        | Method::Collocation { tol, .. } => tol,
        Method::Rk4 { n } | Method::Fdm { n } | Method::FdmRichardson { n } => n as f64,
    }
}

/// Median wall time of repeated solves: repeated until [`TIMING_BUDGET`] has elapsed and at
/// least [`MIN_REPEATS`] times.
fn time_solve(scene: &Scene, method: &Method) -> Result<(f64, Solution)> {
    let mut times = Vec::new();
    let start = Instant::now();
    let mut last = None;
    while times.len() < MIN_REPEATS
        || (start.elapsed() < TIMING_BUDGET && times.len() < MAX_REPEATS)
    {
        let t0 = Instant::now();
        let sol = solve(scene, method)?;
        times.push(t0.elapsed().as_secs_f64());
        last = Some(sol);
    }
    times.sort_by(f64::total_cmp);
    let n = times.len();
    let median = if n % 2 == 1 {
        times[n / 2]
    } else {
        0.5 * (times[n / 2 - 1] + times[n / 2])
    };
    // `last` is set: the loop runs at least MIN_REPEATS >= 1 times.
    last.map(|s| (median, s))
        .ok_or(ModelError::InvalidParameter {
            name: "repeats",
            value: 0.0,
            reason: "no solve was timed",
        })
}

/// Accuracy against cost of the three methods on one scene (the issue's work-precision
/// chart): `fdm` at [`FDM_INTERVALS`], `rk4` at [`RK4_STEPS`], `accurate` at
/// [`ACCURATE_TOLS`]. The error of each point is the tip error against a reference
/// `accurate` solve at [`REFERENCE_TOL`]; a setting that fails to converge is kept as a
/// point with infinite error and time. Fails only if the scene is invalid or the reference
/// solve fails.
pub fn work_precision(scene: &Scene, name: &str) -> Result<Vec<WorkPoint>> {
    let reference = solve(
        scene,
        &Method::Accurate {
            tol: REFERENCE_TOL,
            samples: DEFAULT_INTERVALS,
        },
    )?;
    let mut out = Vec::new();
    for method in work_precision_methods() {
        let point = match time_solve(scene, &method) {
            Ok((seconds, sol)) => WorkPoint {
                scene: name.to_string(),
                // the method that produced the numbers (a fallback is credited to its
                // method), except the automatic choice, which is its own curve
                method: match method {
                    Method::Auto { .. } => "auto",
                    _ => sol.stats.method_used.name(),
                },
                setting: setting(&method),
                error: sol.difference(&reference),
                tip_error: (sol.tip.x - reference.tip.x)
                    .abs()
                    .max((sol.tip.y - reference.tip.y).abs()),
                seconds,
                evaluations: sol.stats.evaluations,
            },
            Err(_) => WorkPoint {
                scene: name.to_string(),
                method: method.name(),
                setting: setting(&method),
                error: f64::INFINITY,
                tip_error: f64::INFINITY,
                seconds: f64::INFINITY,
                evaluations: 0,
            },
        };
        out.push(point);
    }
    Ok(out)
}

/// The points as CSV with the header `method,setting,error,tip_error,seconds,evaluations`
/// (one file per scene; floats in shortest round-trip form, `inf` for failed solves).
pub fn to_csv(points: &[WorkPoint]) -> String {
    let mut s = String::from("method,setting,error,tip_error,seconds,evaluations\n");
    for p in points {
        // Writing to a String cannot fail.
        let _ = writeln!(
            s,
            "{},{:e},{:e},{:e},{:e},{}",
            p.method, p.setting, p.error, p.tip_error, p.seconds, p.evaluations
        );
    }
    s
}

/// Observed orders of convergence `log(e_i / e_{i+1}) / log(h_i / h_{i+1})` between
/// consecutive points of one fixed-step method (`fdm` or `rk4`), in setting order; pairs with
/// a non-finite or zero error give NaN.
pub fn observed_orders(points: &[WorkPoint], method: &str) -> Vec<(f64, f64)> {
    let pts: Vec<&WorkPoint> = points.iter().filter(|p| p.method == method).collect();
    pts.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let order = if a.error.is_finite() && b.error.is_finite() && a.error > 0.0 {
                (a.error / b.error).ln() / (b.setting / a.setting).ln()
            } else {
                f64::NAN
            };
            (a.setting, order)
        })
        .collect()
}

// ---------------------------------------------------------------------------------------
// Stability maps
// ---------------------------------------------------------------------------------------

/// The load of a stability map (thesis §4.2.1, §4.2.2, §4.3.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LoadAxis {
    /// Direction-preserving tip force f at beta = 0 (Figs. 4.3-4.7).
    TipDp,
    /// Angle-preserving tip force f at beta = 0, eq. (4.3) (Figs. 4.9-4.10; the thesis's
    /// FDM fails near f = 15 and f = 25 where phi1 passes -pi/2).
    TipAp,
    /// Fluid load q at alpha = 0, eq. (4.5) (Figs. 4.11-4.17; the thesis's FDM fails for
    /// some theta < 0.2).
    Fluid,
}

impl LoadAxis {
    /// All three axes.
    pub const ALL: [LoadAxis; 3] = [LoadAxis::TipDp, LoadAxis::TipAp, LoadAxis::Fluid];

    /// `tip-dp`, `tip-ap` or `fluid`.
    pub fn name(&self) -> &'static str {
        match self {
            LoadAxis::TipDp => "tip-dp",
            LoadAxis::TipAp => "tip-ap",
            LoadAxis::Fluid => "fluid",
        }
    }

    /// The loads of magnitude `value` on this axis.
    pub fn loads(&self, value: f64) -> Loads {
        match self {
            LoadAxis::TipDp => Loads::tip(TipForce::dp(value, 0.0)),
            LoadAxis::TipAp => Loads::tip(TipForce::ap(value, 0.0)),
            LoadAxis::Fluid => Loads::fluid(value, 0.0),
        }
    }

    /// The issue's load range: 0..40 step 2, AP tip load 0..30 step 1 (so that f = 15 and
    /// f = 25 of §4.2.2 are on the grid).
    pub fn default_loads(&self) -> Vec<f64> {
        match self {
            LoadAxis::TipAp => (0..=30).map(f64::from).collect(),
            _ => (0..=20).map(|i| 2.0 * f64::from(i)).collect(),
        }
    }
}

/// Conicities of the default grid: 0.05, 0.10, ..., 1.
pub fn default_thetas() -> Vec<f64> {
    (1..=20).map(|i| 0.05 * f64::from(i)).collect()
}

/// Base-spring stiffnesses of the default grid: rigid and k = 5.
pub const DEFAULT_KS: [f64; 2] = [f64::INFINITY, 5.0];

/// Tip distance above which a converged solve counts as [`Outcome::Wrong`].
pub const WRONG_TOL: f64 = 1e-2;

/// Tolerance of the `accurate` reference solve of each cell.
pub const MAP_REFERENCE_TOL: f64 = 1e-12;

/// What a method did on one cell of a stability map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Converged, on the branch of the reference (or no reference to compare with).
    Converged {
        /// Load-continuation steps used (0: direct solve).
        continuation_steps: usize,
    },
    /// No convergence (an error, not a panic).
    Failed,
    /// Converged, but the tip is more than [`WRONG_TOL`] from the `accurate` reference: a
    /// different equilibrium branch or a grid too coarse.
    Wrong,
    /// Solved on the reference branch, but by another method than the one mapped (the
    /// method's fallback, e.g. `accurate` -> `fdm-richardson` where shooting is
    /// ill-conditioned): the cell credits the method that produced the numbers.
    FellBack {
        /// The method that produced the numbers.
        method_used: &'static str,
    },
}

impl Outcome {
    /// Whether the method returned a solution on the reference branch.
    pub fn is_converged(&self) -> bool {
        matches!(self, Outcome::Converged { .. })
    }
}

/// Where one method converges over a load x conicity grid at one base stiffness.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityMap {
    /// `fdm`, `rk4` or `accurate`.
    pub method: &'static str,
    /// The load axis.
    pub kind: LoadAxis,
    /// Base stiffness k (`inf`: rigid).
    pub k: f64,
    /// Load magnitudes (rows of `cells`).
    pub loads: Vec<f64>,
    /// Conicities theta (columns of `cells`).
    pub thetas: Vec<f64>,
    /// `cells[i][j]`: the outcome at `loads[i]`, `thetas[j]`.
    pub cells: Vec<Vec<Outcome>>,
    /// `reference[i][j]`: whether the `accurate` reference converged there (where it did not,
    /// a converged cell could not be checked for [`Outcome::Wrong`]).
    pub reference: Vec<Vec<bool>>,
}

impl StabilityMap {
    /// Number of cells with each outcome: (converged, failed, wrong). A cell solved by a
    /// fallback counts as failed: the mapped method did not produce its numbers.
    pub fn counts(&self) -> (usize, usize, usize) {
        let mut c = (0, 0, 0);
        for o in self.cells.iter().flatten() {
            match o {
                Outcome::Converged { .. } => c.0 += 1,
                Outcome::Failed | Outcome::FellBack { .. } => c.1 += 1,
                Outcome::Wrong => c.2 += 1,
            }
        }
        c
    }
}

fn check_grid(loads: &[f64], thetas: &[f64], k: f64) -> Result<()> {
    if loads.is_empty() || thetas.is_empty() {
        return Err(ModelError::InvalidParameter {
            name: "grid",
            value: 0.0,
            reason: "a stability map needs at least one load and one theta",
        });
    }
    for &l in loads {
        finite("load", l)?;
        if l < 0.0 {
            return Err(ModelError::InvalidParameter {
                name: "load",
                value: l,
                reason: "load magnitudes must be >= 0",
            });
        }
    }
    for &t in thetas {
        finite("theta", t)?;
        if !(t > 0.0 && t <= 1.0) {
            return Err(ModelError::InvalidParameter {
                name: "theta",
                value: t,
                reason: "the conicity must be in (0, 1]",
            });
        }
    }
    Support::from_stiffness(k)?;
    Ok(())
}

fn map_scene(kind: LoadAxis, load: f64, theta: f64, support: Support) -> Scene {
    Scene::new(
        Whisker {
            theta,
            a: 0.0,
            b: 0.0,
            support,
        },
        kind.loads(load),
    )
}

/// One cell: whether the reference converged, and each method's outcome.
fn map_cell(methods: &[Method], reference_method: &Method, scene: &Scene) -> (bool, Vec<Outcome>) {
    let reference = solve(scene, reference_method).ok();
    let outcomes = methods
        .iter()
        .map(|method| {
            let sol = match (method, reference_method, &reference) {
                // The same integration as the reference (only the output sampling may
                // differ): its tip is the reference's, no second solve.
                (Method::Accurate { tol, .. }, Method::Accurate { tol: rt, .. }, r)
                    if tol == rt =>
                {
                    return r.as_ref().map_or(Outcome::Failed, converged);
                }
                _ => solve(scene, method),
            };
            match (sol, &reference) {
                (Err(_), _) => Outcome::Failed,
                (Ok(sol), Some(r))
                    if (sol.tip.x - r.tip.x).abs().max((sol.tip.y - r.tip.y).abs()) > WRONG_TOL =>
                {
                    Outcome::Wrong
                }
                (Ok(sol), _) => converged(&sol),
            }
        })
        .collect();
    (reference.is_some(), outcomes)
}

/// A solution's outcome: converged, or fell back to another method.
fn converged(sol: &Solution) -> Outcome {
    if sol.stats.fell_back() {
        Outcome::FellBack {
            method_used: sol.stats.method_used.name(),
        }
    } else {
        Outcome::Converged {
            continuation_steps: sol.stats.continuation_steps,
        }
    }
}

/// Stability maps of several methods over the same grid, sharing one `accurate` reference
/// solve (tolerance [`MAP_REFERENCE_TOL`], the default of [`Method::accurate`], so that the
/// `accurate` map costs no extra solve) per cell: a straight whisker of conicity theta on a
/// base of stiffness `k` (`inf`: rigid) under the load `kind` of each magnitude. Every solve
/// starts cold, as [`solve`] does for a user. A failed solve is recorded as
/// [`Outcome::Failed`]; only an invalid grid is an error. The cells are shared out over
/// rayon's pool (each cell on its own: the maps do not depend on the number of threads).
pub fn stability_maps(
    methods: &[Method],
    kind: LoadAxis,
    loads: &[f64],
    thetas: &[f64],
    k: f64,
) -> Result<Vec<StabilityMap>> {
    check_grid(loads, thetas, k)?;
    let support = Support::from_stiffness(k)?;
    for m in methods {
        // Reject a bad method up front rather than marking every cell as failed.
        solve(&map_scene(kind, 0.0, 1.0, support), m)?;
    }
    let reference_method = Method::Accurate {
        tol: MAP_REFERENCE_TOL,
        samples: 4,
    };
    let cells: Vec<(usize, usize)> = (0..loads.len())
        .flat_map(|i| (0..thetas.len()).map(move |j| (i, j)))
        .collect();
    let results: Vec<(usize, usize, bool, Vec<Outcome>)> = cells
        .par_iter()
        .with_max_len(1)
        .map(|&(i, j)| {
            let scene = map_scene(kind, loads[i], thetas[j], support);
            let (ok, outcomes) = map_cell(methods, &reference_method, &scene);
            (i, j, ok, outcomes)
        })
        .collect();
    let mut maps: Vec<StabilityMap> = methods
        .iter()
        .map(|m| StabilityMap {
            method: m.name(),
            kind,
            k,
            loads: loads.to_vec(),
            thetas: thetas.to_vec(),
            cells: vec![vec![Outcome::Failed; thetas.len()]; loads.len()],
            reference: vec![vec![false; thetas.len()]; loads.len()],
        })
        .collect();
    for (i, j, ok, outcomes) in results {
        for (map, o) in maps.iter_mut().zip(outcomes) {
            map.cells[i][j] = o;
            map.reference[i][j] = ok;
        }
    }
    Ok(maps)
}

/// The stability map of one method (see [`stability_maps`], which shares the reference
/// solves between methods).
pub fn stability_map(
    method: Method,
    kind: LoadAxis,
    loads: &[f64],
    thetas: &[f64],
    k: f64,
) -> Result<StabilityMap> {
    let mut maps = stability_maps(&[method], kind, loads, thetas, k)?;
    maps.pop().ok_or(ModelError::InvalidParameter {
        name: "methods",
        value: 0.0,
        reason: "no method given",
    })
}

/// The methods of the default stability maps: `accurate`, `rk4` and `fdm` at n = 100 (the
/// thesis's h = 0.01).
pub fn default_map_methods() -> [Method; 3] {
    [
        Method::accurate(),
        Method::Rk4 {
            n: DEFAULT_INTERVALS,
        },
        Method::Fdm {
            n: DEFAULT_INTERVALS,
        },
    ]
}

// ---------------------------------------------------------------------------------------
// ANSYS comparison
// ---------------------------------------------------------------------------------------

/// The load of a row of thesis Tables 4.2 / 4.3.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AnsysLoad {
    /// Concentrated force f at the tip, beta = 0 (Table 4.2).
    Tip,
    /// Distributed (fluid) load q along the shaft, alpha = 0 (Table 4.3).
    Fluid,
}

/// Thesis Table 4.2 (beta whisker, tip force): `(f, ANSYS x1, ANSYS y1, model x1, model y1)`
/// in mm, as printed.
pub const TABLE_4_2: [(f64, f64, f64, f64, f64); 5] = [
    (1.0, 20.049, 62.4345, 19.921, 62.4806),
    (5.0, 47.792, 39.589, 47.1817, 40.5992),
    (10.0, 53.722, 29.299, 53.5946, 29.5246),
    (20.0, 57.622, 20.579, 57.4412, 20.9929),
    (40.0, 60.099, 14.716, 60.0015, 14.8689),
];

/// Thesis Table 4.3 (beta whisker, distributed load): `(q, ANSYS x1, ANSYS y1, model x1,
/// model y1)` in mm, as printed.
pub const TABLE_4_3: [(f64, f64, f64, f64, f64); 5] = [
    (1.0, 8.191, 65.61814, 8.1629, 65.6214),
    (5.0, 33.389, 55.667, 32.7863, 56.0642),
    (10.0, 46.77, 42.912, 46.2956, 43.4841),
    (20.0, 54.976, 29.372, 54.8735, 29.5255),
    (40.0, 59.236, 18.742, 59.1591, 18.8305),
];

/// The thesis's printed errors (4.26) of its model against ANSYS, `(error x1, error y1)` in
/// %, Table 4.2 then Table 4.3 (for checking the transcription).
pub const PRINTED_ERRORS: [(f64, f64); 10] = [
    (0.638, 0.074),
    (1.277, 2.552),
    (0.237, 0.770),
    (0.314, 2.011),
    (0.162, 1.039),
    (0.337, 0.005),
    (1.805, 0.714),
    (1.014, 1.331),
    (0.186, 0.523),
    (0.130, 0.472),
];

/// One row of the comparison with ANSYS (thesis §4.5).
#[derive(Clone, Debug, PartialEq)]
pub struct AnsysRow {
    /// Tip force or distributed load.
    pub load_kind: AnsysLoad,
    /// Dimensionless magnitude f or q.
    pub load: f64,
    /// The same load in SI units: N (tip) or N/m (fluid) for the beta whisker [3.16, 3.17].
    pub load_si: f64,
    /// ANSYS tip x1 (mm).
    pub ansys_x1_mm: f64,
    /// ANSYS tip y1 (mm).
    pub ansys_y1_mm: f64,
    /// The thesis model's (FDM) tip x1 (mm).
    pub thesis_x1_mm: f64,
    /// The thesis model's tip y1 (mm).
    pub thesis_y1_mm: f64,
    /// Our `accurate` tip x1 (mm).
    pub ours_x1_mm: f64,
    /// Our `accurate` tip y1 (mm).
    pub ours_y1_mm: f64,
    /// Error (4.26) of ours against ANSYS in x1 (%).
    pub err_ours_x_pct: f64,
    /// Error (4.26) of ours against ANSYS in y1 (%).
    pub err_ours_y_pct: f64,
    /// Error (4.26) of the thesis model against ANSYS in x1 (%).
    pub err_thesis_x_pct: f64,
    /// Error (4.26) of the thesis model against ANSYS in y1 (%).
    pub err_thesis_y_pct: f64,
}

/// The relative error (4.26), `|fem - model| / fem * 100 %`.
pub fn error_pct(fem: f64, model: f64) -> f64 {
    (fem - model).abs() / fem.abs() * 100.0
}

/// Thesis Tables 4.2 and 4.3 with our `accurate` solution added: the beta whisker of Table
/// 2.2 (L = 66.2 mm), uniform, straight, rigidly clamped, under a tip force (beta = 0) or a
/// distributed load (alpha = 0). Our exact elastica differs from ANSYS by up to ~2.4 %, like
/// the thesis's model (its largest: 2.55 %).
pub fn ansys_comparison() -> Result<Vec<AnsysRow>> {
    let phys = Preset::Beta.whisker();
    let l_mm = phys.length * 1e3;
    let method = Method::Accurate {
        tol: 1e-12,
        samples: 4,
    };
    let mut rows = Vec::with_capacity(TABLE_4_2.len() + TABLE_4_3.len());
    for (kind, table) in [(AnsysLoad::Tip, &TABLE_4_2), (AnsysLoad::Fluid, &TABLE_4_3)] {
        for &(load, ax, ay, tx, ty) in table.iter() {
            let (loads, load_si) = match kind {
                AnsysLoad::Tip => (
                    Loads::tip(TipForce::dp(load, 0.0)),
                    load * phys.force_scale(),
                ),
                AnsysLoad::Fluid => (Loads::fluid(load, 0.0), load * phys.line_load_scale()),
            };
            let sol = solve(&Scene::new(Whisker::uniform(), loads), &method)?;
            let (ox, oy) = (sol.tip.x * l_mm, sol.tip.y * l_mm);
            rows.push(AnsysRow {
                load_kind: kind,
                load,
                load_si,
                ansys_x1_mm: ax,
                ansys_y1_mm: ay,
                thesis_x1_mm: tx,
                thesis_y1_mm: ty,
                ours_x1_mm: ox,
                ours_y1_mm: oy,
                err_ours_x_pct: error_pct(ax, ox),
                err_ours_y_pct: error_pct(ay, oy),
                err_thesis_x_pct: error_pct(ax, tx),
                err_thesis_y_pct: error_pct(ay, ty),
            });
        }
    }
    Ok(rows)
}
