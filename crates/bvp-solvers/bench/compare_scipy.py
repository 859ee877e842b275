#!/usr/bin/env python3
"""Work-precision comparison of bvp_solvers::collocation::solve_bvp with scipy's solve_bvp.

Runs the same problems (mesh, guess, parameters, tol in {1e-3, 1e-6}) in scipy and in the
Rust example `collocation_bench` (JSON lines), then writes
  docs/figures/bvp-colloc-vs-scipy.png / .svg  (time and nodes, both solvers, greyscale-safe)
  docs/figures/bvp-colloc-vs-scipy.md          (the table)
Usage (from the repository root):
  python3 -m venv target/scipy-venv && target/scipy-venv/bin/pip install scipy numpy matplotlib
  target/scipy-venv/bin/python crates/bvp-solvers/bench/compare_scipy.py [--rust-json FILE]
"""
import argparse
import json
import subprocess
import time
from math import erf, pi

import numpy as np
from scipy.integrate import solve_bvp

TOLS = [1e-3, 1e-6]


def grid_err(sol, a, b, exact):
    t = np.linspace(a, b, 1001)
    return float(np.max(np.abs(sol.sol(t)[0] - exact(t))))


def winkler(L):
    def f(x, y):
        return np.vstack((y[1], y[2], y[3], 1.0 - 4.0 * y[0]))

    def bc(ya, yb):
        return np.array([ya[0], ya[2], yb[0], yb[2]])

    exact = lambda x: 0.25 * (1 - np.exp(-x) * np.cos(x) - np.exp(-(L - x)) * np.cos(L - x))
    return dict(f=f, bc=bc, x=np.linspace(0, L, 5), y=np.zeros((4, 5)),
                err=lambda s: grid_err(s, 0, L, exact))


