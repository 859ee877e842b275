"""Pure-scipy reference for ``vibrissa.sweep(profile="g1", q=5, points=200)``.

An independent implementation of the same quasi-static sweep (see shared/spec/model.md,
"Contact with an obstacle"), written the way one would with scipy, so that both can be
timed in one process (``python scipy_sweep.py``) and checked against each other.

Scene: uniform straight whisker (theta = 1: EI = 1, A = B = 0), rigid base phi(0) = pi/2 at
(x0, 0), flow q = 5 at alpha = 0 on [0, s1], obstacle y > g1(x) = cosh(x/2) - 4/5 with
contour angle psi = atan g1'(x). The contact force is a DP tip force at s1 with
beta = pi/2 - psi. First-order system in s:

    x' = cos phi, y' = sin phi, phi' = m, m' = f sin(phi+beta) + q (s1-s) sin(phi+alpha)

Every shot integrates it from the base state (x0, 0, pi/2, m0) with solve_ivp (DOP853,
rtol = atol = 1e-12); the boundary-value problems are solved by shooting with
scipy.optimize.root (hybr: MINPACK, finite-difference Jacobian + Broyden updates):

- free whisker (flow only): unknown m0, residual m(1) = 0;
- phase A (tip contact, s1 = 1): unknowns (m0, f, xc), residuals r(1) - (xc, g(xc)), m(1);
- phase B (tangential): unknowns (m0, f, xc, s1), residuals r(s1) - (xc, g(xc)), m(s1),
  phi(s1) - psi;
- phase switch (A->B and B->A are the same point: s1 = 1 and phi(1) = psi): unknowns
  (m0, f, xc, x0), residuals r(1) - (xc, g(xc)), m(1), phi(1) - psi.

Sweep (as vibrissa does it: a coarse pass to find the separation, then the fine pass):
1. the free whisker is x0-independent up to translation: one solve gives its tip offset;
   the first contact is the root x0 of g(x0 + dx_tip) = y_tip on the right branch
   (brentq); tip contact there if phi(1) > psi (the only case handled here).
2. coarse pass: march x0 down in steps of COARSE_STEP with continuation (each row starts
   from the previous row's solution), switching phase at the events (located exactly by the
   switch system above) until the separation: release when f < 0 (in phase A the f = 0
   point is the free whisker again, so the release x0 is the left root of
   g(x0 + dx_tip) = y_tip); snap when a row fails even after halving the step down to 1e-9
   (the fold is then located only to that step).
3. fine pass: `points` x0 evenly spaced from the first contact to the separation (both
   included), again by continuation, plus one row at each phase switch (s1 = 1 and
   phi(1) = psi there; labelled A, as vibrissa does). Pre-contact rows are omitted.
"""
import math
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, root

Q, ALPHA = 5.0, 0.0          # flow (alpha in rad)
TOL = 1e-12                  # integrator rtol = atol
XTOL = 1e-10                 # root() relative step tolerance
COARSE_STEP = 0.1            # x0 step of the coarse pass


def g(x):
    return math.cosh(0.5 * x) - 0.8


def psi_of(xc):
    return math.atan(0.5 * math.sinh(0.5 * xc))


def _rhs(s, y, f, beta, s1):
    phi = y[2]
    return [math.cos(phi), math.sin(phi), y[3],
            f * math.sin(phi + beta) + Q * (s1 - s) * math.sin(phi + ALPHA)]


def _shoot(x0, m0, f, xc, s1):
    """State (x, y, phi, m) at s1 of the whisker loaded by f at s1 normal to the contour at xc."""
    beta = 0.5 * math.pi - psi_of(xc)
    sol = solve_ivp(_rhs, (0.0, s1), [x0, 0.0, 0.5 * math.pi, m0], method="DOP853",
                    rtol=TOL, atol=TOL, args=(f, beta, s1))
    return sol.y[:, -1]


def _res_A(u, x0):
    m0, f, xc = u
    x, y, _, m = _shoot(x0, m0, f, xc, 1.0)
    return [x - xc, y - g(xc), m]


def _res_B(u, x0):
    m0, f, xc, s1 = u
    x, y, phi, m = _shoot(x0, m0, f, xc, s1)
    return [x - xc, y - g(xc), m, phi - psi_of(xc)]


def _res_switch(u):
    m0, f, xc, x0 = u
    x, y, phi, m = _shoot(x0, m0, f, xc, 1.0)
    return [x - xc, y - g(xc), m, phi - psi_of(xc)]


