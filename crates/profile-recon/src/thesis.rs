//! The thesis's reconstruction (section 6.2, eqs. 6.3-6.10), faithfully: per contact row five
//! unknowns, solved by a trust region (`fsolve` in the thesis,
//! [`bvp_solvers::trust_region::solve`] here) around finite-difference solves of the
//! elastica [3.25] (the thesis's solver of Fig. 4.2), warm-started from the previous row.
//!
//! **Unknowns** [6.3, 6.4]: phase A (tip contact, `s1 = 1`): `(xc, yc, psi, f, phi1)`;
//! phase B (tangential contact, `phi1 = psi`): `(xc, yc, psi, f, s1)`.
//!
//! **Model evaluation.** For given `(psi, f, s1, phi1)` the BVP [3.25] on `[0, s1]` is solved
//! by central finite differences with Dirichlet conditions at both ends, `phi(0) = phi0` (the
//! observed base angle: the support model is not needed) and `phi(s1) = phi1`, under the
//! contact loads (DP force at `beta = pi/2 - psi`, flow `q` at `alpha = 0` on `[0, s1]`). It
//! gives the curvatures `kappa0 = phi'(0)`, `kappa1 = phi'(s1)` and, by the trapezoidal rule,
//! the contact point `(x1, y1)`. The grid has 100 intervals on `[0, s1]` (`h = s1/100 <= 0.01`,
//! the thesis's `h = 0.01` for `s1 = 1`): a fixed count rather than `ceil(100 s1)` keeps the
//! residuals smooth in `s1`, which the finite-difference Jacobian of the trust region needs.
//!
//! **Residuals** (six, in five unknowns; a least-squares problem):
//! - [6.5] as two smooth components `x1 - xc`, `y1 - yc` (instead of the distance `d`, which is
//!   not differentiable at its zero);
//! - [6.6] `m1 = e(s1)^4 (kappa1 - A s1 - B) = 0`;
//! - [6.7] `MA + m(0) = 0` with `m(0) = kappa0 - B`;
//! - [6.8] `Ax + q s1 + f sin psi = 0`;
//! - [6.9] `Ay - f cos psi = 0`.
//!
//! The exact model satisfies all six at the true contact, but the FDM one does so only up to
//! its `O(h^2)` discretisation error (both `phi0` and `MA` are imposed, one condition more than
//! a BVP takes): the least-squares minimum keeps a residual of about `1e-5..1e-4`. This is the
//! thesis's observation that "only a tolerance of 1e-4 is achievable". The trust region runs
//! with tolerance `1e-8`; when it cannot get there it is stopped once its best residual has not
//! improved (relative `1e-9`) for [`STALL_ITERATIONS`] Jacobians, and the best point found is
//! the reconstruction, with its residual norm reported in [`ReconPoint::residual`].
//!
//! **Phase** [6.10]: the first contact phase from section 6.2.1 / Remark 6.3 (B when `Ax`
//! rises above `-q` at the first contact row, i.e. the flow acts on `s1 < 1` only, else A);
//! afterwards the phase switches for row `k + 1` when the slope of `Ay` against `x0` jumps,
//! `|dAy/dx0|_{k+1} - dAy/dx0|_k| > a_diff = 1`, evaluated from the observables ahead of the
//! step (one-sided slopes between successive contact rows). A kink between two rows shows in
//! two successive slope differences, so the test is skipped on the row right after a switch.
//! Each solution must also satisfy its phase's conditions (A: `phi1 >= psi`; B: `s1 <= 1`);
//! when it does not (or the solve fails), the row is solved again in the other phase and the
//! hypothesis that satisfies its condition is kept (of two, or of none, the one with the smaller
//! residual). The kept phase is the current phase of the next row.

use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use crate::reconstruct::{force, ReconPoint, ReconSettings};
use beam_model::equations::WhiskerFdmProblem;
use beam_model::{solve as solve_model, Loads, Method, Scene, Whisker};
use bvp_solvers::fdm::{BoundaryCondition, FdmOptions, FdmSolver};
use bvp_solvers::grid::UniformGrid;
use bvp_solvers::trust_region::{self, NonlinearSystem, TrustRegionOptions};
use bvp_solvers::BvpError;
use contact_sim::phase::contact_loads;
use contact_sim::Phase;
use std::cell::RefCell;

/// FDM intervals on `[0, s1]` (the thesis's `h = 0.01` for `s1 = 1`).
pub const INTERVALS: usize = 100;
/// Trust-region tolerance on the residual norm (the thesis reached `1e-4`).
pub const TOLERANCE: f64 = 1e-8;
/// Slope-jump threshold `a_diff` of [6.10].
pub const A_DIFF: f64 = 1.0;
/// Jacobians without a relative improvement of `1e-9` after which a least-squares solve that
/// cannot reach [`TOLERANCE`] is stopped at its best point.
pub const STALL_ITERATIONS: usize = 4;
/// Trust-region iteration budget per row and phase.
const MAX_ITERS: u64 = 100;
/// Admissible range of the contact arc length during the iteration (phase B).
const S1_MIN: f64 = 0.02;

