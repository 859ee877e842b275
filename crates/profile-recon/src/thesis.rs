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
//! contact loads (DP force at `beta = pi/2 - psi`, flow `q` at `alpha` on `[0, s1]`). It
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
//! - [6.8] `Ax + q s1 cos alpha + f sin psi = 0`;
//! - [6.9] `Ay - q s1 sin alpha - f cos psi = 0`.
//!
//! The exact model satisfies all six at the true contact, but the FDM one does so only up to
//! its `O(h^2)` discretisation error (both `phi0` and `MA` are imposed, one condition more than
//! a BVP takes): the least-squares minimum keeps a residual of about `1e-5..1e-4`. This is the
//! thesis's observation that "only a tolerance of 1e-4 is achievable". The trust region runs
//! with tolerance `1e-8`; when it cannot get there, the run is ended once [`STALL_TRIALS`]
//! trial points bring no progress (further trial points are rejected without an FDM solve) and
//! the best point found is the reconstruction, with its residual norm reported in
//! [`ReconPoint::residual`] and the trust-region iterations up to it in
//! [`ReconPoint::evaluations`].
//!
//! **Phase** [6.10]: the first contact phase from section 6.2.1 / Remark 6.3 (B when `Ax`
//! rises above `-q` at the first contact row, i.e. the flow acts on `s1 < 1` only, else A);
//! afterwards the phase switches for row `k + 1` when the slope of `Ay` against `x0` jumps,
//! `|dAy/dx0|_{k+1} - dAy/dx0|_k| > a_diff = 1`, evaluated from the observables ahead of the
//! step (one-sided slopes between successive contact rows). A kink between two rows shows in
//! two successive slope differences, so the test is skipped on the row right after a switch.
//! Each solution must also satisfy its phase's conditions (A: `phi1 >= psi`; B: `s1 <= 1`,
//! section 6.2.2); when it does not, or its residual is above the FDM level ([`SUSPECT`]), or
//! the solve fails, the row is solved again in the other phase, from the previous row's
//! solution, and a hypothesis that satisfies its condition at the FDM level is kept (otherwise
//! the smaller residual). The kept phase is the current phase of the next row. On the
//! chapter-5 cases the slope rule alone misplaces some switches (and with `theta < 1` fires
//! spuriously); the retry corrects them.
//!
//! Every FDM solve starts from the FDM solution at the best point so far (the previous row's at
//! the start of a row), which keeps the evaluations on one branch of the Dirichlet problem.

use crate::common::{contact_force, ReconPoint, ReconSettings};
use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use beam_model::equations::WhiskerFdmProblem;
use beam_model::{solve as solve_model, FluidLoad, Loads, Method, Scene, Solution, Whisker};
use bvp_solvers::fdm::{BoundaryCondition, FdmOptions, FdmSolver};
use bvp_solvers::grid::UniformGrid;
use bvp_solvers::trust_region::{self, NonlinearSystem, TrustRegionOptions};
use bvp_solvers::BvpError;
use contact_sim::phase::contact_loads;
use contact_sim::Phase;
use std::cell::{Cell, RefCell};

/// FDM intervals on `[0, s1]` (the thesis's `h = 0.01` for `s1 = 1`).
pub const INTERVALS: usize = 100;
/// Slope-jump threshold `a_diff` of [6.10].
pub const A_DIFF: f64 = 1.0;
/// Trust-region iteration budget per row and phase.
const MAX_ITERS: u64 = 100;
/// Residual above the FDM level (`<= 1e-3` on the chapter-5 cases) that makes a hypothesis
/// suspect: the other phase is tried too and the smaller residual kept.
pub const SUSPECT: f64 = 1e-3;
/// Trial points without a relative improvement of [`IMPROVEMENT`] after which a least-squares
/// solve that cannot reach `ReconSettings::tol` ends at its best point.
pub const STALL_TRIALS: usize = 12;
/// Relative improvement of the residual norm that counts as progress.
pub const IMPROVEMENT: f64 = 1e-10;
/// Restarts of phase B at the first contact row when neither hypothesis is consistent.
const FIRST_ROW_S1: [f64; 6] = [0.9, 0.8, 0.7, 0.6, 0.5, 0.4];
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

