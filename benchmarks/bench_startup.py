"""Start-up time and memory of the command lines, this tree against a reference commit.

Run: ``python benchmarks/bench_startup.py --before 1f8c377`` (results in LIMITS.md).

Each command runs as its own process through the installed console scripts of the
active environment; ``PYTHONPATH`` points at the tree under test, so both trees use the
same interpreter and packages and differ only in our code. The reference tree is a
``git worktree`` of ``--before`` in a temporary folder, removed afterwards. Runs of the
two trees alternate, so load from other jobs on the machine falls on both alike.

Wall time is the median over the runs; peak memory is the child's maximum resident set
size from ``os.wait4`` (the largest over the runs). The episode command runs once
untimed per tree first, so both find the meshes in the cache.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent

#: (label, argv, runs): the start-up commands of issue 24, then one point episode.
COMMANDS = [
    ("reciprocity --help", [str(BIN / "reciprocity"), "--help"], None),
    ("python -c 'import reciprocity'", [sys.executable, "-c", "import reciprocity"], None),
    ("hjplanner --help", [str(BIN / "hjplanner"), "--help"], None),
    ("reciprocity arenas", [str(BIN / "reciprocity"), "arenas"], None),
    ("reciprocity strategies", [str(BIN / "reciprocity"), "strategies"], None),
    ("reciprocity scenarios", [str(BIN / "reciprocity"), "scenarios"], None),
    ("reciprocity run --arena paper --strategy reciprocity --seed 1",
     [str(BIN / "reciprocity"), "run", "--arena", "paper", "--strategy", "reciprocity", "--seed", "1"], 5),
]


def measure(argv: list[str], tree: Path, cwd: Path) -> tuple[float, float]:
    """Wall seconds and peak resident MB of one run of `argv` with `tree` first on the path."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    t0 = time.perf_counter()
    # stderr goes to a file, not a pipe: a child writing more than a pipe holds would block
    with tempfile.TemporaryFile() as errf:
        proc = subprocess.Popen(argv, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=errf)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
        errf.seek(0)
        err = errf.read().decode(errors="replace")
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} in {tree} exited {proc.returncode}: {err}")
    return wall, usage.ru_maxrss / 1024  # ru_maxrss is in KiB on Linux


def check_tree(tree: Path) -> None:
    """Refuse to measure if `tree`'s packages are not the ones the interpreter imports."""
    code = "import reciprocity, hjplanner, arenas; print(reciprocity.__file__)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env=dict(os.environ, PYTHONPATH=str(tree))).stdout.strip()
    if Path(out).resolve() != (tree / "reciprocity" / "__init__.py").resolve():
        raise SystemExit(f"PYTHONPATH={tree} imports reciprocity from {out}; cannot compare trees")


def compare(before: Path, after: Path, repeat: int, cwd: Path) -> list[tuple]:
    rows = []
    for label, argv, runs in COMMANDS:
        runs = runs or repeat
        if runs < repeat:  # a long command: warm the mesh cache for both trees
            measure(argv, before, cwd)
            measure(argv, after, cwd)
        samples = {before: [], after: []}
        for _ in range(runs):
            for tree in (before, after):
                samples[tree].append(measure(argv, tree, cwd))
        (tb, mb), (ta, ma) = ((statistics.median(w for w, _ in samples[t]), max(m for _, m in samples[t]))
                              for t in (before, after))
        rows.append((label, runs, tb, ta, mb, ma))
        print(f"  {label}: {tb:.3f} s -> {ta:.3f} s, {mb:.0f} MB -> {ma:.0f} MB", file=sys.stderr)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", required=True, help="git ref of the reference tree, e.g. 1f8c377")
    parser.add_argument("--repeat", type=int, default=7, help="runs per start-up command (default 7)")
    args = parser.parse_args()
    from reference_tree import reference_tree
    with reference_tree(args.before, "bench_startup_") as (before, tmp):
        for tree in (before, ROOT):
            check_tree(tree)
        work = tmp / "cwd"
        work.mkdir()
        rows = compare(before, ROOT, args.repeat, work)
    print(f"before: {args.before}; after: the working tree; median wall time, largest peak RSS; "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    print("| command | runs | before s | after s | ratio | before MB | after MB | ratio |")
    print("|---|---|---|---|---|---|---|---|")
    for label, runs, tb, ta, mb, ma in rows:
        print(f"| `{label}` | {runs} | {tb:.2f} | {ta:.2f} | {tb / ta:.1f}x | {mb:.0f} | {ma:.0f} | "
              f"{mb / ma:.1f}x |")


if __name__ == "__main__":
    main()