/// The model quantities of one FDM solve.
#[derive(Clone, Copy, Debug)]
struct Fdm {
    kappa0: f64,
    kappa1: f64,
    x1: f64,
    y1: f64,
}

/// Best point of a trust-region run and the stall counter.
#[derive(Clone, Debug)]
struct Track {
    best: f64,
    best_x: Vec<f64>,
    /// Best norm when the last Jacobian was taken.
    best_at_jacobian: f64,
    jacobians: usize,
    stalled: usize,
    /// Last FDM solution (warm start of the next FDM Newton solve).
    guess: Vec<f64>,
}

/// Rows of [6.5-6.9] for one observable row and one phase hypothesis.
struct RowSystem<'a> {
    whisker: &'a Whisker,
    q: f64,
    row: &'a ObservableRow,
    phase: Phase,
    track: RefCell<Track>,
}

/// Internal signal: the least-squares solve has stalled (caught in [`RowSystem::run`]).
fn stall_signal(residual: f64) -> ReconError {
    ReconError::InconsistentRow {
        row: 0,
        x0: f64::NAN,
        residual,
        phase: '-',
    }
}

impl<'a> RowSystem<'a> {
    fn new(whisker: &'a Whisker, q: f64, row: &'a ObservableRow, phase: Phase) -> Self {
        RowSystem {
            whisker,
            q,
            row,
            phase,
            track: RefCell::new(Track {
                best: f64::INFINITY,
                best_x: Vec::new(),
                best_at_jacobian: f64::INFINITY,
                jacobians: 0,
                stalled: 0,
                guess: Vec::new(),
            }),
        }
    }

    /// `(psi, f, s1, phi1)` of the unknowns `u` [6.3, 6.4].
    fn parts(&self, u: &[f64]) -> (f64, f64, f64, f64) {
        match self.phase {
            Phase::B => (u[2], u[3], u[4], u[2]),
            _ => (u[2], u[3], 1.0, u[4]),
        }
    }

    /// Largest admissible `s1` (the cone must keep a positive diameter).
    fn s1_max(&self) -> f64 {
        let t = 1.0 - self.whisker.theta;
        if t > 0.0 {
            (0.9 / t).min(1.5)
        } else {
            1.5
        }
    }

    /// The FDM solve of [3.25] on `[0, s1]` with `phi(0) = phi0`, `phi(s1) = phi1`.
    fn fdm(&self, psi: f64, f: f64, s1: f64, phi1: f64) -> Result<Fdm> {
        let grid = UniformGrid::new(0.0, s1, INTERVALS)?;
        let loads = contact_loads(self.q, psi, f, s1);
        let problem = WhiskerFdmProblem::new(*self.whisker, loads, phi1);
        let phi0 = self.row.phi0;
        let guess: Vec<f64> = {
            let t = self.track.borrow();
            if t.guess.len() == grid.len() {
                t.guess.clone()
            } else {
                let n = INTERVALS as f64;
                (0..grid.len())
                    .map(|i| phi0 + (phi1 - phi0) * i as f64 / n)
                    .collect()
            }
        };
        let solver = FdmSolver::new(
            BoundaryCondition::Dirichlet(phi0),
            BoundaryCondition::Dirichlet(phi1),
        )
        .with_options(FdmOptions {
            tol: 1e-12,
            max_iter: 50,
            damping: 1.0,
        });
        let sol = solver.solve(&problem, &grid, &guess)?;
        let h = grid.h();
        let (mut x, mut y) = (self.row.x0, 0.0);
        for w in sol.y.windows(2) {
            x += 0.5 * h * (w[0].cos() + w[1].cos());
            y += 0.5 * h * (w[0].sin() + w[1].sin());
        }
        let kappa0 = sol.yp.first().copied().unwrap_or(f64::NAN);
        let kappa1 = sol.yp.last().copied().unwrap_or(f64::NAN);
        self.track.borrow_mut().guess = sol.y;
        Ok(Fdm {
            kappa0,
            kappa1,
            x1: x,
            y1: y,
        })
    }

