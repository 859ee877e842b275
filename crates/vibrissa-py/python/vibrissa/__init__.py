"""vibrissa: whisker-inspired tactile sensing, from Python.

The large-deflection elastica of a tapered, pre-curved whisker on a torsional base spring
under a tip force and a uniform fluid load (:func:`solve`), quasi-static sweeps past a convex
obstacle under flow (:func:`sweep`), identification of the flow and reconstruction of the
obstacle's contour from the base observables only (:func:`reconstruct`, :class:`Streamer`),
and parameter studies over many scenes on the local cores or a Dask cluster (:func:`study`).

Every function is the Rust core of the ``vibrissa`` command line: the same parameters (the
CLI's names and defaults), the same numbers, the same one-line error messages. Values are
dimensionless (lengths in whisker lengths, forces relative to E I / L^2) unless ``units``
names a physical whisker (a preset of the thesis's Table 2.2: ``"beta"``, ``"gamma"``,
``"A1"``, ``"E2"``, or a dict ``length_mm, base_diameter_mm, youngs_modulus_gpa``); then
lengths are in mm, forces in N, moments in N mm, ``q`` in N/m, ``k`` in N m/rad.

The frame: the base at the origin, the whisker pointing along +y; the obstacle lies on the
side y > g(x); the base moves towards -x; a flow at ``alpha_deg = 0`` pushes along +x.

>>> import vibrissa
>>> sol = vibrissa.solve(theta=0.5, q=2.0)
>>> round(sol.tip["x"], 6) > 0
True
>>> sw = vibrissa.sweep(profile="g1", q=5, points=50)
>>> sw.first_contact, sw.phases
('tip', 'ABA')
>>> rec = vibrissa.reconstruct(sw)
>>> abs(rec.q - 5) < 1e-9
True
"""

from __future__ import annotations

import math
import warnings
from typing import Any, Dict, Optional

import numpy as np

from . import _core
from ._errors import InvalidInput, NoContact, SolverError, VibrissaError
from ._params import number, profile_spec, scene_kwargs, units_spec, whisker_spec
from ._results import Calibration, Reconstruction, Solution, Sweep, log_columns
from ._study import study

__version__: str = _core.__version__

__all__ = [
    "solve",
    "sweep",
    "reconstruct",
    "calibrate",
    "Streamer",
    "load_scene",
    "study",
    "Solution",
    "Sweep",
    "Reconstruction",
    "Calibration",
    "VibrissaError",
    "InvalidInput",
    "SolverError",
    "NoContact",
    "__version__",
]


def _model_spec(
    theta: Any, a: Any, b: Any, k: Any, f: Any, beta_deg: Any, load: Any, q: Any,
    alpha_deg: Any, method: Any, n: Any, units: Any,
) -> Dict[str, Any]:
    spec = whisker_spec(theta, a, b, k, units)
    spec.update(
        f=number("f", f),
        beta_deg=number("beta_deg", beta_deg),
        load=load,
        q=number("q", q),
        alpha_deg=number("alpha_deg", alpha_deg),
        method=method,
        n=n,
    )
    return spec


def _scene(spec: Dict[str, Any], profile: Any = None, points: Any = None) -> Dict[str, Any]:
    """The keyword arguments that give a result back."""
    out = {key: spec[key] for key in ("theta", "a", "b", "f", "beta_deg", "q", "alpha_deg")}
    out["k"] = None if spec["k"] == math.inf else spec["k"]
    out.update(load=spec["load"], method=spec["method"], n=spec["n"])
    if spec.get("tol") is not None:
        out["tol"] = spec["tol"]
    units = spec["units"]
    if units is not None and list(units) == ["preset"]:
        units = units["preset"]
    out["units"] = units
    if profile is not None:
        out["profile"] = profile
    if points is not None:
        out["points"] = points
    if spec.get("mu"):
        out["mu"] = spec["mu"]
    if spec.get("motion") not in (None, "translate"):
        out["motion"] = spec["motion"]
    for key in ("x0", "y0", "gamma_deg", "path"):
        if spec.get(key) is not None:
            out[key] = spec[key]
    return out


