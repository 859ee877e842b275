//! Obstacle contours: the region `y > g(x)` above a strictly convex, C^2 curve.
//!
//! Each profile gives `g`, `g'`, `g''`, the contour angle `psi = atan g'(x)` and the
//! curvature `g'' / (1 + g'^2)^(3/2)` (thesis ch. 5.1; contours [5.2, 5.3, 5.11]).

use crate::error::{ContactError, Result};
use bvp_solvers::roots::{bisect, brent, grow_brackets, Growth, RootOptions};
use bvp_solvers::BvpError;
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;

/// A contour point with the derivatives of its coordinates and angle along the contour
/// parameter `t` ([`Profile::at`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContourGeom {
    /// x of the point.
    pub x: f64,
    /// y of the point.
    pub y: f64,
    /// Contour angle psi (tangent direction `(cos psi, sin psi)`).
    pub psi: f64,
    /// dx/dt.
    pub dx: f64,
    /// dy/dt.
    pub dy: f64,
    /// dpsi/dt.
    pub dpsi: f64,
}

/// A convex contour.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Profile {
    /// `y = a (x - xv)^2 + yv`, a > 0.
    Parabola {
        /// Curvature coefficient a > 0.
        a: f64,
        /// Vertex x.
        xv: f64,
        /// Vertex y.
        yv: f64,
    },
    /// `y = a cosh((x - xv)/c) + d`, a, c > 0.
    Cosh {
        /// Amplitude a > 0.
        a: f64,
        /// Length scale c > 0.
        c: f64,
        /// Vertex x.
        xv: f64,
        /// Offset d.
        d: f64,
    },
    /// The lower arc of a circle: `y = yc - sqrt(r^2 - (x - xc)^2)`.
    Circle {
        /// Centre x.
        xc: f64,
        /// Centre y.
        yc: f64,
        /// Radius r > 0.
        r: f64,
    },
    /// A tabulated contour, interpolated by a not-a-knot cubic spline (C^2).
    Points(Spline),
    /// A point obstacle, such as a thin pole (spec/model.md, "Obstacles beyond graphs"):
    /// touched anywhere along the whisker with the force normal to it (phase B, `m(s1) = 0`
    /// beyond it, its contour angle `psi = t` the whisker's own at the contact); the tip
    /// sliding past it releases it ([`crate::sweep::Separation::TipPassed`]).
    Peg {
        /// x of the point.
        x: f64,
        /// y of the point.
        y: f64,
    },
    /// A full circle, touched from any side: tip contact along the circle's normal, or
    /// tangential contact. Parametrised like [`Profile::Circle`] by the polar angle from
    /// its lowest point, `(x + r sin t, y - r cos t)`, contour angle `t`, over all `t`.
    Disc {
        /// Centre x.
        x: f64,
        /// Centre y.
        y: f64,
        /// Radius r > 0.
        r: f64,
    },
}

/// A natural cubic spline through `(x_i, y_i)`, x strictly increasing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spline {
    x: Vec<f64>,
    y: Vec<f64>,
    /// Second derivatives at the knots.
    m: Vec<f64>,
}