def _solve(fun, guess, args=()):
    sol = root(fun, guess, args=args, method="hybr", options={"xtol": XTOL})
    if not sol.success or np.max(np.abs(sol.fun)) > 1e-9:
        raise RuntimeError(sol.message)
    return sol.x


def _row(x0, phase, u):
    """Observables of a solved contact row (u: phase unknowns, m0 and f first)."""
    m0, f, xc = u[:3]
    s1 = u[3] if phase == "B" else 1.0
    beta = 0.5 * math.pi - psi_of(xc)
    return dict(x0=x0, Ax=-(f * math.cos(beta) + Q * s1 * math.cos(ALPHA)),
                Ay=f * math.sin(beta) + Q * s1 * math.sin(ALPHA), MA=-m0,
                phi0=0.5 * math.pi, f=f, phase=phase, u=np.array(u, float))


def _free():
    """Free whisker (flow only), base at x0 = 0: (m0, tip x, tip y, tip angle)."""
    m0 = _solve(lambda u: [_shoot(0.0, u[0], 0.0, 0.0, 1.0)[3]], [-Q / 2])[0]
    x, y, phi, _ = _shoot(0.0, m0, 0.0, 0.0, 1.0)
    return m0, x, y, phi


def solve_row(x0, phase_guess="A", guess=None):
    """Solves the contact row at base position x0, trying `phase_guess` first.

    `guess`: the unknowns of a nearby row of that phase ((m0, f, xc) for A, (m0, f, xc, s1)
    for B); by default the free whisker touching the contour (good near first contact).
    Returns the row dict (x0, Ax, Ay, MA, phi0, f, phase, u); at a phase switch (within
    1e-9) the guessed phase is kept."""
    if guess is None:
        m0, dx, yt, _ = _free()
        guess = [m0, 0.0, x0 + dx]
    phase = phase_guess
    for _ in range(2):                         # the guessed phase, then the other one
        if phase == "A":
            u = _solve(_res_A, list(guess[:3]), (x0,))
            if _shoot(x0, *u, 1.0)[2] >= psi_of(u[2]) - 1e-9:
                return _row(x0, "A", u)
            phase = "B"
        else:
            u = _solve(_res_B, list(guess[:3]) + [guess[3] if len(guess) > 3 else 1.0], (x0,))
            if u[3] <= 1.0 + 1e-9:
                return _row(x0, "B", u)
            phase = "A"
        guess = list(u)
    raise RuntimeError(f"no consistent contact phase at x0 = {x0}")


def _step(x_prev, x0, phase, u):
    """One continuation step from the solved row (x_prev, phase, u) to x0.

    Returns (rows, separation): the event rows met on the way and the row at x0, and None,
    or the rows so far and "release" when f crosses 0 before x0 (raises RuntimeError when
    a solve fails, e.g. past a fold)."""
    rows = []
    while True:
        if phase == "A":
            v = _solve(_res_A, u, (x0,))
            phi1 = _shoot(x0, *v, 1.0)[2]
            switch = phi1 < psi_of(v[2])
        else:
            v = _solve(_res_B, u, (x0,))
            switch = v[3] > 1.0
        if v[1] < 0.0 and not switch:
            return rows, "release"
        if not switch:
            return rows + [_row(x0, phase, v)], None
        # phase switch between x_prev and x0: locate it, emit its row, go on in the new phase
        w = _solve(_res_switch, [u[0], u[1], u[2], x_prev])
        x_prev = w[3]
        rows.append(_row(x_prev, "A", w[:3]))  # s1 = 1 at a switch: labelled A (as vibrissa)
        phase = "B" if phase == "A" else "A"
        u = list(w[:3]) + ([1.0] if phase == "B" else [])


def _release_x0(free, lo, hi):
    """Release in phase A: the free whisker's tip on the contour, x0 in [lo, hi]."""
    _, dx, yt, _ = free
    return brentq(lambda x0: g(x0 + dx) - yt, lo, hi, xtol=1e-15)


