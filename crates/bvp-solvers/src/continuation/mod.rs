//! Continuation: following a branch of solutions of a parameter-dependent problem. One
//! driver, pseudo-arclength with located events; natural-parameter continuation is its
//! special case with the parameter as the one coordinate.
//!
//! # The driver
//!
//! [`Arclength`] ([`arclength`]) traces a [`Curve`], the solutions of `R(u) = 0` with
//! `R: R^N -> R^(N-1)`, point by point: a predictor along the tangent (or the cubic Hermite
//! through the last two points), a corrector on the hyperplane through the prediction, and
//! three pieces every use shares:
//!
//! - the step control ([`ArcControl`]): grown after an easy correction, shortened after a
//!   hard one, halved after a rejected one, a failure below the smallest step;
//! - the step attempt ([`Attempt`]): a corrected point (not yet accepted), a retry with the
//!   step halved, or the corrector's error;
//! - event location ([`locate`], [`Arclength::earliest`]): regula falsi along the chord, every
//!   trial point a solution of the curve.
//!
//! # Natural-parameter continuation
//!
//! [`Continuation::follow`] ([`natural`]) is that driver on the branch `y(lambda)` seen as a
//! curve whose one coordinate is `lambda`: the tangent is `+-1`, the tangent predictor steps
//! `lambda` by exactly the step, the corrector's hyperplane is `lambda = const` (the
//! caller's own solve at a fixed parameter, any number of unknowns), and the step control
//! is [`ArcControl`] with the step doubled after every accepted point
//! ([`Continuation::control`]). Its points carry the state and its secant slope, so the
//! state is predicted by the secant; a [`BranchGuard`] rejects a corrector that lands on
//! another branch; the last step is clipped to end exactly on the target.
//!
//! # Which to use when
//!
//! | use | when |
//! |---|---|
//! | [`Continuation::follow`] | the branch is a graph over the parameter between start and target (loading from zero, moving the base): one solve per step, no tangent, no Jacobian in the parameter; the caller's solver as it is |
//! | [`Arclength`] on a [`Curve`] | the branch may turn back in the parameter (a fold): the caller writes the bordered corrector and the tangent in a few coordinates; events (folds, arrivals, switches) located on the curve |
//!
//! The hand-over: natural continuation stalls at a fold (its step falls below the smallest,
//! or its guard rejects the corrector that lands on another branch), and pseudo-arclength in
//! `(state, lambda)` takes over, passes the fold and locates the arrival at the target.
//! beam-model's load path does that (`methods/load_path.rs`), and so does this module's
//! test `arclength_takes_over_where_the_natural_path_folds` on `x^3 - 3x = lambda`.
//!
//! # What stays apart, and why
//!
//! - The predictor of the state: the natural path predicts its whole state (a `Vec` of any
//!   length: a finite-difference grid, shooting parameters) by the secant, because that
//!   state is not among its coordinates; the arclength's curves have the state in their few
//!   coordinates and predict by the tangent or the Hermite cubic.
//! - The branch guard: the natural path's [`BranchGuard`] measures the corrector's distance
//!   from the secant prediction in the state; on a [`Curve`] the corrector's `radius` and
//!   the tangent-turn check ([`ArcControl::min_turn_cos`]) play that part in the
//!   coordinates. Both reject the step and halve it through the same [`Attempt::Retry`].
//! - The loop: [`Continuation::follow`] owns its loop (budget, clipped last step, the
//!   failure [`ContinuationFailure`] and counters [`ContinuationStats`]); on a [`Curve`] the
//!   loop stays with the caller, like an ODE stepper's, since only it knows what its events
//!   mean (contact-sim's trace switches phases at them, the load path ends at the arrival).

pub mod arclength;
pub mod natural;

pub use arclength::{locate, ArcControl, Arclength, Attempt, Curve, Predictor, MAX_LOCATE};
pub use natural::{BranchGuard, Continuation, ContinuationFailure, ContinuationStats, StallCause};

#[cfg(test)]
mod tests;
