//! Unit tests of the arclength driver, the predictors and `locate`.

use super::*;

/// The ellipse `(x/a)^2 + (y/b)^2 = 1` corrected by Newton on the bordered 2x2 system;
/// counts corrector calls.
struct Ellipse {
    a: f64,
    b: f64,
    calls: std::cell::Cell<usize>,
}

impl Curve<2> for Ellipse {
    type Point = [f64; 2];
    type Error = &'static str;
    fn coords(&self, p: &[f64; 2]) -> [f64; 2] {
        *p
    }
    fn correct(
        &self,
        _from: &[f64; 2],
        p: [f64; 2],
        n: [f64; 2],
        radius: f64,
    ) -> Result<[f64; 2], &'static str> {
        self.calls.set(self.calls.get() + 1);
        let (a2, b2) = (self.a * self.a, self.b * self.b);
        let mut u = p;
        for _ in 0..30 {
            let r0 = u[0] * u[0] / a2 + u[1] * u[1] / b2 - 1.0;
            let r1 = n[0] * (u[0] - p[0]) + n[1] * (u[1] - p[1]);
            if r0.abs() < 1e-15 && r1.abs() < 1e-15 {
                break;
            }
            let (j00, j01, j10, j11) = (2.0 * u[0] / a2, 2.0 * u[1] / b2, n[0], n[1]);
            let det = j00 * j11 - j01 * j10;
            if det.abs() < 1e-300 {
                return Err("singular");
            }
            u[0] -= (j11 * r0 - j01 * r1) / det;
            u[1] -= (j00 * r1 - j10 * r0) / det;
            if (u[0] - p[0]).hypot(u[1] - p[1]) > radius {
                return Err("left the radius");
            }
        }
        Ok(u)
    }
    fn tangent(&self, p: &[f64; 2], dir: &[f64; 2]) -> [f64; 2] {
        let g = [p[0] / (self.a * self.a), p[1] / (self.b * self.b)];
        let n = g[0].hypot(g[1]);
        let t = [-g[1] / n, g[0] / n];
        if t[0] * dir[0] + t[1] * dir[1] < 0.0 {
            [-t[0], -t[1]]
        } else {
            t
        }
    }
    fn iterations(&self, _p: &[f64; 2]) -> usize {
        3
    }
}

/// The Hermite predictor's error on the unit circle falls like `h^4` (16x per halving),
/// the tangent predictor's like `h^2` (4x).
#[test]
fn the_hermite_predictor_is_fourth_order() {
    let circle = Ellipse {
        a: 1.0,
        b: 1.0,
        calls: std::cell::Cell::new(0),
    };
    let miss = |predictor: Predictor, d: f64| {
        let ctl = ArcControl {
            predictor,
            ..ArcControl::default()
        };
        let start = [(-d).cos(), (-d).sin()];
        let mut arc = Arclength::new(&circle, start, [0.0, 1.0], ctl);
        let t = circle.tangent(&[1.0, 0.0], &[0.0, 1.0]);
        arc.accept(&circle, [1.0, 0.0], t);
        let p = arc.predict(d);
        (p[0] - d.cos()).hypot(p[1] - d.sin())
    };
    for predictor in [Predictor::Hermite, Predictor::Tangent] {
        let (e1, e2) = (miss(predictor, 0.2), miss(predictor, 0.1));
        let order = (e1 / e2).log2();
        let want = if predictor == Predictor::Hermite {
            4.0
        } else {
            2.0
        };
        assert!((order - want).abs() < 0.3, "{predictor:?}: order {order}");
    }
    // and over 50x the better one at a step of 0.2 (measured 75x)
    let (h, t) = (miss(Predictor::Hermite, 0.2), miss(Predictor::Tangent, 0.2));
    assert!(h < 0.02 * t, "hermite {h:e}, tangent {t:e}");
}

fn ellipse() -> Ellipse {
    Ellipse {
        a: 2.0,
        b: 0.5,
        calls: std::cell::Cell::new(0),
    }
}

