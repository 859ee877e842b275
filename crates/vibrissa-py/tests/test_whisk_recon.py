"""Logs of any base motion (issue 38): ``reconstruct`` and ``Streamer`` take the pose
columns ``y0``, ``gamma``. Truth: the reconstruction is covariant: a translate log turned
as a whole by ``delta`` about each row's base and lifted by ``y0`` gives the original points
turned and lifted, the flow angle ``alpha - delta``."""

import math

import numpy as np
import pytest

import vibrissa


def turned(sw, delta, y0):
    c, s = math.cos(delta), math.sin(delta)
    ax, ay = np.asarray(sw["Ax"]), np.asarray(sw["Ay"])
    n = len(ax)
    return {
        "x0": np.asarray(sw["x0"], dtype=float),
        "Ax": c * ax - s * ay,
        "Ay": s * ax + c * ay,
        "MA": np.asarray(sw["MA"], dtype=float),
        "phi0": np.asarray(sw["phi0"]) + delta,
        "y0": np.full(n, y0),
        "gamma": np.full(n, delta),
    }


@pytest.mark.parametrize("delta,y0", [(0.5, 0.2), (-0.6, -0.15)])
def test_wrec_a_turned_and_lifted_log_gives_the_turned_and_lifted_points(delta, y0):
    sw = vibrissa.sweep(profile="g2", q=2, alpha_deg=10, theta=0.7, k=25, points=20)
    plain = vibrissa.reconstruct(sw)
    log = turned(sw, delta, y0)
    rec = vibrissa.reconstruct(log, theta=0.7, k=25)
    assert rec.alpha_deg == pytest.approx(10 - math.degrees(delta), abs=1e-9)
    assert rec.obstacle is None
    c, s = math.cos(delta), math.sin(delta)
    m = plain.contact
    assert (rec.contact == m).all()
    dx, dy = plain.x[m] - plain.x0[m], plain.y[m]
    ex, ey = plain.x0[m] + c * dx - s * dy, y0 + s * dx + c * dy
    assert np.max(np.hypot(rec.x[m] - ex, rec.y[m] - ey)) < 1e-9
    # the stream, row by row with each row's pose: the same points
    st = vibrissa.Streamer(theta=0.7, k=25)
    for i in range(len(log["x0"])):
        st.push(*(log[k][i] for k in ("x0", "Ax", "Ay", "MA", "phi0")),
                y0=log["y0"][i], gamma=log["gamma"][i])
    st.finish()
    pts = {p["row"]: p for p in st.points}
    for i in np.flatnonzero(m):
        assert abs(pts[i]["x"] - rec.x[i]) < 1e-9 and abs(pts[i]["y"] - rec.y[i]) < 1e-9
