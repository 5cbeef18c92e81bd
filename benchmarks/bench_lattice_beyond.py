"""Reciprocity on the lattice against the RBPF (issue 11, beyond the paper): the table.

Reads the results of the two campaigns (run them first, resumable)::

    nice python -m reciprocity.cli campaign benchmarks/lattice_beyond.yaml --out runs/lattice_beyond --workers 1
    nice python -m reciprocity.cli campaign benchmarks/lattice_beyond_rbpfmap.yaml --out runs/lattice_beyond_rbpfmap --workers 1
    nice python -m reciprocity.cli campaign benchmarks/lattice_beyond_more.yaml --out runs/lattice_beyond_more --workers 1
    nice python -m reciprocity.cli campaign benchmarks/lattice_beyond_mode.yaml --out runs/lattice_beyond_mode --workers 1
    python benchmarks/bench_lattice_beyond.py [--runs runs] [--timing 5]

and prints, per variant: runs n, the paper's success (reached the source within 100
steps and self-localised) and "reached" alone with Wilson 95 % intervals, the mean steps
over the successes with a t 95 % interval, and the paired differences against ``rbpf`` on
the seed indices both ran (the same lattice, source, start). ``--timing k`` also runs k
episodes of each variant in this process and prints CPU seconds per episode and per step
(``time.process_time``; the campaign only records wall time, inflated by the load).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import duckdb
import numpy as np
from scipy import stats


def wilson(k: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion k/n."""
    if n == 0:
        return (np.nan, np.nan)
    p = k / n
    d = 1 + z ** 2 / n
    c = (p + z ** 2 / (2 * n)) / d
    h = z * np.sqrt(p * (1 - p) / n + z ** 2 / (4 * n ** 2)) / d
    return (c - h, c + h)


def mean_ci(x) -> tuple[float, float, float]:
    x = np.asarray(x, float)
    if x.size < 2:
        return (float(x.mean()) if x.size else np.nan, np.nan, np.nan)
    m, se = x.mean(), x.std(ddof=1) / np.sqrt(x.size)
    t = stats.t.ppf(0.975, x.size - 1)
    return (m, m - t * se, m + t * se)


#: Labels of the variants of lattice_beyond_more.yaml (no grid, so the campaign labels
#: them by the strategy's name alone).
MORE = {"rbpf": "rbpf[planner=path]",
        "lattice-reciprocity": "lattice-reciprocity[map=rbpf,green=sampled,unseen=nominal]"}


def load(root: Path):
    con = duckdb.connect()
    # each campaign's own partitions only, never a recursive glob
    files = [str(p) for p in sorted(root.glob("lattice_beyond*/scenario=*/strategy=*/part-*.parquet"))]
    if not files:
        raise SystemExit(f"no results under {root}/lattice_beyond*; run the campaigns first")
    rows = con.sql(f"SELECT campaign, variant, seed_index, success, reached, self_localised, steps, slips "
                   f"FROM read_parquet({files!r}, union_by_name=true)").fetchall()
    out = {}
    for camp, var, i, succ, reach, loc, steps, slips in rows:
        name = {"lattice-beyond": var, "lattice-beyond-rbpfmap": var.replace("[", "[map=rbpf,"),
                "lattice-beyond-more": MORE.get(var, var + "[more]"),
                "lattice-beyond-mode": var.replace("[", "[rule=path+mode,")}.get(camp, f"{camp}:{var}")
        out.setdefault(name, {})[int(i)] = (bool(succ), bool(reach), bool(loc), int(steps), int(slips or 0))
    return out


