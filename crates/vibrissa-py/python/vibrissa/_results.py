"""Result classes: columns as numpy arrays (attributes, and by name), summaries as plain
values. They hold only numpy arrays and builtins, so they pickle (multiprocessing, Dask)."""

from __future__ import annotations

from typing import Any, Dict, Iterator, List, Optional, Sequence

import numpy as np


class _Columns:
    """Columns as attributes (``r.x0``) and by name (``r["x0"]``), one row each."""

    _names: Sequence[str] = ()

    def __init__(self, columns: Dict[str, Any]) -> None:
        for name in self._names:
            setattr(self, name, columns[name])

    def __getitem__(self, name: str) -> np.ndarray:
        if name not in self._names:
            raise KeyError(f"{name!r}: the columns are {', '.join(self._names)}")
        return getattr(self, name)

    def __len__(self) -> int:
        return len(getattr(self, self._names[0]))

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)

    def keys(self) -> List[str]:
        """The column names."""
        return list(self._names)

    def to_pandas(self) -> Any:
        """The columns as a pandas DataFrame (requires pandas)."""
        import pandas as pd

        return pd.DataFrame({name: getattr(self, name) for name in self._names})


class Solution(_Columns):
    """One equilibrium of the whisker [3.27], base (s = 0) to tip (s = 1).

    Columns ``s, x, y, phi, kappa, m`` (lengths, curvature and moment in the scene's units:
    whisker lengths, or mm, 1/mm and N mm for a physical scene); ``tip`` (x, y, phi),
    ``base`` (the base observables Ax, Ay, MA, phi0 [6.1]), ``stats`` (``method_used``,
    ``model_used``, ``error_estimate``, ``tolerance``, iterations, ...), ``scene`` (the
    keyword arguments that give this solution back), ``load_path`` (None where loading from zero is monotone;
    else a dict: ``folds`` [{lambda, phi1, phi0}] passed on the way, ``arrival`` the
    equilibrium returned, its first arrival at full load, ``other_equilibria`` further along
    the path)."""

    _names = ("s", "x", "y", "phi", "kappa", "m")

    def __init__(self, raw: Dict[str, Any], scene: Dict[str, Any]) -> None:
        super().__init__(raw["columns"])
        self.tip: Dict[str, float] = raw["tip"]
        self.base: Dict[str, float] = raw["base"]
        self.stats: Dict[str, Any] = raw["stats"]
        self.units: str = raw["units"]
        self.length_unit: str = raw["length_unit"]
        self.force_unit: str = raw["force_unit"]
        self.moment_unit: str = raw["moment_unit"]
        self.method: str = raw["method"]
        self.scene: Dict[str, Any] = scene
        self.load_path: Optional[Dict[str, Any]] = raw.get("load_path")

    def __repr__(self) -> str:
        t, b, st = self.tip, self.base, self.stats
        return (
            f"Solution(tip=(x={t['x']:.6g}, y={t['y']:.6g}, phi={t['phi']:.6g}), "
            f"base=(Ax={b['Ax']:.6g}, Ay={b['Ay']:.6g}, MA={b['MA']:.6g}, "
            f"phi0={b['phi0']:.6g}), method_used={st['method_used']!r}, "
            f"error_estimate={st['error_estimate']:.1e}, points={len(self)}, "
            f"units={self.units!r})"
        )


