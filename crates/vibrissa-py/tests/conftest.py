"""Shared fixtures: the `vibrissa` command line (the reference the package must agree with
number for number) and small helpers."""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[3]


def cli_binary() -> Path:
    """The CLI built by the test script (`VIBRISSA_BIN`), else the workspace's release or
    debug build."""
    env = os.environ.get("VIBRISSA_BIN")
    candidates = [Path(env)] if env else []
    candidates += [ROOT / "target" / "release" / "vibrissa", ROOT / "target" / "debug" / "vibrissa"]
    for c in candidates:
        if c.is_file():
            return c
    raise RuntimeError(
        "the vibrissa CLI is not built: run `cargo build --release -p vibrissa-cli` "
        "(or set VIBRISSA_BIN)"
    )


class Cli:
    def __init__(self, binary: Path) -> None:
        self.binary = binary

    def run(self, *args: str, check: bool = True) -> subprocess.CompletedProcess:
        p = subprocess.run(
            [str(self.binary), *args], capture_output=True, text=True, cwd=ROOT, timeout=600
        )
        if check and p.returncode != 0:
            raise AssertionError(f"vibrissa {' '.join(args)} failed: {p.stderr}")
        return p

    def json(self, *args: str) -> dict:
        return json.loads(self.run(*args, "--json").stdout)

    def error(self, *args: str) -> str:
        """The one-line message of a failing command (without `error: `)."""
        p = self.run(*args, check=False)
        assert p.returncode != 0, f"vibrissa {' '.join(args)} succeeded"
        line = p.stderr.strip().splitlines()[-1]
        return line.removeprefix("error: ")


@pytest.fixture(scope="session")
def cli() -> Cli:
    return Cli(cli_binary())


def read_csv(path: Path) -> pd.DataFrame:
    """A CSV written by the CLI, each number parsed by Python's float() (exact for the
    shortest round-trip representation the CLI writes); text columns stay text."""
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:] if line]

    def column(j: int):
        cells = [r[j] for r in rows]
        try:
            return np.array([float(c) for c in cells])
        except ValueError:
            return np.array(cells, dtype=object)

    return pd.DataFrame({h: column(j) for j, h in enumerate(header)})


def assert_same(a: np.ndarray, b: np.ndarray, name: str) -> None:
    """Bit-identical columns (NaN where the other has NaN)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, f"{name}: shapes {a.shape} != {b.shape}"
    same = (a == b) | (np.isnan(a) & np.isnan(b))
    assert same.all(), f"{name}: first difference at row {np.argmin(same)}: {a[~same][:3]} vs {b[~same][:3]}"