impl Spline {
    /// Builds the not-a-knot cubic spline (C^2; g'' linear between knots); needs at least 3
    /// points with strictly increasing x.
    pub fn new(x: Vec<f64>, y: Vec<f64>) -> Result<Self> {
        let bad = |reason: String| ContactError::ProfileSpec {
            spec: "points".into(),
            reason,
        };
        if x.len() != y.len() || x.len() < 3 {
            return Err(bad(format!(
                "need at least 3 (x, y) points, got {} x and {} y",
                x.len(),
                y.len()
            )));
        }
        // finiteness first: a NaN in x is named as such, not as x failing to increase
        for (name, values) in [("x", &x), ("y", &y)] {
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(bad(format!(
                    "{name}[{i}] = {} (point {} of {}, 0-based index {i}): every coordinate \
                     must be a finite number",
                    values[i],
                    i + 1,
                    values.len()
                )));
            }
        }
        for (i, w) in x.windows(2).enumerate() {
            if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater) {
                return Err(bad(format!(
                    "x must increase strictly: x[{}] = {} after x[{i}] = {} (point {})",
                    i + 1,
                    w[1],
                    w[0],
                    i + 2
                )));
            }
        }
        let n = x.len();
        let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
        let slope: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
        if n == 3 {
            // not-a-knot through three points: the parabola, g'' constant
            let m2 = 2.0 * (slope[1] - slope[0]) / (x[2] - x[0]);
            return Ok(Spline {
                x,
                y,
                m: vec![m2; 3],
            });
        }
        // Not-a-knot end conditions (the third derivative continuous at the second and the
        // last but one knot): a convex table gives a convex spline up to its ends, where a
        // natural spline would force g'' = 0. The end values m_0, m_{n-1} are eliminated from
        // the first and last rows, leaving a tridiagonal system for m_1 .. m_{n-2}.
        let k = n - 2;
        let mut tri = bvp_solvers::tridiag::Tridiagonal::new(k);
        let mut rhs = vec![0.0; k];
        for (j, rhs_j) in rhs.iter_mut().enumerate() {
            let i = j + 1;
            let (h0, h1) = (h[i - 1], h[i]);
            let (mut lo, mut d, mut up) = (h0 / 6.0, (h0 + h1) / 3.0, h1 / 6.0);
            if i == 1 {
                // m_0 = (1 + h0/h1) m_1 - (h0/h1) m_2
                d += lo * (1.0 + h0 / h1);
                up -= lo * h0 / h1;
                lo = 0.0;
            }
            if i == n - 2 {
                // m_{n-1} = (1 + h1/h0) m_{n-2} - (h1/h0) m_{n-3}
                d += up * (1.0 + h1 / h0);
                lo -= up * h1 / h0;
                up = 0.0;
            }
            tri.lower[j] = lo;
            tri.diag[j] = d;
            tri.upper[j] = up;
            *rhs_j = slope[i] - slope[i - 1];
        }
        let inner = tri.solve(&rhs)?;
        let mut m = vec![0.0; n];
        m[1..n - 1].copy_from_slice(&inner);
        m[0] = (1.0 + h[0] / h[1]) * m[1] - h[0] / h[1] * m[2];
        m[n - 1] = (1.0 + h[n - 2] / h[n - 3]) * m[n - 2] - h[n - 2] / h[n - 3] * m[n - 3];
        Ok(Spline { x, y, m })
    }

    fn interval(&self, x: f64) -> usize {
        let n = self.x.len();
        match self.x.binary_search_by(|v| v.total_cmp(&x)) {
            Ok(i) => i.min(n - 2),
            Err(i) => i.clamp(1, n - 1) - 1,
        }
    }

    /// Value and first two derivatives at x (cubic extrapolation outside the knots).
    pub fn eval(&self, x: f64) -> (f64, f64, f64) {
        let i = self.interval(x);
        let (x0, x1) = (self.x[i], self.x[i + 1]);
        let h = x1 - x0;
        let (a, b) = ((x1 - x) / h, (x - x0) / h);
        let (m0, m1) = (self.m[i], self.m[i + 1]);
        let (y0, y1) = (self.y[i], self.y[i + 1]);
        let v = a * y0 + b * y1 + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
        let d =
            (y1 - y0) / h - (3.0 * a * a - 1.0) * h * m0 / 6.0 + (3.0 * b * b - 1.0) * h * m1 / 6.0;
        let dd = a * m0 + b * m1;
        (v, d, dd)
    }

    /// The tabulated x range.
    pub fn range(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }
}

impl Profile {
    /// Whether `spec` names one of the thesis's contours (`g1`, `g2`, `ge`), which are in
    /// whisker lengths whatever the unit system of the scene.
    pub fn is_named(spec: &str) -> bool {
        matches!(spec.trim(), "g1" | "g2" | "ge")
    }

    /// Thesis contour g1 (catenary, [5.2]): `y = cosh(x/2) - 4/5`.
    pub fn g1() -> Self {
        Profile::Cosh {
            a: 1.0,
            c: 2.0,
            xv: 0.0,
            d: -0.8,
        }
    }

    /// Thesis contour g2 (parabola, [5.3]; exponent reading of spec/model.md): `y = 1/2 + x^2/2`.
    pub fn g2() -> Self {
        Profile::Parabola {
            a: 0.5,
            xv: 0.0,
            yv: 0.5,
        }
    }

    /// Thesis contour ge (experiment, [5.11]): `y = 2 (x + 5 sqrt(858)/312)^2 + 349/624`,
    /// through the undeformed tip (0, 1).
    pub fn ge() -> Self {
        Profile::Parabola {
            a: 2.0,
            xv: -(5.0 / 312.0) * 858f64.sqrt(),
            yv: 349.0 / 624.0,
        }
    }

