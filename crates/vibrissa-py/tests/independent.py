"""An independent checker of the `vibrissa` CLI's sweeps and reconstructions.

Written from the specs alone (spec/model.md, spec/cli.md, thesis ch. 3 and 5), not from the
Rust sources: every contact row of `observables.csv` is re-integrated by scipy from the
row's own logged base observables, and the model's conditions are checked on that curve.

The elastica (model.md, "Equations" and "Friction at the contact"), integrated from the
base s = 0 with the row's pose (x0, y0), base angle phi0 and moment m(0) = -MA:

    x' = cos phi,  y' = sin phi,  phi' = m / e(s)^4 + A s + B,  e(s) = 1 + (theta - 1) s,
    m' = Px sin phi - Py cos phi,

where P(s) is the force the distal part exerts on [0, s]: the balance of [0, s] with the
support's reactions (Ax, Ay) and the flow q (cos alpha, -sin alpha) per unit length gives

    P(s) = (-Ax - q s cos alpha, -Ay + q s sin alpha)      for s < s1,
    P(s) = 0                                               for s > s1 (nothing beyond),

so the contact force is the jump F = P(s1-) (thesis [3.20]; its moment form m' = f sin(phi +
beta) + q (s1 - s) sin(phi + alpha) is this with F = f (cos beta, -sin beta)). The follicle
law [3.21, 3.22] with the pose turn gamma: phi0 = pi/2 + gamma - MA / k (rigid: k = inf).

Obstacles: a graph y > g(x) (g1, g2, ge, parabola, cosh, points), the lower arc of a circle
(the region above it within the circle's width), a disc, a peg. The penetration of the
whole whisker is BOUNDED: the clearance c(s) (vertical gap g(x) - y for graphs, signed
distance for circles and discs) is Lipschitz in s with constant L = sqrt(1 + max |g'|^2)
on the interval's x-range (|r'| = 1; g' monotone since g is convex), so on [a, b]

    min c >= (c(a) + c(b)) / 2 - L (b - a) / 2,

and intervals whose bound is below the tolerance are bisected until the bound clears it or
a sampled point is itself deeper (a proven violation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

HALF_PI = 0.5 * math.pi


# ---------------------------------------------------------------------------------------
# Obstacles, from spec/cli.md "Profiles" and spec/model.md "Test contours"
# ---------------------------------------------------------------------------------------
class Graph:
    """The region y > g(x), g strictly convex: clearance = g(x) - y (vertical gap)."""

    kind = "graph"

    def __init__(self, g, dg, lo=-math.inf, hi=math.inf):
        self.g, self.dg, self.lo, self.hi = g, dg, lo, hi

    def clearance(self, x, y):
        return self.g(x) - y

    def lipschitz(self, xa, xb):
        """Bound of |d clearance / ds| for x in [xa, xb] (g' monotone: its ends)."""
        m = np.maximum(np.abs(self.dg(xa)), np.abs(self.dg(xb)))
        return np.sqrt(1.0 + m * m)

    def second(self, xa, xb, cmin):
        """Bound of |g''| for x in [xa, xb] (g'' of the presets is monotone or convex on
        each interval: its ends, by a difference of g')."""
        d = 1e-4
        return np.maximum(np.abs(self.dg(xa + d) - self.dg(xa - d)), np.abs(self.dg(xb + d) - self.dg(xb - d))) / (2 * d) * (1 + 1e-6)

    def on_contour(self, xc, yc):
        """Distance-like residual of (xc, yc) from the contour (the gap over its slope)."""
        return (yc - self.g(xc)) / math.sqrt(1.0 + self.dg(xc) ** 2)

    def psi(self, xc, yc):
        return math.atan(self.dg(xc))

    def outward(self, xc, yc):
        p = self.psi(xc, yc)
        return np.array([math.sin(p), -math.cos(p)])


def parabola(a, xv, yv):
    return Graph(lambda x: a * (x - xv) ** 2 + yv, lambda x: 2 * a * (x - xv))


def cosh_profile(a, c, xv, d):
    return Graph(lambda x: a * np.cosh((x - xv) / c) + d, lambda x: a / c * np.sinh((x - xv) / c))


class Circle:
    """`circle:xc,yc,r`: the region above the lower arc y = yc - sqrt(r^2 - (x - xc)^2) within
    |x - xc| <= r (convex: the lower half disc and the strip above it). Clearance: the signed
    distance to that set (1-Lipschitz)."""

    kind = "circle"

    def __init__(self, xc, yc, r):
        self.c, self.r = np.array([xc, yc]), r

    def clearance(self, x, y):
        dx, dy = x - self.c[0], y - self.c[1]
        return np.where(dy <= 0, np.hypot(dx, dy) - self.r, np.abs(dx) - self.r)

    def lipschitz(self, xa, xb):
        return np.ones_like(np.asarray(xa, dtype=float))

    def second(self, xa, xb, cmin):
        """Bound of the distance function's curvature 1 / rho off the circle (rho >= r +
        the clearance's lower bound), beside the whisker's own curvature."""
        return 1.0 / np.maximum(self.r + cmin, 1e-3 * self.r)

    def on_contour(self, xc, yc):
        return math.hypot(xc - self.c[0], yc - self.c[1]) - self.r

    def outward(self, xc, yc):
        v = np.array([xc, yc]) - self.c
        return v / np.linalg.norm(v)

    def psi(self, xc, yc):
        n = self.outward(xc, yc)
        return math.atan2(n[0], -n[1])


class Disc(Circle):
    """`disc:x,y,r`: a full circle, clearance the signed distance |p - c| - r."""

    kind = "disc"

    def clearance(self, x, y):
        return np.hypot(x - self.c[0], y - self.c[1]) - self.r


class Peg:
    """`peg:x,y`: a point. Frictionless force normal to the whisker; no penetration measure
    (a curve misses a point but for a set of measure zero)."""

    kind = "peg"

    def __init__(self, x, y):
        self.c = np.array([x, y])

    def on_contour(self, xc, yc):
        return math.hypot(xc - self.c[0], yc - self.c[1])


def parse_profile(spec: str, table=None):
    """The obstacle a CLI profile string names (spec/cli.md); `points:` takes the analytic
    function `table` the file was tabulated from."""
    if spec == "g1":
        return cosh_profile(1.0, 2.0, 0.0, -0.8)
    if spec == "g2":
        return parabola(0.5, 0.0, 0.5)
    if spec == "ge":
        return parabola(2.0, -(5.0 / 312.0) * math.sqrt(858.0), 349.0 / 624.0)
    kind, _, rest = spec.partition(":")
    if kind == "points":
        return table
    v = [float(t) for t in rest.split(",")]
    return {
        "parabola": lambda: parabola(*v),
        "cosh": lambda: cosh_profile(*v),
        "circle": lambda: Circle(*v),
        "disc": lambda: Disc(*v),
        "peg": lambda: Peg(*v),
    }[kind]()


# ---------------------------------------------------------------------------------------
# The elastica from the base
# ---------------------------------------------------------------------------------------
@dataclass
class Whisker:
    theta: float = 1.0
    a: float = 0.0
    b: float = 0.0
    k: float = math.inf
    q: float = 0.0
    alpha: float = 0.0  # radians


@dataclass
class Curve:
    """The re-integrated whisker: dense pieces [(s_start, s_end, OdeSolution)]."""

    pieces: list = field(default_factory=list)
    steps: list = field(default_factory=list)

    def at(self, s):
        s = np.atleast_1d(np.asarray(s, dtype=float))
        out = np.empty((4, s.size))
        for lo, hi, sol in self.pieces:
            sel = (s >= lo) & (s <= hi)
            if sel.any():
                out[:, sel] = sol(s[sel])
        return out


def integrate(w: Whisker, x0, y0, phi0, ma, ax, ay, s1, rtol=1e-12):
    """Integrate from the base through s1 (loaded) and on to the tip (unloaded: P = 0)."""
    ca, sa = math.cos(w.alpha), math.sin(w.alpha)

    def loaded(s, u):
        e = 1.0 + (w.theta - 1.0) * s
        px = -ax - w.q * s * ca
        py = -ay + w.q * s * sa
        c, sn = math.cos(u[2]), math.sin(u[2])
        return [c, sn, u[3] / e**4 + w.a * s + w.b, px * sn - py * c]

    def free(s, u):
        e = 1.0 + (w.theta - 1.0) * s
        return [math.cos(u[2]), math.sin(u[2]), u[3] / e**4 + w.a * s + w.b, 0.0]

    curve = Curve()
    u0 = [x0, y0, phi0, -ma]
    r1 = solve_ivp(loaded, (0.0, s1), u0, method="DOP853", rtol=rtol, atol=rtol, dense_output=True)
    if not r1.success:
        raise RuntimeError(r1.message)
    curve.pieces.append((0.0, s1, r1.sol))
    curve.steps.append(r1.t)
    end = r1.y[:, -1].copy()
    if s1 < 1.0:
        r2 = solve_ivp(free, (s1, 1.0), end, method="DOP853", rtol=rtol, atol=rtol, dense_output=True)
        if not r2.success:
            raise RuntimeError(r2.message)
        curve.pieces.append((s1, 1.0, r2.sol))
        curve.steps.append(r2.t)
    curve.contact = end
    curve.contact_force = np.array([-ax - w.q * s1 * ca, -ay + w.q * s1 * sa])
    return curve


def min_clearance(curve: Curve, w: "Whisker", obstacle, tol, per_step=6, max_levels=60):
    """(lower bound of min_s clearance, the deepest sampled clearance, its s).

    On an interval [a, b] of length h the clearance c(s) is bounded below by two proven
    bounds, the larger taken: first order, (c(a) + c(b)) / 2 - L h / 2 with L >= |c'|;
    second order, min(c(a), c(b)) - M h^2 / 8 with M >= |c''|, where c'' involves the
    contour's curvature and the whisker's, |kappa| <= max(|kappa(a)|, |kappa(b)|) + K h with
    K >= |kappa'| = |m' / e^4 - 4 (theta - 1) m / e^5 + A| over the whole whisker (|m'| <=
    |P|, the largest shear). Intervals whose bound is below -tol / 1000 and more than tol /
    1000 below their own ends are bisected (so the bound reported is the penetration's, not
    the tolerance's); the search stops with a violation as soon as a sampled point is
    deeper than -tol."""
    report = tol * 1e-3
    knots = []
    for ts in curve.steps:
        ts = np.asarray(ts)
        fine = [ts[:1]]
        for a, b in zip(ts[:-1], ts[1:]):
            fine.append(np.linspace(a, b, per_step + 1)[1:])
        knots.append(np.concatenate(fine))
    s = np.unique(np.concatenate(knots))
    u = curve.at(s)
    c = obstacle.clearance(u[0], u[1])
    worst_sample = (float(c.min()), float(s[np.argmin(c)]))
    # the bound of kappa' over the whole whisker
    e_min = min(1.0, w.theta)
    p_max = float(np.hypot(*curve.contact_force)) + w.q
    m_max = float(np.abs(u[3]).max()) + p_max * float(np.diff(s).max())
    k_prime = p_max / e_min**4 + 4 * abs(w.theta - 1.0) * m_max / e_min**5 + abs(w.a)

    def kappa(ss, uu):
        return uu[3] / (1.0 + (w.theta - 1.0) * ss) ** 4 + w.a * ss + w.b

    k = np.abs(kappa(s, u))
    lo, hi, clo, chi, xlo, xhi, klo, khi = s[:-1], s[1:], c[:-1], c[1:], u[0][:-1], u[0][1:], k[:-1], k[1:]
    rho = obstacle.radius(u[0], u[1]) if hasattr(obstacle, "radius") else None
    bound = math.inf
    for _ in range(max_levels):
        h = hi - lo
        xa = np.minimum(xlo, xhi) - h / 2
        xb = np.maximum(xlo, xhi) + h / 2
        lip = obstacle.lipschitz(xa, xb)
        lb1 = 0.5 * (clo + chi) - 0.5 * lip * h
        kap = np.maximum(klo, khi) + k_prime * h
        m2 = obstacle.second(xa, xb, np.minimum(clo, chi) - h) + kap * lip
        lb2 = np.minimum(clo, chi) - m2 * h * h / 8
        lb = np.maximum(lb1, lb2)
        # settled: the bound clears -tol/1000, or lies within tol/1000 of a sampled point
        ok = (lb >= -report) | (lb >= np.minimum(clo, chi) - report)
        if ok.any():
            bound = min(bound, float(lb[ok].min()))
        bad = ~ok
        if not bad.any():
            break
        lo, hi, clo, chi, xlo, xhi, klo, khi = (v[bad] for v in (lo, hi, clo, chi, xlo, xhi, klo, khi))
        mid = 0.5 * (lo + hi)
        um = curve.at(mid)
        cm = obstacle.clearance(um[0], um[1])
        km = np.abs(kappa(mid, um))
        j = np.argmin(cm)
        if cm[j] < worst_sample[0]:
            worst_sample = (float(cm[j]), float(mid[j]))
        if worst_sample[0] < -tol:
            return worst_sample[0], worst_sample[0], worst_sample[1]
        lo, hi = np.concatenate([lo, mid]), np.concatenate([mid, hi])
        clo, chi = np.concatenate([clo, cm]), np.concatenate([cm, chi])
        xlo, xhi = np.concatenate([xlo, um[0]]), np.concatenate([um[0], xhi])
        klo, khi = np.concatenate([klo, km]), np.concatenate([km, khi])
    else:
        bound = min(bound, float(lb.min()))
    return min(bound, worst_sample[0]), worst_sample[0], worst_sample[1]


# ---------------------------------------------------------------------------------------
# Seeded random scenes over the space the CLI accepts
# ---------------------------------------------------------------------------------------
PROFILE_KINDS = ("g1", "g2", "ge", "parabola", "cosh", "circle", "points", "peg", "disc")
MOTIONS = ("translate", "rotate", "path")


def random_scene(rng: np.random.Generator, index: int, folder) -> dict:
    """One scene: whisker, flow, friction, obstacle and motion drawn over the whole space
    (flags of spec/cli.md), with the files `points:` and `path:` need written to `folder`."""
    sc = {"index": index}
    sc["theta"] = 1.0 if rng.random() < 0.15 else float(math.exp(rng.uniform(math.log(0.05), 0.0)))
    curl = rng.random()
    if curl < 0.2:
        sc["a"], sc["b"] = 0.0, 0.0
    elif curl < 0.85:
        sc["a"], sc["b"] = float(rng.uniform(-1.5, 2.5)), float(rng.uniform(-0.8, 1.5))
    else:  # curled tips: the tip angle A/2 + B up to ~4 rad
        sc["a"], sc["b"] = float(rng.uniform(2.5, 6.0)), float(rng.uniform(0.5, 2.0))
    sc["k"] = math.inf if rng.random() < 0.3 else float(math.exp(rng.uniform(math.log(0.3), math.log(300.0))))
    sc["q"] = 0.0 if rng.random() < 0.15 else float(rng.uniform(0.0, 10.0))
    sc["alpha_deg"] = float(rng.uniform(-85.0, 85.0)) if rng.random() < 0.7 else 0.0
    motion = MOTIONS[rng.choice(3, p=[0.5, 0.25, 0.25])]
    kind = PROFILE_KINDS[rng.integers(len(PROFILE_KINDS))]
    # friction mostly where the CLI sweeps it (translation past graphs), sometimes elsewhere
    # (to see it refused honestly)
    p_mu = 0.5 if motion == "translate" and kind not in ("peg", "disc") else 0.15
    sc["mu"] = float(rng.uniform(0.0, 1.5)) if rng.random() < p_mu else 0.0
    sc["motion"] = motion
    sc["kind"] = kind
    if motion == "rotate":
        sc["x0"], sc["y0"] = float(rng.uniform(-0.3, 0.3)), float(rng.uniform(-0.3, 0.3))
        sc["gamma_deg"] = float(rng.uniform(-60.0, 30.0))
    # the obstacle, placed where the whisker can reach it
    yv = float(rng.uniform(0.35, 0.97))
    xv = float(rng.uniform(-0.6, 0.4))
    if motion == "rotate":
        # a point at distance r from the base, a little counter-clockwise of the whisker
        r = float(rng.uniform(0.35, 0.95))
        ang = HALF_PI + math.radians(sc["gamma_deg"]) + float(rng.uniform(0.1, 1.2))
        xv, yv = sc["x0"] + r * math.cos(ang), sc["y0"] + r * math.sin(ang)
    if kind in ("g1", "g2", "ge"):
        sc["profile"] = kind
        sc["table"] = None
    elif kind == "parabola":
        sc["profile"] = f"parabola:{rng.uniform(0.3, 3.0):.6g},{xv:.6g},{yv:.6g}"
    elif kind == "cosh":
        a, c = float(rng.uniform(0.3, 2.0)), float(rng.uniform(0.4, 2.0))
        sc["profile"] = f"cosh:{a:.6g},{c:.6g},{xv:.6g},{yv - a:.6g}"
    elif kind == "circle":
        r = float(rng.uniform(0.2, 1.2))
        sc["profile"] = f"circle:{xv:.6g},{yv + r:.6g},{r:.6g}"
    elif kind == "disc":
        r = float(rng.uniform(0.03, 0.4))
        if motion == "rotate":
            sc["profile"] = f"disc:{xv:.6g},{yv:.6g},{r:.6g}"
        else:
            sc["profile"] = f"disc:{xv:.6g},{yv + r:.6g},{r:.6g}"
    elif kind == "peg":
        sc["profile"] = f"peg:{xv:.6g},{yv:.6g}"
    else:  # points: a cosh tabulated every 0.005 over x in [-4, 3]
        a, c = float(rng.uniform(0.3, 2.0)), float(rng.uniform(0.5, 2.0))
        a, c, xv, d = float(f"{a:.6g}"), float(f"{c:.6g}"), float(f"{xv:.6g}"), float(f"{yv - a:.6g}")
        xs = np.linspace(-4.0, 3.0, 1401)
        path = folder / f"contour-{index}.csv"
        with open(path, "w") as fh:
            fh.write("x,y\n")
            for x in xs:
                fh.write(f"{float(x)!r},{a * math.cosh((x - xv) / c) + d!r}\n")
        sc["profile"] = f"points:{path}"
        sc["table"] = cosh_profile(a, c, xv, d)
        sc["table"].spacing = 7.0 / 1400.0
        sc["table"].fourth = lambda x, a=a, c=c, xv=xv: a / c**4 * math.cosh((x - xv) / c)
        sc["table_args"] = (a, c, xv, d)
    if motion == "path":
        n = int(rng.integers(3, 8))
        x0s = np.sort(rng.uniform(-2.0, 1.5, n))[::-1]
        x0s[0] = 2.5  # out of reach of every obstacle above
        y0s = rng.uniform(-0.1, 0.1, n)
        gs = rng.uniform(-15.0, 15.0, n)
        ks = np.exp(rng.uniform(math.log(0.5), math.log(200.0), n))
        path = folder / f"path-{index}.csv"
        with open(path, "w") as fh:
            fh.write("x0,y0,gamma_deg,k\n")
            for row in zip(x0s, y0s, gs, ks):
                fh.write(",".join(f"{v:.6g}" for v in row) + "\n")
        sc["path"] = path
        sc["path_rows"] = np.array([[float(f"{v:.6g}") for v in row] for row in zip(x0s, y0s, gs, ks)])
    sc["points"] = int(rng.integers(12, 40))
    # a quarter of the scenes ask for an accuracy: every row then has an estimate <= tol
    sc["tol"] = float(10.0 ** rng.uniform(-9.0, -5.0)) if rng.random() < 0.25 else None
    return sc


def sweep_args(sc: dict, out) -> list:
    """The `vibrissa sweep` command line of a scene."""
    args = ["sweep", "--profile", sc["profile"], "--theta", repr(sc["theta"]), "--a", repr(sc["a"]),
            "--b", repr(sc["b"]), "--k", "inf" if math.isinf(sc["k"]) else repr(sc["k"]),
            "--q", repr(sc["q"]), "--alpha-deg", repr(sc["alpha_deg"]), "--mu", repr(sc["mu"]),
            "--points", str(sc["points"])]
    if sc["motion"] == "rotate":
        args += ["--motion", "rotate", "--x0", repr(sc["x0"]), "--y0", repr(sc["y0"]),
                 "--gamma-deg", repr(sc["gamma_deg"])]
    elif sc["motion"] == "path":
        args += ["--motion", f"path:{sc['path']}"]
    return args + ["--json", "--figures", "none", "--out", str(out)]


def command_line(args) -> str:
    return "vibrissa " + " ".join(a if all(ch not in a for ch in " ;") else repr(a) for a in args)


# ---------------------------------------------------------------------------------------
# The checks of one contact row
# ---------------------------------------------------------------------------------------
def angle_diff(a, b):
    """a - b wrapped to (-pi, pi]."""
    d = math.fmod(a - b, 2 * math.pi)
    if d > math.pi:
        d -= 2 * math.pi
    elif d <= -math.pi:
        d += 2 * math.pi
    return d


def check_row(w: Whisker, obstacle, row: dict, mu: float, pen_tol: float) -> dict:
    """Residuals of one contact row (each a non-negative number, 0 = exact), re-derived
    from the row's base observables and pose by an independent integration."""
    k = row.get("k", w.k)
    s1 = row["s1"]
    gamma = row["gamma"]
    res = {}
    # the follicle [3.21, 3.22] turned by gamma
    law = HALF_PI + gamma - (0.0 if math.isinf(k) else row["MA"] / k)
    res["base_law"] = abs(angle_diff(row["phi0"], law))
    curve = integrate(w, row["x0"], row["y0"], row["phi0"], row["MA"], row["Ax"], row["Ay"], s1)
    x1, y1, phi1, m1 = curve.contact
    # the contact point: the integration's against the row's estimate, and on the contour
    res["contact_point"] = math.hypot(x1 - row["xc"], y1 - row["yc"])
    res["on_contour"] = abs(obstacle.on_contour(x1, y1))
    # the moment at and beyond the contact (P = 0 beyond: m stays m(s1))
    scale_m = max(1.0, abs(row["MA"]))
    res["moment"] = abs(m1) / scale_m
    # the force: the jump of the shear at s1 against f n + ft t with the contour's own angle
    F = curve.contact_force
    fscale = max(1.0, float(np.hypot(*F)))
    if obstacle.kind == "peg":
        # normal to the whisker (the peg has no tangent): the whisker's tangent is the t
        tang = np.array([math.cos(phi1), math.sin(phi1)])
        ft_true = float(F @ tang)
        n_vec = F - ft_true * tang
        fn_true = float(np.hypot(*n_vec))
        psi_true = phi1
    else:
        psi_true = obstacle.psi(x1, y1)
        tang = np.array([math.cos(psi_true), math.sin(psi_true)])
        n_out = obstacle.outward(x1, y1)
        ft_true = float(F @ tang)
        fn_true = float(F @ n_out)
        res["psi"] = abs(angle_diff(row["psi"], psi_true))
    res["force_normal"] = abs(fn_true - row["f"]) / fscale
    res["force_tangential"] = abs(ft_true - row.get("ft", 0.0)) / fscale
    res["f_negative"] = max(0.0, -fn_true) / fscale
    if mu == 0.0:
        res["friction_cone"] = abs(ft_true) / fscale
    else:
        res["friction_cone"] = max(0.0, abs(ft_true) - mu * fn_true) / fscale
        if row.get("slip") == "slip":
            res["slip_on_edge"] = abs(abs(ft_true) - mu * fn_true) / fscale
    # the phase: s1 = 1 at a tip contact, tangency at a tangential one
    if row["phase"] == "A":
        res["phase"] = abs(1.0 - s1)
    elif obstacle.kind != "peg":
        res["phase"] = abs(math.sin(angle_diff(phi1, psi_true)))
    # no penetration, bounded over the whole whisker
    if obstacle.kind != "peg":
        bound, deepest, s_at = min_clearance(curve, w, obstacle, pen_tol)
        res["penetration"] = max(0.0, -bound)
        res["_deepest_s"] = s_at
    return res


def check_free_row(w: Whisker, obstacle, row: dict, eps: float) -> dict:
    """A row before contact: the follicle law, the free end's moment m(1) = 0 under the flow
    alone (the reactions Ax = -q cos alpha, Ay = q sin alpha), and the whole whisker outside
    the obstacle (bounded as for the contact rows; a peg is not checked)."""
    free = dict(row, s1=1.0, xc=0.0, yc=0.0)
    tol = tolerances(w, obstacle if obstacle.kind != "peg" else Peg(0.0, 0.0), free, eps)
    k = row.get("k", w.k)
    law = HALF_PI + row["gamma"] - (0.0 if math.isinf(k) else row["MA"] / k)
    out = {"free_base_law": (abs(angle_diff(row["phi0"], law)), tol["base_law"])}
    flow = (-w.q * math.cos(w.alpha), w.q * math.sin(w.alpha))
    out["free_reactions"] = (math.hypot(row["Ax"] - flow[0], row["Ay"] - flow[1]) / max(1.0, w.q), SAFETY * 3 * eps + INTEGRATOR_FLOOR)
    curve = integrate(w, row["x0"], row["y0"], row["phi0"], row["MA"], row["Ax"], row["Ay"], 1.0)
    out["free_moment"] = (abs(curve.contact[3]) / max(1.0, abs(row["MA"])), tol["moment"])
    if obstacle.kind != "peg":
        bound, _, _ = min_clearance(curve, w, obstacle, tol["penetration"])
        out["free_penetration"] = (max(0.0, -bound), tol["penetration"])
    return out


def sensitivity(w: Whisker, row: dict) -> np.ndarray:
    """|d u / d p| at s1 and at the tip: how the state u = (x, y, phi, m) moves with each
    logged observable p = (phi0, MA, Ax, Ay) (the variational equations of the system
    above, rtol 1e-6: only the size matters). Rows (s1, tip), columns the 4 x 4 matrix."""
    ca, sa = math.cos(w.alpha), math.sin(w.alpha)
    ax, ay, s1 = row["Ax"], row["Ay"], row["s1"]

    def rhs(s, z, loaded):
        e4 = (1.0 + (w.theta - 1.0) * s) ** 4
        x, y, phi, m = z[:4]
        Z = z[4:].reshape(4, 4)
        c, sn = math.cos(phi), math.sin(phi)
        if loaded:
            px, py = -ax - w.q * s * ca, -ay + w.q * s * sa
        else:
            px = py = 0.0
        J = np.array([[0, 0, -sn, 0], [0, 0, c, 0], [0, 0, 0, 1 / e4], [0, 0, px * c + py * sn, 0]])
        dZ = J @ Z
        if loaded:
            dZ[3, 2] += -sn
            dZ[3, 3] += c
        return np.concatenate([[c, sn, m / e4 + w.a * s + w.b, px * sn - py * c], dZ.ravel()])

    Z0 = np.zeros((4, 4))
    Z0[2, 0] = 1.0
    Z0[3, 1] = -1.0
    z0 = np.concatenate([[row["x0"], row["y0"], row["phi0"], -row["MA"]], Z0.ravel()])
    r = solve_ivp(rhs, (0.0, s1), z0, args=(True,), method="DOP853", rtol=1e-6, atol=1e-9)
    out = [np.abs(r.y[4:, -1].reshape(4, 4))]
    if s1 < 1.0:
        r = solve_ivp(rhs, (s1, 1.0), r.y[:, -1], args=(False,), method="DOP853", rtol=1e-6, atol=1e-9)
    out.append(np.abs(r.y[4:, -1].reshape(4, 4)))
    return np.array(out)


# ---------------------------------------------------------------------------------------
# Tolerances from the specs' accuracy
# ---------------------------------------------------------------------------------------
# `sweep --help` (spec/cli.md `--tol`): without --tol the rows are at ~1e-10 (absolute, of
# the observables and the contact point); with --tol T each row has an estimate <= T. A
# residual is allowed SAFETY times what an error of that size in the logged observables
# (phi0, MA, Ax, Ay), propagated through the elastica by its variational equations, and in
# the logged contact point and force, would make: the "~" in "~1e-10" and the estimates'
# own looseness, fixed before the battery was run, not tuned to it.
DEFAULT_ACCURACY = 1e-10
SAFETY = 10.0
INTEGRATOR_FLOOR = 1e-11  # DOP853 at rtol 1e-12 over s in [0, 1], with the dense output


def contour_curvature(obstacle, x, y) -> float:
    if obstacle.kind == "graph":
        h = 1e-5
        d2 = (obstacle.dg(x + h) - obstacle.dg(x - h)) / (2 * h)
        return abs(d2) / (1 + obstacle.dg(x) ** 2) ** 1.5
    if obstacle.kind in ("circle", "disc"):
        return 1.0 / obstacle.r
    return 0.0


def tolerances(w: Whisker, obstacle, row: dict, eps: float) -> dict:
    Z = sensitivity(w, row)
    e = Z @ np.full(4, eps)  # (2, 4): the state's error at s1 and at the tip
    pos1 = e[0, 0] + e[0, 1]
    pos = max(pos1, e[1, 0] + e[1, 1])
    kap = contour_curvature(obstacle, row["xc"], row["yc"])
    # a tabulated contour (points:): the CLI interpolates the table "smoothly" (spec/cli.md);
    # a cubic spline's error bounds (Hall & Meyer 1976): 5/384 h^4 max|g^(4)| in the value,
    # h^3 / 24 max|g^(4)| in the slope, h the table's spacing
    interp_val = interp_slope = 0.0
    if getattr(obstacle, "spacing", None):
        g4 = obstacle.fourth(row["xc"])
        interp_val = 5.0 / 384.0 * obstacle.spacing**4 * g4
        interp_slope = obstacle.spacing**3 / 24.0 * g4
    F = math.hypot(-row["Ax"] - w.q * row["s1"] * math.cos(w.alpha), -row["Ay"] + w.q * row["s1"] * math.sin(w.alpha))
    fscale = max(1.0, F)
    k = row.get("k", w.k)
    t = {
        "base_law": eps * (1.0 + (0.0 if math.isinf(k) else 1.0 / k)),
        "contact_point": pos1 + eps,
        "on_contour": pos1 + eps + interp_val,
        "moment": (e[0, 3] + eps) / max(1.0, abs(row["MA"])),
        "psi": kap * pos1 + eps + interp_slope + (e[0, 2] if obstacle.kind == "peg" else 0.0),
        "force_normal": (3 * eps + F * (kap * pos1 + e[0, 2] + interp_slope)) / fscale,
        "phase": e[0, 2] + kap * pos1 + eps + interp_slope,
        "penetration": pos + eps + interp_val,
    }
    for name in ("force_tangential", "f_negative", "friction_cone", "slip_on_edge"):
        t[name] = t["force_normal"]
    return {n: SAFETY * v + INTEGRATOR_FLOOR for n, v in t.items()}


# ---------------------------------------------------------------------------------------
# Running the CLI and checking a whole sweep
# ---------------------------------------------------------------------------------------
def read_log(path) -> list:
    """observables.csv as a list of dicts (numbers parsed by float(), text kept)."""
    lines = open(path).read().splitlines()
    header = lines[0].split(",")
    rows = []
    for line in lines[1:]:
        if not line:
            continue
        row = {}
        for h, cell in zip(header, line.split(",")):
            try:
                row[h] = float(cell)
            except ValueError:
                row[h] = cell
        rows.append(row)
    return rows


@dataclass
class SceneResult:
    scene: dict
    command: str
    status: str  # "ok", "refused", "crashed"
    code: int = 0
    message: str = ""
    rows: list = field(default_factory=list)
    summary: dict = field(default_factory=dict)
    residuals: list = field(default_factory=list)  # per contact row: {check: (residual, tol)}
    violations: list = field(default_factory=list)  # (check, row index, residual, tol, detail)
    recon: dict = field(default_factory=dict)


def whisker_of(sc: dict) -> Whisker:
    return Whisker(sc["theta"], sc["a"], sc["b"], sc["k"], sc["q"], math.radians(sc["alpha_deg"]))


def check_events(res: SceneResult, tols_f: float):
    """The JSON summary against the rows: phases in the order of the contact rows, the first
    contact's kind, a release at f = 0, a snap where x0 (gamma in a rotation) turns."""
    sm, rows = res.summary, res.rows
    contact = [r for r in rows if r["phase"] in ("A", "B")]
    if not contact:
        res.violations.append(("events", -1, 1.0, 0.0, "a sweep without a contact row"))
        return
    seq = ""
    for r in contact:
        if not seq or seq[-1] != r["phase"]:
            seq += r["phase"]
    if "phases" in sm and sm["phases"] != seq:
        res.violations.append(("events", -1, 1.0, 0.0, f"phases {sm['phases']!r} but the rows give {seq!r}"))
    first = "tip" if contact[0]["phase"] == "A" else "tangential"
    if "first_contact" in sm and sm["first_contact"] != first:
        res.violations.append(("events", 0, 1.0, 0.0, f"first_contact {sm['first_contact']!r}, first row {contact[0]['phase']}"))
    sep = sm.get("separation", "")
    last = contact[-1]
    fscale = max(1.0, abs(last["Ax"]) + abs(last["Ay"]))
    if sep == "release":
        r = abs(last["f"]) / fscale
        res.residuals.append({"release_f": (r, tols_f)})
        if r > tols_f:
            res.violations.append(("release_f", len(rows) - 1, r, tols_f, f"release with f = {last['f']:.3e}"))
    elif sep == "snap":
        # a turning point of the controlled coordinate along the branch: the rows' response
        # steepens as 1/sqrt(distance) there, so the last step's slope of the observables
        # in the controlled coordinate exceeds the average slope of the contact rows
        key = "gamma" if res.scene["motion"] == "rotate" else "x0"
        if len(contact) >= 4:
            c = np.array([r[key] for r in contact])
            ma = np.array([r["MA"] for r in contact])
            last_slope = abs((ma[-1] - ma[-2]) / (c[-1] - c[-2]))
            mean_slope = abs((ma[-1] - ma[0]) / (c[-1] - c[0]))
            res.summary["_snap_steepening"] = last_slope / max(mean_slope, 1e-300)


def run(binary, args, timeout=300):
    import subprocess

    try:
        return subprocess.run([str(binary), *args], capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None


def check_sweep(binary, sc: dict, folder) -> SceneResult:
    """Sweep one scene with the CLI and check every contact row and the summary."""
    import json

    out = folder / f"sweep-{sc['index']}"
    args = sweep_args(sc, out)
    if sc.get("tol"):
        args += ["--tol", repr(sc["tol"])]
    res = SceneResult(sc, command_line(args), "ok")
    p = run(binary, args)
    if p is None:
        res.status, res.message = "timeout", "no answer in 300 s"
        return res
    res.code = p.returncode
    if p.returncode != 0:
        lines = p.stderr.strip().splitlines()
        res.message = lines[-1] if lines else ""
        clean = p.returncode in (1, 2, 3) and len(lines) == 1 and "panic" not in p.stderr
        res.status = "refused" if clean else "crashed"
        return res
    res.summary = json.loads(p.stdout)
    res.rows = read_log(out / "observables.csv")
    obstacle = sc["table"] if sc["kind"] == "points" else parse_profile(sc["profile"])
    w = whisker_of(sc)
    eps = sc.get("tol") or DEFAULT_ACCURACY
    # the rows' order: x0 strictly falling in a translation, gamma rising in a rotation
    key, sign = ("gamma", 1.0) if sc["motion"] == "rotate" else ("x0", -1.0)
    if sc["motion"] != "path":
        c = np.array([r[key] for r in res.rows]) * sign
        if not (np.diff(c) > 0).all():
            res.violations.append(("row_order", int(np.argmin(np.diff(c))), 1.0, 0.0, f"{key} not monotone"))
    worst_f_tol = 0.0
    for i, row in enumerate(res.rows):
        if row["phase"] not in ("A", "B"):
            # a row before contact: the free whisker under the flow alone (s1 = 1, f = 0)
            try:
                r = check_free_row(w, obstacle, row, eps)
            except Exception as e:
                res.violations.append(("integration", i, math.inf, 0.0, repr(e)))
                continue
            entry = {}
            for name, (value, tol) in r.items():
                entry[name] = (value, tol)
                if not value <= tol:
                    res.violations.append((name, i, value, tol, "before contact"))
            res.residuals.append(entry)
            continue
        tol = tolerances(w, obstacle, row, eps)
        worst_f_tol = max(worst_f_tol, tol["force_normal"])
        try:
            r = check_row(w, obstacle, row, sc["mu"], tol["penetration"])
        except Exception as e:  # an integration that fails is a finding too
            res.violations.append(("integration", i, math.inf, 0.0, repr(e)))
            continue
        entry = {}
        for name, value in r.items():
            if name.startswith("_"):
                continue
            entry[name] = (value, tol[name])
            if not value <= tol[name]:
                detail = f"s = {r['_deepest_s']:.6f}" if name == "penetration" else ""
                res.violations.append((name, i, value, tol[name], detail))
        res.residuals.append(entry)
    # the switch rows: s1 = 1 and tangency at once (A->B, B->A events). The event's `row`
    # (1-based) is the new phase's first row; the row added at the switch is that row or the
    # one before it: the better of the two must be the switch.
    for ev in res.summary.get("events", []):
        name = ev.get("event", "")
        if name not in ("A\u2192B", "B\u2192A") or obstacle.kind == "peg":
            continue
        best = None
        for j in (ev.get("row", 0) - 2, ev.get("row", 0) - 1):
            if not 0 <= j < len(res.rows) or res.rows[j]["phase"] not in ("A", "B"):
                continue
            row = res.rows[j]
            curve = integrate(w, row["x0"], row["y0"], row["phi0"], row["MA"], row["Ax"], row["Ay"], row["s1"])
            psi = obstacle.psi(*curve.contact[:2])
            tol = tolerances(w, obstacle, row, eps)["phase"]
            v = max(abs(1.0 - row["s1"]), abs(math.sin(angle_diff(curve.contact[2], psi))))
            if best is None or v / tol < best[0] / best[1]:
                best = (v, tol, j)
        if best is None:
            res.violations.append(("switch", ev.get("row", 0), math.inf, 0.0, f"{name}: no contact row there"))
            continue
        res.residuals.append({"switch": best[:2]})
        if best[0] > best[1]:
            res.violations.append(("switch", best[2], best[0], best[1], name))
    check_events(res, SAFETY * 3 * eps + INTEGRATOR_FLOOR)
    return res


def noisy_log(rows, rng, level=1e-4):
    """The log reordered, thinned to every 3rd row and noised at `level` relative (standard
    deviation level x the column's largest magnitude: the convention of `--noise`)."""
    keep = [dict(r) for r in rows[::3]]
    cols = ("Ax", "Ay", "MA", "phi0")
    scale = {c: max(abs(r[c]) for r in keep) for c in cols}
    for r in keep:
        for c in cols:
            r[c] += level * scale[c] * rng.standard_normal()
    order = rng.permutation(len(keep))
    return [keep[i] for i in order]


def write_log(rows, path):
    cols = [c for c in rows[0].keys()]
    with open(path, "w") as fh:
        fh.write(",".join(cols) + "\n")
        for r in rows:
            fh.write(",".join(repr(r[c]) if isinstance(r[c], float) else str(r[c]) for c in cols) + "\n")


def check_reconstruct(binary, res: SceneResult, folder, rng, level=1e-4) -> dict:
    """`reconstruct` on the swept log reordered, thinned and noised: the contact points
    against the swept ones in units of the reported sigma, mu against the truth."""
    import json

    sc = res.scene
    src = folder / f"sweep-{sc['index']}"
    log = noisy_log(res.rows, rng, level)
    path = folder / f"noisy-{sc['index']}.csv"
    write_log(log, path)
    out = folder / f"rec-{sc['index']}"
    args = ["reconstruct", str(path), str(src / "scene.ron"), "--noise", repr(level),
            "--tolerance", "none", "--json", "--figures", "none", "--out", str(out)]
    if sc["mu"] > 0:
        args += ["--mu", "identify"]
    rec = {"command": command_line(args)}
    p = run(binary, args)
    if p is None or p.returncode != 0:
        rec["status"] = "refused" if p is not None and p.returncode in (1, 2, 3) else "crashed"
        rec["message"] = "timeout" if p is None else (p.stderr.strip().splitlines() or [""])[-1]
        rec["code"] = None if p is None else p.returncode
        return rec
    rec["status"] = "ok"
    summary = json.loads(p.stdout)
    pts = read_log(out / "reconstruction.csv")
    contact = [r for r in log if r["phase"] in ("A", "B")]
    if len(pts) == len(contact):
        pairs = list(zip(pts, contact))  # one point per contact row, in the input's order
    elif sc["motion"] != "rotate":
        truth = {r["x0"]: r for r in contact}
        pairs = [(pt, truth[pt["x0"]]) for pt in pts if pt["x0"] in truth]
    else:
        pairs = []
    rec["unmatched"] = len(contact) - len(pairs)
    z = []
    for pt, t in pairs:
        if math.isnan(pt["x"]) or not isinstance(pt.get("sigma"), float):
            continue
        d = max(abs(pt["x"] - t["xc"]), abs(pt["y"] - t["yc"]))
        z.append(d / pt["sigma"] if pt["sigma"] > 0 else math.inf)
    rec["z"] = z
    mu = summary.get("mu")
    if sc["mu"] > 0 and isinstance(mu, dict) and mu.get("stderr"):
        rec["mu"] = (mu["value"], mu["stderr"], sc["mu"])
    rec["q"] = (summary.get("q"), sc["q"])
    return rec


# ---------------------------------------------------------------------------------------
# A battery: scenes, rows, every check's worst residual and where, failures by class
# ---------------------------------------------------------------------------------------
def refusal_reason(message: str) -> str:
    """The class of a refusal: its message with the numbers and paths taken out."""
    import re

    m = message.removeprefix("error: ")
    m = re.sub(r"(/[^\s:]+)+", "FILE", m)
    m = re.sub(r"\(?[-+]?\d[\d.]*(e[-+]?\d+)?\)?", "N", m)
    m = re.sub(r"[a-z]+:N(,N)*", "PROFILE", m)
    return m[:110]


def battery(binary, seeds, folder, recon=True, log=None) -> dict:
    """Sweep, check and reconstruct the scenes of `seeds` (each seed one scene)."""
    import time

    t0 = time.time()
    rep = {"scenes": 0, "swept": 0, "rows": 0, "contact_rows": 0, "worst": {}, "violations": [],
           "refusals": {}, "crashes": [], "by_kind": {}, "recon": {"logs": 0, "points": 0, "within3": 0,
           "worst_z": (0.0, None), "mu": [], "refusals": {}, "misses": []}}
    for seed in seeds:
        rng = np.random.default_rng([2026, seed])
        sc = random_scene(rng, seed, folder)
        rep["scenes"] += 1
        tag = f"{sc['kind']}/{sc['motion']}" + ("/mu" if sc["mu"] > 0 else "")
        kind = rep["by_kind"].setdefault(tag, {"scenes": 0, "swept": 0, "rows": 0, "violations": 0})
        kind["scenes"] += 1
        res = check_sweep(binary, sc, folder)
        if res.status in ("refused", "timeout"):
            reason = f"exit {res.code}: " + refusal_reason(res.message)
            entry = rep["refusals"].setdefault(reason, {"count": 0, "example": res.command, "message": res.message})
            entry["count"] += 1
            continue
        if res.status == "crashed":
            rep["crashes"].append((res.command, res.code, res.message))
            continue
        rep["swept"] += 1
        kind["swept"] += 1
        rep["rows"] += len(res.rows)
        contact = sum(1 for r in res.rows if r["phase"] in ("A", "B"))
        rep["contact_rows"] += contact
        kind["rows"] += contact
        for j, entry in enumerate(res.residuals):
            for name, (value, tol) in entry.items():
                ratio = value / tol if tol > 0 else math.inf
                w = rep["worst"].get(name)
                if w is None or ratio > w["ratio"]:
                    rep["worst"][name] = {"ratio": ratio, "residual": value, "tol": tol, "seed": seed,
                                          "scene": tag, "command": res.command}
        for v in res.violations:
            kind["violations"] += 1
            rep["violations"].append({"check": v[0], "row": v[1], "residual": v[2], "tol": v[3], "detail": v[4],
                                      "seed": seed, "scene": tag, "command": res.command})
        if recon:
            # the noise from a generator of its own: the draws do not depend on the scene's
            rec = check_reconstruct(binary, res, folder, np.random.default_rng([2026, seed, 1]))
            if rec["status"] != "ok":
                reason = f"exit {rec.get('code')}: " + refusal_reason(rec.get("message", ""))
                e = rep["recon"]["refusals"].setdefault(reason, {"count": 0, "example": rec["command"]})
                e["count"] += 1
                continue
            r = rep["recon"]
            r["logs"] += 1
            r["points"] += len(rec["z"])
            r["within3"] += sum(1 for z in rec["z"] if z <= 3.0)
            for z in rec["z"]:
                if z > r["worst_z"][0]:
                    r["worst_z"] = (z, rec["command"])
            if rec["z"] and max(rec["z"]) > 3.0:
                r["misses"].append({"seed": seed, "scene": tag, "z": sorted(rec["z"])[-3:], "command": rec["command"]})
            if "mu" in rec:
                est, se, true = rec["mu"]
                r["mu"].append({"seed": seed, "est": est, "stderr": se, "true": true, "z": abs(est - true) / se})
        if log:
            log(seed, tag, res)
    rep["seconds"] = time.time() - t0
    return rep
