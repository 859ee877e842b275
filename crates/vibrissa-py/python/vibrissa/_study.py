"""Parameter studies: many scenes mapped over workers, one DataFrame row per scene.

Without a client the scenes run on threads of this process (the native core releases the
GIL, so every core is used); with a ``dask.distributed.Client`` they run on that cluster, in
chunks. A scene's result does not depend on the split: each row is computed on its own from
its scene alone (only ``wall_time_s`` varies).
"""

from __future__ import annotations

import inspect
import math
import os
import time
from collections.abc import Iterable, Mapping
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

TASKS = ("solve", "sweep", "reconstruct")


def _keywords(task: str) -> List[str]:
    """The keyword arguments a scene of ``task`` may hold (those of :func:`vibrissa.solve`
    for ``"solve"``, else of :func:`vibrissa.sweep`)."""
    from . import solve, sweep

    fn = solve if task == "solve" else sweep
    return [
        name
        for name, p in inspect.signature(fn).parameters.items()
        if p.kind is inspect.Parameter.KEYWORD_ONLY
    ]


def _scene_problem(scene: Any, task: str) -> Optional[str]:
    """Why ``scene`` cannot be a scene of ``task`` (not a dict with string keys, or a key
    that is not a keyword argument of the task's function), or None."""
    if not isinstance(scene, Mapping):
        return (
            f"invalid value `{_short_repr(scene)}` for `scene`: expected a dict of keyword "
            f"arguments of vibrissa.{'solve' if task == 'solve' else 'sweep'}, "
            f"got {type(scene).__name__}"
        )
    allowed = _keywords(task)
    for key in scene:
        if not isinstance(key, str) or key not in allowed:
            return (
                f"invalid value `{key if isinstance(key, str) else _short_repr(key)}` for "
                "`scene key`: not a parameter of "
                f"vibrissa.{'solve' if task == 'solve' else 'sweep'} (expected "
                f"{', '.join(allowed)})"
            )
    return None


def _short_repr(value: Any, limit: int = 60) -> str:
    """``repr(value)`` cut to ``limit`` characters (an error row names, not dumps, a value)."""
    try:
        text = repr(value)
    except Exception:  # a broken __repr__ of a user's object
        text = f"<{type(value).__name__}>"
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _error_of(e: Exception) -> Tuple[str, str]:
    """The ``(error, error_class)`` of a failed scene: a :class:`VibrissaError` keeps its
    message and class; a ``TypeError`` or ``ValueError`` raised on a scene's value before it
    reached the core (a value of a type nothing can convert) is an ``InvalidInput``; any
    other exception (a bug of vibrissa) keeps its class, its message marked internal."""
    from ._errors import VibrissaError

    if isinstance(e, VibrissaError):
        return str(e), type(e).__name__
    if isinstance(e, (TypeError, ValueError, OverflowError, KeyError, IndexError)):
        return f"invalid scene: {e}", "InvalidInput"
    return f"internal error (please report): {type(e).__name__}: {e}", type(e).__name__


def run_scene(scene: Any, task: str = "sweep") -> Dict[str, Any]:
    """One scene of a study: its parameters, then the task's results, ``wall_time_s`` and
    ``error`` / ``error_class`` (None on success). Never raises for a scene: a key that is
    not a parameter, a value of a wrong type or out of range, a malformed profile, a
    solver's failure, each is an error row (``error_class`` ``"InvalidInput"``,
    ``"SolverError"`` or ``"NoContact"``)."""
    from . import reconstruct, solve, sweep

    row: Dict[str, Any] = dict(scene) if isinstance(scene, Mapping) else {}
    row = {k if isinstance(k, str) else _short_repr(k): v for k, v in row.items()}
    t0 = time.perf_counter()
    problem = _scene_problem(scene, task)
    if problem is not None:
        row.update(error=problem, error_class="InvalidInput")
        row["wall_time_s"] = time.perf_counter() - t0
        return row
    try:
        if task == "solve":
            sol = solve(**scene)
            row.update(
                tip_x=sol.tip["x"],
                tip_y=sol.tip["y"],
                tip_phi=sol.tip["phi"],
                Ax=sol.base["Ax"],
                Ay=sol.base["Ay"],
                MA=sol.base["MA"],
                phi0=sol.base["phi0"],
                method_used=sol.stats["method_used"],
                error_estimate=sol.stats["error_estimate"],
            )
        else:
            sw = sweep(**scene)
            contact = sw.contact
            row.update(
                first_contact=sw.first_contact,
                first_contact_x0=sw.summary["first_contact_x0"],
                separation=sw.separation,
                separation_x0=sw.summary["separation_x0"],
                phases=sw.phases,
                rows=len(sw),
                contact_rows=int(contact.sum()),
                max_f=float(np.max(sw.f[contact])) if contact.any() else 0.0,
                stick_rows=int((sw.slip == "stick").sum()),
                friction_events=len(sw.friction_events),
            )
            if task == "reconstruct":
                rec = reconstruct(sw, profile=scene.get("profile"))
                row.update(
                    q_identified=rec.q,
                    alpha_deg_identified=rec.alpha_deg,
                    points=int(rec.contact.sum()),
                    max_error=float(np.nanmax(rec.error)) if rec.contact.any() else math.nan,
                    max_sigma=float(np.nanmax(rec.sigma)) if rec.contact.any() else math.nan,
                )
        row.update(error=None, error_class=None)
    except Exception as e:  # every failure of one scene is its row's, never the study's
        error, error_class = _error_of(e)
        row.update(error=error, error_class=error_class)
    row["wall_time_s"] = time.perf_counter() - t0
    return row