class Sweep(_Columns):
    """A quasi-static sweep of the whisker past an obstacle under the flow [ch. 5].

    Columns as in ``observables.csv``: ``x0, Ax, Ay, MA, phi0, f, s1, xc, yc, psi``
    (float64; before contact f = 0, s1 = 1 (the flow loads the whole whisker) and the contact
    point and angle are NaN) and ``phase`` (``"A"``, ``"B"``, ``"none"``), then ``ft`` (the
    tangential part of the contact force along the contour's tangent; 0 without friction;
    ``f`` is the normal part), ``slip`` (``"stick"``, ``"slip"``, ``"none"`` before contact
    and without friction), ``y0`` and ``gamma`` (the base pose, gamma in radians: 0 for the translating
    sweep); rows in the order of the motion (x0 strictly falling for a translation, gamma
    rising for a rotation). ``first_contact``
    (``"tip"`` / ``"tangential"``), ``separation`` (``"snap"``, ``"release"``, ...),
    ``phases`` (e.g. ``"AB"``), ``events`` (dicts: event, row (1-based), x0), ``mu`` (the
    friction coefficient), ``friction_events`` (dicts: event ``"stick→slip"`` /
    ``"slip→stick"``, row, x0, xc, f, ft), ``summary`` (the CLI's ``sweep --json`` object),
    ``scene`` (the keyword arguments that give this sweep back)."""

    _names = (
        "x0", "Ax", "Ay", "MA", "phi0", "f", "s1", "phase", "xc", "yc", "psi",
        "ft", "slip", "y0", "gamma",
    )

    def __init__(self, raw: Dict[str, Any], scene: Dict[str, Any]) -> None:
        cols = dict(raw["columns"])
        cols["phase"] = np.array(raw["phase"], dtype=str)
        cols["slip"] = np.array(raw["slip"], dtype=str)
        super().__init__(cols)
        s = raw["summary"]
        self.summary: Dict[str, Any] = s
        self.first_contact: str = s["first_contact"]
        self.separation: str = s["separation"]
        self.phases: str = s["phases"]
        self.events: List[Dict[str, Any]] = s["events"]
        self.mu: float = s["mu"]
        self.friction_events: List[Dict[str, Any]] = s["friction_events"]
        self.motion: str = s.get("motion", "translate")
        self.pose: Dict[str, Any] = s.get("pose", {})
        self.k: Optional[np.ndarray] = raw["columns"].get("k")
        self.units: str = s["units"]
        self.scene: Dict[str, Any] = scene

    @property
    def contact(self) -> np.ndarray:
        """Boolean mask of the rows in contact."""
        return self.phase != "none"

    def __repr__(self) -> str:
        return (
            f"Sweep(rows={len(self)}, first_contact={self.first_contact!r}, "
            f"separation={self.separation!r}, phases={self.phases!r}, "
            + (f"mu={self.mu!r}, " if self.mu else "")
            + f"profile={self.summary.get('profile')!r}, units={self.units!r})"
        )


