//! Unit tests of natural-parameter continuation: paths on graphs against their closed forms,
//! the jump guard at a fold, the step control's counts and the failures.

use super::*;

/// Newton on `f(x) = 0` from `x0` with the derivative `df`, to `|f| <= 1e-14 (1 + |lambda|)`.
fn newton(
    lambda: f64,
    x0: f64,
    f: impl Fn(f64) -> f64,
    df: impl Fn(f64) -> f64,
) -> Result<f64, BvpError> {
    let mut x = x0;
    for _ in 0..60 {
        let r = f(x);
        if r.abs() <= 1e-14 * (1.0 + lambda.abs()) {
            return Ok(x);
        }
        x -= r / df(x);
    }
    Err(BvpError::NoConvergence {
        method: "test newton",
        iterations: 60,
        residual: f(x),
    })
}

fn cont(initial_step: f64, min_step: f64, max_step: f64) -> Continuation {
    Continuation {
        initial_step,
        min_step,
        max_step,
    }
}

/// `x = sqrt(lambda)` (Newton on `x^2 = lambda`) from `(1, 1)` to 4 and back: the answers
/// are the roots 2 and 1 to rounding, with no rejected step.
#[test]
fn follows_the_square_root_branch_both_ways() {
    let c = cont(0.25, 1e-6, 1.0);
    let sqrt = |l: f64, p: &[f64]| newton(l, p[0], |x| x * x - l, |x| 2.0 * x).map(|x| vec![x]);
    let (x, stats) = c
        .follow(1.0, 4.0, vec![1.0], &BranchGuard::default(), sqrt)
        .unwrap();
    assert!((x[0] - 2.0).abs() < 1e-14, "{}", x[0]);
    // steps 0.25, 0.5, 1.0, 1.0 (max_step), then 0.25 clipped to 4: five steps
    assert_eq!((stats.steps, stats.halvings, stats.jumps), (5, 0, 0));
    let (x, _) = c
        .follow(4.0, 1.0, vec![2.0], &BranchGuard::default(), sqrt)
        .unwrap();
    assert!((x[0] - 1.0).abs() < 1e-14, "{}", x[0]);
    // the slope known at the start (1 / (2 sqrt(1)) = 1/2) is used on the first step:
    // a corrector that accepts only a prediction within 1e-2 of the root succeeds at once
    let strict = |l: f64, p: &[f64]| {
        let x = l.sqrt();
        if (p[0] - x).abs() < 1e-2 {
            Ok(vec![x])
        } else {
            Err(BvpError::InvalidInput {
                name: "prediction",
                value: p[0],
                reason: "too far",
            })
        }
    };
    let c = cont(0.1, 1e-6, 0.1);
    let (x, stats) = c
        .follow_from(
            1.0,
            1.1,
            vec![1.0],
            vec![0.5],
            &BranchGuard::default(),
            strict,
        )
        .unwrap();
    assert_eq!((x[0], stats.steps, stats.halvings), (1.1f64.sqrt(), 1, 0));
    // without the slope the constant prediction 1 is 0.049 off: the step is halved
    let (_, stats) = c
        .follow(1.0, 1.1, vec![1.0], &BranchGuard::default(), strict)
        .unwrap();
    assert!(stats.halvings >= 1, "{stats:?}");
}

/// `x^3 - 3x = lambda` has a lower branch `x < -1` up to its fold at `(lambda, x) = (2, -1)`
/// and beyond it only the upper root (`x = 2.1038...` at `lambda = 3`): Newton from the
/// prediction past the fold lands there, the guard rejects it, and the run stops at the
/// fold; without the guard it ends on the other branch.
#[test]
fn the_jump_guard_stops_at_a_fold_where_newton_changes_branch() {
    let cubic = |l: f64, p: &[f64]| {
        newton(l, p[0], |x| x * x * x - 3.0 * x - l, |x| 3.0 * x * x - 3.0).map(|x| vec![x])
    };
    let c = cont(0.5, 1e-4, 0.5);
    let start = vec![-(3.0f64.sqrt())];
    let guard = BranchGuard::default();
    let mut landed_above = 0;
    let fail = c
        .follow(0.0, 3.0, start.clone(), &guard, |l, p: &[f64]| {
            let x = cubic(l, p)?;
            if x[0] > -1.0 {
                landed_above += 1;
            }
            Ok::<_, BvpError>(x)
        })
        .unwrap_err();
    assert!(fail.reached <= 2.0 && fail.reached > 2.0 - 1e-3, "{fail:?}");
    assert!(fail.step < 2e-4, "{}", fail.step);
    assert_eq!(fail.target, 3.0);
    assert!(landed_above > 0, "Newton did land on the upper branch");
    match fail.cause {
        // the last rejection: a jump, or Newton failing at the fold itself
        StallCause::Jump { at, distance, .. } => {
            assert!(at > 2.0 && distance > 1.0, "{at} {distance}")
        }
        StallCause::Inner(_) => {}
        other => panic!("{other:?}"),
    }
    let open = BranchGuard {
        absolute: f64::INFINITY,
        ..guard
    };
    let (x, _) = c.follow(0.0, 3.0, start, &open, cubic).unwrap();
    // the one real root of x^3 - 3x - 3 (Cardano): cbrt(3/2 + sqrt(5)/2) + cbrt(3/2 - sqrt(5)/2)
    let s5 = 5.0f64.sqrt();
    let upper = (1.5 + 0.5 * s5).cbrt() + (1.5 - 0.5 * s5).cbrt();
    assert!((x[0] - upper).abs() < 1e-14, "{} vs {upper}", x[0]);
}