/// Best point of a trust-region run.
#[derive(Clone, Debug)]
struct Track {
    best: f64,
    best_x: Vec<f64>,
    /// Trial points (residual evaluations outside the Jacobian) so far.
    trials: usize,
    /// Trial at which `best` last improved by a relative [`IMPROVEMENT`].
    trial_at_best: usize,
    /// FDM solution at the best point: the start of every FDM Newton solve, so that all
    /// evaluations follow one branch of the BVP (under large forces the Dirichlet problem has
    /// several solutions, and a warm start from the last trial point could switch branches and
    /// make the residuals discontinuous).
    reference: Vec<f64>,
    /// FDM solution of the last evaluation.
    last: Vec<f64>,
}

/// Rows of [6.5-6.9] for one observable row and one phase hypothesis.
struct RowSystem<'a> {
    whisker: &'a Whisker,
    flow: FluidLoad,
    tol: f64,
    row: &'a ObservableRow,
    phase: Phase,
    track: RefCell<Track>,
    in_jacobian: Cell<bool>,
}

impl<'a> RowSystem<'a> {
    /// The system of one row and phase; `reference` is the FDM solution of the previous row
    /// (nodes at `s = i s1 / INTERVALS`), empty for a linear start.
    fn new(
        whisker: &'a Whisker,
        (flow, tol): (FluidLoad, f64),
        row: &'a ObservableRow,
        phase: Phase,
        reference: Vec<f64>,
    ) -> Self {
        RowSystem {
            whisker,
            flow,
            tol,
            row,
            phase,
            track: RefCell::new(Track {
                best: f64::INFINITY,
                best_x: Vec::new(),
                trials: 0,
                trial_at_best: 0,
                reference,
                last: Vec::new(),
            }),
            in_jacobian: Cell::new(false),
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
        let loads = contact_loads(self.flow, psi, f, s1);
        let problem = WhiskerFdmProblem::new(*self.whisker, loads, phi1);
        let phi0 = self.row.phi0;
        let guess: Vec<f64> = {
            let t = self.track.borrow();
            if t.reference.len() == grid.len() {
                t.reference.clone()
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
        self.track.borrow_mut().last = sol.y;
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
        let (sa, ca) = self.flow.alpha.sin_cos();
        r[4] = self.row.ax + self.flow.q * s1 * ca + f * sp; // [6.8]
        r[5] = self.row.ay - self.flow.q * s1 * sa - f * cp; // [6.9]
    }

    /// Solves the row from `start`.
    fn run(self, start: &[f64]) -> Result<Solved> {
        let opts = TrustRegionOptions {
            tol: self.tol,
            max_iters: MAX_ITERS,
            initial_radius: 0.1,
            max_radius: 10.0,
        };
        let (u, residual, iterations) = match trust_region::solve(&self, start, &opts) {
            Ok(sol) => (sol.x, sol.residual_norm, sol.iterations as usize),
            // The least-squares minimum above the tolerance (the FDM level): the best point found.
            Err(ReconError::Bvp(BvpError::NoConvergence { .. }))
                if self.track.borrow().best.is_finite() =>
            {
                let t = self.track.borrow();
                (t.best_x.clone(), t.best, t.trial_at_best)
            }
            Err(e) => return Err(e),
        };
        Ok(Solved {
            phase: self.phase,
            u,
            residual,
            iterations,
            shape: self.track.into_inner().reference,
        })
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

    /// The residuals [6.5-6.9]; after [`STALL_TRIALS`] trial points without progress every
    /// further trial point is rejected (NaN) without an FDM solve, which ends the run cheaply.
    fn residual(&self, x: &[f64], r: &mut [f64]) -> Result<()> {
        let trial = !self.in_jacobian.get();
        if trial {
            let mut t = self.track.borrow_mut();
            t.trials += 1;
            if t.trials - t.trial_at_best > STALL_TRIALS {
                r.iter_mut().for_each(|v| *v = f64::NAN);
                return Ok(());
            }
        }
        self.eval(x, r);
        let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut t = self.track.borrow_mut();
        if norm.is_finite() && norm < t.best {
            if trial && norm < t.best * (1.0 - IMPROVEMENT) {
                t.trial_at_best = t.trials;
            }
            t.best = norm;
            t.best_x = x.to_vec();
            t.reference = std::mem::take(&mut t.last);
        }
        Ok(())
    }

    /// Forward differences, as the default of the trait (marked so that the perturbed points
    /// do not count as trial points).
    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> Result<()> {
        const N: usize = 5;
        const M: usize = 6;
        self.in_jacobian.set(true);
        let mut r0 = [0.0; M];
        let mut r1 = [0.0; M];
        let mut xp = x.to_vec();
        let mut out = self.residual(x, &mut r0);
        let sq = f64::EPSILON.sqrt();
        for j in 0..N {
            if out.is_err() {
                break;
            }
            let h = sq * x[j].abs().max(1.0);
            xp[j] = x[j] + h;
            let hh = xp[j] - x[j];
            out = self.residual(&xp, &mut r1);
            xp[j] = x[j];
            for i in 0..M {
                jac[i * N + j] = (r1[i] - r0[i]) / hh;
            }
        }
        self.in_jacobian.set(false);
        out
    }
}

/// A solved hypothesis.
#[derive(Clone, Debug)]
struct Solved {
    phase: Phase,
    u: Vec<f64>,
    residual: f64,
    iterations: usize,
    /// FDM solution at the point (warm start of the next row).
    shape: Vec<f64>,
}

impl Solved {
    /// Whether the phase's conditions hold (A: `phi1 >= psi`; B: `s1 <= 1`) [6.2.2].
    fn valid(&self) -> bool {
        match self.phase {
            Phase::B => self.u[4] <= 1.0 + 1e-9,
            _ => self.u[4] >= self.u[2] - 1e-9,
        }
    }

    /// Acceptable without trying the other phase: valid and consistent to the FDM level.
    fn good(&self) -> bool {
        self.valid() && self.residual <= SUSPECT
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

/// Slope `dAy/dx0` between rows `a` and `b`.
fn slope(a: &ObservableRow, b: &ObservableRow) -> f64 {
    (b.ay - a.ay) / (b.x0 - a.x0)
}

/// The phase switches of [6.10] along the contact rows: a jump of the slope of `Ay` ahead of
/// the step, not tested again on the row right after a switch.
#[derive(Clone, Copy, Debug, Default)]
struct SlopeRule {
    just_switched: bool,
}

impl SlopeRule {
    /// The phase of row `order[k]` from the current `phase`.
    fn phase_at(
        &mut self,
        rows: &[ObservableRow],
        order: &[usize],
        k: usize,
        phase: Phase,
    ) -> Phase {
        if k < 2 {
            return phase;
        }
        let (a, b, c) = (&rows[order[k - 2]], &rows[order[k - 1]], &rows[order[k]]);
        let delta = (slope(b, c) - slope(a, b)).abs();
        if !self.just_switched && delta > A_DIFF {
            self.just_switched = true;
            other(phase)
        } else {
            self.just_switched = false;
            phase
        }
    }
}

/// Where a row starts: the previous row's solution, its phase and its FDM solution.
struct Warm {
    u: Vec<f64>,
    phase: Phase,
    shape: Vec<f64>,
}

impl Warm {
    /// The start of a solve in phase `ph`.
    fn start_for(&self, ph: Phase) -> Vec<f64> {
        if ph == self.phase {
            self.u.clone()
        } else {
            convert(&self.u, ph)
        }
    }
}

/// One contact row of the thesis's method.
struct RowSolve<'a> {
    whisker: &'a Whisker,
    /// Flow and trust-region tolerance.
    system: (FluidLoad, f64),
    /// 0-based index of the row.
    i: usize,
    row: &'a ObservableRow,
}

impl RowSolve<'_> {
    /// The row solved in phase `ph` from `u`.
    fn attempt(&self, warm: &Warm, ph: Phase, u: &[f64]) -> Result<Solved> {
        RowSystem::new(self.whisker, self.system, self.row, ph, warm.shape.clone()).run(u)
    }

    /// The row solved in `phase`, and in the other phase too when that solution is not
    /// good: one that is good, else the smaller residual; an error naming the row if neither
    /// can be solved.
    fn solve(&self, warm: &Warm, phase: Phase) -> Result<Solved> {
        let first_try = self.attempt(warm, phase, &warm.start_for(phase));
        if let Ok(s) = &first_try {
            if s.good() {
                return first_try;
            }
        }
        let second = self.attempt(warm, other(phase), &warm.start_for(other(phase)));
        match (first_try, second) {
            (_, Ok(b)) if b.good() => Ok(b),
            (Ok(a), Ok(b)) => Ok(if b.residual < a.residual { b } else { a }),
            (Ok(a), Err(_)) => Ok(a),
            (Err(_), Ok(b)) => Ok(b),
            (Err(e), Err(_)) => {
                let residual = match e {
                    ReconError::InconsistentRow { residual, .. } => residual,
                    ReconError::Bvp(BvpError::NoConvergence { residual, .. }) => residual,
                    _ => f64::NAN,
                };
                Err(ReconError::InconsistentRow {
                    row: self.i,
                    x0: self.row.x0,
                    residual,
                    phase: if phase == Phase::B { 'B' } else { 'A' },
                })
            }
        }
    }

    /// First row without a consistent hypothesis: a tangential first contact far from the
    /// tip (s1 well below 1) is out of reach of the start s1 = 1; restart phase B from a few
    /// s1 on the free whisker (contact point r(s1), force balance [6.8, 6.9]).
    fn restart(&self, warm: &Warm, free: &Solution, mut chosen: Solved) -> Solved {
        let row = self.row;
        for s1 in FIRST_ROW_S1 {
            let j = free
                .elastica
                .s
                .iter()
                .position(|&s| s >= s1)
                .unwrap_or(free.elastica.s.len().saturating_sub(1));
            let (f, psi) = contact_force(row, self.system.0, s1);
            let (Some(&x), Some(&y)) = (free.elastica.x.get(j), free.elastica.y.get(j)) else {
                continue;
            };
            if let Ok(b) = self.attempt(warm, Phase::B, &[row.x0 + x, y, psi, f, s1]) {
                if b.good() || b.residual < chosen.residual {
                    let done = b.good();
                    chosen = b;
                    if done {
                        break;
                    }
                }
            }
        }
        chosen
    }

    /// The point of the solution `s`, checked against `consistency_tol`.
    fn point(&self, s: &Solved, consistency_tol: Option<f64>) -> Result<ReconPoint> {
        if let Some(tol) = consistency_tol {
            if s.residual.is_nan() || s.residual > tol {
                return Err(ReconError::InconsistentRow {
                    row: self.i,
                    x0: self.row.x0,
                    residual: s.residual,
                    phase: if s.phase == Phase::B { 'B' } else { 'A' },
                });
            }
        }
        Ok(ReconPoint {
            row: self.i,
            x0: self.row.x0,
            x: s.u[0],
            y: s.u[1],
            s1: s.s1(),
            f: s.u[3],
            psi: s.u[2],
            phase: s.phase,
            residual: s.residual,
            sigma: f64::NAN,
            alternatives: 0,
            evaluations: s.iterations,
        })
    }
}

/// Checks that `order` is not empty, that its rows exist and are finite; its first row.
fn first_row(rows: &[ObservableRow], order: &[usize]) -> Result<usize> {
    let Some(&first) = order.first() else {
        return Err(ReconError::TooFewRows {
            found: 0,
            needed: 1,
            what: "the thesis method needs at least one contact row",
        });
    };
    for &i in order {
        rows.get(i)
            .ok_or(ReconError::TooFewRows {
                found: rows.len(),
                needed: i + 1,
                what: "a contact row index is beyond the log",
            })?
            .validate(i)?;
    }
    Ok(first)
}

/// The first phase (6.2.1, Remark 6.3) and the warm start of the first row `row0`: force
/// balance with `s1 = 1` [6.8, 6.9] and the free tip of the whisker under the flow (thesis
/// 6.1), with the free whisker.
fn first_start(
    whisker: &Whisker,
    flow: FluidLoad,
    row0: &ObservableRow,
    settings: &ReconSettings,
) -> Result<(Warm, Solution)> {
    let q = flow.q;
    // The flow acts on [0, s1] only in phase B, so the contact force of [6.8] at s1 = 1
    // points away from the contour (f sin psi < 0) at a tangential first contact.
    let level = settings.noise.unwrap_or(crate::common::NOISE_FLOOR);
    let noticeable = (100.0 * level).max(1e-7) * (1.0 + q);
    let (fs, _) = crate::common::force_components(row0, flow, 1.0);
    let phase = if -fs > noticeable { Phase::B } else { Phase::A };
    let free = solve_model(
        &Scene::new(*whisker, Loads::fluid(q, flow.alpha)),
        &Method::accurate(),
    )?;
    let (f0, psi0) = contact_force(row0, flow, 1.0);
    let u = vec![
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
    let warm = Warm {
        u,
        phase,
        shape: Vec::new(),
    };
    Ok((warm, free))
}

/// Reconstructs the contact rows `rows[order[k]]` (`order`: 0-based indices sorted by `x0`,
/// the order of a sweep) by the thesis's method (module docs): five unknowns per row
/// [6.3, 6.4] from the six residuals of [6.5-6.9] by the trust region (tolerance
/// `settings.tol`) around FDM solves of [3.25], warm-started from the previous row, phases by
/// [6.10]. The flow `(q, alpha)` enters the loads and the force balance [6.8, 6.9].
///
/// The first row starts from force balance with `s1 = 1` [6.8, 6.9] and the free tip of the
/// whisker under the flow (thesis 6.1); if neither phase is consistent there, phase B is
/// restarted from a few `s1 < 1` with the contact point on the free whisker (a tangential first
/// contact far from the tip).
///
/// # Errors
/// - [`ReconError::TooFewRows`] without contact rows (`order` empty);
/// - [`ReconError::NonFinite`] for a non-finite observable;
/// - [`ReconError::Model`] if the free whisker cannot be solved;
/// - [`ReconError::InconsistentRow`] if neither phase can be solved at a row, or (with
///   `settings.consistency_tol`) the best residual of a row exceeds it;
/// - [`ReconError::Bvp`] for other solver failures.
pub fn reconstruct_rows(
    whisker: &Whisker,
    flow: FluidLoad,
    rows: &[ObservableRow],
    order: &[usize],
    settings: &ReconSettings,
) -> Result<Vec<ReconPoint>> {
    let first = first_row(rows, order)?;
    let (mut warm, free) = first_start(whisker, flow, &rows[first], settings)?;
    let mut phase = warm.phase;
    let mut rule = SlopeRule::default();
    let mut points = Vec::with_capacity(order.len());
    for (k, &i) in order.iter().enumerate() {
        // [6.10]: slope jump of Ay ahead of the step (contact rows only).
        phase = rule.phase_at(rows, order, k, phase);
        let solve = RowSolve {
            whisker,
            system: (flow, settings.tol),
            i,
            row: &rows[i],
        };
        let mut chosen = solve.solve(&warm, phase)?;
        if k == 0 && !chosen.good() {
            chosen = solve.restart(&warm, &free, chosen);
        }
        points.push(solve.point(&chosen, settings.consistency_tol)?);
        phase = chosen.phase;
        warm = Warm {
            u: chosen.u,
            phase: chosen.phase,
            shape: chosen.shape,
        };
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(x0: f64, ay: f64) -> ObservableRow {
        ObservableRow {
            x0,
            ax: 0.0,
            ay,
            ma: 0.0,
            phi0: 0.0,
        }
    }

    #[test]
    fn the_slope_rule_switches_on_a_kink_once() {
        // Ay = x0 up to 0.3, then Ay = 0.3 + 5 (x0 - 0.3): one kink, slope jump 4 > A_DIFF
        let rows: Vec<ObservableRow> = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6]
            .iter()
            .map(|&x: &f64| row(x, if x <= 0.3 { x } else { 0.3 + 5.0 * (x - 0.3) }))
            .collect();
        let order: Vec<usize> = (0..rows.len()).collect();
        let mut rule = SlopeRule::default();
        let phases: Vec<Phase> = (0..rows.len())
            .map(|k| rule.phase_at(&rows, &order, k, Phase::A))
            .collect();
        // the jump shows at row 4 (slopes 1 then 5); row 5 is not tested again
        let want = [
            Phase::A,
            Phase::A,
            Phase::A,
            Phase::A,
            Phase::B,
            Phase::A,
            Phase::A,
        ];
        assert_eq!(phases, want);
    }

    #[test]
    fn phases_convert_into_each_other() {
        let u = [1.0, 2.0, 0.3, 4.0, 0.7];
        // B from A: s1 just below the tip; A from B: phi1 = psi
        assert_eq!(convert(&u, Phase::B), vec![1.0, 2.0, 0.3, 4.0, 1.0 - 1e-3]);
        assert_eq!(convert(&u, Phase::A), vec![1.0, 2.0, 0.3, 4.0, 0.3]);
        assert_eq!(other(Phase::A), Phase::B);
        assert_eq!(other(Phase::B), Phase::A);
    }
}
