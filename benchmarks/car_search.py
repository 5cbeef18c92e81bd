"""The car's search on generated arenas and on ``paper`` and ``maze`` (issue 35).

Draw ``i`` of a generated family ``F`` is the arena ``arenas.generate(F, i)`` with its own
source and start; draw ``i`` of ``paper`` or ``maze`` is that arena with a source and start
drawn as a campaign draws them (``reciprocity.campaign.worker.world_draw``, campaign seed
2026). Each is run on the simulated car (physics, camera, HJ planner) with the
``reciprocity`` strategy at its defaults, the map known, episode seed ``i``. The arenas
take turns, so a run cut short covers all of them. Rows are appended to a CSV as
episodes finish; a second run resumes.

Each row keeps whether the true source is reachable by the car (``source_reachable``,
the evaluator's judgement), the stop, the readings, the wall contacts and the car's
simulated seconds per second of computing (``speed``).

    nice -n 10 python benchmarks/car_search.py --draws 6 --out benchmarks/car_search/runs.csv
    python benchmarks/car_search.py --table benchmarks/car_search/runs.csv

``paper`` and ``maze`` as a campaign runs them (two workers), then as rows of the same CSV:

    reciprocity campaign benchmarks/search_car_both.yaml --out car_campaign
    python benchmarks/car_search.py --from-campaign car_campaign --out benchmarks/car_search/campaign.csv

``--world KEY=VALUE`` sets a key of every draw's world (``map=unknown``: the car maps the
walls with its lidar). ``--minutes M`` stops starting new draws after M minutes. ``--only unreachable`` runs only
the draws whose source the evaluator judges out of the car's reach (judged at reset; the
rest are skipped), and ``--set KEY=VALUE`` passes a parameter to the strategy:

    nice -n 10 python benchmarks/car_search.py --arenas paper --draws 200 --only unreachable --out benchmarks/car_search/unreachable.csv
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from pathlib import Path

FIELDS = ["arena", "draw", "success", "source_reachable", "stop", "error", "n_measurements",
          "collisions", "sim_time_s", "wall_time_s", "speed", "mass_out_of_reach"]
ARENAS = ("rooms", "spiral", "ring", "pillars", "maze", "office", "paper", "builtin-maze")
CAMPAIGN_SEED = 2026


def scenario_of(name: str, i: int):
    """The scenario of draw `i` of arena `name` (a generated family, ``paper`` or
    ``builtin-maze``)."""
    import arenas
    from reciprocity.campaign.spec import episode_seed
    from reciprocity.campaign.worker import world_draw
    from reciprocity.scenarios import load_scenario
    if name in ("paper", "builtin-maze"):
        sc = load_scenario(arenas.load(name.removeprefix("builtin-")))
        draw = world_draw(sc, episode_seed(CAMPAIGN_SEED, i))
        return sc.with_world(draw)
    return load_scenario(arenas.generate(name, i))


def run(names: list[str], draws: int, out: Path, minutes: float | None, start: int = 0,
        only: str = "all", params: dict | None = None, world: dict | None = None) -> None:
    from resumable import appending, deadline, done_keys
    from reciprocity.env import SearchEnv, rollout
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    done = done_keys(out, lambda r: (r["arena"], int(r["draw"])))
    expired = deadline(minutes)
    with appending(out, FIELDS) as w:
        for i in range(start, start + draws):
            for name in names:
                if (name, i) in done:
                    continue
                if expired():
                    return
                env = SearchEnv(scenario_of(name, i), platform="car", world=world or None)
                if only != "all":               # the evaluator's judgement, made at reset
                    env.reset(seed=i)
                    if env.source_reachable != (only == "reachable"):
                        continue
                t0 = time.perf_counter()
                s = rollout(env, StrategyAgent(STRATEGIES["reciprocity"], dict(params or {})), i).summary
                wall = time.perf_counter() - t0
                row = dict(arena=name, draw=i, success=s["success"], source_reachable=s.get("source_reachable"),
                           stop=s["stop_reason"].split(":")[0], error=round(float(s["error"]), 2),
                           n_measurements=s["n_measurements"], collisions=s.get("collisions", 0),
                           sim_time_s=round(float(s["sim_time_s"]), 1), wall_time_s=round(wall, 2),
                           speed=round(float(s["sim_time_s"]) / wall, 1),
                           mass_out_of_reach=s.get("mass_out_of_reach"))
                w.writerow(row)
                w.file.flush()
                print(row, flush=True)


def from_campaign(folder: Path, out: Path) -> None:
    """Rows of this script's CSV from a campaign's results (``reciprocity campaign``),
    the arena named by the scenario; the wall time is the episode's own."""
    import duckdb
    con = duckdb.connect()
    rel = con.execute(
        f"SELECT scenario, seed_index, success, source_reachable, stop_reason, error, n_measurements, "
        f"collisions, sim_time_s, wall_time_s FROM read_parquet('{folder}/**/*.parquet', "
        f"hive_partitioning=true) ORDER BY scenario, seed_index")
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, FIELDS)
        w.writeheader()
        for sc, i, ok, reach, stop, err, n, hits, sim, wall in rel.fetchall():
            w.writerow(dict(arena=sc, draw=i, success=ok, source_reachable=reach, stop=stop.split(":")[0],
                            error=round(err, 2), n_measurements=n, collisions=hits or 0,
                            sim_time_s=round(sim, 1), wall_time_s=round(wall, 2), speed=round(sim / wall, 1),
                            mass_out_of_reach=None))