def problems():
    P = {}
    P["exp"] = dict(
        f=lambda x, y: np.vstack((y[1], y[0])),
        bc=lambda ya, yb: np.array([ya[0] - 1, yb[0]]),
        x=np.linspace(0, 1, 5), y=np.zeros((2, 5)),
        err=lambda s: grid_err(s, 0, 1, lambda x: (np.exp(-x) - np.exp(x - 2)) / (1 - np.exp(-2))))
    P["sturm_liouville"] = dict(
        f=lambda x, y, p: np.vstack((y[1], -p[0] ** 2 * y[0])),
        bc=lambda ya, yb, p: np.array([ya[0], yb[0], ya[1] - p[0]]),
        x=np.linspace(0, pi, 5), y=np.ones((2, 5)), p=[0.5],
        err=lambda s: max(grid_err(s, 0, pi, np.sin), abs(s.p[0] - 1)))
    P["emden"] = dict(
        f=lambda x, y: np.vstack((y[1], -y[0] ** 5)),
        bc=lambda ya, yb: np.array([ya[1], yb[0] - (3 / 4) ** 0.5]),
        x=np.linspace(0, 1, 10), y=np.vstack((np.full(10, (3 / 4) ** 0.5), np.full(10, 1e-4))),
        S=np.array([[0, 0], [0, -2.0]]),
        err=lambda s: grid_err(s, 0, 1, lambda x: (1 + x ** 2 / 3) ** -0.5))

    def big_f(x, y):
        f = np.zeros_like(y)
        f[::2] = y[1::2]
        return f

    P["big_n60"] = dict(
        f=big_f, bc=lambda ya, yb: np.hstack((ya[::2], yb[::2] - 1)),
        x=np.linspace(0, 1, 5), y=np.zeros((60, 5)),
        err=lambda s: grid_err(s, 0, 1, lambda x: x))
    eps = 1e-3
    k = np.sqrt(2 * eps)
    verf = np.vectorize(erf)
    P["shock"] = dict(
        f=lambda x, y: np.vstack((y[1], -(x * y[1] + eps * pi ** 2 * np.cos(pi * x)
                                          + pi * x * np.sin(pi * x)) / eps)),
        bc=lambda ya, yb: np.array([ya[0] + 2, yb[0]]),
        x=np.linspace(-1, 1, 5), y=np.zeros((2, 5)),
        err=lambda s: grid_err(s, -1, 1, lambda x: np.cos(pi * x) + verf(x / k) / erf(1 / k)))

    def nl_bc(ya, yb):
        kappa, ioA, ioC, V, f = 1.64, 0.01, 1.0e-4, 0.5, 38.9
        hA = -ya[0]
        hC = V - yb[0] - 1.0
        return np.array([ioA * (np.exp(f * hA) - np.exp(-f * hA)) + kappa * ya[1],
                         ioC * (np.exp(f * hC) - np.exp(-f * hC)) - kappa * yb[1]])

    P["nonlin_bc"] = dict(
        f=lambda x, y: np.vstack((y[1], np.zeros_like(x))), bc=nl_bc,
        x=np.linspace(0, 0.1, 5), y=np.zeros((2, 5)),
        err=lambda s: grid_err(s, 0, 0.1, lambda x: -0.13426436116763119 - 1.1308709 * x))
    P["periodic"] = dict(
        f=lambda x, y: np.vstack((y[1], np.cos(x) - 2 * y[0])),
        bc=lambda ya, yb: ya - yb,
        x=np.linspace(0, 2 * pi, 7), y=np.zeros((2, 7)),
        err=lambda s: grid_err(s, 0, 2 * pi, np.cos))
    xm = np.linspace(0, pi, 10)
    P["mathieu"] = dict(
        f=lambda x, y, p: np.vstack((y[1], -(p[0] - 10 * np.cos(2 * x)) * y[0])),
        bc=lambda ya, yb, p: np.array([ya[1], yb[1], ya[0] - 1]),
        x=xm, y=np.vstack((np.cos(4 * xm), -4 * np.sin(4 * xm))), p=[15.0],
        err=lambda s: abs(s.p[0] - 17.096581684366047))
    A = 2 / np.sinh(4 - pi)
    P["twobvp"] = dict(
        f=lambda x, y: np.vstack((y[1], -np.abs(y[0]))),
        bc=lambda ya, yb: np.array([ya[0], yb[0] + 2]),
        x=np.linspace(0, 4, 5), y=np.vstack((np.ones(5), np.zeros(5))),
        err=lambda s: grid_err(s, 0, 4, lambda x: np.where(x <= pi, A * np.sin(x),
                                                            -A * np.sinh(x - pi))))
    P["falkner_skan"] = dict(
        f=lambda x, y: np.vstack((y[1], y[2], -y[0] * y[2] - 0.5 * (1 - y[1] ** 2))),
        bc=lambda ya, yb: np.array([ya[0], ya[1], yb[1] - 1]),
        x=np.linspace(0, 6, 10), y=np.vstack((np.zeros(10), np.zeros(10), np.ones(10))),
        err=lambda s: abs(s.y[2, 0] - 0.92768))
    th = 1.0
    for _ in range(200):
        th = 2 ** 0.5 * np.cosh(th / 4)
    P["bratu"] = dict(
        f=lambda x, y: np.vstack((y[1], -np.exp(y[0]))),
        bc=lambda ya, yb: np.array([ya[0], yb[0]]),
        x=np.linspace(0, 1, 5), y=np.zeros((2, 5)),
        err=lambda s: grid_err(s, 0, 1, lambda x: -2 * np.log(np.cosh(th * (x - 0.5) / 2)
                                                               / np.cosh(th / 4))))
    P["layer_k100"] = dict(
        f=lambda x, y: np.vstack((y[1], 1e4 * y[0])),
        bc=lambda ya, yb: np.array([ya[0] - 1, yb[0]]),
        x=np.linspace(0, 1, 5), y=np.zeros((2, 5)),
        err=lambda s: grid_err(s, 0, 1, lambda x: np.exp(-100 * x) * (1 - np.exp(-200 * (1 - x)))
                               / (1 - np.exp(-200))))
    xe = np.linspace(0, 1, 5)
    P["euler_buckling"] = dict(
        f=lambda x, y, p: np.vstack((y[1], -p[0] * y[0])),
        bc=lambda ya, yb, p: np.array([ya[0], yb[0], ya[1] - 1]),
        x=xe, y=np.vstack((np.sin(pi * xe) / pi, np.cos(pi * xe))), p=[8.0],
        err=lambda s: abs(s.p[0] - pi ** 2) / pi ** 2)
    P["winkler_L30"] = winkler(30.0)
    P["winkler_L50"] = winkler(50.0)
    return P


