"""``mu=`` (issue 39): Coulomb friction at the contact through the Python package. The same
rows as ``vibrissa sweep --mu`` bit for bit, the new columns (``ft``, ``slip``, ``y0``,
``gamma``), ``mu=0`` exactly the frictionless sweep, refusals naming ``--mu``, and a study
over mu."""

import json

import numpy as np
import pytest

import vibrissa
from conftest import assert_same, read_csv

# A tapered whisker on a spring under a weak flow, past a small circle: its contact stays at
# the tip and slides to the snap for every mu below (the frictional tip contact).
SCENE = {"profile": "circle:0.3,1.2,0.3", "q": 0.5, "theta": 0.5, "k": 20.0, "points": 16}
# The same whisker pre-curved, past g2: it sticks from the touch; with mu = 10 to the snap.
STUCK = {"profile": "g2", "q": 0.5, "theta": 0.3, "a": 1.0, "b": 0.5, "points": 12}

COLUMNS = ("x0", "Ax", "Ay", "MA", "phi0", "f", "s1", "xc", "yc", "psi", "ft", "y0", "gamma")


def cli_flags(scene: dict) -> list:
    out = []
    for key, value in scene.items():
        out += ["--" + key.replace("_", "-"), value if isinstance(value, str) else repr(value)]
    return out


@pytest.mark.parametrize("scene,mu", [(SCENE, 0.5), (SCENE, 1.0), (STUCK, 10.0)])
def test_mu_gives_the_rows_of_the_cli(cli, tmp_path, scene, mu):
    out = tmp_path / "sweep"
    ref = json.loads(
        cli.run("sweep", *cli_flags(scene), "--mu", repr(mu), "--json", "--figures", "none",
                "--out", str(out)).stdout
    )
    sw = vibrissa.sweep(**scene, mu=mu)
    csv = read_csv(out / "observables.csv")
    assert len(sw) == len(csv)
    for col in COLUMNS:
        assert_same(sw[col], csv[col].to_numpy(), col)
    assert list(sw.phase) == list(csv["phase"])
    assert list(sw.slip) == list(csv["slip"])
    assert sw.mu == ref["mu"] == mu
    assert sw.friction_events == ref["friction_events"]
    contact = sw.contact
    assert set(sw.slip[contact]) <= {"stick", "slip"}
    assert set(sw.slip[~contact]) == {"none"}
    # the law: |ft| <= mu f on every row, |ft| = mu f on sliding rows
    f, ft = sw.f[contact], sw.ft[contact]
    assert (np.abs(ft) <= mu * f * (1 + 1e-9) + 1e-12).all()
    sliding = sw.slip[contact] == "slip"
    assert np.allclose(np.abs(ft[sliding]), mu * f[sliding], rtol=1e-8, atol=1e-12)
    # the scene gives the sweep back, mu included
    assert sw.scene["mu"] == mu
    again = vibrissa.sweep(**sw.scene)
    assert_same(again.MA, sw.MA, "MA")


def test_mu_zero_is_the_frictionless_sweep():
    base = vibrissa.sweep(**SCENE)
    zero = vibrissa.sweep(**SCENE, mu=0.0)
    for col in COLUMNS:
        assert_same(zero[col], base[col], col)
    assert (base.ft == 0).all() and (base.y0 == 0).all() and (base.gamma == 0).all()
    assert set(base.slip) == {"none"}
    assert base.mu == 0 and base.friction_events == []
    assert "mu" not in base.scene


@pytest.mark.parametrize("bad", [-0.1, float("nan"), 10.5, float("inf")])
def test_bad_mu_is_refused_as_the_cli_refuses_it(cli, bad):
    with pytest.raises(vibrissa.InvalidInput) as e:
        vibrissa.sweep(**SCENE, mu=bad)
    assert "for `--mu`" in str(e.value)
    assert "[0, 10]" in str(e.value)


def test_a_study_sweeps_over_mu():
    mus = [0.0, 0.25, 0.5, 1.0]
    df = vibrissa.study([dict(SCENE, mu=mu) for mu in mus], workers=2)
    assert list(df["mu"]) == mus
    assert df["error"].isna().all(), list(df["error"])
    # each row is that scene's own sweep
    for mu, max_f in zip(mus, df["max_f"]):
        assert max_f == float(np.max(vibrissa.sweep(**SCENE, mu=mu).f))
    assert df["friction_events"].notna().all()