/// Traces the ellipse once around from (a, 0): every accepted point lies on it, the
/// trace passes the folds of x (at y = 0) and of y (at x = 0), and the sum of its chords
/// agrees with the perimeter (Gauss-Kummer series) to the chords' shortfall plus the
/// last step's overshoot.
#[test]
fn traces_an_ellipse_through_its_folds() {
    let curve = ellipse();
    let ctl = ArcControl {
        initial: 0.05,
        max: 0.05,
        ..ArcControl::default()
    };
    let mut arc = Arclength::new(&curve, [2.0, 0.0], [0.0, 1.0], ctl);
    let (mut length, mut x_turns, mut y_turns) = (0.0, 0, 0);
    let mut last = [2.0, 0.0];
    for _ in 0..10_000 {
        let Attempt::Point(p, t) = arc.attempt(&curve) else {
            continue;
        };
        let on = p[0] * p[0] / 4.0 + p[1] * p[1] / 0.25 - 1.0;
        assert!(on.abs() < 1e-13, "off the ellipse by {on:e}");
        x_turns += usize::from((last[0] > 0.0) != (p[0] > 0.0));
        let closed = last[1] < 0.0 && p[1] >= 0.0;
        y_turns += usize::from(closed || (last[1] > 0.0 && p[1] <= 0.0));
        length += (p[0] - last[0]).hypot(p[1] - last[1]);
        last = p;
        arc.accept(&curve, p, t);
        if closed {
            break;
        }
    }
    assert_eq!((x_turns, y_turns), (2, 2));
    // the perimeter, 4 a E(e) with e^2 = 1 - (b/a)^2, by Gauss-Kummer
    let h = ((2.0 - 0.5) / (2.0 + 0.5f64)).powi(2);
    let mut series = 1.0;
    let mut c = 1.0;
    for k in 1..30 {
        // binomial(1/2, k)^2 h^k
        c *= (0.5 - (k as f64 - 1.0)) / k as f64;
        series += c * c * h.powi(k);
    }
    let perimeter = std::f64::consts::PI * 2.5 * series;
    // the chords fall short of the arc by ~h^2 kappa^2/24 per unit length; the last
    // step overshoots the start by at most one step
    let over = length - perimeter;
    assert!(
        over > -1e-3 && over < 0.05 + 1e-3,
        "{length} vs {perimeter}"
    );
}

/// Events located on the curve: the crossing of y = 0 past the fold of x at (-a, 0) and
/// the earliest of two events (x = 1 before x = 0 going left from the top).
#[test]
fn locates_events_exactly_and_keeps_the_earliest() {
    let curve = ellipse();
    let y = |q: &[f64; 2]| Ok::<f64, &'static str>(q[1]);
    let at = locate(
        &curve,
        &[-1.9, 0.5 * (1.0 - 0.9025f64).sqrt()],
        &[-1.9, -0.5 * (1.0 - 0.9025f64).sqrt()],
        &y,
        1e-14,
    )
    .unwrap();
    assert!((at[0] + 2.0).abs() < 1e-12 && at[1].abs() < 1e-12, "{at:?}");

    let top = [1.5, 0.5 * (1.0 - 0.5625f64).sqrt()];
    let arc = Arclength::new(&curve, top, [-1.0, 0.0], ArcControl::default());
    let left = [-1.5, top[1]];
    type G = Box<dyn Fn(&[f64; 2]) -> Result<f64, &'static str>>;
    let events: Vec<(char, G)> = vec![
        ('0', Box::new(|q: &[f64; 2]| Ok(q[0]))),
        ('1', Box::new(|q: &[f64; 2]| Ok(q[0] - 1.0))),
    ];
    let (key, p) = arc
        .earliest(&curve, &left, &events, 1e-13)
        .unwrap()
        .unwrap();
    assert_eq!(key, '1');
    assert!((p[0] - 1.0).abs() < 1e-12);
    assert!((p[0] * p[0] / 4.0 + p[1] * p[1] / 0.25 - 1.0).abs() < 1e-13);
}

/// The step grows after easy corrections up to the largest, is halved when the
/// corrector fails, and a failure below the smallest step gives the corrector's error.
#[test]
fn the_step_adapts_and_a_failure_below_the_smallest_step_is_reported() {
    let curve = ellipse();
    let ctl = ArcControl {
        initial: 0.01,
        max: 0.04,
        min: 1e-3,
        ..ArcControl::default()
    };
    let mut arc = Arclength::new(&curve, [2.0, 0.0], [0.0, 1.0], ctl);
    let mut steps = Vec::new();
    for _ in 0..6 {
        if let Attempt::Point(p, t) = arc.attempt(&curve) {
            arc.accept(&curve, p, t);
            steps.push(arc.step());
        }
    }
    assert!((steps[0] - 0.016).abs() < 1e-15, "{steps:?}");
    assert_eq!(*steps.last().unwrap(), 0.04);
    // a corrector that always fails: halvings until below min, then its error
    struct Never;
    impl Curve<2> for Never {
        type Point = [f64; 2];
        type Error = &'static str;
        fn coords(&self, p: &[f64; 2]) -> [f64; 2] {
            *p
        }
        fn correct(
            &self,
            _from: &[f64; 2],
            _p: [f64; 2],
            _n: [f64; 2],
            _r: f64,
        ) -> Result<[f64; 2], &'static str> {
            Err("never")
        }
        fn tangent(&self, _p: &[f64; 2], _d: &[f64; 2]) -> [f64; 2] {
            [1.0, 0.0]
        }
        fn iterations(&self, _p: &[f64; 2]) -> usize {
            1
        }
    }
    let mut arc = Arclength::new(&Never, [0.0, 0.0], [1.0, 0.0], ctl);
    let mut retries = 0;
    let err = loop {
        match arc.attempt(&Never) {
            Attempt::Retry => retries += 1,
            Attempt::Failed(e) => break e,
            Attempt::Point(..) => unreachable!(),
        }
    };
    // 0.01 -> 0.005 -> 0.0025 -> 0.00125 -> 0.000625 < 1e-3
    assert_eq!((retries, err), (3, "never"));
    assert!(curve.calls.get() > 0);
}
