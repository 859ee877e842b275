"""The hostile-input suite of the Python package (issue #34 items 5 and 8): seeded random
scenes, logs and profiles a careless or unlucky user passes, each outcome checked for its
CLASS: a result, or a :class:`vibrissa.VibrissaError` (``InvalidInput``, ``SolverError``,
``NoContact``) whose message is one line naming the culprit; never another exception, never
a panic. A study of all of them returns one row per scene, every failure an error row.

The seed is ``VIBRISSA_HOSTILE_SEED`` (default below); the counts per class are printed
(``pytest -s``)."""

from __future__ import annotations

import math
import os
from collections import Counter

import numpy as np
import pytest

import vibrissa

SEED = int(os.environ.get("VIBRISSA_HOSTILE_SEED", "0x5EED0034"), 0)

#: Values a careless user passes where a number goes.
HOSTILE = [
    1e300, -1e300, 1e-320, -0.0, 0.0, math.nan, math.inf, -math.inf, -1.0, 2.5e3,
    "abc", "", "1.5", None, True, [1.0, 2.0], (1,), {"a": 1}, object(), np.float32(0.5),
    np.int64(3), np.array([1.0]), complex(1, 1), 10**400,
]

#: Keys of a scene and a plausible value of each.
SCENE = {
    "theta": 0.75, "a": 0.0, "b": 0.0, "k": 20.0, "q": 5.0, "alpha_deg": 0.0,
    "profile": "g1", "points": 8, "tol": None, "units": None, "method": "accurate",
}

ERRORS = (vibrissa.InvalidInput, vibrissa.SolverError, vibrissa.NoContact)

PROFILES = [
    "", "points:", "points:/nonexistent.csv", "parabola:1,2", "parabola:a,b,c", "circle:0,0,-1",
    "cosh:0,0,0,0", "g9", ":", "g1 ", "parabola:nan,0,0.5", 5, None, ("x",), ([0.0, 1.0], [1.0]),
    (["a", "b", "c"], [1, 2, 3]), ([0.0, math.nan, 1.0], [1.0, 0.5, 1.0]),
    ([0.0, 1.0, 2.0], [1.0, math.inf, 1.0]), ([0.0, 2.0, 1.0], [1.0, 1.0, 1.0]),
    (np.zeros((2, 2)), np.zeros(2)), {"x": [1, 2]},
]


def hostile_scenes(n: int, rng: np.random.Generator) -> list:
    """``n`` scenes, each a plausible sweep with one or two keys made hostile (a value of
    :data:`HOSTILE`, a bad profile, an unknown key, a key removed)."""
    scenes = []
    for _ in range(n):
        s = dict(SCENE)
        for _ in range(int(rng.integers(1, 3))):
            what = int(rng.integers(0, 5))
            key = list(SCENE)[int(rng.integers(0, len(SCENE)))]
            if what == 0:
                s[key] = HOSTILE[int(rng.integers(0, len(HOSTILE)))]
            elif what == 1:
                s["profile"] = PROFILES[int(rng.integers(0, len(PROFILES)))]
            elif what == 2:
                s["bogus_" + key] = 1.0
            elif what == 3:
                s.pop(key, None)
            else:
                s["points"] = [0, 1, 2, 10**12, -3, 2.5, "8", math.nan][int(rng.integers(0, 8))]
        scenes.append(s)
    return scenes


def one_line(e: BaseException) -> str:
    text = str(e)
    assert text and "\n" not in text, f"{type(e).__name__}: {text!r}"
    assert "panicked" not in text and "internal error" not in text, text
    return text


def test_every_hostile_sweep_is_a_result_or_a_vibrissa_error():
    rng = np.random.default_rng(SEED)
    scenes = hostile_scenes(120, rng)
    counts: Counter = Counter()
    for s in scenes:
        try:
            sw = vibrissa.sweep(**s)
        except ERRORS as e:
            counts[type(e).__name__] += 1
            one_line(e)
        except TypeError as e:
            # an unknown keyword of a direct call is Python's own TypeError (the call is
            # malformed); anything else would be a bug
            counts["TypeError (unknown keyword)"] += 1
            assert "unexpected keyword argument" in str(e), (s, e)
        else:
            counts["ok"] += 1
            assert len(sw) > 0 and np.all(np.diff(sw.x0) < 0)
    print(f"\nhostile sweeps, seed {SEED:#x}: {dict(counts)}")
    assert counts["ok"] > 0 and counts["InvalidInput"] > 0


def test_a_study_of_hostile_scenes_has_one_row_each_and_never_raises():
    rng = np.random.default_rng(SEED + 1)
    scenes = hostile_scenes(80, rng)
    # elements that are not scenes at all are error rows too
    scenes += [None, 5, "g1", ["theta", 1.0], {1: 2}, {"theta": object()}]
    df = vibrissa.study(scenes, workers=2)
    assert len(df) == len(scenes)
    classes = Counter(df["error_class"].fillna("ok"))
    print(f"\nhostile study, seed {SEED + 1:#x}: {dict(classes)}")
    assert set(classes) <= {"ok", "InvalidInput", "SolverError", "NoContact"}, classes
    for msg in df["error"].dropna():
        assert "\n" not in msg and "internal error" not in msg, msg
    # each row is what a direct call says
    for i, s in enumerate(scenes[:80]):
        row = df.iloc[i]
        try:
            vibrissa.sweep(**s)
        except ERRORS as e:
            assert row["error_class"] == type(e).__name__ and row["error"] == str(e), (s, row)
        except TypeError:
            assert row["error_class"] == "InvalidInput" and "scene key" in row["error"], (s, row)
        else:
            assert row["error"] is None or (isinstance(row["error"], float) and math.isnan(row["error"])), (s, row)