    /// The six residuals [6.5-6.9]; NaN (a rejected trial point) where the model cannot be
    /// evaluated (`s1` out of range, FDM failure).
    fn eval(&self, u: &[f64], r: &mut [f64]) {
        let (psi, f, s1, phi1) = self.parts(u);
        let w = self.whisker;
        let model = if (S1_MIN..=self.s1_max()).contains(&s1) && u.iter().all(|v| v.is_finite()) {
            self.fdm(psi, f, s1, phi1).ok()
        } else {
            None
        };
        let Some(m) = model else {
            r.iter_mut().for_each(|v| *v = f64::NAN);
            return;
        };
        let (sp, cp) = psi.sin_cos();
        r[0] = m.x1 - u[0]; // [6.5], x component
        r[1] = m.y1 - u[1]; // [6.5], y component
        r[2] = w.stiffness(s1) * (m.kappa1 - w.kappa0(s1)); // [6.6]
        r[3] = self.row.ma + w.stiffness(0.0) * (m.kappa0 - w.b); // [6.7]
        r[4] = self.row.ax + self.q * s1 + f * sp; // [6.8]
        r[5] = self.row.ay - f * cp; // [6.9]
    }

    /// Solves the row from `start`: `(u, residual norm, iterations)`.
    fn run(&self, start: &[f64]) -> Result<(Vec<f64>, f64, usize)> {
        let opts = TrustRegionOptions {
            tol: TOLERANCE,
            max_iters: MAX_ITERS,
            initial_radius: 0.1,
            max_radius: 10.0,
        };
        match trust_region::solve(self, start, &opts) {
            Ok(sol) => Ok((sol.x, sol.residual_norm, sol.iterations as usize)),
            Err(e) => {
                let t = self.track.borrow();
                let stalled = matches!(e, ReconError::InconsistentRow { phase: '-', .. });
                let no_conv = matches!(e, ReconError::Bvp(BvpError::NoConvergence { .. }));
                if (stalled || no_conv) && t.best.is_finite() {
                    Ok((t.best_x.clone(), t.best, t.jacobians))
                } else {
                    Err(e)
                }
            }
        }
    }
}

impl NonlinearSystem for RowSystem<'_> {
    type Error = ReconError;

    fn n_unknowns(&self) -> usize {
        5
    }

    fn n_residuals(&self) -> usize {
        6
    }

    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<()> {
        self.eval(x, r);
        let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut t = self.track.borrow_mut();
        if norm.is_finite() && norm < t.best {
            t.best = norm;
            t.best_x = x.to_vec();
        }
        Ok(())
    }

    /// Forward differences (as the default), counting Jacobians to detect a stalled
    /// least-squares solve.
    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> Result<()> {
        {
            let mut t = self.track.borrow_mut();
            t.jacobians += 1;
            if t.best < t.best_at_jacobian * (1.0 - 1e-9) {
                t.best_at_jacobian = t.best;
                t.stalled = 0;
            } else {
                t.stalled += 1;
                if t.stalled >= STALL_ITERATIONS {
                    return Err(stall_signal(t.best));
                }
            }
        }
        let (n, m) = (5, 6);
        let mut r0 = [0.0; 6];
        let mut r1 = [0.0; 6];
        let mut xp = x.to_vec();
        self.residual(x, &mut r0)?;
        let sq = f64::EPSILON.sqrt();
        for j in 0..n {
            let h = sq * x[j].abs().max(1.0);
            xp[j] = x[j] + h;
            let hh = xp[j] - x[j];
            self.residual(&xp, &mut r1)?;
            xp[j] = x[j];
            for i in 0..m {
                jac[i * n + j] = (r1[i] - r0[i]) / hh;
            }
        }
        Ok(())
    }
}

/// A solved hypothesis.
#[derive(Clone, Debug)]
struct Solved {
    phase: Phase,
    u: Vec<f64>,
    residual: f64,
    iterations: usize,
}

impl Solved {
    /// Whether the phase's conditions hold (A: `phi1 >= psi`; B: `s1 <= 1`) [6.2.2].
    fn valid(&self) -> bool {
        match self.phase {
            Phase::B => self.u[4] <= 1.0 + 1e-9,
            _ => self.u[4] >= self.u[2] - 1e-9,
        }
    }

    fn s1(&self) -> f64 {
        if self.phase == Phase::B {
            self.u[4]
        } else {
            1.0
        }
    }
}

/// Start of the other phase from a solution of one: B from A with `s1` just below 1, A from B
/// with `phi1 = psi`.
fn convert(u: &[f64], to: Phase) -> Vec<f64> {
    let mut v = u.to_vec();
    v[4] = match to {
        Phase::B => 1.0 - 1e-3,
        _ => u[2],
    };
    v
}

fn other(phase: Phase) -> Phase {
    if phase == Phase::B {
        Phase::A
    } else {
        Phase::B
    }
}

/// Slope `dAy/dx0` between rows `i - 1` and `i`.
fn slope(rows: &[ObservableRow], i: usize) -> f64 {
    (rows[i].ay - rows[i - 1].ay) / (rows[i].x0 - rows[i - 1].x0)
}

