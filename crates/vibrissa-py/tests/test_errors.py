"""Bad input raises the right class with the CLI's message; no panic reaches Python."""

import math
import pickle

import numpy as np
import pytest

import vibrissa

CASES = [
    # (python call, CLI args, class)
    (lambda: vibrissa.solve(theta=-1.0), ["solve", "--theta", "-1.0"], vibrissa.InvalidInput),
    (lambda: vibrissa.solve(theta=0.001), ["solve", "--theta", "0.001"], vibrissa.InvalidInput),
    (lambda: vibrissa.solve(k=-2.0), ["solve", "--k", "-2.0"], vibrissa.InvalidInput),
    (lambda: vibrissa.solve(f=1e9), ["solve", "--f", "1000000000.0"], vibrissa.InvalidInput),
    (lambda: vibrissa.solve(q=math.nan), ["solve", "--q", "NaN"], vibrissa.InvalidInput),
    (lambda: vibrissa.solve(method="newton"), ["solve", "--method", "newton"], vibrissa.InvalidInput),
    (lambda: vibrissa.solve(method="fdm", n=2), ["solve", "--method", "fdm", "--n", "2"], vibrissa.InvalidInput),
    (lambda: vibrissa.sweep(profile="g1", q=5, alpha_deg=95.0), ["sweep", "--profile", "g1", "--q", "5.0", "--alpha-deg", "95.0", "--out", "/tmp/_vib_x"], vibrissa.InvalidInput),
    (lambda: vibrissa.sweep(profile="g1", points=1), ["sweep", "--profile", "g1", "--points", "1", "--out", "/tmp/_vib_x"], vibrissa.InvalidInput),
    (lambda: vibrissa.sweep(profile="circle:0,1"), ["sweep", "--profile", "circle:0,1", "--out", "/tmp/_vib_x"], vibrissa.InvalidInput),
    (lambda: vibrissa.sweep(profile="points:/nonexistent.csv"), ["sweep", "--profile", "points:/nonexistent.csv", "--out", "/tmp/_vib_x"], vibrissa.InvalidInput),
    (lambda: vibrissa.sweep(profile="parabola:1,0,5", q=1.0), ["sweep", "--profile", "parabola:1,0,5", "--q", "1.0", "--out", "/tmp/_vib_x"], vibrissa.NoContact),
    (lambda: vibrissa.sweep(), ["sweep", "--out", "/tmp/_vib_x"], vibrissa.InvalidInput),
]


@pytest.mark.parametrize("case", range(len(CASES)))
def test_message_and_class_as_cli(cli, case):
    call, args, cls = CASES[case]
    with pytest.raises(cls) as e:
        call()
    assert str(e.value) == cli.error(*args)


def test_class_hierarchy():
    assert issubclass(vibrissa.InvalidInput, ValueError)
    assert issubclass(vibrissa.InvalidInput, vibrissa.VibrissaError)
    assert issubclass(vibrissa.SolverError, RuntimeError)
    assert issubclass(vibrissa.NoContact, vibrissa.SolverError)
    with pytest.raises(ValueError):
        vibrissa.solve(theta=2.0)


@pytest.mark.parametrize(
    "call, fragment",
    [
        (lambda: vibrissa.solve(theta="thin"), "`'thin'` for `--theta`: not a number"),
        (lambda: vibrissa.solve(load="xp"), "for `--load`"),
        (lambda: vibrissa.solve(units="zeta"), "unknown whisker preset"),
        (lambda: vibrissa.solve(units={"length": 3}), "unknown key"),
        (lambda: vibrissa.solve(tol=1e-20), "for `--tol`"),
        (lambda: vibrissa.sweep(profile="g1", q=5, tol=1.0), "for `--tol`"),
        (lambda: vibrissa.sweep(profile="g1", q=5, tol="abc"), "for `--tol`: not a number"),
        (lambda: vibrissa.reconstruct({c: np.zeros(3) for c in ("x0", "Ax", "Ay", "MA", "phi0")}, tol=0.0), "for `--tol`"),
        (lambda: vibrissa.sweep(profile="g1", q=5, f=1.0), "a sweep computes the contact force itself"),
        (lambda: vibrissa.sweep(profile="g1", q=5, method="fdm"), "always solves its contact phases"),
        (lambda: vibrissa.sweep(profile=([0.0, 1.0], [1.0])), "x and y must be 1-D arrays of one length"),
        (lambda: vibrissa.sweep(profile=([0.0, 2.0, 1.0], [1.0, 1.0, 1.0]), q=1.0), "points:(x, y) arrays"),
        (lambda: vibrissa.reconstruct({"x0": [1.0, 2.0]}), "missing required column"),
        (lambda: vibrissa.reconstruct({c: [1.0] for c in ("x0", "Ax", "Ay", "MA", "phi0")}), "at least 2 rows"),
        (lambda: vibrissa.reconstruct({c: np.zeros(3) for c in ("x0", "Ax", "Ay", "MA", "phi0")}, method="magic"), "unknown reconstruction method"),
        (lambda: vibrissa.reconstruct({c: np.zeros(3) for c in ("x0", "Ax", "Ay", "MA", "phi0")}, noise=-1.0), "--noise"),
        (lambda: vibrissa.study([{}], task="fly"), "for `task`"),
    ],
)
def test_python_side_inputs_raise_invalid_input(call, fragment):
    with pytest.raises(vibrissa.InvalidInput) as e:
        call()
    assert fragment in str(e.value)


def test_log_row_named_in_message():
    sw = vibrissa.sweep(profile="g1", q=5, points=20)
    log = {c: np.array(sw[c]) for c in ("x0", "Ax", "Ay", "MA", "phi0")}
    log["MA"][14] = np.nan
    with pytest.raises(vibrissa.InvalidInput) as e:
        vibrissa.reconstruct(log)
    assert str(e.value).startswith("log row:15: column `MA`")


def test_errors_pickle():
    for err in (vibrissa.InvalidInput("x"), vibrissa.NoContact("y")):
        back = pickle.loads(pickle.dumps(err))
        assert type(back) is type(err) and str(back) == str(err)
