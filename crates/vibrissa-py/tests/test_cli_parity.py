"""Every function against the command line on the same scenes: identical numbers, and the
same error class and message for refused input. The scenes are a seeded random battery over
the parameter space the CLI accepts (units included), plus the shipped scene files."""

import math
import random
from pathlib import Path

import numpy as np
import pytest

import vibrissa
from conftest import ROOT, assert_same, read_csv


def flags(scene: dict) -> list:
    """The CLI flags of a keyword scene (numbers in Python's repr, the shortest round trip)."""
    out = []
    for key, value in scene.items():
        if value is None or key in ("units", "profile", "points"):
            continue
        flag = "--" + key.replace("_", "-")
        out += [flag, value if isinstance(value, str) else repr(value)]
    if scene.get("profile") is not None:
        out += ["--profile", scene["profile"]]
    if scene.get("points") is not None:
        out += ["--points", str(scene["points"])]
    return out


def units_scene_file(tmp: Path, units) -> list:
    """A scene file carrying `units` (the CLI takes units only from a scene file)."""
    if units is None:
        return []
    path = tmp / "units.ron"
    path.write_text(f'(units: Physical(preset: "{units}"), whisker: ())\n')
    return [str(path)]


def random_solve_scene(rng: random.Random) -> dict:
    load = rng.choice(["dp", "ap"])
    method = rng.choice(["accurate", "accurate", "fdm", "fdm-richardson", "rk4"])
    return {
        "theta": round(rng.uniform(0.1, 1.0), 6),
        "a": round(rng.uniform(-2, 2), 6),
        "b": round(rng.uniform(-2, 2), 6),
        "k": rng.choice([None, round(rng.uniform(5, 50), 4)]),
        "f": round(rng.uniform(0, 8), 6),
        "beta_deg": round(rng.uniform(-90, 90), 4),
        "load": load,
        "q": round(rng.uniform(0, 8), 6),
        "alpha_deg": round(rng.uniform(-60, 60), 4),
        "method": method,
        "n": rng.choice([None, 64, 200]),
    }


SOLVE_SCENES = [random_solve_scene(random.Random(1000 + i)) for i in range(24)]


@pytest.mark.parametrize("scene", SOLVE_SCENES, ids=lambda s: f"{s['method']}-theta{s['theta']}")
def test_solve_matches_cli(cli, tmp_path, scene):
    out = tmp_path / "out"
    p = cli.run("solve", *flags(scene), "--json", "--out", str(out), check=False)
    if p.returncode != 0:
        # refused or failed alike: same class, same message
        with pytest.raises(vibrissa.VibrissaError) as e:
            vibrissa.solve(**scene)
        assert str(e.value) == p.stderr.strip().splitlines()[-1].removeprefix("error: ")
        assert isinstance(e.value, vibrissa.SolverError if p.returncode == 1 else vibrissa.InvalidInput)
        return
    import json

    ref = json.loads(p.stdout)
    sol = vibrissa.solve(**scene)
    for key in ("x", "y", "phi"):
        assert sol.tip[key] == ref["tip"][key]
    for key in ("Ax", "Ay", "MA", "phi0"):
        assert sol.base[key] == ref["base"][key]
    assert sol.stats == ref["stats"]
    csv = read_csv(out / "elastica.csv")
    for col in ("s", "x", "y", "phi", "kappa", "m"):
        assert_same(sol[col], csv[col].to_numpy(), col)
    # the scene given back reproduces the solution
    again = vibrissa.solve(**sol.scene)
    assert again.tip == sol.tip


