"""Keyword arguments -> the normalised ``spec`` dict the native core reads, and a scene
file's JSON form -> keyword arguments."""

from __future__ import annotations

import math
from typing import Any, Dict, Mapping, Optional

import numpy as np

from ._errors import InvalidInput

#: Keys of a physical unit system (``units=dict(...)``), as in a scene file's
#: ``units: Physical(...)``.
UNIT_KEYS = ("preset", "length_mm", "base_diameter_mm", "youngs_modulus_gpa")


def units_spec(units: Any) -> Optional[Dict[str, Any]]:
    """``None`` (dimensionless), a preset name of the thesis's Table 2.2 (``"beta"``,
    ``"gamma"``, ``"A1"``, ``"E2"``) or a dict with some of :data:`UNIT_KEYS`."""
    if units is None:
        return None
    if isinstance(units, str):
        if units.strip().lower() == "dimensionless":
            return None
        return {"preset": units}
    if isinstance(units, Mapping):
        unknown = sorted(set(units) - set(UNIT_KEYS))
        if unknown:
            raise InvalidInput(
                f"invalid value `{unknown[0]}` for `units`: unknown key, expected "
                + ", ".join(UNIT_KEYS)
            )
        return {k: units[k] for k in UNIT_KEYS if units.get(k) is not None}
    raise InvalidInput(
        f"invalid value `{units!r}` for `units`: expected None, a preset name "
        "(beta, gamma, A1, E2) or a dict"
    )


def profile_spec(profile: Any) -> Any:
    """A profile string, or a pair of 1-D arrays ``(x, y)`` as float64 arrays."""
    if profile is None or isinstance(profile, str):
        return profile
    try:
        x, y = profile
    except (TypeError, ValueError):
        raise InvalidInput(
            f"invalid value `{type(profile).__name__}` for `profile`: expected a profile "
            "string (g1, circle:xc,yc,r, points:FILE.csv, ...) or a pair of 1-D arrays (x, y)"
        ) from None
    try:
        x = np.ascontiguousarray(x, dtype=np.float64)
        y = np.ascontiguousarray(y, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InvalidInput(
            "invalid value `points:(x, y) arrays` for `profile`: x and y must be 1-D arrays "
            f"of numbers ({e})"
        ) from None
    if x.ndim != 1 or y.ndim != 1 or len(x) != len(y):
        raise InvalidInput(
            "invalid value `points:(x, y) arrays` for `profile`: x and y must be 1-D arrays "
            f"of one length, got shapes {x.shape} and {y.shape}"
        )
    return (x, y)


def number(name: str, value: Any) -> Optional[float]:
    """A number (``None`` stays ``None``); anything else is an :class:`InvalidInput`."""
    if value is None:
        return None
    if isinstance(value, (bool, np.bool_)) or isinstance(value, str):
        raise InvalidInput(f"invalid value `{value!r}` for `--{name.replace('_', '-')}`: not a number")
    try:
        return float(value)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInput(
            f"invalid value `{value!r}` for `--{name.replace('_', '-')}`: not a number"
        ) from None


def whisker_spec(
    theta: Any, a: Any, b: Any, k: Any, units: Any
) -> Dict[str, Any]:
    """The whisker's part of a spec (``k=None`` or ``math.inf``: rigid)."""
    kk = number("k", k)
    return {
        "theta": number("theta", theta),
        "a": number("a", a),
        "b": number("b", b),
        "k": math.inf if kk is None else kk,
        "units": units_spec(units),
    }


def scene_kwargs(scene: Mapping[str, Any]) -> Dict[str, Any]:
    """A scene file's JSON form (``units, whisker, loads, profile, mu, sweep, method``) as the
    keyword arguments of :func:`vibrissa.solve` / :func:`vibrissa.sweep` (``mu`` only where
    the scene has friction, so that a frictionless scene's dict is as before)."""
    w = scene.get("whisker") or {}
    loads = scene.get("loads") or {}
    method = scene.get("method") or {}
    units = scene.get("units")
    if isinstance(units, Mapping) and "Physical" in units:
        phys = {k: v for k, v in (units["Physical"] or {}).items() if v is not None}
        units = phys["preset"] if list(phys) == ["preset"] else phys
    else:
        units = None
    sweep = scene.get("sweep")
    k = w.get("k")
    return {
        "theta": w.get("theta", 1.0),
        "a": w.get("a", 0.0),
        "b": w.get("b", 0.0),
        "k": None if k is None else k,
        "f": loads.get("f", 0.0),
        "beta_deg": loads.get("beta_deg", 0.0),
        "load": str(loads.get("load", "Dp")).lower(),
        "q": loads.get("q", 0.0),
        "alpha_deg": loads.get("alpha_deg", 0.0),
        "method": method.get("name", "accurate"),
        "n": method.get("n"),
        "units": units,
        "profile": scene.get("profile"),
        "points": None if sweep is None else sweep.get("points"),
        **({"mu": scene["mu"]} if scene.get("mu") else {}),
        # the base motion where the scene sets one (a path's table stays a file name:
        # give sweep() its columns as path=)
        **{key: scene[key] for key in ("motion", "x0", "y0", "gamma_deg", "path")
           if scene.get(key) is not None},
    }