class Reconstruction(_Columns):
    """The contour reconstructed from a log of base observables [ch. 6].

    One row per row of the log, in its order: ``x0`` (as given), the contact point ``x, y``,
    ``s1``, ``f``, ``psi``, ``phase`` (``"A"``, ``"B"``, ``"none"`` before contact, where the
    other columns hold NaN), ``sigma`` (the point's error estimate, a length), ``residual``,
    ``hypotheses`` (how many phase hypotheses fitted), and ``error`` (the distance to the
    true contour [6.11]) when a ``profile`` was given. ``q``, ``alpha_deg``: the flow
    (identified unless given); ``noise``: the relative noise level used.

    Friction (issue 39; ``reconstruct(mu=...)``): ``ft`` the tangential part of each contact
    force along the contour's tangent (a force; the frictional reconstruction's, NaN where
    the tangent is unknown or no mu was identified) and ``slip`` (``"slip"``, ``"stick"``,
    ``"none"``) per row; ``mu`` a dict ``value, stderr, given, rows, chi2_dof`` (identified
    from ``rows`` sliding rows, or given; None when no row slides with a force, or with
    method ``thesis``/``tol``); ``friction`` the evidence (``sliding_rows, mu_violations,
    friction_z, friction_line, proves_friction``, or ``identified: False, reason``);
    ``warnings`` what the CLI prints on stderr (a log that proves friction)."""

    _base_names = (
        "x0", "x", "y", "s1", "f", "psi", "phase", "sigma", "residual", "hypotheses", "ft", "slip",
    )
    #: The pose columns of a log of any base motion (issue 38), copied as given where the
    #: log had them and moved (a translate log has none): ``y0``, ``gamma`` (rad), ``k``.
    _pose_names = ("y0", "gamma", "k")

    def __init__(self, raw: Dict[str, Any]) -> None:
        cols = dict(raw["columns"])
        cols["phase"] = np.array(raw["phase"], dtype=str)
        cols["slip"] = np.array(raw.get("slip", ["none"] * len(raw["phase"])), dtype=str)
        if "ft" not in cols:
            cols["ft"] = np.full(len(raw["phase"]), np.nan)
        self._names = (
            self._base_names
            + (("error",) if "error" in cols else ())
            + tuple(n for n in self._pose_names if n in cols)
        )
        super().__init__(cols)
        s = raw["summary"]
        self.summary: Dict[str, Any] = s
        self.q: float = s["q"]
        self.alpha_deg: float = s["alpha_deg"]
        self.noise: float = s["noise"]
        self.q_given: bool = s["q_given"]
        self.alpha_given: bool = s["alpha_given"]
        self.units: str = s["units"]
        #: The obstacle the contact points give (issue 38): ``{"kind": "peg", "x", "y",
        #: "stderr_x", "stderr_y", "spread", "rows"}`` for a peg (the ``profile`` a peg, or
        #: every point the same point), ``{"kind": "disc", "x", "y", "r", "stderr": [3],
        #: "rms", "rows"}`` for a ``disc:`` profile (the least-squares circle); else None.
        self.obstacle: Optional[Dict[str, Any]] = raw.get("obstacle")
        #: Coulomb's mu (issue 39): ``{"value", "stderr", "given", "rows", "chi2_dof"}``, or None.
        self.mu: Optional[Dict[str, Any]] = raw.get("mu")
        #: The friction evidence of the log (see the class docs).
        self.friction: Dict[str, Any] = raw.get("friction") or {}
        #: The warnings issued (the CLI's stderr lines).
        self.warnings: List[str] = list(raw.get("warnings", ()))

    @property
    def contact(self) -> np.ndarray:
        """Boolean mask of the rows with a contact point."""
        return self.phase != "none"

    def _mu_repr(self) -> str:
        m = self.mu
        if not m:
            return ""
        if m.get("given"):
            return f", mu={m['value']:.6g} given"
        return f", mu={m['value']:.6g}±{m['stderr']:.1e} ({m['rows']} sliding rows)"

    def __repr__(self) -> str:
        err = ""
        if "error" in self._names and self.contact.any():
            err = f", max_error={np.nanmax(self.error):.2e}"
        return (
            f"Reconstruction(rows={len(self)}, points={int(self.contact.sum())}, "
            f"q={self.q:.6g}{' given' if self.q_given else ''}, "
            f"alpha_deg={self.alpha_deg:.4g}{' given' if self.alpha_given else ''}, "
            f"max_sigma={np.nanmax(self.sigma) if self.contact.any() else float('nan'):.1e}"
            f"{err}{self._mu_repr()}, units={self.units!r})"
        )


