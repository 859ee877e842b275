"""``motion=`` (issue 38): whisking, paths, pegs and discs through the Python package. The
same rows as ``vibrissa sweep --motion rotate`` bit for bit, the linear limit of whisking
against a pole (dMA/dgamma -> 3/r; Kaneko 1998, Solomon & Hartmann 2006), the pose columns,
a path given as a DataFrame or a dict, and refusals naming the keyword."""

import json
import math

import numpy as np
import pandas as pd
import pytest

import vibrissa
from conftest import assert_same, read_csv

COLUMNS = ("x0", "Ax", "Ay", "MA", "phi0", "f", "s1", "xc", "yc", "psi", "ft", "y0", "gamma")

# A tapered whisker on a spring in a slanted flow, whisked from a turned start about a base
# off the origin past a disc; and the straight rigid whisker past a pole.
DISC = {"profile": "disc:-0.3,0.8,0.15", "theta": 0.6, "k": 25.0, "q": 0.5, "alpha_deg": 20.0,
        "points": 24, "motion": "rotate", "x0": 0.05, "y0": -0.02, "gamma_deg": -10.0}
PEG = {"profile": "peg:-0.2,0.6", "points": 200, "motion": "rotate"}


def cli_flags(scene: dict) -> list:
    out = []
    for key, value in scene.items():
        out += ["--" + key.replace("_", "-"), value if isinstance(value, str) else repr(value)]
    return out


@pytest.mark.parametrize("scene", [DISC, PEG])
def test_rotate_gives_the_rows_of_the_cli(cli, tmp_path, scene):
    out = tmp_path / "sweep"
    ref = json.loads(
        cli.run("sweep", *cli_flags(scene), "--json", "--figures", "none",
                "--out", str(out)).stdout
    )
    sw = vibrissa.sweep(**scene)
    csv = read_csv(out / "observables.csv")
    assert len(sw) == len(csv)
    for col in COLUMNS:
        assert_same(sw[col], csv[col].to_numpy(), col)
    assert list(sw.phase) == list(csv["phase"])
    assert sw.motion == ref["motion"] == "rotate"
    assert {key: list(v) for key, v in sw.pose.items()} == ref["pose"]
    # the pose: the base stays put, gamma rises from the start
    assert (sw.x0 == scene.get("x0", 0.0)).all() and (sw.y0 == scene.get("y0", 0.0)).all()
    assert (np.diff(sw.gamma) > 0).all()
    assert sw.gamma[0] >= math.radians(scene.get("gamma_deg", 0.0)) - 1e-15
    # phi0 = pi/2 + gamma - MA/k row by row (spec/model.md, "Base motions")
    k = scene.get("k", math.inf)
    assert np.allclose(sw.phi0, np.pi / 2 + sw.gamma - sw.MA / k, rtol=0, atol=1e-9)
    # the scene gives the sweep back
    again = vibrissa.sweep(**sw.scene)
    assert_same(again.MA, sw.MA, "MA")


def test_whisking_against_a_pole_is_linear_theory():
    """The straight uniform rigid whisker at the origin touches `peg:-0.2,0.6` at the peg's
    angle atan(1/3), and the base moment rises as dMA/dgamma = 3/r, r = sqrt(0.4), to second
    order in the turn past the touch."""
    sw = vibrissa.sweep(**PEG)
    r = math.sqrt(0.4)
    gt = math.atan2(0.2, 0.6)
    assert sw.phases == "B" and sw.separation == "tip passed the peg"
    assert abs(sw.pose["gamma_deg"][0] - math.degrees(gt)) < 1e-6
    d = sw.gamma - gt
    near = sw.contact & (d > 1e-3) & (d < 0.05)
    assert near.sum() >= 3
    rel = (np.abs(sw.MA[near]) / d[near] - 3 / r) / (3 / r)
    assert (np.abs(rel) < 0.5 * d[near] ** 2).all(), rel
    # the contact point stays on the peg
    assert np.allclose(sw.xc[sw.contact], -0.2, atol=1e-12)
    assert np.allclose(sw.yc[sw.contact], 0.6, atol=1e-12)


def test_physical_units_scale_the_base_and_the_peg():
    """In a physical scene the base and the peg are in mm: the same rows as the
    dimensionless scene with every length divided by L (66.2 mm)."""
    L = 66.2
    ph = vibrissa.sweep(profile=f"peg:{-0.2 * L},{0.6 * L}", theta=0.6, motion="rotate",
                        x0=0.05 * L, y0=-0.1 * L, gamma_deg=-5.0, points=12, units="beta")
    nd = vibrissa.sweep(profile="peg:-0.2,0.6", theta=0.6, motion="rotate", x0=0.05,
                        y0=-0.1, gamma_deg=-5.0, points=12)
    assert len(ph) == len(nd)
    for col in ("x0", "y0", "xc", "yc", "s1"):
        ok = ~np.isnan(nd[col])
        assert np.allclose(ph[col][ok], L * nd[col][ok], rtol=1e-9, atol=1e-9), col
    assert np.allclose(ph.gamma, nd.gamma, rtol=0, atol=1e-9)


