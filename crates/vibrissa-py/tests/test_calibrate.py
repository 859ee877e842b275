"""`vibrissa.calibrate` (issue 19): the whisker's own parameters from sweeps past known
contours, the same numbers as `vibrissa calibrate --json`."""

import numpy as np
import pytest

import vibrissa

TRUTH = dict(theta=0.6, a=0.5, b=0.3, k=20.0)
POST = "circle:-0.2,1.3,0.5"


def test_a_sweep_past_a_post_gives_the_truth_from_a_wrong_start():
    sw = vibrissa.sweep(profile=POST, q=2.0, alpha_deg=10.0, points=40, **TRUTH)
    cal = vibrissa.calibrate(sw, theta=0.8, a=0.3, b=0.2, k=30.0)
    for name, truth in TRUTH.items():
        p = cal.parameters[name]
        assert p["identifiable"]
        assert abs(p["value"] - truth) < 1e-7 * max(truth, 1.0), (name, p)
        assert p["stderr"] < 1e-6
    assert abs(cal.logs[0]["q"] - 2.0) < 1e-8
    assert abs(cal.logs[0]["alpha_deg"] - 10.0) < 1e-6
    assert cal.rms_residual < 1e-8
    assert "theta=0.6" in repr(cal)
    # the calibrated whisker reconstructs an unknown object
    other = "parabola:1.5,-0.2,0.55"
    unknown = vibrissa.sweep(profile=other, q=2.0, alpha_deg=10.0, points=20, **TRUTH)
    rec = vibrissa.reconstruct(unknown.to_pandas() if hasattr(unknown, "to_pandas") else unknown,
                               profile=other, **cal.whisker)
    assert np.nanmax(rec.error) < 1e-7


def test_logs_as_pairs_and_the_free_whisker_alone():
    # Rows of the free whisker alone cannot determine theta, a, b: the calibration refuses
    # them (issue 34 item 4), naming why; the follicle law still determines k alone.
    sw = vibrissa.sweep(profile=POST, q=2.0, points=20, **TRUTH)
    cols = {n: sw[n][:10] for n in ("x0", "Ax", "Ay", "MA", "phi0")}
    with pytest.raises(vibrissa.InvalidInput, match="free whisker"):
        vibrissa.calibrate([(cols, POST)], theta=0.8, k=30.0, fit=["theta", "a", "b", "k"])
    cal = vibrissa.calibrate([(cols, POST)], theta=0.6, a=0.5, b=0.3, k=30.0, fit=["k"])
    assert cal.parameters["k"]["identifiable"]
    assert abs(cal.value("k") - 20.0) < 1e-8
    assert any("follicle law only" in w for w in cal.warnings)


def test_bad_input_is_refused_with_the_cli_message():
    sw = vibrissa.sweep(profile=POST, q=2.0, points=10, **TRUTH)
    with pytest.raises(vibrissa.InvalidInput, match="zeta"):
        vibrissa.calibrate(sw, fit="theta,zeta")
    with pytest.raises(vibrissa.InvalidInput, match="dimensionless"):
        vibrissa.calibrate(sw, fit="ei")
    with pytest.raises(vibrissa.InvalidInput, match="profile"):
        vibrissa.calibrate({n: sw[n] for n in ("x0", "Ax", "Ay", "MA", "phi0")})