@pytest.mark.parametrize("units", ["beta", "gamma", "E2"])
def test_solve_physical_matches_cli(cli, tmp_path, units):
    scene = {"theta": 0.6, "k": 2e-4, "q": 0.004, "f": 1e-5, "beta_deg": 20.0}
    out = tmp_path / "out"
    cli.run("solve", *units_scene_file(tmp_path, units), *flags(scene), "--out", str(out))
    sol = vibrissa.solve(units=units, **scene)
    csv = read_csv(out / "elastica.csv")
    for col in ("s", "x", "y", "phi", "kappa", "m"):
        assert_same(sol[col], csv[col].to_numpy(), col)
    assert sol.units == "physical" and sol.length_unit == "mm"
    assert sol.tip["x"] == sol.x[-1] and sol.tip["y"] == sol.y[-1]


def random_sweep_scene(rng: random.Random) -> dict:
    profile = rng.choice(["g1", "g2", "ge", "circle:0.3,1.6,0.6", "parabola:1.5,0.2,0.7", "cosh:1,2,0,-0.8"])
    return {
        "profile": profile,
        "points": rng.choice([20, 60]),
        "theta": round(rng.uniform(0.3, 1.0), 4),
        "a": round(rng.uniform(-0.5, 0.5), 4),
        "b": round(rng.uniform(-0.5, 0.5), 4),
        "k": rng.choice([None, round(rng.uniform(5, 40), 3)]),
        "q": round(rng.uniform(0, 6), 4),
        "alpha_deg": round(rng.uniform(-30, 30), 3),
    }


SWEEP_SCENES = [random_sweep_scene(random.Random(2000 + i)) for i in range(8)]


def check_sweep_against_folder(sw, folder: Path, summary: dict) -> None:
    csv = read_csv(folder / "observables.csv")
    assert len(sw) == len(csv)
    for col in ("x0", "Ax", "Ay", "MA", "phi0", "f", "s1", "xc", "yc", "psi"):
        assert_same(sw[col], csv[col].to_numpy(), col)
    assert list(sw.phase) == list(csv["phase"])
    for key in ("first_contact", "separation", "phases", "rows", "events", "first_contact_row"):
        assert sw.summary[key] == summary[key], key


@pytest.mark.parametrize("scene", SWEEP_SCENES, ids=lambda s: f"{s['profile']}-q{s['q']}")
def test_sweep_and_reconstruct_match_cli(cli, tmp_path, scene):
    out = tmp_path / "sweep"
    p = cli.run("sweep", *flags(scene), "--json", "--out", str(out), check=False)
    if p.returncode != 0:
        with pytest.raises(vibrissa.VibrissaError) as e:
            vibrissa.sweep(**scene)
        assert str(e.value) == p.stderr.strip().splitlines()[-1].removeprefix("error: ")
        return
    import json

    sw = vibrissa.sweep(**scene)
    check_sweep_against_folder(sw, out, json.loads(p.stdout))
    # reconstruction: the CLI from the folder, Python from the Sweep (its whisker lent)
    rec_dir = tmp_path / "rec"
    cli.run("reconstruct", str(out), "--profile", scene["profile"], "--out", str(rec_dir))
    rec = vibrissa.reconstruct(sw, profile=scene["profile"])
    ref = read_csv(rec_dir / "reconstruction.csv")
    m = rec.contact
    assert m.sum() == len(ref)
    for col in ("x0", "x", "y", "s1", "f", "psi", "error"):
        assert_same(rec[col][m], ref[col].to_numpy(), col)
    assert list(rec.phase[m]) == list(ref["phase"])
    assert np.isnan(rec.x[~m]).all()


def test_physical_sweep_matches_cli_and_scaled_dimensionless(cli, tmp_path):
    scene_file = ROOT / "scenes" / "physical-beta-g1.ron"
    out = tmp_path / "sweep"
    summary = cli.json("sweep", str(scene_file), "--out", str(out))
    kwargs = vibrissa.load_scene(scene_file)
    sw = vibrissa.sweep(**kwargs)
    check_sweep_against_folder(sw, out, summary)
    assert sw.units == "physical"
    # the CLI's reconstruct of the folder == Python's of the Sweep (mm, N, N mm)
    rec_dir = tmp_path / "rec"
    cli.run("reconstruct", str(out), "--out", str(rec_dir))
    rec = vibrissa.reconstruct(sw)
    ref = read_csv(rec_dir / "reconstruction.csv")
    for col in ("x0", "x", "y", "s1", "f", "psi"):
        assert_same(rec[col][rec.contact], ref[col].to_numpy(), col)