class Calibration:
    """The whisker's own parameters fitted to logs of sweeps past known contours
    (``vibrissa calibrate``).

    ``parameters``: per fitted name (``theta, a, b, k, ei, mu``) a dict ``value, stderr,
    identifiable, unit`` (``value`` and ``stderr`` None where the logs cannot determine the
    parameter; ``k`` also ``rigid`` and its ``compliance``); ``whisker``: the calibrated
    whisker as keywords (``theta, a, b, k``, scene units; unidentifiable parameters at their
    start values) for ``solve``, ``sweep``, ``reconstruct``; ``logs``: per log its fitted flow
    (``q, q_stderr, alpha_deg, alpha_deg_stderr``) and row counts; ``rms_residual``: the RMS
    distance of the reconstructed contact points to their contours (scene length unit);
    ``correlation``, ``determined`` (combinations of unidentifiable parameters the logs do
    determine), ``noise_level``, ``warnings``; ``mu``: with ``mu`` fitted, a dict ``value,
    stderr`` (None when no row slides: not identifiable), ``identifiable, sliding_rows,
    stick_rows, lower_bound`` (the sticking rows' largest ``|ft|/fn``), ``cone_violations``;
    None when ``mu`` was not fitted; ``raw`` the whole object."""

    def __init__(self, raw: Dict[str, Any]) -> None:
        self.raw: Dict[str, Any] = raw
        self.parameters: Dict[str, Dict[str, Any]] = raw["parameters"]
        w = dict(raw["whisker"])
        w.pop("ei", None)
        if w.get("k") is None:
            w["k"] = None
        self.whisker: Dict[str, Any] = w
        self.logs: List[Dict[str, Any]] = raw["logs"]
        self.rms_residual: float = optional(raw["rms_residual"])
        self.correlation: Dict[str, Any] = raw["correlation"]
        self.determined: List[str] = raw["determined"]
        self.noise_level: float = optional(raw["noise_level"])
        self.warnings: List[str] = raw["warnings"]
        self.units: str = raw["units"]
        self.mu: Optional[Dict[str, Any]] = raw.get("mu")

    def value(self, name: str) -> Optional[float]:
        """The estimate of parameter ``name`` (None if not identifiable)."""
        return self.parameters[name]["value"]

    def __repr__(self) -> str:
        parts = []
        for name, p in self.parameters.items():
            if p["identifiable"] and p["value"] is not None:
                parts.append(f"{name}={p['value']:.6g}±{p['stderr']:.1e}")
            elif p["identifiable"]:
                parts.append(f"{name}=inf (rigid)")
            else:
                parts.append(f"{name}=not identifiable")
        return f"Calibration({', '.join(parts)}, logs={len(self.logs)}, units={self.units!r})"


def log_columns(log: Any) -> Dict[str, np.ndarray]:
    """The columns ``x0, Ax, Ay, MA, phi0`` of a Sweep, a DataFrame or a dict of arrays,
    and the pose columns ``y0, gamma`` (and a path's ``k``) where present, as contiguous
    float64 arrays."""
    from ._errors import InvalidInput

    out: Dict[str, np.ndarray] = {}
    for name in ("x0", "Ax", "Ay", "MA", "phi0"):
        try:
            col = log[name]
        except (KeyError, IndexError, TypeError):
            raise InvalidInput(
                f"invalid value `{name}` for `log`: missing required column (a log needs "
                "x0, Ax, Ay, MA and phi0)"
            ) from None
        try:
            arr = np.ascontiguousarray(np.asarray(col, dtype=np.float64))
        except (TypeError, ValueError):
            raise InvalidInput(
                f"invalid value `{name}` for `log`: the column must be a 1-D array of numbers"
            ) from None
        if arr.ndim != 1:
            raise InvalidInput(
                f"invalid value `{name}` for `log`: the column must be 1-D, got shape {arr.shape}"
            )
        out[name] = arr
    # the base pose of a log of any motion (issue 38), and a path's k, where the log has it
    for name in ("y0", "gamma", "k"):
        try:
            col = log[name]
        except (KeyError, IndexError, TypeError):
            # a Sweep keeps a path's k as the attribute ``k`` (None without one)
            col = getattr(log, name, None) if name == "k" else None
            if not isinstance(col, np.ndarray):
                continue
        try:
            arr = np.ascontiguousarray(np.asarray(col, dtype=np.float64))
        except (TypeError, ValueError):
            raise InvalidInput(
                f"invalid value `{name}` for `log`: the column must be a 1-D array of numbers"
            ) from None
        out[name] = arr
    return out


def optional(v: Optional[float]) -> float:
    """``None`` as NaN."""
    return float("nan") if v is None else float(v)
