//! Method `accurate` (`ReconMethod::Accurate`), one shot from the base per row: the module is
//! named for what it does, as `beam_model::shot` shoots from the loaded end, and so that it
//! does not read as a twin of [`accuracy`](crate::accuracy) (accuracy on demand, which runs
//! this method at the tolerance an accuracy needs).
//!
//! The observables ARE the initial values of the first-order system at the
//! base, `(phi, m, x, y)(0) = (phi0, -MA, x0, 0)` (spec/model.md, thesis ch. 6 reformulated).
//!
//! For a contact at `s1` the internal force at `s < s1` is fixed by the base reaction and the
//! flow on `[0, s]` alone [6.8, 6.9]: it does not depend on `s1`. So ONE integration from the
//! base over `[0, 1]` (under the phase-A loads of the row) gives the state of every phase
//! hypothesis at once:
//! - phase A (`s1 = 1`): consistent when `m(1) = 0` [6.6] and `phi(1) >= psi`; the contact
//!   point is `r(1)`;
//! - phase B: every root `s1` of the moment condition `m(s1) = 0` on `(0, 1)`, all of them
//!   bracketed on the dense output (each step cut in [`SAMPLES`] parts, and each part with an
//!   extremum of `m` cut there, so that two close roots are not lost) and located by Brent;
//!   consistent when the contact is tangential, `phi(s1) = psi(s1)`; the point is `r(s1)`.
//!   Extrema of `m` towards zero (roots of `m'`, bracketed the same way) are hypotheses too,
//!   with `m(s1)` as one more residual: as `f -> 0` in phase B (a release) the root of `m` is
//!   double and has no sign change.
//!
//! The phase is the hypothesis with the smallest residual relative to its own noise
//! sensitivity (`z = |residual| / sigma_unit`), not the slope-jump rule [6.10] and not a
//! neighbouring row: every row is reconstructed on its own. The Jacobian of the residuals and of
//! the contact point with respect to `(Ax, Ay, MA, phi0)` comes from the variational equations
//! of the same system, carried along the steps of the same base integration (`variational`:
//! one Runge-Kutta step of order 4 per step of the base run, its coefficients from the run's
//! own slopes; an error estimate needs a few digits); it gives both the `z` of each hypothesis
//! and the error estimate of the point (the noise level propagated through it, roots moved by
//! `ds1 = -dm / m'(s1)`).
//!
//! Under noise the measured observables are not exactly consistent with any hypothesis; the
//! point is that of the most likely consistent observables (the residual's share of the
//! point's error removed, `project`), its error estimate the conditional deviation given
//! the residual, widened by whatever else fits the row as well: other consistent hypotheses
//! (`RowEval::ambiguity`) and, for a tip contact, a tangential contact just short of the
//! tip (`RowEval::tip_ambiguity`).
//!
//! The base integration drives the DOP853 stepper itself (`base_run`): the cubic Hermite part
//! of each step's interpolant (free) judges the step, the 7th-order interpolant (three more
//! evaluations) is made only on the steps that may hold a root or an extremum of `m`.
//!
//! | file | concept |
//! |---|---|
//! | `base_ode` | the system integrated from the base [3.25, 6.8, 6.9] and its variational equations |
//! | `base_run` | the stepper-driven integration of a row, its interpolants where they are needed |
//! | `variational` | the variational equations carried along the base run's steps: the Jacobian of a row |
//! | `scan` | the phase-B roots and extrema of `m`, bracketed on the dense output |
//! | `evaluate` | one row under one flow: every hypothesis with its `z`, Jacobian and linear projection |
//! | `hypotheses` | the hypotheses of a row and the choice among them at a noise level |
//! | `tip` | phase-B look-alikes just short of the tip of a phase-A row |
//! | `trig` | `sin` and `cos` of the tangent angle for the base system, by table and series |
//! | `project` | the most likely consistent observables of a noisy row (Gauss-Newton) |
//! | `point` | the reconstructed point of a row with its error estimate |

mod base_ode;
mod base_run;
mod context;
mod evaluate;
mod hypotheses;
mod point;
mod project;
mod scan;
mod tip;
mod variational;

pub(crate) use base_ode::{base_ivp, base_ivp_fast};
pub(crate) use evaluate::evaluate;
#[cfg(test)]
pub(crate) use evaluate::tests;
pub(crate) use hypotheses::RowEval;
pub(crate) use point::RowAt;

pub(crate) use context::RowCtx;
pub use context::{K_SIGMA, MAX_WINDING, PROJECT_MIN, SAMPLES, TIP_GRID};
