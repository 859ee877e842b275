"""The command line's 200-point sweep, whole process, side by side with the scipy script
(issue #21: the CLI with its default outputs >= 300x faster than `scipy_sweep.py`).

Builds nothing: give it the release binary. In one run it times

1. `vibrissa sweep --profile g1 --q 5 --points 200 --out DIR` (default outputs: the CSVs,
   `scene.ron` and the SVG figures), N times, a fresh output folder each time;
2. the same with `--figures none` (CSVs and `scene.ron` only), interleaved with 1. so that
   both see the same load on the machine;
3. the same sweep by the pure-scipy reference `sweep_scipy(200)` of `scipy_sweep.py`, in
   this process (its Python start-up and imports are not counted: the conservative side),

and prints the medians (and the fastest run) and the ratio scipy / CLI. A CLI run is the
whole process: spawn, dynamic loading, the solve, the files written and synced, the exit;
timed from before `posix_spawn` to after `waitpid`.

    python crates/vibrissa-py/bench/bench_cli.py target/release/vibrissa [--runs 15]
        [--scipy-runs 1] [--no-scipy] [--target 300] [--out-root DIR]

The output folders are made under `--out-root` (default: the system's temporary folder),
on whatever disk that is: the CLI flushes its files to disk before it exits (see
`atomic.rs`), so a busy disk shows in its time; a tmpfs would hide that cost.

Needs numpy and scipy for 3. (`--no-scipy` skips it). Exit status 0, also when the target
ratio is missed (the verdict is printed): this is a measurement, not a test.
"""

import argparse
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

SWEEP = ["sweep", "--profile", "g1", "--q", "5", "--points", "200"]


def run_cli(binary: str, extra: list, out: str) -> float:
    """One whole-process run (seconds); raises with the CLI's stderr if it failed."""
    argv = [binary, *extra, *SWEEP, "--out", out]
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        t0 = time.perf_counter()
        pid = os.posix_spawn(
            binary,
            argv,
            os.environ,
            file_actions=[
                (os.POSIX_SPAWN_DUP2, devnull, 1),
                (os.POSIX_SPAWN_DUP2, devnull, 2),
            ],
        )
        _, status = os.waitpid(pid, 0)
        elapsed = time.perf_counter() - t0
    finally:
        os.close(devnull)
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        import subprocess

        err = subprocess.run(argv, capture_output=True, text=True).stderr.strip()
        raise SystemExit(f"{' '.join(argv)} failed (exit {code}): {err}")
    return elapsed


def time_cli(binary: str, runs: int, work: Path) -> dict:
    """Medians and minima of `runs` runs of each variant, interleaved; a warm-up run each."""
    variants = {"default outputs (SVG figures)": [], "--figures none": []}
    flags = {"default outputs (SVG figures)": [], "--figures none": ["--figures", "none"]}
    for i in range(-1, runs):
        for name, times in variants.items():
            out = work / f"run{i + 1}-{len(flags[name])}"
            t = run_cli(binary, flags[name], str(out))
            if i >= 0:
                times.append(t)
            if not (out / "observables.csv").is_file():
                raise SystemExit(f"{out}: no observables.csv was written")
            shutil.rmtree(out)
    return {
        name: (statistics.median(ts), min(ts), max(ts)) for name, ts in variants.items()
    }


def time_scipy(runs: int) -> tuple:
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    try:
        from scipy_sweep import sweep_scipy
    except ImportError as e:
        raise SystemExit(f"the scipy reference needs numpy and scipy ({e}); or pass --no-scipy")
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        cols = sweep_scipy(200)
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), len(cols["x0"])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("binary", help="the release binary, e.g. target/release/vibrissa")
    ap.add_argument("--runs", type=int, default=15, help="CLI runs per variant (default 15)")
    ap.add_argument("--scipy-runs", type=int, default=1, help="scipy sweeps (default 1)")
    ap.add_argument("--no-scipy", action="store_true", help="time the CLI only")
    ap.add_argument("--target", type=float, default=300.0, help="ratio to reach (default 300)")
    ap.add_argument("--out-root", help="where the output folders are made (default: temp)")
    args = ap.parse_args()
    binary = shutil.which(args.binary) or args.binary
    if not os.access(binary, os.X_OK):
        raise SystemExit(f"{args.binary}: not an executable (build it: cargo build --release)")
    binary = os.path.abspath(binary)
    if args.runs < 1 or args.scipy_runs < 1:
        raise SystemExit("--runs and --scipy-runs must be at least 1")

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    with tempfile.TemporaryDirectory(prefix="vibrissa-bench-cli-", dir=args.out_root) as work:
        cli = time_cli(binary, args.runs, Path(work))
        print(f"{binary}; output folders in {work}; load average {load:.2f} ({os.cpu_count()} cores)")
    print(f"vibrissa sweep g1, q = 5, 200 points, whole process, {args.runs} runs each:")
    for name, (med, best, worst) in cli.items():
        print(
            f"  {name:31s} median {1e3 * med:7.2f} ms   "
            f"fastest {1e3 * best:7.2f} ms   slowest {1e3 * worst:7.2f} ms"
        )
    if args.no_scipy:
        return
    med, best, rows = time_scipy(args.scipy_runs)
    print(
        f"scipy_sweep.sweep_scipy(200) ({rows} contact rows), in-process, "
        f"{args.scipy_runs} run(s): median {med:.3f} s, fastest {best:.3f} s"
    )
    default = cli["default outputs (SVG figures)"][0]
    none = cli["--figures none"][0]
    ratio = med / default
    print(f"ratio scipy / CLI (default outputs): {ratio:7.0f}x   (target {args.target:.0f}x: "
          f"{'met' if ratio >= args.target else 'missed'}; the CLI may take "
          f"{1e3 * med / args.target:.2f} ms)")
    print(f"ratio scipy / CLI (--figures none):  {med / none:7.0f}x")


if __name__ == "__main__":
    main()