def run_chunk(scenes: Sequence[Any], task: str = "sweep") -> List[Dict[str, Any]]:
    """The rows of a chunk of scenes, in order (the unit of work sent to a Dask worker)."""
    return [run_scene(s, task) for s in scenes]


def _positive(name: str, value: Any) -> Optional[int]:
    """``value`` as a positive integer (None stays None), else :class:`InvalidInput`."""
    from ._errors import InvalidInput

    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InvalidInput(
            f"invalid value `{_short_repr(value)}` for `{name}`: expected a positive integer"
        )
    return int(value)


def _checked_call(scenes: Any, task: Any, workers: Any, chunk_size: Any) -> List[Any]:
    """The scenes of a well-formed call of :func:`study` as a list (each still unchecked:
    its problems are its row's); raises :class:`InvalidInput` naming the argument of a
    malformed call."""
    from ._errors import InvalidInput

    if not isinstance(task, str) or task not in TASKS:
        raise InvalidInput(
            f"invalid value `{_short_repr(task)}` for `task`: expected one of {', '.join(TASKS)}"
        )
    _positive("workers", workers)
    _positive("chunk_size", chunk_size)
    if isinstance(scenes, (Mapping, str, bytes)) or not isinstance(scenes, Iterable):
        raise InvalidInput(
            f"invalid value `{_short_repr(scenes)}` for `scenes`: expected a sequence of "
            f"dicts (one per scene), got {type(scenes).__name__}"
        )
    return [dict(s) if isinstance(s, Mapping) else s for s in scenes]


def study(
    scenes: Sequence[Any],
    task: str = "sweep",
    client: Any = None,
    workers: Optional[int] = None,
    chunk_size: Optional[int] = None,
) -> Any:
    """Runs ``task`` (``"solve"``, ``"sweep"`` or ``"reconstruct"``: a sweep, then its log
    reconstructed with the flow identified) for every scene (a dict of keyword arguments of
    :func:`vibrissa.sweep` / :func:`vibrissa.solve`) and returns a pandas DataFrame, one row
    per scene in the given order: the scene's parameters (``mu`` among them: a study over
    the friction coefficient is a list of scenes that differ in ``mu``), then
    ``first_contact``, ``separation``, ``phases``, ``rows``, ``contact_rows``, ``max_f``,
    ``stick_rows``, ``friction_events`` (how many stick/slip switches) (sweeps; tip and base
    values for solves; identified flow and max contour error for reconstructions),
    ``wall_time_s`` and ``error`` / ``error_class`` (the message and class of a refused
    scene; the study goes on).

    Every failure of one scene is its row: an element that is not a dict, a key that is not
    a parameter of :func:`vibrissa.sweep` (:func:`vibrissa.solve` for ``task="solve"``), a
    value of a wrong type or out of range, a malformed profile (``error_class``
    ``"InvalidInput"``), a solver's failure (``"SolverError"``, ``"NoContact"``). Only a
    malformed call of ``study`` itself raises :class:`vibrissa.InvalidInput`: ``scenes``
    not a sequence (a dict, a string, None), an unknown ``task``, ``workers`` or
    ``chunk_size`` not a positive integer.

    ``client``: a ``dask.distributed.Client`` to run on its cluster (the scenes are sent in
    chunks of ``chunk_size``, default about four chunks per worker thread); None runs on
    ``workers`` threads of this process (default: every core).
    """
    import pandas as pd

    scenes = _checked_call(scenes, task, workers, chunk_size)
    if client is None:
        n = workers or os.cpu_count() or 1
        if n == 1 or len(scenes) <= 1:
            rows = [run_scene(s, task) for s in scenes]
        else:
            with ThreadPoolExecutor(max_workers=n) as pool:
                rows = list(pool.map(lambda s: run_scene(s, task), scenes))
    else:
        threads = sum(client.nthreads().values()) or 1
        size = chunk_size or max(1, math.ceil(len(scenes) / (4 * threads)))
        chunks = [scenes[i : i + size] for i in range(0, len(scenes), size)]
        futures = client.map(run_chunk, chunks, task=task, pure=False)
        rows = [r for chunk in client.gather(futures) for r in chunk]
    return pd.DataFrame(rows)
