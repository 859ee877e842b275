"""``mu=`` (issue 39): Coulomb friction at the contact through the Python package. The same
rows as ``vibrissa sweep --mu`` bit for bit, the new columns (``ft``, ``slip``, ``y0``,
``gamma``), ``mu=0`` exactly the frictionless sweep, refusals naming ``--mu``, and a study
over mu."""

import json
import math

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


# ---- reconstruct(mu=...) and calibrate(fit=[..., "mu"]) against the CLI (issue 39) ----


def _same_mu(got, cli_json) -> None:
    """The CLI JSON's ``mu`` (its null a NaN here: ``chi2_dof`` of a given mu)."""
    if cli_json is None:
        assert got is None
        return
    assert set(got) == set(cli_json)
    for key, want in cli_json.items():
        have = got[key]
        if want is None and isinstance(have, float):
            assert math.isnan(have), key
        else:
            assert have == want, key


def _same_friction(got: dict, cli_json: dict) -> None:
    """The CLI JSON's ``friction``, its line numbered as Python numbers a log's rows (``log
    row:N``, 1-based: the CLI's file line minus its header)."""
    want, got = dict(cli_json), dict(got)
    if want.get("friction_line") is not None:
        want["friction_line"] -= 1
    _same_mu(got.pop("mu", None), want.pop("mu", None))
    assert got == want


def _frictional_folder(cli, tmp_path, mu):
    out = tmp_path / "sweep"
    cli.run("sweep", *cli_flags(SCENE), "--mu", repr(mu), "--figures", "none", "--out", str(out))
    return out, vibrissa.sweep(**SCENE, mu=mu)


@pytest.mark.parametrize("mu", ["identify", 0.5])
def test_reconstruct_mu_gives_the_numbers_of_the_cli(cli, tmp_path, mu):
    folder, sw = _frictional_folder(cli, tmp_path, 0.5)
    rec_dir = tmp_path / "rec"
    ref = json.loads(cli.run("reconstruct", str(folder), "--mu", str(mu), "--json",
                             "--figures", "none", "--out", str(rec_dir)).stdout)
    rec = vibrissa.reconstruct(sw, mu=mu)
    csv = read_csv(rec_dir / "reconstruction.csv")
    m = rec.contact
    assert m.sum() == len(csv)
    for col in ("x0", "x", "y", "s1", "f", "psi", "sigma", "ft"):
        assert_same(rec[col][m], csv[col].to_numpy(), col)
    _same_mu(rec.mu, ref["mu"])
    _same_friction(rec.friction, ref["friction"])
    assert set(rec.slip[m]) <= {"slip", "stick"} and set(rec.slip[~m]) == {"none"}
    if mu == "identify":
        # the truth the log was swept with (16 rows: the tangent traced from the tip
        # contacts limits it to about 5e-6 here)
        assert abs(rec.mu["value"] - 0.5) < 1e-4 and not rec.mu["given"]
        assert f"mu={rec.mu['value']:.6g}" in repr(rec)
        # ft against the sweep's own (the tangent traced from the contact points): inside
        # the traced contour within 2.2e-5 on this 16-row log; at its end (a one-sided
        # stencil) 2.0e-3 since the tangent is a weighted mean over the degrees (ftan,
        # docs/friction-recon.md; 9e-4 before, when one chance agreement of two degrees
        # could also give a false proof of friction)
        assert np.allclose(rec.ft[m][:-1], sw.ft[m][:-1], rtol=0, atol=1e-4)
        assert abs(rec.ft[m][-1] - sw.ft[m][-1]) < 3e-3
    else:
        assert rec.mu["given"] and rec.mu["value"] == 0.5


def test_reconstruct_default_identifies_mu_and_warns_as_the_cli(cli, tmp_path):
    folder, sw = _frictional_folder(cli, tmp_path, 0.5)
    p = cli.run("reconstruct", str(folder), "--json", "--figures", "none",
                "--out", str(tmp_path / "rec"))
    ref = json.loads(p.stdout)
    with pytest.warns(UserWarning, match="the log shows friction") as w:
        rec = vibrissa.reconstruct(sw)
    # the CLI's stderr line, word for word (the row numbered as Python numbers it)
    line = ref["friction"]["friction_line"]
    assert str(w[0].message).replace(f"(line {line - 1},", f"(line {line},") in p.stderr
    _same_mu(rec.mu, ref["mu"])
    assert rec.friction["proves_friction"]
    _same_friction(rec.friction, ref["friction"])
    csv = read_csv(tmp_path / "rec" / "reconstruction.csv")
    for col in ("x", "y", "f", "sigma"):
        assert_same(rec[col][rec.contact], csv[col].to_numpy(), col)
    # the frictionless sweep of the scene: mu near 0, warned about exactly when the CLI warns
    # (on this 16-row circle the traced tangent's error once gave a false proof, z = 942;
    # z = 0.73 since the tangent's estimate, docs/friction-recon.md)
    folder0 = tmp_path / "plain"
    cli.run("sweep", *cli_flags(SCENE), "--figures", "none", "--out", str(folder0))
    p0 = cli.run("reconstruct", str(folder0), "--json", "--figures", "none",
                 "--out", str(tmp_path / "rec0"))
    import warnings as _w

    with _w.catch_warnings(record=True) as caught:
        _w.simplefilter("always")
        r0 = vibrissa.reconstruct(vibrissa.sweep(**SCENE))
    assert bool(caught) == ("the log shows friction" in p0.stderr)
    _same_mu(r0.mu, json.loads(p0.stdout)["mu"])
    assert abs(r0.mu["value"]) < 1e-4


@pytest.mark.parametrize("bad", [-1.0, 11.0, "abc"])
def test_reconstruct_bad_mu_is_refused_as_the_cli(cli, tmp_path, bad):
    folder, sw = _frictional_folder(cli, tmp_path, 0.5)
    msg = cli.error("reconstruct", str(folder), "--mu", str(bad), "--out", str(tmp_path / "r"))
    with pytest.raises(vibrissa.InvalidInput) as e:
        vibrissa.reconstruct(sw, mu=bad)
    assert str(e.value) == msg


def test_calibrate_fits_mu_as_the_cli(cli, tmp_path):
    folder, sw = _frictional_folder(cli, tmp_path, 0.5)
    ref = cli.json("calibrate", f"{folder / 'observables.csv'}={SCENE['profile']}",
                   "--fit", "theta,k,mu", "--theta", "0.6", "--k", "15")
    cal = vibrissa.calibrate(sw, fit=["theta", "k", "mu"], theta=0.6, k=15.0)
    assert cal.mu == ref["mu"]
    assert abs(cal.mu["value"] - 0.5) < 1e-8 and cal.mu["sliding_rows"] > 5
    assert cal.parameters["mu"] == ref["parameters"]["mu"]
    assert "mu=0.5" in repr(cal)
