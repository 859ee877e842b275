"""The examples a researcher copies run as written (headless matplotlib) and draw their
figures."""

import os
import subprocess
import sys

import pytest

from conftest import ROOT

EXAMPLES = sorted((ROOT / "examples" / "python").glob("*.py"))


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.stem)
def test_example_runs(tmp_path, script):
    env = dict(os.environ, MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, str(script), str(tmp_path)], capture_output=True,
                       text=True, env=env, timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    pngs = list(tmp_path.glob("*.png"))
    assert pngs and all(f.stat().st_size > 10_000 for f in pngs)


def test_there_are_three_examples():
    assert {p.stem for p in EXAMPLES} >= {"quickstart", "flow_from_log", "study_snap_release"}
