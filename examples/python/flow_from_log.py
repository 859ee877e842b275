"""Calibrating the flow from a sensor log with pandas.

A log as a lab records it: a CSV of base observables (x0, Ax, Ay, MA, phi0), noisy, rows in
whatever order the logger wrote them. vibrissa identifies the flow (q and its angle) from
the rows where the whisker is free, then reconstructs the touched contour, each point with
its error estimate.

    python examples/python/flow_from_log.py [OUT_DIR]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

import vibrissa

out = Path(sys.argv[1] if len(sys.argv) > 1 else "vibrissa-flow")
out.mkdir(parents=True, exist_ok=True)
whisker = dict(theta=0.6, a=0.2, b=0.1, k=15.0)
true_q, true_alpha = 3.2, 12.0

# The "experiment": a sweep past a circular post under an oblique flow, relative noise 1e-4.
sw = vibrissa.sweep(profile="circle:0.2,1.45,0.7", q=true_q, alpha_deg=true_alpha, points=150, **whisker)
log = sw.to_pandas()[["x0", "Ax", "Ay", "MA", "phi0"]]
rng = np.random.default_rng(1)
noise = 1e-4
for col in ("Ax", "Ay", "MA", "phi0"):
    log[col] += noise * np.abs(log[col]).max() * rng.standard_normal(len(log))
log = log.sample(frac=1.0, random_state=2)  # any row order
log.to_csv(out / "sensor_log.csv", index=False)

# The analysis, from the CSV alone (and the whisker's parameters).
data = pd.read_csv(out / "sensor_log.csv")
rec = vibrissa.reconstruct(data, noise=noise, tolerance="none", **whisker)
print(rec)
print(f"flow: q = {rec.q:.5f} (true {true_q}), alpha = {rec.alpha_deg:.3f} deg (true {true_alpha})")
res = rec.to_pandas()
pts = res[res.phase != "none"]
print(pts[["x0", "x", "y", "sigma", "phase"]].describe())

fig, ax = plt.subplots(figsize=(3.35, 1.9), constrained_layout=True)
t = np.linspace(0, 2 * np.pi, 400)
ax.fill(0.2 + 0.7 * np.cos(t), 1.45 + 0.7 * np.sin(t), color="0.85", lw=0)
ax.plot(0.2 + 0.7 * np.cos(t), 1.45 + 0.7 * np.sin(t), "k-", lw=0.8, label="post (true)")
ax.errorbar(pts.x, pts.y, xerr=3 * pts.sigma, yerr=3 * pts.sigma, fmt="o", ms=1.8, mfc="none",
            elinewidth=0.5, label=r"reconstructed ($\pm 3\sigma$)")
ax.set_aspect("equal")
ax.set_xlim(-0.6, 1.0)
ax.set_ylim(0.65, 1.25)
ax.set_xlabel("$x$")
ax.set_ylabel("$y$")
ax.legend(frameon=False, fontsize=7, loc="upper center", ncol=1)
fig.savefig(out / "flow_from_log.png", dpi=300)
print("wrote", out / "flow_from_log.png")
assert abs(rec.q - true_q) < 1e-2 and abs(rec.alpha_deg - true_alpha) < 0.5