def run_scipy(P):
    rows = {}
    for name, d in P.items():
        for tol in TOLS:
            kw = dict(tol=tol, max_nodes=100000)
            if "p" in d:
                kw["p"] = d["p"]
            if "S" in d:
                kw["S"] = d["S"]
            call = lambda: solve_bvp(d["f"], d["bc"], d["x"], d["y"], **kw)
            sol = call()
            best = float("inf")
            t_start = time.perf_counter()
            reps = 0
            while reps < 3 or (time.perf_counter() - t_start < 1.0 and reps < 50):
                t0 = time.perf_counter()
                call()
                best = min(best, time.perf_counter() - t0)
                reps += 1
            rows[(name, tol)] = dict(nodes=int(sol.x.size), error=float(d["err"](sol)),
                                     time_s=best, status=int(sol.status))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rust-json", help="output of the Rust example (default: run it)")
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--scipy-json", help="cache of the scipy results: read if present, else written")
    args = ap.parse_args()
    if args.rust_json:
        lines = open(args.rust_json).read().splitlines()
    else:
        lines = subprocess.run(["cargo", "run", "--release", "--example", "collocation_bench",
                                "-p", "bvp-solvers"], check=True, capture_output=True,
                               text=True).stdout.splitlines()
    rust = {}
    for ln in lines:
        r = json.loads(ln)
        rust[(r["problem"], float(r["tol"]))] = r
    P = problems()
    import os
    if args.scipy_json and os.path.exists(args.scipy_json):
        sp = {(r["problem"], r["tol"]): r for r in json.load(open(args.scipy_json))}
    else:
        sp = run_scipy(P)
        if args.scipy_json:
            json.dump([dict(problem=k[0], tol=k[1], **v) for k, v in sp.items()],
                      open(args.scipy_json, "w"), indent=1)
    table = ["| problem | tol | nodes (Rust / scipy) | max error (Rust / scipy) "
             "| time Rust | time scipy | speed-up |", "|---|---|---|---|---|---|---|"]
    names, ratios = [], {t: [] for t in TOLS}
    for name in P:
        names.append(name)
        for tol in TOLS:
            r, s = rust.get((name, tol)), sp[(name, tol)]
            if r is None or "nodes" not in r:
                table.append(f"| {name} | {tol:.0e} | failed: {r} | | | | |")
                ratios[tol].append(float("nan"))
                continue
            ratio = s["time_s"] / r["time_s"]
            ratios[tol].append(ratio)
            table.append(f"| {name} | {tol:.0e} | {r['nodes']} / {s['nodes']}"
                         f"{'' if s['status'] == 0 else ' (status ' + str(s['status']) + ')'} "
                         f"| {r['error']:.1e} / {s['error']:.1e} | {r['time_s'] * 1e6:.0f} us "
                         f"| {s['time_s'] * 1e3:.2f} ms | {ratio:.0f}x |")
    os_out = args.out
    os.makedirs(os_out, exist_ok=True)
    with open(os.path.join(os_out, "bvp-colloc-vs-scipy.md"), "w") as fh:
        fh.write("\n".join(table) + "\n")
    print("\n".join(table))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({"font.size": 7, "axes.linewidth": 0.6})
    fig, ax = plt.subplots(figsize=(85 / 25.4, 75 / 25.4))
    markers = {1e-3: ("o", "tol 1e-3"), 1e-6: ("s", "tol 1e-6")}
    for tol in TOLS:
        rt = [rust[(n, tol)]["time_s"] for n in names if "nodes" in rust.get((n, tol), {})]
        st = [sp[(n, tol)]["time_s"] for n in names if "nodes" in rust.get((n, tol), {})]
        mk, lab = markers[tol]
        ax.scatter(st, rt, marker=mk, s=14, facecolors="none" if tol == 1e-3 else "black",
                   edgecolors="black", linewidths=0.7, label=lab)
    lo, hi = 1e-7, 10
    xs = np.array([lo, hi])
    for k, ls in [(1, "-"), (20, "--"), (100, ":")]:
        ax.plot(xs, xs / k, ls, color="0.4", lw=0.7, label=f"{k}x faster" if k > 1 else "equal")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(1e-4, 10)
    ax.set_ylim(1e-7, 1)
    ax.set_xlabel("scipy solve_bvp time per solve [s]")
    ax.set_ylabel("bvp-solvers collocation time [s]")
    ax.set_title(f"Same problems, same tol ({len(names)} problems)", fontsize=7)
    ax.legend(frameon=False, fontsize=6, loc="upper left")
    ax.grid(True, which="major", lw=0.3, color="0.85")
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(os_out, f"bvp-colloc-vs-scipy.{ext}"), dpi=300)
    for tol in TOLS:
        r = np.array(ratios[tol])
        print(f"tol {tol:.0e}: speed-up min {np.nanmin(r):.0f}x median {np.nanmedian(r):.0f}x")


if __name__ == "__main__":
    main()