def sweep_scipy(points=200):
    """The contact rows of the sweep (dict of numpy arrays; see the module docstring)."""
    free = _free()
    m0, dx, yt, phi1 = free
    xt = 2.0 * math.acosh(yt + 0.8)            # right root of g(x) = y_tip
    x_fc = xt - dx
    if phi1 <= psi_of(xt):
        raise NotImplementedError("tangential first contact")
    first = _row(x_fc, "A", [m0, 0.0, xt])

    # coarse pass: find the separation
    x, phase, u, h = x_fc, "A", first["u"], COARSE_STEP
    while True:
        try:
            rows, sep = _step(x, x - h, phase, list(u))
        except RuntimeError:
            h *= 0.5
            if h < 1e-9:
                kind, x_sep = "snap", x
                break
            continue
        if sep == "release":
            if phase != "A":
                raise NotImplementedError("release in phase B")
            kind, x_sep = "release", _release_x0(free, x - h, x)
            break
        x, phase, u = rows[-1]["x0"], rows[-1]["phase"], rows[-1]["u"]
        h = min(2.0 * h, COARSE_STEP)

    # fine pass: evenly spaced rows from the first contact to the separation
    grid = np.linspace(x_fc, x_sep, points)
    out, (phase, u) = [first], ("A", first["u"])
    for x_prev, x0 in zip(grid[:-2], grid[1:-1]):
        rows, sep = _step(x_prev, x0, phase, list(u))
        if sep is not None:
            raise RuntimeError("separation before the coarse pass found it")
        out += rows
        phase, u = rows[-1]["phase"], rows[-1]["u"]
    if kind == "release":                      # f = 0: the free whisker again
        out.append(_row(x_sep, "A", [m0, 0.0, x_sep + dx]))
    else:
        out.append(_step(grid[-2], x_sep, phase, list(u))[0][-1])
    cols = {k: np.array([r[k] for r in out]) for k in ("x0", "Ax", "Ay", "MA", "phi0", "f")}
    cols["phase"] = np.array([r["phase"] for r in out], dtype=str)
    cols["separation"] = kind
    return cols


def compare(points=200):
    """Runs both sweeps; returns first contact / separation x0 and value differences."""
    import vibrissa

    v = vibrissa.sweep(profile="g1", q=5, points=points)
    s = sweep_scipy(points)
    c = v.contact
    # every vibrissa contact row re-solved at its own x0 (continuation along vibrissa's rows)
    diff = dict(Ax=0.0, Ay=0.0, MA=0.0, f=0.0)
    phase, guess, phases = v.phase[c][0], None, []
    for x0, ph, *vals in zip(v.x0[c], v.phase[c], v.Ax[c], v.Ay[c], v.MA[c], v.f[c]):
        if guess is not None and ph != phase:   # follow vibrissa's phase label at a switch
            guess = list(guess[:3]) + ([1.0] if ph == "B" else [])
        r = solve_row(float(x0), ph, guess)
        phase, guess = r["phase"], list(r["u"])
        phases.append(r["phase"])
        for k, val in zip(diff, vals):
            diff[k] = max(diff[k], abs(r[k] - val))
    same_grid = np.max(np.abs(s["x0"] - v.x0[c])) if len(s["x0"]) == c.sum() else np.nan
    return dict(
        first_contact_x0=(v.x0[c][0], s["x0"][0]),
        separation_x0=(v.x0[c][-1], s["x0"][-1]),
        separation=(v.separation, s["separation"]),
        contact_rows=(int(c.sum()), len(s["x0"])),
        phase_columns_agree=bool(same_grid < 1e-9 and np.all(s["phase"] == v.phase[c])),
        # solve_row at vibrissa's x0s (the fair value check)
        max_abs_diff_same_x0=diff,
        solve_row_phase_mismatches=int(np.sum(np.array(phases) != v.phase[c])),
        # the two sweeps row by row (their grids differ by max_x0_diff_rows)
        max_x0_diff_rows=same_grid,
        max_abs_diff_rows={k: np.max(np.abs(s[k] - getattr(v, k)[c])) for k in diff},
    )


if __name__ == "__main__":
    import vibrissa

    t = time.perf_counter()
    sweep_scipy()
    t_scipy = time.perf_counter() - t
    t_vib = float("inf")
    for _ in range(5):
        t = time.perf_counter()
        vibrissa.sweep(profile="g1", q=5, points=200)
        t_vib = min(t_vib, time.perf_counter() - t)
    print(f"scipy sweep:    {t_scipy:.3f} s (one run)")
    print(f"vibrissa sweep: {t_vib * 1e3:.3f} ms (best of 5)")
    print(f"ratio:          {t_scipy / t_vib:.0f}x")
    for k, val in compare().items():
        print(f"{k}: {val}")
