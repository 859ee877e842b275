"""Parameter studies: many scenes mapped over workers, one DataFrame row per scene.

Without a client the scenes run on threads of this process (the native core releases the
GIL, so every core is used); with a ``dask.distributed.Client`` they run on that cluster, in
chunks. A scene's result does not depend on the split: each row is computed on its own from
its scene alone (only ``wall_time_s`` varies).
"""

from __future__ import annotations

import math
import os
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Dict, List, Optional, Sequence

import numpy as np

TASKS = ("solve", "sweep", "reconstruct")


def run_scene(scene: Dict[str, Any], task: str = "sweep") -> Dict[str, Any]:
    """One scene of a study: its parameters, then the task's results, ``wall_time_s`` and
    ``error`` / ``error_class`` (None on success). Never raises for a refused scene."""
    from . import reconstruct, solve, sweep
    from ._errors import VibrissaError

    row: Dict[str, Any] = dict(scene)
    t0 = time.perf_counter()
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
    except VibrissaError as e:
        row.update(error=str(e), error_class=type(e).__name__)
    row["wall_time_s"] = time.perf_counter() - t0
    return row


def run_chunk(scenes: Sequence[Dict[str, Any]], task: str = "sweep") -> List[Dict[str, Any]]:
    """The rows of a chunk of scenes, in order (the unit of work sent to a Dask worker)."""
    return [run_scene(s, task) for s in scenes]


def study(
    scenes: Sequence[Dict[str, Any]],
    task: str = "sweep",
    client: Any = None,
    workers: Optional[int] = None,
    chunk_size: Optional[int] = None,
) -> Any:
    """Runs ``task`` (``"solve"``, ``"sweep"`` or ``"reconstruct"``: a sweep, then its log
    reconstructed with the flow identified) for every scene (a dict of keyword arguments of
    :func:`vibrissa.sweep` / :func:`vibrissa.solve`) and returns a pandas DataFrame, one row
    per scene in the given order: the scene's parameters, then ``first_contact``,
    ``separation``, ``phases``, ``rows``, ``contact_rows``, ``max_f`` (sweeps; tip and base
    values for solves; identified flow and max contour error for reconstructions),
    ``wall_time_s`` and ``error`` / ``error_class`` (the message and class of a refused
    scene; the study goes on).

    ``client``: a ``dask.distributed.Client`` to run on its cluster (the scenes are sent in
    chunks of ``chunk_size``, default about four chunks per worker thread); None runs on
    ``workers`` threads of this process (default: every core).
    """
    import pandas as pd

    if task not in TASKS:
        from ._errors import InvalidInput

        raise InvalidInput(
            f"invalid value `{task}` for `task`: expected one of {', '.join(TASKS)}"
        )
    scenes = [dict(s) for s in scenes]
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
