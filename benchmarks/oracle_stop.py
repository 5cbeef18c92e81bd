"""How many of the core search's readings its stop rule costs (issue 33): against an oracle stop.

For draws of the generated families (point observer, map known, ``reciprocity`` at its
defaults, episode seed = draw), each reading's estimate is compared with the true source.
The *oracle stop* is the first reading from which the estimate stays within R cm to the
end of the search: no stop that sees only the readings can stop sooner with that estimate,
and the gap to the real stop is what the stop rule costs. Rows (one JSON line per episode:
the error after every reading) are appended to ``--out`` and a run resumes.

    python benchmarks/oracle_stop.py --draws 10 --out benchmarks/unseen_arenas/oracle_stop.jsonl
    python benchmarks/oracle_stop.py --table benchmarks/unseen_arenas/oracle_stop.jsonl
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

FAMILIES = ("rooms", "spiral", "ring", "pillars", "maze", "office")
RADII = (3.0, 5.0)


def record(out: Path, draws: int, start: int = 0) -> None:
    """Run draws ``start .. start + draws - 1`` of every family; append one line per episode."""
    import arenas
    from reciprocity.env import SearchEnv, rollout
    from reciprocity.scenarios import load_scenario
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    done = set()
    if out.exists():
        done = {(r["family"], r["draw"]) for r in map(json.loads, out.read_text().splitlines())}
    with out.open("a") as f:
        for i in range(start, start + draws):
            for fam in FAMILIES:
                if (fam, i) in done:
                    continue
                episode = rollout(SearchEnv(load_scenario(arenas.generate(fam, i))),
                                  StrategyAgent(STRATEGIES["reciprocity"], {}), i)
                s = episode.summary
                src = np.asarray(s["source"], dtype=float)
                errs = [None if r.get("estimate") is None
                        else float(np.hypot(*(np.asarray(r["estimate"], dtype=float)[:2] - src)))
                        for r in episode.trace]
                f.write(json.dumps(dict(family=fam, draw=i, n=s["n_measurements"], error=s["error"],
                                        success=s["success"], errs=errs)) + "\n")
                f.flush()


def oracle(errs: list, radius: float) -> int | None:
    """The first reading (1-based) from which the estimate stays within `radius` cm; None
    when the last one is farther."""
    k = None
    for i in range(len(errs) - 1, -1, -1):
        if errs[i] is None or errs[i] > radius:
            break
        k = i + 1
    return k


def table(path: Path) -> str:
    rows = [json.loads(line) for line in path.read_text().splitlines()]
    lines = ["| family | episodes | readings at the stop: median / mean | oracle stop, 3 cm: median / mean | "
             "oracle stop, 5 cm: median / mean | stop cost (3 cm): mean [95 %] |",
             "|---|---:|---|---|---|---|"]
    for fam in (*FAMILIES, "all"):
        rs = [r for r in rows if fam in (r["family"], "all")]
        if not rs:
            continue
        n = np.array([r["n"] for r in rs], dtype=float)
        cells = []
        for radius in RADII:
            k = np.array([oracle(r["errs"], radius) or r["n"] for r in rs], dtype=float)
            cells.append(f"{np.median(k):g} / {k.mean():.2f}")
        gap = n - np.array([oracle(r["errs"], 3.0) or r["n"] for r in rs], dtype=float)
        half = 1.96 * gap.std(ddof=1) / np.sqrt(len(gap)) if len(gap) > 1 else float("nan")
        lines.append(f"| {fam} | {len(rs)} | {np.median(n):g} / {n.mean():.2f} | {cells[0]} | {cells[1]} | "
                     f"{gap.mean():.2f} [{gap.mean() - half:.2f}, {gap.mean() + half:.2f}] |")
    return "\n".join(lines)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--draws", type=int, default=10)
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--out", type=Path, default=Path("oracle_stop.jsonl"))
    ap.add_argument("--table", type=Path, help="print the table of this file, run nothing")
    a = ap.parse_args(argv)
    if a.table:
        print(table(a.table))
    else:
        record(a.out, a.draws, a.start)


if __name__ == "__main__":
    main()
