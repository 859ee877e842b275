//! The variational equations of the base system [3.25, 6.8, 6.9] with respect to the
//! observables `(Ax, Ay, MA, phi0)`, carried along the steps of the row's one base
//! integration ([`BaseRun`]) instead of a second integration ([`sensitivities`]).
//!
//! The equations are linear in the sensitivities, with coefficients that depend on the base
//! state only through `sin phi`, `cos phi` (and the arc). On each step of the base run those
//! are free at both ends (they are the step's slopes `x' = cos phi`, `y' = sin phi`); one
//! `sin_cos` at the step's middle gives the third node of a classical Runge-Kutta step of
//! order 4 over the base run's own step. The middle's `phi` is the quintic Hermite
//! interpolant of the ends' `phi`, `phi'`, `phi''` (error `O(h^6)`). The base run's steps are
//! those of an 8th-order integration of the same dynamics at the method's tolerance, so the
//! 4th-order step on them is accurate to several digits (the error estimate needs a few;
//! unit test against the variational equations integrated with the state at 1e-12).

use super::base_ode::{by, comp, BaseOde};
use super::base_run::BaseRun;
use bvp_solvers::integrator::{OdeSystem, StepInterpolant};

/// The sensitivities of the state `(phi, m, x, y)` with respect to `(Ax, Ay, MA, phi0)`:
/// `[c][j]` is that of component `c` with respect to observable `j`.
pub(super) type Sens = [[f64; 4]; 4];

/// The sensitivities at the base: `d m(0) / d MA = -1`, `d phi(0) / d phi0 = 1`.
pub(super) fn initial_sens() -> Sens {
    let mut y = [[0.0; 4]; 4];
    y[comp::M][by::MA] = -1.0;
    y[comp::PHI][by::PHI0] = 1.0;
    y
}

/// The coefficients of the variational equations at one arc.
#[derive(Clone, Copy, Debug)]
struct Coef {
    sp: f64,
    cp: f64,
    /// `1 / e^4`.
    inv_e4: f64,
    /// `d m' / d phi`.
    jm: f64,
}

impl Coef {
    fn at(ode: &BaseOde, s: f64, sp: f64, cp: f64) -> Self {
        Coef {
            sp,
            cp,
            inv_e4: ode.compliance(s),
            jm: ode.rate(s, sp, cp).dm_dphi,
        }
    }

    /// The derivative of the sensitivities `y` (as [`BaseOde`]'s variational part):
    /// `dphi' = dm / e^4`, `dm' = jm dphi + (-sin phi, cos phi, 0, 0)_j`,
    /// `dx' = -sin phi dphi`, `dy' = cos phi dphi`.
    #[inline]
    fn rate(&self, y: &Sens) -> Sens {
        let [dphi, dm, _, _] = y;
        // d(f cos beta)/dAx = -1, d(f sin beta)/dAy = 1
        let explicit = [-self.sp, self.cp, 0.0, 0.0];
        let mut d = [[0.0; 4]; 4];
        for j in 0..4 {
            d[0][j] = dm[j] * self.inv_e4;
            d[1][j] = self.jm * dphi[j] + explicit[j];
            d[2][j] = -self.sp * dphi[j];
            d[3][j] = self.cp * dphi[j];
        }
        d
    }
}

/// `y + a d`.
#[inline]
fn axpy(y: &Sens, a: f64, d: &Sens) -> Sens {
    let mut out = *y;
    for (o, di) in out.as_flattened_mut().iter_mut().zip(d.as_flattened()) {
        *o += a * di;
    }
    out
}

/// A point of the base run: its arc, `phi`, `phi'`, `phi''` and the coefficients there.
#[derive(Clone, Copy, Debug)]
struct Knot {
    s: f64,
    phi: f64,
    dphi: f64,
    ddphi: f64,
    coef: Coef,
}

impl Knot {
    /// From the state `u` and its derivative `du` at `s`.
    fn new(ode: &BaseOde, s: f64, u: &[f64; 4], du: &[f64; 4]) -> Self {
        Knot {
            s,
            phi: u[0],
            dphi: du[0],
            ddphi: ode.phi_curvature_rate(s, u[1], du[1]),
            coef: Coef::at(ode, s, du[3], du[2]),
        }
    }

