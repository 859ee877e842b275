"""The independent checker (`independent.py`) on the CLI: seeded random scenes over the
whole input space, every contact row re-integrated by scipy (DOP853, rtol 1e-12) from its
logged base observables and checked against spec/model.md (the follicle law, the contact
point on the contour, the force's jump, normal or in the cone, the moment beyond the
contact, no penetration BOUNDED over the whole whisker), the JSON's phases and events
against the rows, and `reconstruct` on the log reordered, thinned and noised.

A small seeded subset runs in the default suite (seconds); the full battery (300 scenes)
runs with `VIBRISSA_INDEPENDENT_FULL=1` and writes `target/independent/report.json`
(docs/independent-check.md has the command and the figures).
"""

import json
import math
import os

import numpy as np
import pytest

import independent as ind
from conftest import ROOT, cli_binary

FULL = os.environ.get("VIBRISSA_INDEPENDENT_FULL") == "1"
FULL_SCENES = int(os.environ.get("VIBRISSA_INDEPENDENT_SCENES", "300"))

# seeds of the subset: a tip-then-tangential frictional sweep of g1 (ABA, snap), a rotation
# past a circle, a disc and a parabola, a peg, a translated circle, a frictional ge
SUBSET = [2, 5, 9, 12, 13, 14, 15, 19]


@pytest.fixture(scope="module")
def binary():
    return cli_binary()


# ------------------------------------------------------------------ the checker can fail
def test_the_elastica_of_the_checker_meets_the_linear_limit():
    """A uniform rigid straight whisker under a small tip load f (beta = 0): the base
    reactions Ax = -f, MA = -m(0) = f (the moment of f at the tip about the base... with
    m' = f sin(phi) and m(1) = 0: m(0) = -f), tip deflection f / 3 (model.md, small loads)."""
    f = 1e-6
    w = ind.Whisker()
    c = ind.integrate(w, 0.0, 0.0, math.pi / 2, ma=f, ax=-f, ay=0.0, s1=1.0)
    x1, y1, phi1, m1 = c.contact
    assert abs(m1) < 1e-15
    assert x1 == pytest.approx(f / 3, rel=1e-5)
    assert phi1 - math.pi / 2 == pytest.approx(-f / 2, rel=1e-5)


def test_the_penetration_bound_is_a_bound():
    """A straight whisker along x = 0.1 against the parabola y = (x - 0.1)^2 + 0.5 - d: the
    whisker crosses the contour from s = 0.5 - d on, as deep as d + ... at the tip; the
    bound reports exactly the depth of the deepest point (the tip, 0.5 + d)."""
    w = ind.Whisker()
    c = ind.integrate(w, 0.1, 0.0, math.pi / 2, 0.0, 0.0, 0.0, 1.0)
    ob = ind.parabola(1.0, 0.1, 0.98)
    bound, deepest, s = ind.min_clearance(c, w, ob, 1e-9)
    assert bound <= -0.02 + 1e-12 and deepest == pytest.approx(-0.02, abs=1e-12)
    clear = ind.parabola(1.0, 0.1, 1.0 + 1e-7)
    bound, deepest, s = ind.min_clearance(c, w, clear, 1e-9)
    assert -1e-12 <= bound <= 1e-7 + 1e-12
    assert s == pytest.approx(1.0)


def test_planted_errors_are_caught(binary, tmp_path):
    """The same row with MA off by 1e-6, or its base pushed 1e-3 into the obstacle, fails
    the contact-point and the penetration checks (a checker that cannot fail checks
    nothing)."""
    rng = np.random.default_rng([2026, 13])
    sc = ind.random_scene(rng, 13, tmp_path)
    res = ind.check_sweep(binary, sc, tmp_path)
    assert res.status == "ok" and not res.violations, res.violations[:3]
    w, ob = ind.whisker_of(sc), ind.parse_profile(sc["profile"])
    row = next(r for r in res.rows if r["phase"] == "B")
    tol = ind.tolerances(w, ob, row, ind.DEFAULT_ACCURACY)
    good = ind.check_row(w, ob, row, sc["mu"], tol["penetration"])
    assert good["contact_point"] <= tol["contact_point"]
    bad = ind.check_row(w, ob, dict(row, MA=row["MA"] + 1e-6), sc["mu"], tol["penetration"])
    assert bad["contact_point"] > tol["contact_point"] and bad["moment"] > tol["moment"]
    deep = ind.check_row(w, ob, dict(row, y0=row["y0"] + 1e-3), sc["mu"], tol["penetration"])
    assert deep["penetration"] > 1e-4  # the signed distance: 1e-3 up, across a slanted arc