@pytest.mark.parametrize("as_frame", [True, False])
def test_a_path_is_given_as_columns(as_frame):
    """`motion="path"` with `path=` a DataFrame or a dict of arrays: swept once contact-sim
    follows paths (every row's pose on the path), refused by name until then."""
    cols = {"x0": [0.0, 0.0, 0.0], "y0": [0.0, 0.0, 0.0], "gamma_deg": [0.0, 30.0, 60.0]}
    path = pd.DataFrame(cols) if as_frame else {k: np.array(v) for k, v in cols.items()}
    try:
        sw = vibrissa.sweep(profile="peg:-0.2,0.6", motion="path", path=path, points=10)
    except vibrissa.SolverError as e:
        assert "path" in str(e)
        return
    assert sw.motion == "path"
    assert ((sw.gamma >= -1e-12) & (sw.gamma <= math.radians(60) + 1e-12)).all()


def test_bad_motions_are_refused_by_name():
    with pytest.raises(vibrissa.InvalidInput, match="motion"):
        vibrissa.sweep(profile="g1", motion="whisk")
    with pytest.raises(vibrissa.InvalidInput, match="y0"):
        vibrissa.sweep(profile="g1", y0=0.1)
    with pytest.raises(vibrissa.InvalidInput, match="gamma"):
        vibrissa.sweep(profile="g1", motion="rotate", gamma_deg=math.nan)
    with pytest.raises(vibrissa.InvalidInput, match="path"):
        vibrissa.sweep(profile="g1", motion="path")
    with pytest.raises(vibrissa.InvalidInput, match="gamma_deg"):
        vibrissa.sweep(profile="g1", motion="path", path={"x0": [0, 0], "y0": [0, 0]})
    with pytest.raises(vibrissa.InvalidInput, match="k"):
        vibrissa.sweep(profile="g1", motion="path",
                       path={"x0": [0, 0], "y0": [0, 0], "gamma_deg": [0, 9], "k": [1, -1]})


def test_friction_with_whisking_against_a_peg():
    """mu > 0 with rotate against a peg (docs/friction-whisk.md): gamma rises, every contact
    row touches the peg with its force on the cone's edge (the default straight whisker
    pinned at a peg cannot stick: the chord of [0, s1] is s1, so it slides, s1 rising); a
    pre-curved whisker under a flow at mu = 1.5 sticks at the touch with s1 fixed, then
    switches to slip."""
    mu = 0.3
    sw = vibrissa.sweep(profile="peg:-0.2,0.6", motion="rotate", mu=mu, points=20)
    assert (np.diff(sw.gamma) > 0).all()
    c = sw.contact
    assert set(sw.slip[c]) == {"slip"} and set(sw.slip[~c]) == {"none"}
    assert np.allclose(sw.xc[c], -0.2) and np.allclose(sw.yc[c], 0.6)
    f, ft = sw.f[c], sw.ft[c]
    assert np.allclose(np.abs(ft), mu * f, rtol=1e-8, atol=1e-12)
    assert (np.diff(sw.s1[c]) > 0).all()
    assert sw.mu == mu and sw.friction_events == []
    bent = vibrissa.sweep(profile="peg:-0.2,0.6", motion="rotate", mu=1.5, points=20,
                          theta=0.5, a=0.2, b=0.1, k=20.0, q=0.5)
    c = bent.contact
    slip = bent.slip[c]
    assert slip[0] == "stick" and slip[1] == "slip"
    assert bent.s1[c][0] == bent.s1[c][1]
    assert [e["event"] for e in bent.friction_events] == ["stick→slip"]


def test_a_scene_files_motion_is_read(tmp_path):
    """`load_scene` gives the scene's motion keys; `sweep(**load_scene(p))` whisks as the
    keywords do, and `solve(**load_scene(p))` ignores them."""
    p = tmp_path / "whisk.ron"
    p.write_text('(whisker: (theta: 0.6, k: Some(25.0)), profile: Some("disc:-0.3,0.8,0.15"), '
                 'motion: "rotate", x0: 0.05, y0: -0.02, gamma_deg: -10.0, '
                 'sweep: Some((points: 24)), loads: (q: 0.5, alpha_deg: 20.0))')
    kw = vibrissa.load_scene(p)
    assert (kw["motion"], kw["x0"], kw["y0"], kw["gamma_deg"]) == ("rotate", 0.05, -0.02, -10.0)
    a = vibrissa.sweep(**kw)
    b = vibrissa.sweep(**DISC)
    for col in COLUMNS:
        assert_same(a[col], b[col], col)
    vibrissa.solve(**kw)
