"""`vibrissa.calibrate` on whisking logs (issue 38, item 3; docs/whisking-recon.md, "Paths in
the calibration"): a path log (poses changing x0, y0, gamma at once, the follicle's k per
row) as a Sweep and as a DataFrame, and a rotation past a peg with a translation past g2
jointly, give the numbers of `vibrissa calibrate --json` on the same logs bit for bit; the
Reconstruction carries the log's pose columns."""

import numpy as np

import vibrissa

from conftest import read_csv

PEG = "peg:-0.25,0.55"
TRUTH = dict(theta=0.8, a=0.2, b=0.1, q=1.0, alpha_deg=10.0)
START = dict(theta=1.0, a=0.0, b=0.0, k=1000.0)
PATH = dict(
    x0=np.array([0.05, 0.0, -0.04]),
    y0=np.array([-0.1, -0.06, 0.0]),
    gamma_deg=np.array([-6.0, 23.0, 57.0]),
    k=np.array([15.0, 40.0, 25.0]),
)
PATH_CSV = "x0,y0,gamma_deg,k\n0.05,-0.1,-6,15\n0.0,-0.06,23,40\n-0.04,0.0,57,25\n"


def _cli_flags(d):
    return [x for n, v in d.items() for x in (f"--{n.replace('_', '-')}", repr(v))]


def _same(py, cli_json):
    for name, p in cli_json["parameters"].items():
        assert py.parameters[name]["value"] == p["value"], (name, py.parameters[name], p)
        assert py.parameters[name]["stderr"] == p["stderr"], name
    for lp, lc in zip(py.logs, cli_json["logs"]):
        assert lp["q"] == lc["q"] and lp["alpha_deg"] == lc["alpha_deg"], (lp, lc)


def test_wleft_a_path_log_calibrates_as_the_cli(cli, tmp_path):
    (tmp_path / "path.csv").write_text(PATH_CSV)
    cli.run(
        "sweep", "--motion", f"path:{tmp_path / 'path.csv'}", "--profile", PEG,
        *_cli_flags(TRUTH), "--points", "30", "--figures", "none", "--out", str(tmp_path / "sw"),
    )
    log = tmp_path / "sw" / "observables.csv"
    c = cli.json(
        "calibrate", str(log), "--profile", PEG, "--fit", "theta,a,b",
        *_cli_flags(START),
    )
    # the Python sweep of the same path is the CLI's log
    sw = vibrissa.sweep(profile=PEG, motion="path", path=PATH, points=30, **TRUTH)
    df = read_csv(log)
    for name in ("x0", "Ax", "Ay", "MA", "phi0", "y0", "gamma", "k"):
        given = sw.k if name == "k" else sw[name]
        assert np.array_equal(given, df[name].to_numpy()), name
    for log_in in (sw, df):
        py = vibrissa.calibrate([(log_in, PEG)], fit="theta,a,b", **START)
        _same(py, c)
        assert abs(py.parameters["theta"]["value"] - 0.8) < 1e-8
    # the reconstruction carries the pose columns as given
    rec = vibrissa.reconstruct(df, profile=PEG, theta=0.8, a=0.2, b=0.1, k=20.0)
    assert np.array_equal(rec.gamma, df["gamma"].to_numpy())
    assert np.array_equal(rec.k, df["k"].to_numpy())
    assert np.nanmax(rec.error) < 1e-8


def test_wleft_a_rotation_and_a_translation_calibrate_jointly_as_the_cli(cli, tmp_path):
    w = dict(theta=0.8, a=0.2, b=0.1, k=30.0, q=1.0, alpha_deg=10.0)
    cli.run(
        "sweep", "--motion", "rotate", "--x0", "0.05", "--y0", "-0.1", "--gamma-deg", "-6",
        "--profile", PEG, *_cli_flags(w), "--points", "30", "--figures", "none",
        "--out", str(tmp_path / "rot"),
    )
    cli.run(
        "sweep", "--profile", "g2", *_cli_flags(w), "--points", "30", "--figures", "none",
        "--out", str(tmp_path / "tr"),
    )
    rot, tr = tmp_path / "rot" / "observables.csv", tmp_path / "tr" / "observables.csv"
    c = cli.json(
        "calibrate", f"{rot}={PEG}", f"{tr}=g2", *_cli_flags(START),
    )
    py = vibrissa.calibrate([(read_csv(rot), PEG), (read_csv(tr), "g2")], **START)
    _same(py, c)
    for name, truth in (("theta", 0.8), ("a", 0.2), ("b", 0.1), ("k", 30.0)):
        assert abs(py.parameters[name]["value"] - truth) < 1e-8 * max(truth, 1.0), name