# ------------------------------------------------------------------------- the CLI
def _summary(rep):
    lines = [f"{rep['scenes']} scenes, {rep['swept']} swept, {rep['contact_rows']} contact rows, "
             f"{len(rep['violations'])} violations, {rep['seconds']:.0f} s"]
    for name, w in sorted(rep["worst"].items()):
        lines.append(f"  {name:17s} worst {w['residual']:.2e} (tol {w['tol']:.2e}, ratio {w['ratio']:.2e}) seed {w['seed']} {w['scene']}")
    r = rep["recon"]
    lines.append(f"  reconstruct: {r['logs']} logs, {r['within3']}/{r['points']} points within 3 sigma, worst {r['worst_z'][0]:.2f}")
    return "\n".join(lines)


def test_subset(binary, tmp_path):
    rep = ind.battery(binary, SUBSET, tmp_path)
    print(_summary(rep))
    assert rep["swept"] == len(SUBSET), rep["refusals"]
    assert not rep["crashes"]
    assert rep["contact_rows"] > 150
    assert not rep["violations"], rep["violations"][:5]
    r = rep["recon"]
    assert r["logs"] == len(SUBSET) and r["points"] > 40
    # 3 sigma covers 99.7 % of a normal error: no miss but the known ones (xfail below)
    assert {m["seed"] for m in r["misses"]} <= set(KNOWN_RECON_MISSES), r["misses"]
    for m in r["mu"]:
        assert m["z"] <= 3.0, m


# Reconstruction misses the battery found (docs/independent-check.md, "reconstruct"): the
# frictional reconstruction of a noisy log near a phase switch.
KNOWN_RECON_MISSES = {
    19: "g1, mu 1.26 (--mu identify): one of 9 points 5.4 reported sigmas off under noise 1e-4",
}

# Sweeps the battery found violating the model and not fixed here (docs/independent-check.md)
KNOWN_SWEEP_VIOLATIONS = {
    62: "theta 0.063, q 9.5: the rows before contact (the free whisker) break the follicle law "
        "by 1.7e-8 and the first contact row by 1.6e-9, against the default ~1e-10 "
        "(--tol sees it: a sweep asking 1e-9 is refused with an estimate of 7.6e-8)",
}


@pytest.mark.xfail(strict=True, reason="known: a frictional point beyond 3 reported sigmas")
@pytest.mark.parametrize("seed", sorted(KNOWN_RECON_MISSES))
def test_known_reconstruction_misses(binary, tmp_path, seed):
    rep = ind.battery(binary, [seed], tmp_path)
    assert not rep["recon"]["misses"], rep["recon"]["misses"]


@pytest.mark.skipif(not FULL, reason="the full battery: VIBRISSA_INDEPENDENT_FULL=1")
def test_full_battery(binary, tmp_path):
    """The full battery: a report, then the verdict (no violation, no crash)."""
    out = ROOT / "target" / "independent"
    out.mkdir(parents=True, exist_ok=True)

    def log(seed, tag, res):
        if res.violations:
            print(f"seed {seed} {tag}: {len(res.violations)} violations, first {res.violations[0]}", flush=True)

    rep = ind.battery(binary, range(FULL_SCENES), tmp_path, log=log)
    (out / "report.json").write_text(json.dumps(rep, indent=1, default=str))
    print(_summary(rep))
    assert not rep["crashes"], rep["crashes"][:3]
    new = [v for v in rep["violations"] if v["seed"] not in KNOWN_SWEEP_VIOLATIONS]
    assert not new, f"{len(new)} violations, see target/independent/report.json"
    r = rep["recon"]
    # 3 sigma: 99.7 % of normal errors; the battery's 997 points allow ~3 misses
    assert r["within3"] >= 0.99 * r["points"], r["misses"]
    assert all(m["z"] <= 3.0 for m in r["mu"]), r["mu"]


@pytest.mark.xfail(strict=True, reason="known: the free whisker of a slender whisker to ~1e-8 only")
@pytest.mark.parametrize("seed", sorted(KNOWN_SWEEP_VIOLATIONS))
def test_known_sweep_violations(binary, tmp_path, seed):
    rep = ind.battery(binary, [seed], tmp_path, recon=False)
    assert not rep["violations"], rep["violations"][:2]


def test_the_battery_findings_stay_fixed(binary, tmp_path):
    """Seed 17 (a curled whisker's frictional sweep of g1 that started with its body 9.96e-3
    inside the contour) is refused as without friction; seed 47 (a rotation on a soft
    follicle whose rows before contact lay 0.19 inside g2) sweeps with every row checked."""
    rng = np.random.default_rng([2026, 17])
    res = ind.check_sweep(binary, ind.random_scene(rng, 17, tmp_path), tmp_path)
    assert res.status == "refused" and res.code == 3, res.message
    assert "inside the contour" in res.message
    rng = np.random.default_rng([2026, 47])
    res = ind.check_sweep(binary, ind.random_scene(rng, 47, tmp_path), tmp_path)
    assert res.status == "ok" and len(res.residuals) > 30
    assert not res.violations, res.violations[:3]