@pytest.mark.parametrize("task", ["solve", "sweep", "reconstruct"])
def test_study_error_rows_name_the_culprit(task):
    base = {"profile": "g1", "points": 8} if task != "solve" else {}
    scenes = [
        {"theta": 0.5, "q": 1.0, "profile": "g1", "points": 8} if task != "solve" else {"q": 1.0},
        {"bogus": 1.0},
        {"theta": "thin", **base},
        {"theta": [1, 2], **base},
        {"profile": (["a", "b", "c"], [1, 2, 3])} if task != "solve" else {"units": 5},
        {"profile": ([0.0, math.nan, 1.0], [1.0, 0.5, 1.0])} if task != "solve" else {"load": 7},
        "not a scene",
        {"theta": -1.0, **base},
    ]
    df = vibrissa.study(scenes, task=task, workers=1)
    assert len(df) == len(scenes)
    assert df["error"].isna().iloc[0], df["error"].iloc[0]
    errors = list(df["error"])
    classes = list(df["error_class"])
    assert classes[1:] == ["InvalidInput"] * (len(scenes) - 1), classes
    assert "`bogus`" in errors[1] and "scene key" in errors[1]
    assert "--theta" in errors[2] and "thin" in errors[2]
    assert "--theta" in errors[3]
    if task != "solve":
        assert "profile" in errors[4]
        assert "x[1] = NaN" in errors[5], errors[5]
    assert "`scene`" in errors[6] and "str" in errors[6]
    assert "--theta" in errors[7]


@pytest.mark.parametrize(
    "call, fragment",
    [
        (lambda: vibrissa.study({"q": 1}), "for `scenes`"),
        (lambda: vibrissa.study("g1"), "for `scenes`"),
        (lambda: vibrissa.study(None), "for `scenes`"),
        (lambda: vibrissa.study(5), "for `scenes`"),
        (lambda: vibrissa.study([{}], task=3), "for `task`"),
        (lambda: vibrissa.study([{}], workers=0), "for `workers`"),
        (lambda: vibrissa.study([{}], workers=1.5), "for `workers`"),
        (lambda: vibrissa.study([{}], chunk_size=-1), "for `chunk_size`"),
    ],
)
def test_only_a_malformed_study_call_raises(call, fragment):
    with pytest.raises(vibrissa.InvalidInput) as e:
        call()
    assert fragment in one_line(e.value)


def test_a_nan_in_a_profile_names_the_array_and_its_index():
    x = np.linspace(-2.0, 2.0, 401)
    y = np.cosh(x / 2) - 0.8
    for name, arrays in (("x", (x.copy(), y)), ("y", (x, y.copy()))):
        (arrays[0] if name == "x" else arrays[1])[200] = np.nan
        with pytest.raises(vibrissa.InvalidInput) as e:
            vibrissa.sweep(profile=arrays, q=5.0, points=8)
        text = one_line(e.value)
        assert f"{name}[200] = NaN" in text and "point 201 of 401" in text, text
        assert "value 402" not in text


def test_hostile_logs_and_streams_are_results_or_vibrissa_errors():
    rng = np.random.default_rng(SEED + 2)
    sw = vibrissa.sweep(profile="g1", q=5.0, theta=0.75, k=20.0, points=10)
    base = {c: np.array(sw[c], dtype=float) for c in ("x0", "Ax", "Ay", "MA", "phi0")}
    counts: Counter = Counter()
    for _ in range(40):
        log = {c: v.copy() for c, v in base.items()}
        col = list(log)[int(rng.integers(0, 5))]
        what = int(rng.integers(0, 4))
        if what == 0:
            log[col][int(rng.integers(0, len(log[col])))] = [math.nan, math.inf, 1e300, -0.0][int(rng.integers(0, 4))]
        elif what == 1:
            del log[col]
        elif what == 2:
            log[col] = log[col][:-1]
        else:
            log[col] = np.array(["a"] * len(log[col]), dtype=object)
        try:
            vibrissa.reconstruct(log, theta=0.75, k=20.0)
            counts["ok"] += 1
        except ERRORS as e:
            counts[type(e).__name__] += 1
            one_line(e)
        s = vibrissa.Streamer(q=5.0, theta=0.75, k=20.0)
        try:
            n = min(len(v) for v in log.values()) if len(log) == 5 else 0
            for i in range(n):
                s.push(*(float(log[c][i]) for c in ("x0", "Ax", "Ay", "MA", "phi0")))
            s.finish()
        except ERRORS as e:
            one_line(e)
        except ValueError as e:
            # float("a") of the caller's own conversion, before vibrissa sees the row
            assert "could not convert" in str(e)
    print(f"\nhostile logs, seed {SEED + 2:#x}: {dict(counts)}")
    assert counts["ok"] > 0
