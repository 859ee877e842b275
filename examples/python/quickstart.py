"""vibrissa quickstart: one equilibrium, a sweep past an obstacle under flow, the contour
reconstructed from the base observables alone, and a figure of both.

    python examples/python/quickstart.py [OUT_DIR]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless; remove to show windows
import matplotlib.pyplot as plt
import numpy as np

import vibrissa

out = Path(sys.argv[1] if len(sys.argv) > 1 else "vibrissa-quickstart")
out.mkdir(parents=True, exist_ok=True)

# 1. One equilibrium: a tapered, pre-curved whisker on an elastic follicle under a flow.
sol = vibrissa.solve(theta=0.5, a=0.3, b=0.2, k=20, q=3.0)
print(sol)
print("base observables:", sol.base, "error estimate:", sol.stats["error_estimate"])

# 2. A sweep past the catenary g1 under the flow q = 5 (dimensionless), 200 contact rows.
sw = vibrissa.sweep(profile="g1", theta=0.75, k=20, q=5, points=200)
print(sw)
print(sw.to_pandas().head())

# 3. Identify the flow and reconstruct the contour from the observables alone.
rec = vibrissa.reconstruct(sw, profile="g1")
print(rec)
print(f"identified q = {rec.q:.12f}, max contour error {np.nanmax(rec.error):.1e}")

# 4. Figure: the observables against the base position, and the contour.
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(6.9, 2.8), constrained_layout=True)
for name, style in (("Ax", "-"), ("Ay", "--"), ("MA", "-.")):
    ax1.plot(sw.x0, sw[name], style, lw=1.2, label=name)
ax1.axvline(sw.x0[sw.contact][0], color="0.5", lw=0.6, ls=":")
ax1.set_xlabel("base position $x_0$")
ax1.set_ylabel("base observables")
ax1.invert_xaxis()  # the base travels towards -x
ax1.legend(frameon=False, fontsize=7)
x = np.linspace(np.nanmin(rec.x) - 0.3, np.nanmax(rec.x) + 0.3, 200)
ax2.fill_between(x, np.cosh(x / 2) - 0.8, 2.2, color="0.9", lw=0)  # the obstacle (solid)
ax2.plot(x, np.cosh(x / 2) - 0.8, "k-", lw=0.8, label="true contour $g_1$")
ax2.plot(rec.x[::8], rec.y[::8], "o", ms=3, mfc="none", mec="C0", mew=0.8, label="reconstructed (every 8th)")
ax2.set_aspect("equal")
ax2.set_xlabel("$x$")
ax2.set_ylabel("$y$")
ax2.set_ylim(0, 2.2)
ax2.legend(frameon=False, fontsize=7, loc="upper center")
fig.savefig(out / "quickstart.png", dpi=300)
print("wrote", out / "quickstart.png")