def solve(
    *,
    theta: float = 1.0,
    a: float = 0.0,
    b: float = 0.0,
    k: Optional[float] = None,
    f: float = 0.0,
    beta_deg: float = 0.0,
    load: str = "dp",
    q: float = 0.0,
    alpha_deg: float = 0.0,
    method: str = "accurate",
    n: Optional[int] = None,
    tol: Optional[float] = None,
    units: Any = None,
    profile: Any = None,
    points: Any = None,
    mu: Any = None,
    motion: Any = None,
    x0: Any = None,
    y0: Any = None,
    gamma_deg: Any = None,
    path: Any = None,
) -> Solution:
    """Solves one equilibrium of the whisker [3.27] (``vibrissa solve``).

    Parameters (the CLI's flags): ``theta`` tip/base diameter ratio (0.01..1), ``a, b`` the
    Cesaro pre-curvature kappa0(s) = a s + b, ``k`` the base spring (None or ``math.inf``:
    rigid), ``f, beta_deg, load`` the tip force, its angle and kind (``"dp"`` direction- or
    ``"ap"`` angle-preserving), ``q, alpha_deg`` the fluid load per length and its angle,
    ``method`` (``"accurate"``, ``"fdm"``, ``"fdm-richardson"``, ``"rk4"``,
    ``"multiple-shooting"``, ``"collocation"``: Lobatto collocation with its own load
    continuation, ``tol`` its accuracy, default 1e-8), ``n`` grid
    intervals (output intervals for ``accurate``; default 100), ``units`` (module docs).
    ``tol``: the accuracy asked for (absolute, in [1e-12, 1e-2]); with ``method="accurate"``
    (the default) it selects ``"auto"``, the cheapest model and method whose error
    estimate meets it (``stats["method_used"]`` says which method: ``"picard"`` for weak and
    moderate loads; ``stats["model_used"]`` which model: ``"linear"`` where linear
    small-deflection theory provably meets it, else ``"elastica"``).
    None: ``accurate``'s default accuracy (estimate <= 1e-8).
    ``profile``, ``points``, ``mu`` and the base motion (``motion, x0, y0, gamma_deg,
    path``) are ignored (as ``vibrissa solve SCENE.ron`` ignores them), so that ``solve(**load_scene(path))`` works.

    Returns a :class:`Solution`. Raises :class:`InvalidInput` for a bad parameter and
    :class:`SolverError` when no solution meets the accuracy.
    """
    if tol is not None and method == "accurate":
        method = "auto"
    spec = _model_spec(theta, a, b, k, f, beta_deg, load, q, alpha_deg, method, n, units)
    spec["tol"] = None if tol is None else number("tol", tol)
    return Solution(_core.solve(spec), _scene(spec))


def sweep(
    *,
    profile: Any = None,
    points: int = 200,
    theta: float = 1.0,
    a: float = 0.0,
    b: float = 0.0,
    k: Optional[float] = None,
    q: float = 0.0,
    alpha_deg: float = 0.0,
    f: float = 0.0,
    beta_deg: float = 0.0,
    load: str = "dp",
    method: str = "accurate",
    n: Optional[int] = None,
    tol: Optional[float] = None,
    units: Any = None,
    mu: float = 0.0,
    motion: str = "translate",
    x0: float = 0.0,
    y0: float = 0.0,
    gamma_deg: float = 0.0,
    path: Any = None,
) -> Sweep:
    """Sweeps the whisker past the obstacle ``profile`` under the flow (``vibrissa sweep``).

    ``profile``: a CLI profile string (``"g1"``, ``"g2"``, ``"ge"``,
    ``"parabola:a,xv,yv"``, ``"cosh:a,c,xv,d"``, ``"circle:xc,yc,r"``,
    ``"points:FILE.csv"``) or a pair of 1-D arrays ``(x, y)`` of a tabulated contour (in the
    scene's units, x increasing). ``points``: contact rows, evenly spaced in x0 (plus a row
    at each event). ``q, alpha_deg``: the flow (alpha in (-90, 90) degrees). The tip force
    must stay 0 (the sweep computes the contact force) and the method ``accurate``.
    ``tol``: the accuracy asked for of every row (absolute, dimensionless, in [1e-12, 1e-2];
    ``sweep --tol``): the contact rows solved at tolerances derived from it, each with an
    a-posteriori error estimate (``summary["max_estimate"]``, ``summary["max_estimate_row"]``);
    a row whose estimate exceeds it raises :class:`SolverError` naming the row. None: the
    sweep's own accuracy (~1e-10 per row, no estimates).
    ``mu``: the Coulomb friction coefficient at the contact (dimensionless, in [0, 10];
    ``sweep --mu``): stick (the touching point of the whisker stays put, |ft| <= mu f) and
    slip (|ft| = mu f against the sliding), in the columns ``ft`` and ``slip`` and the
    ``friction_events``. 0 is the frictionless sweep, bit for bit.
    ``motion``: how the base moves (``sweep --motion``): ``"translate"`` (the base at
    (x0, 0) moves towards -x), ``"rotate"`` (whisking: the base stays at (``x0``, ``y0``),
    in the scene's length unit, and turns counter-clockwise from ``gamma_deg`` degrees until
    the whisker separates; rows evenly spaced in the turn), or ``"path"`` with ``path`` a
    pandas DataFrame or a dict of 1-D arrays ``x0, y0, gamma_deg`` and optionally ``k`` (the
    follicle stiffness along the path, in the scene's stiffness unit). ``x0, y0,
    gamma_deg`` other than 0 belong to a rotation. Profiles also name obstacles touched
    from any side: ``"peg:x,y"`` (a point) and ``"disc:x,y,r"``.

    Returns a :class:`Sweep`. Raises :class:`InvalidInput`, :class:`NoContact` when the
    whisker never touches the obstacle, :class:`SolverError` when a contact phase cannot be
    solved to the accuracy.
    """
    spec = _model_spec(theta, a, b, k, f, beta_deg, load, q, alpha_deg, method, n, units)
    spec["tol"] = number("tol", tol)
    spec["profile"] = profile_spec(profile)
    spec["points"] = points
    spec["mu"] = number("mu", mu)
    spec.update(_motion_spec(motion, x0, y0, gamma_deg, path))
    raw = _core.sweep(spec)
    return Sweep(raw, _scene(spec, profile if profile is not None else raw["scene"]["profile"], points))


