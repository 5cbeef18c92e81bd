"""The core search on arenas it has never seen (issue 33): generated arenas, map known
and map unknown.

Draw ``i`` of family ``F`` is the arena ``arenas.generate(F, i)`` with its own source and
start (each draw a new arena, source and start), run with the point observer and the
``reciprocity`` strategy at its defaults, the map known and the map unknown (the default
64-beam, 40 cm lidar), episode seed ``i``. The families take turns, so a run cut short
covers all of them. Rows are appended to a CSV as episodes finish; a second run resumes.

    nice -n 10 python benchmarks/unseen_arenas.py --draws 50 --out benchmarks/unseen_arenas/runs.csv
    python benchmarks/unseen_arenas.py --table benchmarks/unseen_arenas/runs.csv > benchmarks/unseen_arenas.md

``--minutes M`` stops starting new draws after M minutes.
"""

from __future__ import annotations

import argparse
import csv
import resource
import sys
import time
from pathlib import Path

import numpy as np

MODES = {"known": {}, "unknown": {"map": "unknown"}}
FIELDS = ["family", "draw", "mode", "arena", "success", "converged", "stop", "error", "n_measurements",
          "path_length", "wall_time_s", "remesh_failures", "peak_rss_mb", "surveys"]


def run(families: list[str], draws: int, out: Path, minutes: float | None, modes=tuple(MODES),
        start: int = 0, params: dict | None = None, world_keys: dict | None = None) -> None:
    import arenas
    from reciprocity.env import SearchEnv, rollout
    from reciprocity.scenarios import load_scenario
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    from resumable import appending, deadline, done_keys
    done = done_keys(out, lambda r: (r["family"], int(r["draw"]), r["mode"]))
    expired = deadline(minutes)
    with appending(out, FIELDS) as w:
        for i in range(start, start + draws):
            for fam in families:
                if expired():
                    return
                scenario = load_scenario(arenas.generate(fam, i))
                for mode, world in MODES.items():
                    if (fam, i, mode) in done or mode not in modes:
                        continue
                    env = SearchEnv(scenario, world={**(world_keys or {}), **world})
                    t0 = time.perf_counter()
                    s = rollout(env, StrategyAgent(STRATEGIES["reciprocity"], dict(params or {})), i).summary
                    w.writerow(dict(family=fam, draw=i, mode=mode, arena=s["arena"], success=s["success"],
                                    converged=s["converged"], stop=s["stop"],
                                    error=None if s["error"] is None else round(s["error"], 3),
                                    n_measurements=s["n_measurements"], path_length=round(s["path_length"], 1),
                                    wall_time_s=round(time.perf_counter() - t0, 2),
                                    remesh_failures=s.get("remesh_failures", ""), surveys=s.get("surveys", ""),
                                    peak_rss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024))
                    w.file.flush()


def _q(values, q: float) -> str:
    v = np.asarray([x for x in values if x is not None and x == x], dtype=float)
    return "–" if v.size == 0 else f"{np.quantile(v, q):.3g}"


def _wilson(k: int, n: int) -> str:
    """Wilson 95 % interval of k successes in n, in percent (scipy's)."""
    from scipy.stats import binomtest
    ci = binomtest(k, n).proportion_ci(method="wilson")
    return f"[{100 * ci.low:.0f}, {100 * ci.high:.0f}]"


def table(paths) -> str:
    rows = []
    for path in ([paths] if isinstance(paths, Path) else paths):
        with Path(path).open() as f:
            rows += list(csv.DictReader(f))
    for r in rows:
        r["success"] = r["success"] == "True"
        r["error"] = float(r["error"]) if r["error"] not in ("", "None") else None
        for k in ("n_measurements", "path_length", "wall_time_s"):
            r[k] = float(r[k])
        r["surveys"] = float(r.get("surveys") or 0)
    lines = [f"{len(rows)} episodes: {len({(r['family'], r['draw']) for r in rows})} (arena, source, start) "
             "draws, point observer, `reciprocity` at its defaults; peak RSS of a benchmark process "
             f"{max(int(r['peak_rss_mb']) for r in rows)} MB.", "",
             "| family | map | episodes | success [95 %] | error median / p95 (cm) | readings median / p90 "
             "| surveys median | path median (cm) | s / episode | re-mesh failures |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    fams = list(dict.fromkeys(r["family"] for r in rows)) + ["all"]
    for fam in fams:
        for mode in MODES:
            sel = [r for r in rows if (fam == "all" or r["family"] == fam) and r["mode"] == mode]
            if not sel:
                continue
            fails = sum(int(r["remesh_failures"] or 0) for r in sel) if mode == "unknown" else "–"
            k = sum(r["success"] for r in sel)
            lines.append(
                f"| {fam} | {mode} | {len(sel)} | {100 * k / len(sel):.0f} % {_wilson(k, len(sel))} "
                f"| {_q([r['error'] for r in sel], 0.5)} / {_q([r['error'] for r in sel], 0.95)} "
                f"| {_q([r['n_measurements'] for r in sel], 0.5)} / {_q([r['n_measurements'] for r in sel], 0.9)} "
                f"| {_q([r['surveys'] for r in sel], 0.5) if mode == 'unknown' else '–'} "
                f"| {_q([r['path_length'] for r in sel], 0.5)} | {np.mean([r['wall_time_s'] for r in sel]):.1f} "
                f"| {fails} |")
    known = {(r["family"], r["draw"]): r for r in rows if r["mode"] == "known"}
    pairs = [(known[(r["family"], r["draw"])], r) for r in rows
             if r["mode"] == "unknown" and (r["family"], r["draw"]) in known]
    if pairs:
        a = np.array([p[0]["n_measurements"] for p in pairs])
        b = np.array([p[1]["n_measurements"] for p in pairs])
        lines += ["", f"Map unknown against map known, {len(pairs)} paired draws: readings median "
                      f"{np.median(b):.3g} against {np.median(a):.3g} ({np.median(b) / np.median(a):.2f}x), "
                      f"mean {b.mean():.3g} against {a.mean():.3g} ({b.mean() / a.mean():.2f}x)."]
    return "\n".join(lines)


def main(argv=None) -> int:
    import arenas
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--families", nargs="*", default=list(arenas.FAMILIES))
    p.add_argument("--draws", type=int, default=10, help="draws per family")
    p.add_argument("--minutes", type=float, help="start no new draw after this many minutes")
    p.add_argument("--out", type=Path, default=Path("unseen_arenas_runs.csv"))
    p.add_argument("--modes", default="known,unknown", help="comma-separated: known, unknown")
    p.add_argument("--start", type=int, default=0, help="first draw")
    p.add_argument("--table", type=Path, nargs="+", help="print the table of runs CSV(s) instead")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="a parameter of the reciprocity strategy (YAML value), e.g. source_clearance=0")
    p.add_argument("--world", action="append", default=[], metavar="KEY=VALUE",
                   help="a key of every draw's world (YAML value), e.g. noise=3")
    args = p.parse_args(argv)
    from resumable import strategy_sets
    try:
        params = strategy_sets(args.set)
        world_keys = strategy_sets(args.world)
    except ValueError as exc:
        p.error(str(exc))
    if args.table:
        print(table(args.table))
        return 0
    modes = tuple(m for m in args.modes.split(",") if m)
    if not modes or set(modes) - set(MODES):
        p.error(f"--modes takes known and/or unknown; got {args.modes!r}")
    run(args.families, args.draws, args.out, args.minutes, modes, args.start, params, world_keys)
    print(table(args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
