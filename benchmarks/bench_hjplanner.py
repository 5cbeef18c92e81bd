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

``--before REF`` instead compares the working tree with git ref REF (checked
out in a temporary ``git worktree``): each measurement runs in a fresh process
with ``PYTHONPATH`` at one tree, the trees alternating, ``--rounds`` times; the
table gives the best wall time of each.  The anchor is HamiltonFastMarching's
``Dubins2`` model, printed beside when its Python front end (``agd``/``hfmpy``)
imports; it ships wheels only for Python 3.12 and 3.13, so on 3.11 the issue's
numbers stand in (HFM 1.7-2.3 s / 0.054 and 9.7-12.0 s / 0.027).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from hjplanner import SolverOptions, ValueFunctionBank, point_distance, solve

RHO = 0.3
DOMAIN = ((-1.0, 1.0), (-1.0, 1.0))
ROOT = Path(__file__).resolve().parents[1]
#: The issue's HamiltonFastMarching Dubins2 figures: (seconds low, high, mean abs error) per grid.
HFM_ISSUE = {(101, 64): (1.7, 2.3, 0.054), (201, 72): (9.7, 12.0, 0.027)}
BANK_COMMAND = "--arena paper --spacing 12.7 --rho 15 --h 1.5 --ntheta 48 --clearance 4 --reverse"


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


def hfm_table(repeat: int) -> None:
    """HamiltonFastMarching's Dubins2 on the reference grids, if its Python front end imports."""
    try:
        from agd import Eikonal  # noqa: F401  (HFM's front end; wheels for Python 3.12/3.13 only)
    except ImportError:
        print("\nHFM (agd/hfmpy) not importable here; the issue's numbers: "
              + ", ".join(f"{n} x {n} x {nt}: {lo}-{hi} s / {err}" for (n, nt), (lo, hi, err) in HFM_ISSUE.items()))
        return
    print("\n| HFM Dubins2 grid | wall time (s) | mean abs err |")
    print("| --- | --- | --- |")
    for n, ntheta in HFM_ISSUE:
        h = 2.0 / (n - 1)
        hfm = Eikonal.dictIn({"model": "Dubins2", "xi": RHO, "seed": [0.0, 0.0, 0.0], "cost": 1.0,
                              "exportValues": 1})
        hfm.SetRect(sides=[[-1, 1], [-1, 1], [0, 2 * np.pi]], dims=[n, n, ntheta])
        seconds, out = best_time(lambda: hfm.Run(), repeat)
        values = out["values"]

        class Interp:
            def __call__(self, x, y, th):
                i = np.clip(np.rint((x + 1) / h).astype(int), 0, n - 1)
                j = np.clip(np.rint((y + 1) / h).astype(int), 0, n - 1)
                k = np.rint(np.mod(th, 2 * np.pi) / (2 * np.pi / ntheta)).astype(int) % ntheta
                return values[i, j, k]

        print(f"| {n} x {n} x {ntheta} | {seconds:.2f} | {reference_errors(Interp()).mean():.4f} |")


def measure(threads: int, bank: bool) -> dict:
    """One tree's numbers (run in a child process): reference solves and, optionally, the paper bank."""
    solve(DOMAIN, (0, 0), RHO, 0.2, 8)
    out = {}
    for n, ntheta in HFM_ISSUE:
        options = SolverOptions(threads=threads)
        seconds, vf = best_time(lambda: solve(DOMAIN, (0, 0), RHO, 2.0 / (n - 1), ntheta, options=options), 3)
        out[f"{n}"] = dict(seconds=seconds, error=float(reference_errors(vf).mean()), sweeps=vf.meta["sweeps"])
    if bank:
        out["bank"] = bank_command_time()
    return out


def bank_command_time() -> float:
    """Wall time of ``hjplanner bank`` on paper with a cold (empty) cache, in a fresh process."""
    with tempfile.TemporaryDirectory() as cache:
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "hjplanner", "bank", *BANK_COMMAND.split(), "--quiet"], check=True,
                       capture_output=True, env=dict(os.environ, HJPLANNER_CACHE=cache))
        return time.perf_counter() - t0


def compare(ref: str, rounds: int, threads: int, bank: bool) -> None:
    """Before (git ref) against after (the working tree), alternating fresh processes."""
    from reference_tree import reference_tree
    with reference_tree(ref, "bench_hjplanner_") as (before, tmp):
        results = {"before": [], "after": []}
        for _ in range(rounds):
            for label, tree in (("before", before), ("after", ROOT)):
                code = (f"import json, sys; sys.path.insert(0, {str(ROOT / 'benchmarks')!r}); "
                        f"import bench_hjplanner as b; print(json.dumps(b.measure({threads}, {bank})))")
                env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tree)] + sys.path[1:]))
                run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                                     env=env, cwd=tmp)
                results[label].append(json.loads(run.stdout.strip().splitlines()[-1]))
    print(f"before: {ref}; after: the working tree; {threads} thread(s); best of {rounds} alternating rounds; "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    print("| what | before | after | ratio | anchor (HFM, issue) |")
    print("| --- | --- | --- | --- | --- |")
    for n, ntheta in HFM_ISSUE:
        b = min(r[f"{n}"]["seconds"] for r in results["before"])
        a = min(r[f"{n}"]["seconds"] for r in results["after"])
        eb, ea = results["before"][0][f"{n}"]["error"], results["after"][0][f"{n}"]["error"]
        lo, hi, err = HFM_ISSUE[(n, ntheta)]
        print(f"| {n} x {n} x {ntheta}: s / mean abs err (sweeps) | {b:.3f} / {eb:.4f} "
              f"({results['before'][0][f'{n}']['sweeps']}) | {a:.3f} / {ea:.4f} "
              f"({results['after'][0][f'{n}']['sweeps']}) | {b / a:.2f}x | {lo}-{hi} s / {err} |")
    if bank:
        b = min(r["bank"] for r in results["before"])
        a = min(r["bank"] for r in results["after"])
        print(f"| `hjplanner bank {BANK_COMMAND}`, cold, s | {b:.1f} | {a:.1f} | {b / a:.2f}x | - |")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--rho", type=float, default=15.0, help="turning radius on paper (cm)")
    parser.add_argument("--spacing", type=float, default=12.7, help="bank lattice spacing (cm)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--no-paper", action="store_true", help="skip the paper-arena timings")
    parser.add_argument("--before", help="git ref to compare the working tree with (alternating processes)")
    parser.add_argument("--rounds", type=int, default=3, help="alternating rounds per tree with --before")
    parser.add_argument("--threads", type=int, default=1, help="solver threads with --before")
    args = parser.parse_args(argv)
    if args.before:
        compare(args.before, args.rounds, args.threads, not args.no_paper)
        return 0
    print(f"numba load/compile + first tiny solve in a fresh process: {compile_time():.2f} s "
          f"(cache=True; a cold cache compiles, later runs load)")
    print()
    reference_table(args.repeat)
    hfm_table(args.repeat)
    if not args.no_paper:
        paper_table(args.rho, args.spacing, args.workers)
    return 0


if __name__ == "__main__":
    sys.exit(main())
