"""Speed and accuracy of hjplanner.solve; prints tables (run: python benchmarks/bench_hjplanner.py).

Reference setup (REFERENCE.md, "Hamilton-Jacobi simple-car value function"):
domain [-1, 1]^2, rho = 0.3, point target at the origin, absolute error of
φ against the closed form (hjplanner.dubins.point_distance) over random
poses whose exact distance is below 0.95.  Wall times are the best of a few
runs after a warm-up, so numba compilation (reported separately) is excluded.
Also, on the `paper` arena: one value function and the whole bank of targets
12.7 cm apart (as in the paper), with its build time and size on disk, for the
car platform's planner (h = 1.5 cm, 48 headings, clearance 4 cm, reverse) and
for the 1 cm / 72-heading forward planner.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from hjplanner import SolverOptions, ValueFunctionBank, point_distance, solve

RHO = 0.3
DOMAIN = ((-1.0, 1.0), (-1.0, 1.0))


def compile_time() -> float:
    """Seconds to import and run a first tiny solve in a fresh process (numba cache cold or warm)."""
    code = ("import time; t = time.perf_counter(); import hjplanner; "
            "hjplanner.solve(((-1, 1), (-1, 1)), (0, 0), 0.3, 0.2, 8); print(time.perf_counter() - t)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    return float(out.stdout.strip())


def reference_errors(vf, n: int = 20000, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    poses = rng.uniform([-1, -1, 0], [1, 1, 2 * np.pi], (12 * n, 3))
    exact = point_distance(poses[:, 0], poses[:, 1], poses[:, 2], RHO)
    keep = exact < 0.95
    poses, exact = poses[keep][:n], exact[keep][:n]
    return np.abs(vf(poses[:, 0], poses[:, 1], poses[:, 2]) - exact)


def best_time(fn, repeat: int):
    times, result = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return min(times), result


def reference_table(repeat: int) -> None:
    solve(DOMAIN, (0, 0), RHO, 0.2, 8)  # warm-up: load / compile the kernels
    print("| grid | threads | wall time (s) | sweeps | mean abs err | median | p95 |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for n, ntheta in [(101, 64), (201, 72)]:
        h = 2.0 / (n - 1)
        for threads in (1, 2):
            options = SolverOptions(threads=threads)
            seconds, vf = best_time(lambda: solve(DOMAIN, (0, 0), RHO, h, ntheta, options=options), repeat)
            err = reference_errors(vf)
            print(f"| {n} x {n} x {ntheta} | {threads} | {seconds:.3f} | {vf.meta['sweeps']} | {err.mean():.4f} "
                  f"| {np.median(err):.4f} | {np.percentile(err, 95):.4f} |")


def paper_table(rho: float, spacing: float, workers: int) -> None:
    try:
        import arenas
        paper = arenas.load("paper")
    except Exception as exc:  # the arenas package is optional here
        print(f"(paper arena unavailable: {exc})")
        return
    target = tuple(float(c) for c in paper.source)
    print(f"\npaper arena, rho = {rho:g} cm, bank spacing {spacing:g} cm, {workers} processes:")
    print("| planner | one value function (s) | sweeps | bank targets | bank build (s) | bank size (MB) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for label, h, ntheta, clearance, reverse in [("car: h 1.5, 48 headings, clearance 4, reverse", 1.5, 48, 4.0, True),
                                                 ("h 1, 72 headings, clearance 3, forward", 1.0, 72, 3.0, False)]:
        seconds, vf = best_time(lambda: solve(paper, target, rho, h, ntheta, clearance=clearance, reverse=reverse), 2)
        with tempfile.TemporaryDirectory() as cache:
            bank = ValueFunctionBank(paper, spacing, rho=rho, h=h, ntheta=ntheta, clearance=clearance,
                                     reverse=reverse, cache_dir=cache)
            total = bank.build(workers=workers, progress=False)
            size = sum(f.stat().st_size for f in bank.directory.iterdir())
        print(f"| {label} | {seconds:.2f} | {vf.meta['sweeps']} | {len(bank)} | {total:.1f} | {size / 1e6:.1f} |")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--rho", type=float, default=15.0, help="turning radius on paper (cm)")
    parser.add_argument("--spacing", type=float, default=12.7, help="bank lattice spacing (cm)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--no-paper", action="store_true", help="skip the paper-arena timings")
    args = parser.parse_args(argv)
    print(f"numba load/compile + first tiny solve in a fresh process: {compile_time():.2f} s "
          f"(cache=True; a cold cache compiles, later runs load)")
    print()
    reference_table(args.repeat)
    if not args.no_paper:
        paper_table(args.rho, args.spacing, args.workers)
    return 0


if __name__ == "__main__":
    sys.exit(main())