/// A corrector that needs the prediction within 0.3 of the answer `x(lambda) = lambda`:
/// the constant first prediction fails three times, then the secant is exact.
#[test]
fn counts_halvings_and_rejects_bad_settings() {
    let c = cont(1.0, 1e-3, 1.0);
    let near = |l: f64, g: &[f64]| {
        if (g[0] - l).abs() > 0.3 {
            Err(BvpError::InvalidInput {
                name: "guess",
                value: g[0],
                reason: "too far",
            })
        } else {
            Ok(vec![l])
        }
    };
    let (x, stats) = c
        .follow(0.0, 2.0, vec![0.0], &BranchGuard::default(), near)
        .unwrap();
    assert_eq!(x, vec![2.0]);
    // h = 1 and 0.5 fail; at 0.25 the answer is 0.25 from the prediction, more than the
    // guard's 0.2: a jump; 0.125 is accepted, then the exact secant: 0.25, 0.5, 1.0 and
    // the last 0.125 (clipped)
    assert_eq!((stats.steps, stats.halvings, stats.jumps), (5, 3, 1));
    let (x, _) = c
        .follow(2.0, 1.0, vec![2.0], &BranchGuard::default(), near)
        .unwrap();
    assert_eq!(x, vec![1.0]);
    let bad = cont(0.0, 1e-3, 1.0)
        .follow(0.0, 1.0, vec![0.0], &BranchGuard::default(), near)
        .unwrap_err();
    assert!(matches!(
        bad.cause,
        StallCause::Invalid(BvpError::InvalidInput {
            name: "initial_step",
            ..
        })
    ));
    let bad = c
        .follow(0.0, f64::NAN, vec![0.0], &BranchGuard::default(), near)
        .unwrap_err();
    assert!(matches!(
        bad.cause,
        StallCause::Invalid(BvpError::InvalidInput { name: "to", .. })
    ));
    let bad = c
        .follow_from(0.0, 1.0, vec![0.0], vec![], &BranchGuard::default(), near)
        .unwrap_err();
    assert!(matches!(
        bad.cause,
        StallCause::Invalid(BvpError::DimensionMismatch { .. })
    ));
}

/// Newton on `y^3 + y = lambda` (one root for every lambda): `follow` reaches lambda = 10
/// and the answer solves the equation to rounding.
fn cubic_newton(lambda: f64, y0: f64) -> Result<f64, BvpError> {
    let mut y = y0;
    for it in 0..30 {
        let r = y * y * y + y - lambda;
        if r.abs() < 1e-13 * (1.0 + lambda.abs()) {
            return Ok(y);
        }
        y -= r / (3.0 * y * y + 1.0);
        if it == 29 {
            break;
        }
    }
    Err(BvpError::NoConvergence {
        method: "cubic",
        iterations: 30,
        residual: y * y * y + y - lambda,
    })
}

#[test]
fn follow_reaches_the_target_with_a_secant_predictor() {
    let cont = Continuation {
        initial_step: 0.1,
        min_step: 1e-6,
        max_step: 0.5,
    };
    let mut calls = 0;
    let (y, stats) = cont
        .follow(
            0.0,
            10.0,
            vec![0.0],
            &BranchGuard::default(),
            |l, p: &[f64]| {
                calls += 1;
                cubic_newton(l, p[0]).map(|y| vec![y])
            },
        )
        .unwrap();
    // y^3 + y = 10 has the root y = 2 exactly
    assert!((y[0] - 2.0).abs() < 1e-12, "{}", y[0]);
    assert_eq!(stats.halvings, 0);
    assert_eq!(stats.steps, calls);
}

/// [`Continuation::follow`] from `(0, [0])` to 1 with steps in `[0.01, 0.25]`: its failure.
fn failure_to_one(
    guard: &BranchGuard,
    correct: impl FnMut(f64, &[f64]) -> Result<Vec<f64>, BvpError>,
) -> ContinuationFailure<BvpError> {
    cont(0.25, 0.01, 0.25)
        .follow(0.0, 1.0, vec![0.0], guard, correct)
        .unwrap_err()
}

#[test]
fn follow_fails_with_the_last_inner_error_or_the_jump() {
    // a corrector that fails beyond lambda = 0.5 with its own error
    let fail = failure_to_one(&BranchGuard::default(), |l, _p| {
        if l > 0.5 {
            Err(BvpError::NoConvergence {
                method: "inner",
                iterations: 7,
                residual: l,
            })
        } else {
            Ok(vec![l])
        }
    });
    assert_eq!(fail.reached, 0.5);
    assert!(fail.step < 0.02 && fail.step >= 0.01, "{}", fail.step);
    match fail.cause {
        StallCause::Inner(BvpError::NoConvergence {
            method: "inner",
            iterations: 7,
            residual,
        }) => assert!(residual > 0.5 && residual < 0.52, "{residual}"),
        other => panic!("{other:?}"),
    }
    // a corrector that lands on another branch (y jumps by 1 at lambda > 0.5)
    let guard = BranchGuard {
        absolute: 0.2,
        relative: 0.5,
        max_attempts: 1000,
    };
    let fail = failure_to_one(&guard, |l, _p| Ok(vec![if l > 0.5 { l + 1.0 } else { l }]));
    assert_eq!(fail.reached, 0.5);
    match fail.cause {
        StallCause::Jump { distance, .. } => assert!(distance > 0.9, "{distance}"),
        other => panic!("{other:?}"),
    }
    // the corrector budget (a guard wide enough to accept the first, unpredicted step)
    let guard = BranchGuard {
        absolute: 1.0,
        relative: 0.5,
        max_attempts: 3,
    };
    let fail = failure_to_one(&guard, |l, _p| Ok(vec![l]));
    assert_eq!(fail.cause, StallCause::Budget { max_attempts: 3 });
    assert_eq!(fail.steps, 3);
}