    /// An end of a step (`theta` 0 or 1, at arc `s`): the step's state and slope there (from
    /// the cubic part's coefficients, one division).
    fn of_step(ode: &BaseOde, p: &StepInterpolant<4>, theta: f64, s: f64) -> Option<Self> {
        let [r0, r1, r2, r3] = p.cubic_coefficients()?;
        let inv_h = 1.0 / p.h();
        let (mut u, mut du) = ([0.0; 4], [0.0; 4]);
        for i in 0..4 {
            u[i] = r0[i] + theta * (r1[i] + (1.0 - theta) * (r2[i] + theta * r3[i]));
            du[i] =
                (r1[i] + (1.0 - 2.0 * theta) * r2[i] + theta * (2.0 - 3.0 * theta) * r3[i]) * inv_h;
        }
        Some(Knot::new(ode, s, &u, &du))
    }

    /// Any arc of the run: the 7th-order interpolant where the run has it (the cubic
    /// elsewhere), the slope from the system itself.
    fn at(run: &BaseRun, ode: &BaseOde, s: f64) -> Option<Self> {
        let (mut u, mut du) = ([0.0; 4], [0.0; 4]);
        if !run.eval_into(s, &mut u) && !run.cubic_at(s, &mut u, &mut du) {
            return None;
        }
        ode.rhs(s, &u, &mut du);
        Some(Knot::new(ode, s, &u, &du))
    }
}

/// The sensitivities `y` at `a.s` carried to `b.s` by one classical Runge-Kutta step (its
/// middle node from the quintic Hermite interpolant of `phi`).
fn advance(ode: &BaseOde, a: &Knot, b: &Knot, y: &Sens) -> Sens {
    let h = b.s - a.s;
    let phi_mid = 0.5 * (a.phi + b.phi)
        + 5.0 / 32.0 * h * (a.dphi - b.dphi)
        + h * h / 64.0 * (a.ddphi + b.ddphi);
    let (sp, cp) = ode.sin_cos(phi_mid);
    let mid = Coef::at(ode, a.s + 0.5 * h, sp, cp);
    let k1 = a.coef.rate(y);
    let k2 = mid.rate(&axpy(y, 0.5 * h, &k1));
    let k3 = mid.rate(&axpy(y, 0.5 * h, &k2));
    let k4 = b.coef.rate(&axpy(y, h, &k3));
    let mut out = *y;
    for (c, row) in out.iter_mut().enumerate() {
        for (j, o) in row.iter_mut().enumerate() {
            *o += h / 6.0 * (k1[c][j] + 2.0 * (k2[c][j] + k3[c][j]) + k4[c][j]);
        }
    }
    out
}