def _motion_spec(motion: Any, x0: Any, y0: Any, gamma_deg: Any, path: Any) -> Dict[str, Any]:
    """The base motion's entries of a sweep's spec: the motion's name, the start pose of a
    rotation (given only where it is one, or not 0: the library refuses a start pose without
    a rotation), and a path's columns as contiguous float64 arrays."""
    if not isinstance(motion, str):
        raise InvalidInput(f"invalid value `{motion!r}` for `motion`: expected \"translate\", \"rotate\" or \"path\"")
    out: Dict[str, Any] = {"motion": motion}
    rotate = motion.strip().lower() == "rotate"
    for name, v in (("x0", x0), ("y0", y0), ("gamma_deg", gamma_deg)):
        v = number(name, v)
        if rotate or (v is not None and v != 0.0):
            out[name] = v
    if path is not None:
        cols: Dict[str, Any] = {}
        for name in ("x0", "y0", "gamma_deg", "k"):
            try:
                c = path[name]
            except (KeyError, IndexError, TypeError):
                if name == "k":
                    continue
                raise InvalidInput(
                    f"invalid value `{name}` for `path`: missing column: a path has the "
                    "columns x0, y0, gamma_deg[, k]"
                ) from None
            c = getattr(c, "to_numpy", lambda c=c: c)()
            try:
                arr = np.ascontiguousarray(c, dtype=np.float64)
            except (TypeError, ValueError):
                raise InvalidInput(
                    f"invalid value `{name}` for `path`: a column must be a 1-D sequence of numbers"
                ) from None
            if arr.ndim != 1:
                raise InvalidInput(
                    f"invalid value `{name}` for `path`: a column must be a 1-D sequence of numbers"
                )
            cols[name] = arr
        out["path"] = cols
    return out


