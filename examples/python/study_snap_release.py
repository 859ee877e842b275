"""A 500-scene study: where does the whisker snap off the obstacle, and where is it released
slowly by the flow, over the flow q and the taper theta? Runs on every local core, or on a
Dask cluster: pass a scheduler address (the one line that changes).

    python examples/python/study_snap_release.py [OUT_DIR] [SCHEDULER_ADDRESS]
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import vibrissa

out = Path(sys.argv[1] if len(sys.argv) > 1 else "vibrissa-study")
out.mkdir(parents=True, exist_ok=True)
client = None
if len(sys.argv) > 2:
    from dask.distributed import Client

    client = Client(sys.argv[2])  # e.g. a SLURMCluster's scheduler

qs = np.linspace(0.0, 8.0, 25)
thetas = np.linspace(0.2, 1.0, 20)
scenes = [
    {"profile": "g1", "q": float(q), "theta": float(t), "k": 20.0, "points": 50}
    for t in thetas
    for q in qs
]
t0 = time.perf_counter()
df = vibrissa.study(scenes, client=client)
wall = time.perf_counter() - t0
print(f"{len(df)} sweeps in {wall:.2f} s ({1e3 * wall / len(df):.1f} ms per sweep wall, "
      f"{1e3 * df.wall_time_s.mean():.1f} ms per sweep of compute)")
print(df.groupby("separation").size())
df.to_csv(out / "study.csv", index=False)

kinds = ["snap", "release"]
code = np.array([kinds.index(s) if s in kinds else 2 for s in df.separation.fillna("error")])
grid = code.reshape(len(thetas), len(qs))
fig, ax = plt.subplots(figsize=(3.35, 2.6), constrained_layout=True)
# three distinct greys (readable in greyscale and by colour-blind readers)
cmap = matplotlib.colors.ListedColormap(["#f0f0f0", "#8c8c8c", "#111111"])
ax.pcolormesh(qs, thetas, grid, cmap=cmap, vmin=-0.5, vmax=2.5, shading="nearest")
for i, name in enumerate(kinds + ["other"]):
    ax.plot([], [], "s", color=cmap(i), mec="k", mew=0.4, label=name)
ax.set_xlabel("flow $q$")
ax.set_ylabel(r"taper $\theta$")
ax.legend(frameon=False, fontsize=7, ncol=3, loc="lower center", bbox_to_anchor=(0.5, 1.0),
          title="separation from $g_1$ ($k = 20$)", title_fontsize=7)
fig.savefig(out / "snap_release.png", dpi=300)
print("wrote", out / "snap_release.png")