/// The sensitivities at the arcs `at` (in any order; `None` outside `[0, s_end]`), carried
/// along the steps of `run` (module docs) up to the last of them.
pub(super) fn sensitivities(run: &BaseRun, ode: &BaseOde, at: &[f64]) -> Vec<Option<Sens>> {
    let mut out = vec![None; at.len()];
    let mut order: Vec<usize> = (0..at.len())
        .filter(|&k| at[k] >= 0.0 && at[k] <= run.s_end)
        .collect();
    order.sort_by(|&i, &j| at[i].total_cmp(&at[j]));
    let mut pending = order.into_iter().peekable();
    let mut y = initial_sens();
    let mut steps = run.steps().peekable();
    // the end of a step is the start of the next
    let mut next_left = None;
    while let Some(step) = steps.next() {
        let last = steps.peek().is_none();
        let Some(left) = next_left
            .take()
            .or_else(|| Knot::of_step(ode, step.interp, 0.0, step.start))
        else {
            break;
        };
        // the arcs on this step (its end belongs to the next one, but for the last step)
        while let Some(&i) = pending.peek() {
            let s = at[i];
            if s > step.end || (s == step.end && !last) {
                break;
            }
            out[i] = if s == step.start {
                Some(y)
            } else {
                Knot::at(run, ode, s).map(|b| advance(ode, &left, &b, &y))
            };
            pending.next();
        }
        if pending.peek().is_none() {
            break;
        }
        let Some(right) = Knot::of_step(ode, step.interp, 1.0, step.end) else {
            break;
        };
        y = advance(ode, &left, &right, &y);
        next_left = Some(right);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::base_ode::sens_block;
    use super::super::base_ode::tests::row;
    use super::*;
    use crate::observables::ObservableRow;
    use beam_model::{FluidLoad, Whisker};
    use bvp_solvers::integrator::{Dop853, OdeSolution};

    #[test]
    fn quintic_middle_is_exact_for_quintics() {
        // phi = s^5 on [0, 1] through the Hermite data: 1/32 at the middle
        let (a, b) = ((0.0, 0.0, 0.0), (1.0, 5.0, 20.0));
        let h = 1.0;
        let mid = 0.5 * (a.0 + b.0) + 5.0 / 32.0 * h * (a.1 - b.1) + h * h / 64.0 * (a.2 + b.2);
        assert!((mid - 1.0 / 32.0f64).abs() < 1e-16);
    }

    /// The largest error, relative to the column's size, of sensitivities `got` at `arcs`
    /// against the dense output `exact` of the variational equations.
    fn error_of(arcs: &[f64], got: &[Sens], exact: &OdeSolution) -> f64 {
        let mut worst: f64 = 0.0;
        for (s, g) in arcs.iter().zip(got) {
            let e = exact.eval(*s).unwrap();
            for j in 0..4 {
                let col = sens_block(&e, j);
                let size = col.iter().fold(1e-3f64, |a, v| a.max(v.abs()));
                for (gc, v) in g.iter().zip(col) {
                    worst = worst.max((gc[j] - v).abs() / size);
                }
            }
        }
        worst
    }

    /// The errors of the carried sensitivities of row `r` and of the variational equations
    /// integrated with the state at 1e-3 (the former separate Jacobian integration), both
    /// against that integration at 1e-13.
    fn errors(w: &Whisker, flow: FluidLoad, r: &ObservableRow) -> (f64, f64) {
        let opts = Dop853 {
            h_init: Some(0.05),
            ..Dop853::new(1e-12, 1e-12)
        };
        let ode = BaseOde::new(w, flow, r, false).fast();
        let run = BaseRun::new(&ode, r, &opts).unwrap();
        let arcs = [0.0, 0.137, 0.5, 0.77, 0.999, 1.0];
        let got: Vec<Sens> = sensitivities(&run, &ode, &arcs)
            .into_iter()
            .map(|g| g.expect("an arc of the run"))
            .collect();
        let sode = BaseOde::new(w, flow, r, true);
        let u0 = sode.initial(r);
        let at = |tol: f64| {
            let opts = Dop853::new(tol, tol).with_dense(true);
            opts.integrate(&sode, 0.0, 1.0, &u0).unwrap()
        };
        let (exact, loose) = (at(1e-13), at(1e-3));
        let old: Vec<Sens> = arcs
            .iter()
            .map(|&s| {
                let v = loose.eval(s).unwrap();
                let mut out = [[0.0; 4]; 4];
                for (c, row) in out.iter_mut().enumerate() {
                    for (j, o) in row.iter_mut().enumerate() {
                        *o = sens_block(&v, j)[c];
                    }
                }
                out
            })
            .collect();
        (error_of(&arcs, &got, &exact), error_of(&arcs, &old, &exact))
    }

    #[test]
    fn carried_sensitivities_match_the_variational_integration() {
        let cases = [
            (
                Whisker::uniform(),
                FluidLoad { q: 5.0, alpha: 0.0 },
                row(-5.5, 1.2, 0.4, 0.3),
            ),
            (
                Whisker::new(0.6, 2.0, -1.0, f64::INFINITY),
                FluidLoad { q: 3.0, alpha: 0.2 },
                row(-1.0, 6.0, 0.9, 1.5),
            ),
            (
                Whisker::new(0.2, 0.3, 0.2, f64::INFINITY),
                FluidLoad { q: 0.8, alpha: 0.3 },
                row(-0.5, 0.9, 0.2, 1.4),
            ),
        ];
        for (w, flow, r) in cases {
            // measured: 6e-6, 4e-5, 8e-5 (the integration at 1e-3: 1.5e-4, 6.5e-4, 4.5e-3)
            let (carried, loose) = errors(&w, flow, &r);
            assert!(carried < 2e-4, "{carried:e} for {w:?}");
            assert!(carried < 0.1 * loose, "{carried:e} vs {loose:e} for {w:?}");
        }
    }

    #[test]
    fn arcs_outside_the_run_have_none() {
        let w = Whisker::uniform();
        let flow = FluidLoad { q: 0.0, alpha: 0.0 };
        let r = row(0.0, 0.0, -20.0, 0.0);
        let ode = BaseOde::new(&w, flow, &r, false);
        let run = BaseRun::new(&ode, &r, &Dop853::new(1e-12, 1e-12)).unwrap();
        let got = sensitivities(&run, &ode, &[0.9, 0.1, -0.1]);
        assert!(got[0].is_none() && got[1].is_some() && got[2].is_none());
        // the unloaded arc: phi = phi0 - MA s, so d phi / d phi0 = 1 everywhere
        assert!((got[1].unwrap()[0][3] - 1.0).abs() < 1e-12);
    }
}