def reconstruct(
    log: Any,
    profile: Any = None,
    q: Optional[float] = None,
    alpha_deg: Optional[float] = None,
    noise: Optional[float] = None,
    *,
    theta: Optional[float] = None,
    a: Optional[float] = None,
    b: Optional[float] = None,
    k: Optional[float] = None,
    method: str = "accurate",
    tolerance: Any = None,
    tol: Optional[float] = None,
    units: Any = None,
    mu: Any = None,
    **ignored: Any,
) -> Reconstruction:
    """Identifies the flow and reconstructs the obstacle's contour from a log of base
    observables [ch. 6] (``vibrissa reconstruct``).

    ``log``: a :class:`Sweep`, a pandas DataFrame or a dict of 1-D arrays with at least the
    columns ``x0, Ax, Ay, MA, phi0`` (in the scene's units), rows in any order; each contact
    row's point is computed on its own. ``q``, ``alpha_deg``: the flow if known (else
    identified from the rows before contact). ``noise``: the log's relative noise level
    (else estimated). ``profile``: the true contour, if known, for the ``error`` column
    [6.11]. The whisker (``theta, a, b, k, units``) is the one that recorded the log: a
    keyword left at None is the Sweep's own when ``log`` is a :class:`Sweep` (as
    ``vibrissa reconstruct DIR`` reads the sweep's scene), else the CLI's default (theta 1,
    a = b = 0, rigid, dimensionless). ``method``: ``"accurate"`` or ``"thesis"``;
    ``tolerance``: the consistency tolerance of a row (default 1e-6 accurate, 1e-3 thesis;
    ``"none"`` for noisy logs). ``tol``: the accuracy asked for of every contact point
    (absolute, dimensionless, in [1e-12, 1e-2]; method ``accurate``; ``reconstruct --tol``):
    each point with an a-posteriori error estimate (``summary["max_estimate"]``,
    ``summary["max_estimate_row"]``); a point whose estimate exceeds it raises
    :class:`SolverError` naming its row. Other keywords of a scene (``f, beta_deg, load, n,
    points``) are ignored, so that ``reconstruct(log, **load_scene(path))`` works (the
    scene's ``q`` is then taken as given: pass ``q=None`` to identify it).

    ``mu`` (Coulomb friction at the contact, issue 39; ``reconstruct --mu``): None (the
    default) gives the frictionless points and beside them mu identified from the sliding rows
    with its standard error (``Reconstruction.mu``; a log that proves friction warns, its
    ``sigma`` widened to cover the frictional points); ``"identify"`` gives the frictional
    points (``f`` the normal part of the contact force, ``ft`` the tangential part, ``slip``)
    with mu identified; a number in [0, 10] gives the frictional points with mu fixed (``0``:
    the frictionless points, checked for friction). Method ``accurate`` only for ``mu`` given;
    a scene's ``mu`` (``**load_scene(path)``) is taken as given. Warnings of the CLI's stderr
    are issued as :class:`UserWarning`.

    Returns a :class:`Reconstruction`. Raises :class:`InvalidInput` for a bad parameter or
    log (naming the row: ``log row:N``), :class:`SolverError` when no row fits.
    """
    unknown = sorted(set(ignored) - {"f", "beta_deg", "load", "n", "points"})
    if unknown:
        raise TypeError(f"reconstruct() got an unexpected keyword argument {unknown[0]!r}")
    theta, a, b, k, units = _whisker_of(log, theta, a, b, k, units)
    spec = whisker_spec(theta, a, b, k, units)
    spec.update(
        q=number("q", q),
        alpha_deg=number("alpha_deg", alpha_deg),
        noise=number("noise", noise),
        method=method,
        tolerance=tolerance,
        tol=number("tol", tol),
        profile=profile_spec(profile),
        # a number as the CLI would get it (Python's repr, so messages quote it alike)
        mu=mu if mu is None or isinstance(mu, str) else repr(float(number("mu", mu))),
    )
    raw = _core.reconstruct(log_columns(log), spec)
    for w in raw.get("warnings", ()):
        warnings.warn(w, UserWarning, stacklevel=2)
    return Reconstruction(raw)


def calibrate(
    logs: Any,
    profile: Any = None,
    *,
    fit: Any = None,
    theta: Optional[float] = None,
    a: Optional[float] = None,
    b: Optional[float] = None,
    k: Optional[float] = None,
    q: Optional[float] = None,
    alpha_deg: Optional[float] = None,
    starts: Optional[int] = None,
    units: Any = None,
) -> Calibration:
    """Fits the whisker's own parameters to logs of sweeps past known contours
    (``vibrissa calibrate``).

    ``logs``: one log or a list of logs (each a :class:`Sweep`, a DataFrame or a dict of 1-D
    arrays with ``x0, Ax, Ay, MA, phi0`` in the scene's units), or a list of ``(log,
    profile)`` pairs; ``profile``: the known contour of every log without its own (a profile
    string or ``(x, y)`` arrays; a :class:`Sweep` brings its own). ``fit``: the parameters, a
    list or comma-separated string of ``theta, a, b, k, ei, mu`` (``ei`` in physical units
    only; ``mu`` the friction coefficient at the contact, from the sliding rows: ``.mu``;
    default ``theta, a, b, k``). ``theta, a, b, k, units``: the start whisker (those left at
    None from the first Sweep's scene). ``q`` with ``alpha_deg``: a known flow held fixed
    (else each log's flow is fitted). ``starts``: local fits at most (default 4).

    Returns a :class:`Calibration`. Raises :class:`InvalidInput` for a bad parameter or log,
    :class:`SolverError` when the fit fails.
    """
    items = logs if isinstance(logs, (list, tuple)) and not _is_pair(logs) else [logs]
    pairs = []
    first = None
    for item in items:
        log, prof = item if _is_pair(item) else (item, None)
        if prof is None and isinstance(log, Sweep):
            prof = log.scene.get("profile")
        if prof is None:
            prof = profile
        if prof is None:
            raise InvalidInput("profile: every log needs its known contour (profile=... or (log, profile))")
        first = first if first is not None else log
        pairs.append((log_columns(log), profile_spec(prof)))
    theta, a, b, k, units = _whisker_of(first, theta, a, b, k, units)
    spec = whisker_spec(theta, a, b, k, units)
    if isinstance(fit, (list, tuple)):
        fit = ",".join(fit)
    spec.update(
        fit=fit,
        starts=number("starts", starts),
        q=number("q", q),
        alpha_deg=number("alpha_deg", alpha_deg),
    )
    return Calibration(_core.calibrate(pairs, spec))