def table(paths: list[Path]) -> str:
    """Markdown: success on reachable draws, unreachable stops, contacts, speed."""
    import numpy as np
    from scipy.stats import binomtest
    rows = [r for p in paths for r in csv.DictReader(p.open())]
    yes = lambda v: str(v) == "True"                                           # noqa: E731

    def rate(k, n):
        if n == 0:
            return "-"
        ci = binomtest(k, n).proportion_ci(0.95, method="wilson")
        return f"{k}/{n} = {k / n:.0%} [{ci.low:.0%}, {ci.high:.0%}]"

    out = ["| arena | draws | success, reachable source | readings median (reachable) | unreachable: "
           "`unreachable` stops (≤ 10 readings) | contacts | speed: overall / slowest |",
           "|---|---:|---|---:|---|---:|---|"]
    for name in [*dict.fromkeys(r["arena"] for r in rows), "all"]:
        sub = [r for r in rows if name in ("all", r["arena"])]
        reach = [r for r in sub if yes(r["source_reachable"])]
        unreach = [r for r in sub if not yes(r["source_reachable"])]
        stops = sum(r["stop"] == "unreachable" for r in unreach)
        quick = sum(r["stop"] == "unreachable" and int(r["n_measurements"]) <= 10 for r in unreach)
        sim = sum(float(r["sim_time_s"]) for r in sub)
        wall = sum(float(r["wall_time_s"]) for r in sub)
        slow = min(float(r["speed"]) for r in sub)
        med = f'{np.median([int(r["n_measurements"]) for r in reach]):g}' if reach else "-"
        out.append(f"| {name} | {len(sub)} | {rate(sum(yes(r['success']) for r in reach), len(reach))} | "
                   f"{med} | {stops}/{len(unreach)} ({quick}) | "
                   f"{sum(int(r['collisions']) for r in sub)} | {sim / wall:.1f}x / {slow:.1f}x |")
    return "\n".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--arenas", default=",".join(ARENAS), help="comma-separated families or paper, builtin-maze")
    ap.add_argument("--draws", type=int, default=6)
    ap.add_argument("--start", type=int, default=0, help="first draw")
    ap.add_argument("--out", type=Path, default=Path("benchmarks/car_search/runs.csv"))
    ap.add_argument("--minutes", type=float, default=None)
    ap.add_argument("--table", type=Path, nargs="+", default=None, help="print the table of these CSVs")
    ap.add_argument("--from-campaign", type=Path, default=None,
                    help="write --out from this campaign folder's results instead of running")
    ap.add_argument("--only", choices=("all", "reachable", "unreachable"), default="all",
                    help="run only the draws whose source the evaluator judges so (judged at reset; "
                         "the others are skipped and not written)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a parameter of the reciprocity strategy (YAML value), e.g. source_clearance=0")
    ap.add_argument("--world", action="append", default=[], metavar="KEY=VALUE",
                    help="a key of every draw's world (YAML value), e.g. map=unknown")
    a = ap.parse_args(argv)
    from resumable import strategy_sets
    try:
        params = strategy_sets(a.set)
        world = strategy_sets(a.world)
        if world:           # checked on the first draw before any episode: a bad key fails here
            from reciprocity.errors import SearchError
            from reciprocity.env.spec import environment_spec
            try:
                environment_spec(scenario_of(a.arenas.split(",")[0], a.start), platform="car", world=world)
            except SearchError as exc:
                raise ValueError(str(exc)) from None
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if a.from_campaign:
        from_campaign(a.from_campaign, a.out)
        return 0
    if a.table:
        print(table(a.table))
        return 0
    run(a.arenas.split(","), a.draws, a.out, a.minutes, a.start, a.only, params, world)
    return 0


if __name__ == "__main__":
    sys.exit(main())
