//! The thesis's walk along the contact rows: the phase rule [6.10] ([`SlopeRule`]), the warm
//! start from the previous row ([`Warm`]), one row solved in its phase and, failing that, in
//! the other ([`RowSolve`]), and the start of the first row.

use super::system::{convert, other, RowSystem, Solved};
use crate::common::{contact_force, ReconSettings};
use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use crate::result::ReconPoint;
use beam_model::{solve as solve_model, FluidLoad, Loads, Method, Scene, Solution, Whisker};
use bvp_solvers::BvpError;
use contact_sim::Phase;

/// Slope-jump threshold `a_diff` of [6.10].
pub const A_DIFF: f64 = 1.0;
/// Restarts of phase B at the first contact row when neither hypothesis is consistent.
const FIRST_ROW_S1: [f64; 6] = [0.9, 0.8, 0.7, 0.6, 0.5, 0.4];

/// Slope `dAy/dx0` between rows `a` and `b`.
fn slope(a: &ObservableRow, b: &ObservableRow) -> f64 {
    (b.ay - a.ay) / (b.x0 - a.x0)
}

/// The phase switches of [6.10] along the contact rows: a jump of the slope of `Ay` ahead of
/// the step, not tested again on the row right after a switch.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct SlopeRule {
    pub(super) just_switched: bool,
}

impl SlopeRule {
    /// The phase of row `order[k]` from the current `phase`.
    pub(super) fn phase_at(
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
pub(super) struct Warm {
    pub(super) u: Vec<f64>,
    pub(super) phase: Phase,
    pub(super) shape: Vec<f64>,
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
pub(super) struct RowSolve<'a> {
    pub(super) whisker: &'a Whisker,
    /// Flow and trust-region tolerance.
    pub(super) system: (FluidLoad, f64),
    /// 0-based index of the row.
    pub(super) i: usize,
    pub(super) row: &'a ObservableRow,
}

impl RowSolve<'_> {
    /// The row solved in phase `ph` from `u`.
    fn attempt(&self, warm: &Warm, ph: Phase, u: &[f64]) -> Result<Solved> {
        RowSystem::new(self.whisker, self.system, self.row, ph, warm.shape.clone()).run(u)
    }

    /// The row solved in `phase`, and in the other phase too when that solution is not
    /// good: one that is good, else the smaller residual; an error naming the row if neither
    /// can be solved.
    pub(super) fn solve(&self, warm: &Warm, phase: Phase) -> Result<Solved> {
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
                    phase,
                })
            }
        }
    }

    /// First row without a consistent hypothesis: a tangential first contact far from the
    /// tip (s1 well below 1) is out of reach of the start s1 = 1; restart phase B from a few
    /// s1 on the free whisker (contact point r(s1), force balance [6.8, 6.9]).
    pub(super) fn restart(&self, warm: &Warm, free: &Solution, mut chosen: Solved) -> Solved {
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
    pub(super) fn point(&self, s: &Solved, consistency_tol: Option<f64>) -> Result<ReconPoint> {
        if let Some(tol) = consistency_tol {
            if s.residual.is_nan() || s.residual > tol {
                return Err(ReconError::InconsistentRow {
                    row: self.i,
                    x0: self.row.x0,
                    residual: s.residual,
                    phase: s.phase,
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
pub(super) fn first_row(rows: &[ObservableRow], order: &[usize]) -> Result<usize> {
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
pub(super) fn first_start(
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
}
