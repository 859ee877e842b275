"""Type stubs of the native core (`vibrissa._core`). The public API is `vibrissa`; these
functions take the normalised `spec` dicts built there."""

from typing import Any, Dict, List, Optional, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

def solve(spec: Dict[str, Any]) -> Dict[str, Any]:
    """{"columns": {s, x, y, phi, kappa, m: float64 arrays}, "tip", "base", "stats",
    "scene", "units", "method", "n", "length_unit", "force_unit", "moment_unit"}"""

def sweep(spec: Dict[str, Any]) -> Dict[str, Any]:
    """{"columns": {x0, Ax, Ay, MA, phi0, f, s1, xc, yc, psi, ft, y0, gamma: float64 arrays},
    "phase": list[str], "slip": list[str], "summary": dict (sweep --json), "scene": dict (scene.ron)}"""

def calibrate(logs: List[Tuple[Dict[str, npt.NDArray[np.float64]], Any]], spec: Dict[str, Any]) -> Dict[str, Any]: ...
def reconstruct(log: Dict[str, npt.NDArray[np.float64]], spec: Dict[str, Any]) -> Dict[str, Any]:
    """{"columns": {x0, x, y, s1, f, psi, sigma, residual, hypotheses, ft[, error]},
    "phase": list[str], "slip": list[str], "summary": dict, "mu": dict | None,
    "friction": dict, "warnings": list[str]} (``spec["mu"]``: None, "identify" or a number,
    as ``reconstruct --mu``)"""

def load_scene(path: str) -> Dict[str, Any]:
    """The scene file as JSON-like values."""

class Streamer:
    def __init__(self, spec: Dict[str, Any]) -> None: ...
    def push(
        self, x0: float, Ax: float, Ay: float, MA: float, phi0: float, y0: float = ..., gamma: float = ...
    ) -> Optional[Dict[str, Any]]: ...
    def finish(self) -> List[Dict[str, Any]]: ...
    @property
    def points(self) -> List[Dict[str, Any]]: ...
    @property
    def rows(self) -> int: ...
    @property
    def flow(self) -> Optional[Tuple[float, float]]: ...
