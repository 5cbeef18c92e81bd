"""Driver memory over a long campaign: 10^4 trivial episodes, RSS per stored batch.

The episodes are the cheapest pair there is (a 3-step random walk on otto's 19 x 19 grid,
about a millisecond each), so the run measures the driver: the Dask client and the
scheduler (which a local cluster runs inside the driver process), the in-flight window,
the row buffer and the Parquet writes. The driver's resident memory is sampled at every
stored batch; the growth is the last sample minus the one after the first 10 % of the
episodes (the warm-up: imports, the cluster, the first Parquet writer). Acceptance:
at most 50 MB over 10^4 episodes (issue 19).

Run::

    python benchmarks/bench_campaign_memory.py [--episodes 10000] [--workers 1] [--out DIR]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import psutil

from reciprocity.campaign import load_spec, run_campaign
from reciprocity.campaign.store import ResultStore

SCENARIO = """\
description: otto's 2-D grid with a 3-step cap (the cheapest episode)
world: plume
platform: walker
bounds: [0, 19, 0, 19]
source: drawn
initial_hit: random
start: [9.5, 9.5]
rate: 2
a: 0.5
D: 1
tau: 1
V: 0
dt: 1
found_radius: 0.5
motion: grid
step: 1
moves: 4
max_hits: auto
max_steps: 3
"""

LIMIT_MB = 50.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--episodes", type=int, default=10_000)
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--out", help="results folder (default: a temporary one)")
    args = ap.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "otto-3.yaml").write_text(SCENARIO)
        (folder / "spec.yaml").write_text(
            f"name: memory\nseeds: {args.episodes}\nstrategies: {{random-walk: {{n_steps: 3}}}}\n"
            "scenarios: [otto-3.yaml]\n")
        out = Path(args.out) if args.out else folder / "out"
        process = psutil.Process()
        samples: list[tuple[int, float]] = []      # (episodes stored, RSS MB)
        write = ResultStore.write

        def sampled_write(store, rows):
            rows = list(rows)
            files = write(store, rows)
            done = (samples[-1][0] if samples else 0) + len(rows)
            samples.append((done, process.memory_info().rss / 2**20))
            return files

        ResultStore.write = sampled_write           # instrument the driver's batch writes
        rss0 = process.memory_info().rss / 2**20
        t0 = time.perf_counter()
        result = run_campaign(load_spec(folder / "spec.yaml"), out, workers=args.workers,
                              progress=False)
        wall = time.perf_counter() - t0
        ResultStore.write = write

    warm = next(s for s in samples if s[0] >= args.episodes // 10)
    last, peak = samples[-1], max(mb for _, mb in samples)
    growth = last[1] - warm[1]
    print(f"episodes: {result.n_run} run ({result.n_failed} failed) in {wall:.0f} s "
          f"({1e3 * wall / max(result.n_run, 1):.1f} ms an episode, {args.workers} worker(s)), "
          f"{len(samples)} batches")
    print(f"driver RSS: {rss0:.0f} MB before, {warm[1]:.0f} MB after {warm[0]} episodes, "
          f"{last[1]:.0f} MB after {last[0]}, peak {peak:.0f} MB")
    for done, mb in samples[:: max(1, len(samples) // 10)]:
        print(f"  {done:>6} episodes  {mb:7.1f} MB")
    verdict = "PASS" if growth <= LIMIT_MB else "FAIL"
    print(f"growth from {warm[0]} to {last[0]} episodes: {growth:+.1f} MB "
          f"(limit {LIMIT_MB:.0f} MB): {verdict}")


if __name__ == "__main__":
    main()