/// Reconstructs the contact rows `rows[first..]` by the thesis's method (module docs): five
/// unknowns per row [6.3, 6.4] from the six residuals of [6.5-6.9] by the trust region around
/// FDM solves of [3.25], warm-started from the previous row, phases by [6.10].
///
/// The first row starts from force balance with `s1 = 1` [6.8, 6.9] and the free tip of the
/// whisker under the flow `q` (thesis 6.1).
///
/// # Errors
/// - [`ReconError::TooFewRows`] without contact rows (`first >= rows.len()`);
/// - [`ReconError::NonFinite`] for a non-finite observable;
/// - [`ReconError::Model`] if the free whisker cannot be solved;
/// - [`ReconError::InconsistentRow`] if neither phase can be solved at a row, or (with
///   `settings.consistency_tol`) the best residual of a row exceeds it;
/// - [`ReconError::Bvp`] for other solver failures.
pub fn reconstruct_rows(
    whisker: &Whisker,
    q: f64,
    rows: &[ObservableRow],
    first: usize,
    settings: &ReconSettings,
) -> Result<Vec<ReconPoint>> {
    if first >= rows.len() {
        return Err(ReconError::TooFewRows {
            found: 0,
            needed: 1,
            what: "the thesis method needs at least one contact row",
        });
    }
    for (i, r) in rows.iter().enumerate() {
        r.validate(i + 1)?;
    }
    let row0 = &rows[first];
    // First phase (6.2.1, Remark 6.3): the flow acts on [0, s1] only in phase B, so Ax rises
    // above -q at a tangential first contact.
    let noticeable = (100.0 * settings.noise_floor).max(1e-7) * (1.0 + q);
    let mut phase = if row0.ax > -q + noticeable {
        Phase::B
    } else {
        Phase::A
    };
    // Warm start of the first row: force balance with s1 = 1, free tip under the flow.
    let free = solve_model(
        &Scene::new(*whisker, Loads::fluid(q, 0.0)),
        &Method::accurate(),
    )?;
    let (f0, psi0) = force(row0, q, 1.0);
    let mut start = vec![
        row0.x0 + free.tip.x,
        free.tip.y,
        psi0,
        f0,
        if phase == Phase::B {
            1.0 - 1e-3
        } else {
            free.tip.phi
        },
    ];
    let mut points = Vec::with_capacity(rows.len() - first);
    let mut just_switched = false;
    for (i, row) in rows.iter().enumerate().skip(first) {
        // [6.10]: slope jump of Ay ahead of the step (contact rows only).
        if i >= first + 2 {
            let delta = (slope(rows, i) - slope(rows, i - 1)).abs();
            if !just_switched && delta > A_DIFF {
                start = convert(&start, other(phase));
                phase = other(phase);
                just_switched = true;
            } else {
                just_switched = false;
            }
        }
        let attempt = |ph: Phase, u: &[f64]| -> Result<Solved> {
            let sys = RowSystem::new(whisker, q, row, ph);
            let (u, residual, iterations) = sys.run(u)?;
            Ok(Solved {
                phase: ph,
                u,
                residual,
                iterations,
            })
        };
        let first_try = attempt(phase, &start);
        let chosen = match first_try {
            Ok(s) if s.valid() => s,
            first_try => {
                let base = match &first_try {
                    Ok(s) => s.u.clone(),
                    Err(_) => start.clone(),
                };
                let second = attempt(other(phase), &convert(&base, other(phase)));
                match (first_try, second) {
                    (_, Ok(b)) if b.valid() => b,
                    (Ok(a), Ok(b)) => {
                        if b.residual < a.residual {
                            b
                        } else {
                            a
                        }
                    }
                    (Ok(a), Err(_)) => a,
                    (Err(_), Ok(b)) => b,
                    (Err(e), Err(_)) => {
                        let residual = match e {
                            ReconError::InconsistentRow { residual, .. } => residual,
                            ReconError::Bvp(BvpError::NoConvergence { residual, .. }) => residual,
                            _ => f64::NAN,
                        };
                        return Err(ReconError::InconsistentRow {
                            row: i + 1,
                            x0: row.x0,
                            residual,
                            phase: if phase == Phase::B { 'B' } else { 'A' },
                        });
                    }
                }
            }
        };
        if let Some(tol) = settings.consistency_tol {
            if !(chosen.residual <= tol) {
                return Err(ReconError::InconsistentRow {
                    row: i + 1,
                    x0: row.x0,
                    residual: chosen.residual,
                    phase: if chosen.phase == Phase::B { 'B' } else { 'A' },
                });
            }
        }
        phase = chosen.phase;
        points.push(ReconPoint {
            row: i,
            x0: row.x0,
            x: chosen.u[0],
            y: chosen.u[1],
            s1: chosen.s1(),
            f: chosen.u[3],
            psi: chosen.u[2],
            phase: chosen.phase,
            residual: chosen.residual,
            evaluations: chosen.iterations,
        });
        start = chosen.u;
    }
    Ok(points)
}