def _is_pair(x: Any) -> bool:
    """Whether ``x`` is a ``(log, profile)`` pair."""
    return (
        isinstance(x, tuple)
        and len(x) == 2
        and not isinstance(x[0], (str, float, int))
        and (isinstance(x[1], str) or (isinstance(x[1], tuple) and len(x[1]) == 2))
    )


def _whisker_of(log: Any, theta: Any, a: Any, b: Any, k: Any, units: Any) -> tuple:
    """The whisker keywords, those left at None taken from a Sweep's scene."""
    scene = log.scene if isinstance(log, Sweep) else {}

    def pick(v: Any, key: str, default: Any) -> Any:
        return v if v is not None else scene.get(key, default)

    return (
        pick(theta, "theta", 1.0),
        pick(a, "a", 0.0),
        pick(b, "b", 0.0),
        pick(k, "k", None),
        pick(units, "units", None),
    )


class Streamer:
    """One sensor row in, its contact point out (``vibrissa reconstruct --stream``).

    ``Streamer(q=None, alpha_deg=None, noise=None, theta=..., a=..., b=..., k=...,
    units=None)``: with the flow given, every row is decided at once; otherwise rows are
    held until the first row before contact fixes the flow. ``push(x0, Ax, Ay, MA, phi0)``
    returns the row's contact point (a dict: row (0-based), x0, x, y, s1, f, psi, phase,
    sigma, residual, hypotheses) or None (a row before contact, or held); ``points`` lists
    every point released so far (held rows included); ``finish()`` reconstructs rows still
    held and returns their points.
    """

    def __init__(
        self,
        q: Optional[float] = None,
        alpha_deg: Optional[float] = None,
        noise: Optional[float] = None,
        *,
        theta: float = 1.0,
        a: float = 0.0,
        b: float = 0.0,
        k: Optional[float] = None,
        tolerance: Any = None,
        units: Any = None,
        **ignored: Any,
    ) -> None:
        unknown = sorted(set(ignored) - {"f", "beta_deg", "load", "n", "points", "profile", "method"})
        if unknown:
            raise TypeError(f"Streamer() got an unexpected keyword argument {unknown[0]!r}")
        spec = whisker_spec(theta, a, b, k, units)
        spec.update(
            q=number("q", q),
            alpha_deg=number("alpha_deg", alpha_deg),
            noise=number("noise", noise),
            tolerance=tolerance,
        )
        self._inner = _core.Streamer(spec)

    def push(
        self,
        x0: float,
        Ax: float,
        Ay: float,
        MA: float,
        phi0: float,
        y0: float = 0.0,
        gamma: float = 0.0,
    ) -> Optional[Dict[str, Any]]:
        """Takes the next row; returns its contact point, or None (before contact, or held
        until the flow is known). A row of a rotation or a path gives its base pose ``y0``
        and ``gamma`` (radians) too (0 for the translating sweep)."""
        return self._inner.push(
            float(x0), float(Ax), float(Ay), float(MA), float(phi0), float(y0), float(gamma)
        )

    def finish(self) -> list:
        """Ends the stream; returns the points of rows still held."""
        return self._inner.finish()

    @property
    def points(self) -> list:
        """Every point released so far, in row order."""
        return self._inner.points

    @property
    def rows(self) -> int:
        """Rows received so far."""
        return self._inner.rows

    @property
    def flow(self) -> Optional[tuple]:
        """``(q, alpha_deg)`` once known, else None."""
        return self._inner.flow

    def __repr__(self) -> str:
        return repr(self._inner)


def load_scene(path: Any) -> Dict[str, Any]:
    """Reads a scene RON file (checked as the CLI checks it) into a dict of the keyword
    arguments of :func:`solve` / :func:`sweep` (``theta, a, b, k, f, beta_deg, load, q,
    alpha_deg, method, n, units, profile, points``). A ``points:FILE.csv`` profile's path is
    made relative to the working directory."""
    return scene_kwargs(_core.load_scene(str(path)))