def test_array_profile_equals_points_file(tmp_path):
    x = np.linspace(-3, 3, 61)
    y = np.cosh(x / 2) - 0.8
    path = tmp_path / "post.csv"
    path.write_text("x,y\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(x, y)))
    a = vibrissa.sweep(profile=(x, y), q=4, points=30)
    b = vibrissa.sweep(profile=f"points:{path}", q=4, points=30)
    for col in a.keys():
        if col in ("phase", "slip"):  # labels, not numbers
            assert list(a[col]) == list(b[col]), col
        else:
            assert_same(a[col], b[col], col)
    assert a.scene["profile"][0] is x


@pytest.mark.parametrize("path", sorted((ROOT / "scenes").glob("*.ron")), ids=lambda p: p.stem)
def test_shipped_scenes_solve_as_cli(cli, path):
    ref = cli.json("solve", str(path))
    sol = vibrissa.solve(**vibrissa.load_scene(path))
    if ref["units"] == "dimensionless":
        assert sol.tip["x"] == ref["tip"]["x"] and sol.base["MA"] == ref["base"]["MA"]
    else:
        assert sol.tip["x"] == pytest.approx(ref["physical"]["tip_m"]["x"] * 1e3, rel=1e-14)
    assert sol.stats == ref["stats"]


def test_streamer_equals_batch():
    sw = vibrissa.sweep(profile="g2", theta=0.7, k=15, q=3, points=40)
    rec = vibrissa.reconstruct(sw, q=3, alpha_deg=0)
    st = vibrissa.Streamer(q=3, alpha_deg=0, theta=0.7, k=15)
    got = [st.push(sw.x0[i], sw.Ax[i], sw.Ay[i], sw.MA[i], sw.phi0[i]) for i in range(len(sw))]
    for i, p in enumerate(got):
        if p is None:
            assert not rec.contact[i]
        else:
            # the stream decides each row with its own noise floor (the batch estimates
            # one): the same point within the error estimates
            assert p["row"] == i and p["phase"] == rec.phase[i]
            tol = 3 * max(p["sigma"], rec.sigma[i]) + 1e-12
            assert abs(p["x"] - rec.x[i]) <= tol and abs(p["y"] - rec.y[i]) <= tol
    assert len(st.points) == int(rec.contact.sum())
    # without the flow: held until the first free row, then released in order
    st2 = vibrissa.Streamer(theta=0.7, k=15)
    for i in range(len(sw)):
        st2.push(sw.x0[i], sw.Ax[i], sw.Ay[i], sw.MA[i], sw.phi0[i])
    st2.finish()
    assert st2.flow[0] == pytest.approx(3, abs=1e-12)
    assert [p["row"] for p in st2.points] == list(np.flatnonzero(rec.contact))


def test_reconstruct_any_row_order_and_dataframe():
    sw = vibrissa.sweep(profile="g1", q=5, points=50)
    df = sw.to_pandas()
    shuffled = df.sample(frac=1.0, random_state=7).reset_index(drop=True)
    a = vibrissa.reconstruct(df, profile="g1")
    b = vibrissa.reconstruct(shuffled, profile="g1")
    order = {x0: i for i, x0 in enumerate(a.x0)}
    for i, x0 in enumerate(b.x0):
        j = order[x0]
        assert (b.x[i] == a.x[j]) or (math.isnan(b.x[i]) and math.isnan(a.x[j]))
    assert np.nanmax(a.error) < 1e-9
    assert a.q == pytest.approx(5, abs=1e-12)


@pytest.mark.parametrize("tol", [1e-4, 1e-8])
def test_solve_tol_matches_cli(cli, tmp_path, tol):
    scene = {"theta": 0.5, "k": 10.0, "q": 0.5, "f": 0.2, "beta_deg": 20.0}
    import json

    p = cli.run("solve", *flags({**scene, "method": "auto"}), "--tol", repr(tol), "--json",
                "--out", str(tmp_path / "o"))
    ref = json.loads(p.stdout)
    sol = vibrissa.solve(**scene, tol=tol)
    assert sol.stats == ref["stats"]
    assert sol.stats["method_used"] == "picard" and sol.stats["tolerance"] == tol
    assert sol.tip == ref["tip"]
    exact = vibrissa.solve(**scene)
    assert abs(sol.tip["x"] - exact.tip["x"]) <= tol
    assert vibrissa.solve(**sol.scene).tip == sol.tip


def test_solve_reports_the_model_used(cli, tmp_path):
    """A weak flow at a loose accuracy is linear theory's (its a-priori bound meets it),
    within its estimate of the elastica; the default is the elastica's; as the CLI says."""
    import json

    weak = {"theta": 0.5, "k": 10.0, "q": 0.05}
    sol = vibrissa.solve(**weak, tol=1e-3)
    assert sol.stats["model_used"] == "linear" and sol.stats["method_used"] == "picard"
    exact = vibrissa.solve(**weak)
    assert exact.stats["model_used"] == "elastica"
    for key in ("x", "y"):
        assert abs(sol.tip[key] - exact.tip[key]) <= sol.stats["error_estimate"] + 1e-8
    p = cli.run("solve", *flags({**weak, "method": "auto"}), "--tol", "1e-3", "--json",
                "--out", str(tmp_path / "o"))
    assert json.loads(p.stdout)["stats"] == sol.stats


@pytest.mark.parametrize("tol", [1e-6, 1e-4])
def test_sweep_and_reconstruct_tol_match_cli(cli, tmp_path, tol):
    """``tol`` of sweep and reconstruct: the CLI's numbers and estimates, every row and
    point within ``tol`` of the default run's, the estimates reported and the scene kept."""
    import json

    scene = {"profile": "g1", "q": 5.0, "theta": 0.75, "k": 20.0, "points": 40}
    out = tmp_path / "sweep"
    ref = json.loads(cli.run("sweep", *flags(scene), "--tol", repr(tol), "--json",
                             "--out", str(out)).stdout)
    sw = vibrissa.sweep(**scene, tol=tol)
    check_sweep_against_folder(sw, out, ref)
    assert sw.summary["tol"] == tol == ref["tol"]
    assert sw.summary["max_estimate"] == ref["max_estimate"] <= tol
    assert sw.summary["max_estimate_row"] == ref["max_estimate_row"]
    base = vibrissa.sweep(**scene)
    assert "max_estimate" not in base.summary
    for col in ("x0", "Ax", "Ay", "MA", "phi0", "xc", "yc"):
        d = np.nanmax(np.abs(np.asarray(sw[col]) - np.asarray(base[col])))
        assert d <= sw.summary["max_estimate"], col
    # the scene keeps the accuracy asked for
    assert sw.scene["tol"] == tol
    assert vibrissa.sweep(**sw.scene).summary["max_estimate"] == sw.summary["max_estimate"]
    # the default log reconstructed at tol, as the CLI does
    rec_dir = tmp_path / "rec"
    ref = json.loads(cli.run("reconstruct", str(tmp_path / "sweep"), "--tol", repr(tol), "--json",
                             "--out", str(rec_dir)).stdout)
    rec = vibrissa.reconstruct(sw, tol=tol)
    assert rec.summary["tol"] == tol
    assert rec.summary["max_estimate"] == ref["max_estimate"] <= tol
    exact = vibrissa.reconstruct(sw)
    m = rec.contact
    d = np.hypot(rec.x[m] - exact.x[m], rec.y[m] - exact.y[m]).max()
    assert d <= rec.summary["max_estimate"]