def table(res) -> None:
    print("| variant | n | success % [95 %] | reached % [95 %] | steps over successes [95 %] |")
    print("|---|---|---|---|---|")
    for name in sorted(res):
        r = np.array(list(res[name].values()))
        n, k, kr = len(r), int(r[:, 0].sum()), int(r[:, 1].sum())
        lo, hi = wilson(k, n)
        rlo, rhi = wilson(kr, n)
        m, mlo, mhi = mean_ci(r[r[:, 0] == 1, 3])
        print(f"| {name} | {n} | {100 * k / n:.0f} [{100 * lo:.0f}, {100 * hi:.0f}] | "
              f"{100 * kr / n:.0f} [{100 * rlo:.0f}, {100 * rhi:.0f}] | {m:.1f} [{mlo:.1f}, {mhi:.1f}] |")
    pairs = [(name, "rbpf") for name in sorted(res) if name != "rbpf"]
    pairs += [("lattice-reciprocity[map=rbpf,green=estimated]", "lattice-reciprocity[map=rbpf,green=complete]"),
              ("lattice-reciprocity[map=rbpf,green=sampled,unseen=nominal]",
               "lattice-reciprocity[map=rbpf,green=estimated]"),
              ("lattice-reciprocity[rule=path+mode,strength=null]", "lattice-reciprocity[strength=null]"),
              ("lattice-reciprocity[rule=path+mode,strength=12.0]", "lattice-reciprocity[strength=12.0]")]
    print("\nPaired on the common seed indices (same lattice, source, start, noise seed):")
    for a, b in pairs:
        if a in res and b in res:
            paired(res, a, b)


def paired(res, name: str, ref: str) -> None:
    """Success discordance (exact McNemar) and steps difference where both succeeded."""
    common = sorted(set(res[ref]) & set(res[name]))
    a = np.array([res[name][i] for i in common])
    b = np.array([res[ref][i] for i in common])
    both = (a[:, 0] == 1) & (b[:, 0] == 1)
    d, dlo, dhi = mean_ci(a[both, 3] - b[both, 3])
    only_a, only_b = int(((a[:, 0] == 1) & (b[:, 0] == 0)).sum()), int(((a[:, 0] == 0) & (b[:, 0] == 1)).sum())
    p = stats.binomtest(only_a, only_a + only_b).pvalue if only_a + only_b else 1.0
    ra, rb = int(((a[:, 1] == 1) & (b[:, 1] == 0)).sum()), int(((a[:, 1] == 0) & (b[:, 1] == 1)).sum())
    pr = stats.binomtest(ra, ra + rb).pvalue if ra + rb else 1.0
    print(f"  {name} vs {ref}: n = {len(common)}; success only the first {only_a}, only the second {only_b} "
          f"(McNemar exact p = {p:.2g}); reached only the first {ra}, only the second {rb} (p = {pr:.2g}); "
          f"steps difference where both succeeded ({int(both.sum())}): {d:+.1f} [{dlo:+.1f}, {dhi:+.1f}]")


def timing(k: int) -> None:
    from reciprocity.api import run
    variants = [("rbpf", "rbpf", {}), ("lattice-reciprocity[strength=null]", "lattice-reciprocity", {}),
                ("lattice-reciprocity[strength=12.0]", "lattice-reciprocity", {"strength": 12.0}),
                ("lattice-reciprocity[map=rbpf,green=estimated]", "lattice-reciprocity", {"map": "rbpf"}),
                ("lattice-reciprocity[map=rbpf,green=complete]", "lattice-reciprocity",
                 {"map": "rbpf", "green": "complete"}),
                ("rbpf[planner=path]", "rbpf", {"planner": "path"}),
                ("lattice-reciprocity[map=rbpf,green=sampled,unseen=nominal]", "lattice-reciprocity",
                 {"map": "rbpf", "green": "sampled", "unseen": "nominal"})]
    print(f"\nCPU time ({k} episodes each, this process, time.process_time):")
    for label, strat, params in variants:
        t0, steps = time.process_time(), 0
        for seed in range(k):
            steps += run("ristic-lattice", strat, seed=seed, params=params, world={"map": "known"}).summary["steps"]
        cpu = time.process_time() - t0
        print(f"  {label}: {cpu / k:.2f} s per episode, {1e3 * cpu / steps:.1f} ms per step")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", default="runs", type=Path, help="folder holding the campaigns' result folders")
    ap.add_argument("--timing", default=0, type=int, help="also time k episodes per variant")
    a = ap.parse_args()
    table(load(a.runs))
    if a.timing:
        timing(a.timing)


if __name__ == "__main__":
    main()
