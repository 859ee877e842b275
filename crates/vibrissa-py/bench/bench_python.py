"""Timings of the Python package, each beside its peer in one process:

1. `vibrissa.sweep(profile="g1", q=5, points=200)` (the scene of `cargo bench --bench
   sweep`): median and best of N calls, to set beside the criterion figure;
2. the same sweep by the pure-scipy script `scipy_sweep.py` (one run: seconds), and the
   ratio;
3. a 1,000-scene study on the local cores: wall time, compute time summed over the scenes,
   and the process's CPU time over the wall time (2.0 = both cores busy throughout).

    python crates/vibrissa-py/bench/bench_python.py [--no-scipy] [--scenes N]
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import vibrissa

sys.path.insert(0, str(Path(__file__).parent))


def time_sweep(n: int = 30):
    vibrissa.sweep(profile="g1", q=5, points=200)  # warm
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        vibrissa.sweep(profile="g1", q=5, points=200)
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times)


def study_scenes(n: int):
    rng = np.random.default_rng(1000)
    profiles = ["g1", "g2", "circle:0.3,1.3,0.6", "parabola:1.5,0.2,0.5"]
    return [
        {
            "profile": profiles[i % len(profiles)],
            "q": float(rng.uniform(0, 8)),
            "alpha_deg": float(rng.uniform(-30, 30)),
            "theta": float(rng.uniform(0.3, 1.0)),
            "k": None if i % 3 == 0 else float(rng.uniform(5, 40)),
            "points": 100,
        }
        for i in range(n)
    ]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--no-scipy", action="store_true")
    ap.add_argument("--scenes", type=int, default=1000)
    args = ap.parse_args()
    med, best = time_sweep()
    print(f"vibrissa.sweep(g1, q=5, 200 points): median {1e3 * med:.2f} ms, best {1e3 * best:.2f} ms")
    if not args.no_scipy:
        from scipy_sweep import sweep_scipy

        t0 = time.perf_counter()
        sweep_scipy(200)
        t_scipy = time.perf_counter() - t0
        med2, best2 = time_sweep(10)
        print(f"scipy sweep: {t_scipy:.2f} s; vibrissa (after it) median {1e3 * med2:.2f} ms; "
              f"ratio {t_scipy / med2:.0f}x (median), {t_scipy / best2:.0f}x (best)")
    scenes = study_scenes(args.scenes)
    c0, t0 = time.process_time(), time.perf_counter()
    df = vibrissa.study(scenes)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    print(f"study of {len(df)} sweeps on the local cores: wall {wall:.2f} s, compute summed "
          f"{df.wall_time_s.sum():.2f} s, CPU/wall {cpu / wall:.2f}, refused "
          f"{int(df.error.notna().sum())} ({', '.join(sorted(set(df.error_class.dropna())))})")


if __name__ == "__main__":
    main()