    /// Parses a CLI profile spec: `g1`, `g2`, `ge`, `parabola:a,xv,yv`, `cosh:a,c,xv,d`,
    /// `circle:xc,yc,r`. Tabulated contours (`points:FILE`) are read by the caller and built
    /// with [`Profile::points`].
    pub fn parse(spec: &str) -> Result<Self> {
        let bad = |reason: &str| ContactError::ProfileSpec {
            spec: spec.to_string(),
            reason: reason.to_string(),
        };
        let (kind, args) = match spec.split_once(':') {
            Some((k, a)) => (k.trim(), Some(a)),
            None => (spec.trim(), None),
        };
        let nums = |n: usize| -> Result<Vec<f64>> {
            let a =
                args.ok_or_else(|| bad(&format!("{kind} needs {n} comma-separated numbers")))?;
            let v: Vec<f64> = a
                .split(',')
                .map(|t| t.trim().parse::<f64>())
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| bad(&format!("{kind} needs {n} comma-separated numbers")))?;
            if v.len() != n {
                return Err(bad(&format!("{kind} needs {n} numbers, got {}", v.len())));
            }
            if v.iter().any(|x| !x.is_finite()) {
                return Err(bad("parameters must be finite"));
            }
            Ok(v)
        };
        let p = match kind {
            "g1" if args.is_none() => Profile::g1(),
            "g2" if args.is_none() => Profile::g2(),
            "ge" if args.is_none() => Profile::ge(),
            "parabola" => {
                let v = nums(3)?;
                Profile::Parabola { a: v[0], xv: v[1], yv: v[2] }
            }
            "cosh" => {
                let v = nums(4)?;
                Profile::Cosh { a: v[0], c: v[1], xv: v[2], d: v[3] }
            }
            "circle" => {
                let v = nums(3)?;
                Profile::Circle { xc: v[0], yc: v[1], r: v[2] }
            }
            "peg" => {
                let v = nums(2)?;
                Profile::Peg { x: v[0], y: v[1] }
            }
            "disc" => {
                let v = nums(3)?;
                Profile::Disc { x: v[0], y: v[1], r: v[2] }
            }
            "points" => return Err(bad("tabulated profiles are read from a CSV file (points:FILE.csv)")),
            _ => return Err(bad("unknown profile: expected g1, g2, ge, parabola:a,xv,yv, cosh:a,c,xv,d, circle:xc,yc,r, peg:x,y, disc:x,y,r or points:FILE.csv")),
        };
        p.validate_parameters().map_err(bad)?;
        Ok(p)
    }

    /// A tabulated contour through the given points.
    pub fn points(x: Vec<f64>, y: Vec<f64>) -> Result<Self> {
        Ok(Profile::Points(Spline::new(x, y)?))
    }

    fn validate_parameters(&self) -> std::result::Result<(), &'static str> {
        match *self {
            Profile::Parabola { a, .. } if a <= 0.0 => {
                Err("a parabola needs a > 0 to be convex (obstacle above it)")
            }
            Profile::Cosh { a, c, .. } if a <= 0.0 || c <= 0.0 => {
                Err("cosh needs a > 0 and c > 0 to be convex")
            }
            Profile::Circle { r, .. } if r <= 0.0 => Err("a circle needs r > 0"),
            Profile::Disc { r, .. } if r <= 0.0 => {
                Err("a disc needs r > 0 (a point obstacle is peg:x,y)")
            }
            _ => Ok(()),
        }
    }

    /// A short name for messages.
    pub fn name(&self) -> String {
        match self {
            p if *p == Profile::g1() => "g1".into(),
            p if *p == Profile::g2() => "g2".into(),
            p if *p == Profile::ge() => "ge".into(),
            Profile::Parabola { a, xv, yv } => format!("parabola:{a},{xv},{yv}"),
            Profile::Cosh { a, c, xv, d } => format!("cosh:{a},{c},{xv},{d}"),
            Profile::Circle { xc, yc, r } => format!("circle:{xc},{yc},{r}"),
            Profile::Points(s) => format!("points({} knots)", s.x.len()),
            Profile::Peg { x, y } => format!("peg:{x},{y}"),
            Profile::Disc { x, y, r } => format!("disc:{x},{y},{r}"),
        }
    }

    /// `(g, g', g'')` at x. Outside a circle's span the values are NaN.
    pub fn eval(&self, x: f64) -> (f64, f64, f64) {
        match *self {
            Profile::Parabola { a, xv, yv } => {
                let u = x - xv;
                (a * u * u + yv, 2.0 * a * u, 2.0 * a)
            }
            Profile::Cosh { a, c, xv, d } => {
                let u = (x - xv) / c;
                let ch = u.cosh();
                (a * ch + d, a / c * u.sinh(), a / (c * c) * ch)
            }
            Profile::Circle { xc, yc, r } | Profile::Disc { x: xc, y: yc, r } => {
                let u = x - xc;
                let w2 = r * r - u * u;
                if w2 <= 0.0 {
                    return (f64::NAN, f64::NAN, f64::NAN);
                }
                let w = w2.sqrt();
                (yc - w, u / w, r * r / (w2 * w))
            }
            Profile::Points(ref s) => s.eval(x),
            Profile::Peg { .. } => (f64::NAN, f64::NAN, f64::NAN),
        }
    }

    /// `g(x)` (the first of [`Profile::eval`], without the derivatives).
    pub fn y(&self, x: f64) -> f64 {
        match *self {
            Profile::Parabola { a, xv, yv } => {
                let u = x - xv;
                a * u * u + yv
            }
            Profile::Cosh { a, c, xv, d } => a * ((x - xv) / c).cosh() + d,
            Profile::Circle { xc, yc, r } | Profile::Disc { x: xc, y: yc, r } => {
                let u = x - xc;
                let w2 = r * r - u * u;
                if w2 <= 0.0 {
                    return f64::NAN;
                }
                yc - w2.sqrt()
            }
            Profile::Points(ref s) => s.eval(x).0,
            Profile::Peg { .. } => f64::NAN,
        }
    }

    /// Contour angle `psi = atan g'(x)` (measured from the x axis).
    pub fn psi(&self, x: f64) -> f64 {
        self.eval(x).1.atan()
    }

    /// Curvature `g'' / (1 + g'^2)^(3/2)`.
    pub fn curvature(&self, x: f64) -> f64 {
        let (_, d, dd) = self.eval(x);
        dd / (1.0 + d * d).powf(1.5)
    }

    /// The x where the contour is lowest (`g' = 0`), the vertex.
    pub fn vertex(&self) -> f64 {
        match *self {
            Profile::Parabola { xv, .. } | Profile::Cosh { xv, .. } => xv,
            Profile::Circle { xc, .. }
            | Profile::Disc { x: xc, .. }
            | Profile::Peg { x: xc, .. } => xc,
            Profile::Points(ref s) => {
                let (a, b) = s.range();
                // g' is increasing on a convex spline: bisection for g' = 0, clamped.
                if s.eval(a).1 >= 0.0 {
                    return a;
                }
                if s.eval(b).1 <= 0.0 {
                    return b;
                }
                bisect(|m| Some(s.eval(m).1 < 0.0), a, b, 200)
            }
        }
    }

    /// The x range where the contour is defined (infinite for closed forms).
    pub fn domain(&self) -> (f64, f64) {
        match *self {
            Profile::Circle { xc, r, .. } | Profile::Disc { x: xc, r, .. } => (xc - r, xc + r),
            Profile::Peg { x, .. } => (x, x),
            Profile::Points(ref s) => s.range(),
            _ => (f64::NEG_INFINITY, f64::INFINITY),
        }
    }

    /// The range of the contour parameter `t` ([`Profile::at`]): `x` itself for graphs
    /// (infinite for closed forms, the table's range for tabulated contours), the polar angle
    /// in `[-pi/2, pi/2]` for a circle's lower arc, vertical ends included.
    pub fn param_range(&self) -> (f64, f64) {
        match *self {
            Profile::Circle { .. } => (-FRAC_PI_2, FRAC_PI_2),
            Profile::Peg { .. } | Profile::Disc { .. } => (f64::NEG_INFINITY, f64::INFINITY),
            _ => self.domain(),
        }
    }

    /// The contour point at parameter `t` with the derivatives of its coordinates and of its
    /// angle with respect to `t`. Graphs use `t = x`: `(x, g, atan g')` with derivatives
    /// `(1, g', g''/(1 + g'^2))`; a circle uses its polar angle from the lowest point:
    /// `(xc + r sin t, yc - r cos t, t)`, smooth up to the vertical ends `t = +-pi/2`.
    pub fn at(&self, t: f64) -> ContourGeom {
        match *self {
            Profile::Circle { xc, yc, r } | Profile::Disc { x: xc, y: yc, r } => {
                let (s, c) = t.sin_cos();
                ContourGeom {
                    x: xc + r * s,
                    y: yc - r * c,
                    psi: t,
                    dx: r * c,
                    dy: r * s,
                    dpsi: 1.0,
                }
            }
            Profile::Peg { x, y } => ContourGeom {
                x,
                y,
                psi: t,
                dx: 0.0,
                dy: 0.0,
                dpsi: 1.0,
            },
            _ => {
                let (g, d, dd) = self.eval(t);
                ContourGeom {
                    x: t,
                    y: g,
                    psi: d.atan(),
                    dx: 1.0,
                    dy: d,
                    dpsi: dd / (1.0 + d * d),
                }
            }
        }
    }

    /// The height of the contour point at parameter `t` (`at(t).y`, without the rest).
    pub fn y_at(&self, t: f64) -> f64 {
        match *self {
            Profile::Circle { yc, r, .. } | Profile::Disc { y: yc, r, .. } => yc - r * t.cos(),
            Profile::Peg { y, .. } => y,
            _ => self.y(t),
        }
    }

    /// Whether the contour is strictly convex at parameter `t` (the turning rate of its
    /// tangent `dpsi/dt` is positive), with the second derivative `g''` for messages.
    pub fn convex_at(&self, t: f64) -> Result<()> {
        let geom = self.at(t);
        if geom.dpsi > 0.0 && geom.dpsi.is_finite() {
            return Ok(());
        }
        Err(ContactError::NotConvex {
            profile: self.name(),
            x: geom.x,
            g2: self.eval(geom.x).2,
        })
    }

    /// The parameter of the contour point right of the lowest point at height `y`, on the
    /// whole parameter range (a circle's arc up to its vertical end), searched first around
    /// `hint` (the answer for a nearby height): `None` below the lowest point or above the
    /// contour's range. The bracket grows from `hint` by steps of 1e-3, x4
    /// ([`bvp_solvers::roots::grow_brackets`]), to the first sign change of `y(t) - y`, so a
    /// sequence of close heights costs a few evaluations each instead of a search of the
    /// whole flank; a `hint` off the flank (or NaN) searches the whole flank (from the lowest
    /// point by steps of 1, 2, 4, ... up to 1e6 where the range is infinite). Brent's method
    /// to adjacent floats on the monotone right flank (bisection if it fails).
    pub fn param_right_near(&self, y: f64, hint: f64) -> Option<f64> {
        let (t_lo, t_hi) = self.param_range();
        let tv = match *self {
            Profile::Circle { .. } => 0.0,
            _ => self.vertex(),
        };
        if y.is_nan() || y < self.y_at(tv) {
            return None;
        }
        let lo = tv.max(t_lo);
        let hi = if t_hi.is_finite() {
            if self.y_at(t_hi) < y {
                return None;
            }
            t_hi
        } else {
            f64::INFINITY
        };
        let (a, b) = match self.bracket_near(y, hint, lo, hi) {
            Some(ab) => ab,
            None if hi.is_finite() => (lo, hi),
            None => {
                let below = |t: f64| Some(self.y_at(t) < y);
                let growth = Growth::within(1.0, 2.0, 1e6);
                let (_, b) = grow_brackets(below, tv, true, (tv, hi), growth).next()?;
                (lo, b)
            }
        };
        let opts = RootOptions {
            xtol: 0.0,
            ftol: 0.0,
            max_iter: 200,
        };
        let f = |m: f64| -> std::result::Result<f64, BvpError> { Ok(self.y_at(m) - y) };
        Some(match brent(f, a, b, &opts) {
            Ok(root) => root.x,
            Err(_) => bisect(|m| Some(self.y_at(m) < y), a, b, 200),
        })
    }

    /// A bracket `[a, b]` within `[lo, hi]` of the height `y` on the rising right flank,
    /// grown from `hint` towards `y` (see [`Profile::param_right_near`]); `None` if `hint` is
    /// not in `[lo, hi]` or 30 growths do not bracket it.
    fn bracket_near(&self, y: f64, hint: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
        if !(hint >= lo && hint <= hi) {
            return None;
        }
        let below = self.y_at(hint) < y;
        // one side only: up the flank from below the height, down it from above
        let span = if below { (hint, hi) } else { (lo, hint) };
        let growth = Growth {
            first: 1e-3,
            factor: 4.0,
            steps: 30,
            chained: true,
        };
        grow_brackets(|t| Some(self.y_at(t) < y), hint, below, span, growth).next()
    }

    /// Whether the obstacle is a point ([`Profile::Peg`]).
    pub fn is_peg(&self) -> bool {
        matches!(self, Profile::Peg { .. })
    }

    /// Whether the obstacle is not the region above a graph (a peg or a disc): its first
    /// touch is found by [`Profile::clearance`] along the motion, not on a right flank.
    pub fn is_closed(&self) -> bool {
        matches!(self, Profile::Peg { .. } | Profile::Disc { .. })
    }

    /// The curvature of the contour at parameter `t`: [`Profile::curvature`] at its x for
    /// graphs, `1/r` for a disc, infinite for a peg (no whisker bends around a point more
    /// sharply than it).
    pub fn curvature_at(&self, t: f64) -> f64 {
        match *self {
            Profile::Peg { .. } => f64::INFINITY,
            Profile::Disc { r, .. } => 1.0 / r,
            _ => self.curvature(self.at(t).x),
        }
    }

    /// The signed clearance of the point `(x, y)` from the obstacle: positive outside,
    /// negative inside, zero on its boundary: `g(x) - y` below a graph (a circle's arc also
    /// `max`-ed with the distance outside its vertical sides, `|x - xc| - r`), the distance
    /// to the boundary for a disc, `|p - c| - r`; for a peg the distance to the point
    /// (never negative: a peg's touch is seen as a crossing, [`crate::first_contact`]).
    pub fn clearance(&self, x: f64, y: f64) -> f64 {
        match *self {
            Profile::Peg { x: px, y: py } => (x - px).hypot(y - py),
            Profile::Disc { x: cx, y: cy, r } => (x - cx).hypot(y - cy) - r,
            Profile::Circle { xc, r, .. } => {
                let side = (x - xc).abs() - r;
                if side >= 0.0 {
                    side
                } else {
                    (self.y(x) - y).max(side)
                }
            }
            _ => self.y(x) - y,
        }
    }

    /// Checks strict convexity where a whisker of unit length with its base on `y = 0` can
    /// touch the contour (heights up to 1): closed forms are convex by their parameters; a
    /// table's `g''` is linear between knots, so it is checked at every knot below that
    /// height and at the neighbours of such knots. Names the first knot where it fails.
    pub fn check_reachable_convex(&self) -> Result<()> {
        let Profile::Points(ref s) = *self else {
            return Ok(());
        };
        let n = s.x.len();
        for i in 0..n {
            let near = (i.saturating_sub(1)..(i + 2).min(n)).any(|j| s.y[j] <= 1.0);
            if near && (s.m[i].is_nan() || s.m[i] <= 0.0) {
                return Err(ContactError::NotConvex {
                    profile: self.name(),
                    x: s.x[i],
                    g2: s.m[i],
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The height alone (`y`, `y_at`) is bit for bit the height of the full evaluation
    /// (`eval`, `at`), for every kind of contour, inside and outside a circle's span; and the
    /// inverse on the right flank (Brent) returns the parameter of that height.
    #[test]
    fn heights_alone_match_the_full_evaluation() {
        let table: Vec<f64> = (0..=20).map(|j| -2.0 + 0.2 * j as f64).collect();
        let ys = table.iter().map(|x| 0.5 * x * x + 0.3).collect();
        let profiles = [
            Profile::g1(),
            Profile::g2(),
            Profile::parse("circle:0.2,1.1,0.6").unwrap(),
            Profile::points(table, ys).unwrap(),
        ];
        for p in &profiles {
            for k in 0..=40 {
                let x = -1.5 + 0.075 * k as f64;
                let (a, b) = (p.y(x), p.eval(x).0);
                assert!(
                    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                    "{}",
                    p.name()
                );
                assert_eq!(
                    p.y_at(0.01 * k as f64).to_bits(),
                    p.at(0.01 * k as f64).y.to_bits()
                );
            }
            let y = p.y_at(p.vertex()) + 0.3;
            let t = p.param_right_near(y, f64::NAN).unwrap();
            assert!(
                (p.y_at(t) - y).abs() <= 1e-14,
                "{}: {}",
                p.name(),
                p.y_at(t) - y
            );
        }
    }
}
