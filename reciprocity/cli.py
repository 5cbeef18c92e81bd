"""The ``reciprocity`` command line: list arenas, run one episode, run the demo."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import arenas
from arenas import ArenaError
from arenas.families import PREFIX as GENERATED
from arenas.files import check_output, parse_yaml
from arenas.geometry import check_strength
from arenas.poses import pose_from_degrees

from .errors import ReciprocityError

# The episode machinery (.api, .scenarios, .strategies and what they pull in) is
# imported inside the commands that run or list it, so that --help, `arenas` and a
# usage error answer without it (issue 24: start-up).

__all__ = ["main"]


def _floats(text: str, what: str, sizes: tuple[int, ...]) -> list[float]:
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise ReciprocityError(f"{what} must be comma-separated numbers like 70,70; got {text!r}") from None
    if len(vals) not in sizes or not all(math.isfinite(v) for v in vals):
        raise ReciprocityError(f"{what} needs {' or '.join(map(str, sizes))} finite numbers; got {text!r}")
    return vals


def _pairs(item: str) -> list[str]:
    """``a=1,b=2`` as ``["a=1", "b=2"]``; ``a=1,2`` (a value with a comma) stays whole."""
    pieces = item.split(",")
    return pieces if len(pieces) > 1 and all("=" in p for p in pieces) else [item]


def _params(items: list[str], flag: str = "--set", example: str = "eps=0.1") -> dict:
    """KEY=VALUE flags (repeated, or comma-joined as ``a=1,b=2``) as a mapping; each value
    is read as YAML (numbers, booleans, lists), strictly."""
    out = {}
    for item in (p for it in items for p in _pairs(it)):
        if "=" not in item:
            raise ReciprocityError(f"{flag} expects KEY=VALUE (e.g. {flag} {example}); got {item!r}")
        key, value = (s.strip() for s in item.split("=", 1))
        if not key:
            raise ReciprocityError(f"{flag} expects KEY=VALUE with a key (e.g. {flag} {example}); got {item!r}")
        if key in out:
            raise ReciprocityError(f"{flag} {key} is given twice; give each key once")
        out[key] = parse_yaml(value, f"{flag} {key}", error=ReciprocityError)
    return out


def _progress(desc: str):
    """A per-step progress bar on stderr: redrawn in place in a terminal, silent when
    stderr is not one (a log file, CI); with the episode's budget as its total, so a long
    episode shows an estimate of the time left (an upper bound: most stop before it)."""
    from tqdm import tqdm
    bar = tqdm(desc=desc, unit="step", leave=False, file=sys.stderr, disable=not sys.stderr.isatty())

    def update(record):
        if record.region_area is not None:
            bar.set_postfix_str(f"area {record.region_area:.0f} cm²")
        elif len(record.readings):
            bar.set_postfix_str(f"reading {record.readings[-1]:.3g}")
        bar.update(1)

    def set_total(total: int) -> None:
        bar.total = total
        bar.refresh()
    update.close = bar.close
    update.set_total = set_total
    return update


def _summary_line(s: dict) -> str:
    est = "-" if s["estimate"] is None else f"({s['estimate'][0]:.2f}, {s['estimate'][1]:.2f})"
    if s.get("estimates") is not None and len(s["estimates"]) != 1:     # several sources: how many
        est = f"{len(s['estimates'])} sources of {len(s.get('sources') or [s['source']])}"
    err = "-" if s["error"] is None else f"{s['error']:.2f}"
    sim = f"{s['sim_time_s']:.0f}" if "sim_time_s" in s else "-"
    return (f"{s['strategy']:<12} {s['n_measurements']:>5} {s['n_samples']:>7} "
            f"{s['path_length']:>9.1f} {sim:>7} {s['wall_time_s']:>7.1f} {err:>9}  {est:<18} "
            f"{s.get('collisions', 0):>8}  {s['stop_reason']}")


#: A stop reason that is not the strategy's own rule, in words.
_STOPPED = {"step cap": "step cap reached", "no target": "no admissible place left to go",
            "unreachable": "what it believes lies out of reach", "gave up": "gave up"}


#: Why a lattice search that reached the source failed (Ristic et al. 2014, Sec. 5.1).
_NOT_LOCALISED = ", but the searcher's own position was not localised"


#: World kinds whose lengths are cm (an arena's).
ARENA_WORLDS = ("poisson", "flow")


def _verdict(s: dict, radius: float) -> str:
    """The last line of a run: whether it succeeded and why it stopped, in words.

    Parameters
    ----------
    s : dict
        The episode summary.
    radius : float
        The scenario's success radius (cm in arena worlds, the world's unit elsewhere).

    Returns
    -------
    str
        E.g. ``success: no — step cap reached (30 readings)`` or ``success: no —
        converged, error 5.94 > success radius 5``.
    """
    yes = "yes" if s["success"] else "no"
    reason, _, detail = str(s["stop_reason"]).partition(": ")
    if not s["converged"]:
        return f"success: no — {_STOPPED.get(reason, reason)}" + (f" ({detail})" if detail else "")
    if s["stop"] == "found":
        line = f"success: {yes} — {detail or 'an observer reached the source'}"
        return line + _NOT_LOCALISED if s.get("self_localised") is False else line
    unit = " cm" if s["world"] in ARENA_WORLDS else ""
    words = f"converged ({detail})" if detail else "converged"
    if s.get("errors") is not None:                                 # several sources
        errors = [e for e in s["errors"] if e is not None]
        worst = f", worst error {max(errors):.2f}{unit}" if errors else ""
        return (f"success: {yes} — {words}, {s.get('n_sources_estimated')} sources found of "
                f"{len(s['errors'])}{worst} (success radius {radius:g}{unit})")
    if s["error"] is None:
        return f"success: {yes} — {words}, no estimate"
    sign = "<=" if s["error"] <= radius else ">"
    line = f"success: {yes} — {words}, error {s['error']:.2f}{unit} {sign} success radius {radius:g}{unit}"
    return line + _NOT_LOCALISED if s.get("self_localised") is False else line


def _header(world: str = "poisson") -> str:
    """Column names; lengths are cm in arena (poisson, flow) worlds, the world's unit elsewhere,
    and time is simulated seconds (steps in step-counted worlds)."""
    unit = "cm" if world in ARENA_WORLDS else "  "
    return (f"{'strategy':<12} {'meas.':>5} {'samples':>7} {'path ' + unit:>9} {'time':>7} {'wall s':>7} "
            f"{'error ' + unit:>9}  {'estimate':<18} {'contacts':>8}  stop")


def _write_figures(out: Path, episode, arena, *, video: bool = False) -> list[Path]:
    """The episode's figures (PNG) from its record (``run(..., figures=True)``); on the car
    also its painted floor, the sensor calibration and (unless told not to) the video; in a
    ``flow`` world (unless told not to) the video of the search over the wind."""
    from .viz.episode import episode_figures
    out.mkdir(parents=True, exist_ok=True)
    s = episode.summary
    prefix = s["strategy"] if s["platform"] == "point" else f"{s['strategy']}_{s['platform']}"
    files = []
    for name, fig in episode_figures(episode, arena):
        files.append(out / f"{prefix}_{name}.png")
        fig.savefig(files[-1], dpi=150)
    floor = episode.truth.get("floor")
    if floor is not None:                                       # the testbed
        files.extend(_write_testbed_files(out, floor, episode.truth["calibration"]))
        if video:
            from .viz.video import write_video
            files.append(write_video(out / f"{prefix}.mp4", episode, arena, floor.image,
                                     imaging=episode.belief.get("imaging")))
    elif video and "wind" in episode.truth and episode.trace:     # a flow world
        from .viz.count_video import write_count_video
        files.append(write_count_video(out / f"{prefix}.mp4", episode, arena))
    return files


def _write_testbed_files(out: Path, floor, calibration) -> list[Path]:
    """The painted floor (PNG + sidecar) and the sensor calibration (Fig. 3)."""
    from matplotlib.figure import Figure
    floor_png = out / "floor.png"
    if not floor_png.exists():
        floor.save(floor_png)
    fig = Figure(figsize=(5, 3.6), layout="constrained")
    calibration.plot(fig.add_subplot())
    fig.savefig(out / "calibration.png", dpi=150)
    return [floor_png, out / "calibration.png"]


def cmd_arenas(args) -> int:
    print(f"{'name':<8} {'free area cm²':>13}  description")
    for name in arenas.builtin_names():
        a = arenas.load(name)
        print(f"{name:<8} {a.area:>13.0f}  {arenas.builtin_description(name)}")
    return 0


def cmd_scenarios(args) -> int:
    from .scenarios import load_scenario, scenario_description, scenario_names
    names = scenario_names()
    wn = max(len(n) for n in names)
    print(f"{'name':<{wn}} {'world':<9} {'platform':<8}  description")
    for name in names:
        sc = load_scenario(name)
        # a scenario file's description came with it: read each file once
        print(f"{name:<{wn}} {sc.world:<9} {sc.platform:<8}  {sc.description or scenario_description(name)}")
    return 0


def cmd_strategies(args) -> int:
    from .strategies import STRATEGIES
    rows = []
    for name, cls in STRATEGIES.items():
        first = " ".join((cls.__doc__ or "").strip().split("\n\n")[0].split())
        doc = first if len(first) <= 100 else first[:99].rstrip() + "…"
        rows.append((name, ", ".join(cls.worlds), "any" if cls.agents is None else str(cls.agents), doc))
    wn = max(len("name"), *(len(r[0]) for r in rows))
    ww = max(len("worlds"), *(len(r[1]) for r in rows))
    print(f"{'name':<{wn}} {'worlds':<{ww}} {'observers':<9}  description")
    for name, worlds, agents, doc in rows:
        print(f"{name:<{wn}} {worlds:<{ww}} {agents:<9}  {doc}")
    return 0


def _world_overrides(args) -> dict:
    """The --source/--strength/--start/--noise/--mismatch/--unknown-map/--lidar flags as world
    overrides."""
    world = {}
    if args.source is not None:
        world["source"] = _floats(args.source, "--source", (2,))
    if args.strength is not None:                # checked with the common flags (_validate_common)
        world["strength"] = args.strength
    if args.start is not None:
        st = _floats(args.start, "--start", (2, 3))
        world["start"] = pose_from_degrees(st).tolist()
    if args.noise is not None:
        world["noise"] = args.noise
    if args.mismatch:
        world["mismatch"] = _params(args.mismatch, "--mismatch", "strength_factor=1.2")
    if getattr(args, "unknown_map", False):
        world["map"] = "unknown"
    if getattr(args, "lidar", None):
        world["lidar"] = _params(args.lidar, "--lidar", "beams=64,range=40")
    return world


#: Largest seed accepted (numpy's SeedSequence takes any non-negative integer; 2**63 - 1
#: keeps seeds exact in JSON, Parquet and every language that reads them).
MAX_SEED = 2**63 - 1
#: Most observers of one episode (the multi-agent papers use 2-5).
MAX_AGENTS = 64


def _validate_common(args) -> None:
    if not 0 <= args.seed <= MAX_SEED:
        raise ReciprocityError(f"--seed must be a whole number from 0 to {MAX_SEED}; got {args.seed}")
    if not math.isfinite(args.h) or not 0.2 <= args.h <= 20:
        raise ReciprocityError(f"--h must be a mesh size in cm from 0.2 to 20; got {args.h!r}")
    if args.noise is not None and (not math.isfinite(args.noise) or not 0 <= args.noise <= 1e6):
        raise ReciprocityError(f"--noise must be a number from 0 to 1e6 (signal units); got {args.noise!r}")
    if args.strength is not None:
        check_strength(args.strength, "--strength")
    agents = getattr(args, "agents", None)
    if agents is not None and not 1 <= agents <= MAX_AGENTS:
        raise ReciprocityError(f"--agents must be a whole number from 1 to {MAX_AGENTS}; got {agents}")


@dataclass
class _Planned:
    """One episode, checked and ready to run: its :class:`~reciprocity.api.EpisodeSpec`."""

    spec: object

    @property
    def strategy(self) -> str:
        return self.spec.strategy

    @property
    def scenario(self):
        return self.spec.scenario


def _random_draw(args, sc) -> dict:
    """``--random-source``: the true source and the start of an arena scenario, drawn from
    the episode seed as a campaign's ``random_source: true`` and ``reciprocity/Poisson-v0``
    draw them."""
    from .campaign.worker import world_draw
    if sc.world != "poisson":
        raise ReciprocityError(f"--random-source draws the source and start in an arena; scenario {sc.name!r} "
                               f"is a {sc.world} world")
    if args.source is not None or args.start is not None:
        raise ReciprocityError("--random-source draws the source and the start: give neither --source nor --start")
    return world_draw(sc, args.seed)


def _plan(args, scenario: str, strategy: str, params: dict) -> _Planned:
    """Validate one episode's inputs cheaply (no meshing or solving)."""
    from .api import check, strategy_parameters
    from .scenarios import load_scenario
    from .strategies import STRATEGIES
    _validate_common(args)
    world = _world_overrides(args)
    params = dict(params)
    if strategy in STRATEGIES and "h" in strategy_parameters(strategy):
        params.setdefault("h", args.h)
    sc = load_scenario(scenario, source=world.get("source"))
    if getattr(args, "random_source", False):
        world.update(_random_draw(args, sc))
    options = _params(args.car, "--car", "planner=bank")
    platform = getattr(args, "platform", None)
    if options and (platform or sc.platform) != "car":
        raise ReciprocityError("--car options need --platform car")
    return _Planned(check(sc, strategy, params=params, platform=platform, agents=getattr(args, "agents", None),
                          world=world, platform_options=options, seeds=args.seed))


def _run_one(args, plan: _Planned, out: Path | None):
    """Run one planned episode; figures and the trace into `out`."""
    from .api import run
    prog = _progress(plan.strategy) if not args.quiet else None
    try:
        episode = run(plan.spec, seed=args.seed, progress=prog, figures=out is not None)
    finally:
        if prog is not None:
            prog.close()
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        episode.to_json(out / f"{plan.strategy}_episode.json")
        # the strategy's record holds something to draw, or a flow world its video
        if episode.belief or (args.video and "wind" in (episode.truth or {})):
            arena = plan.scenario.arena                 # None in a plume or filament world
            if arena is not None:
                arena = arena.with_scenario(start=episode.summary["start"])
            _write_figures(out, episode, arena, video=args.video)
    return episode


def _arena_plan(args, strategy: str, params: dict) -> _Planned:
    """:func:`_plan` for ``--arena``: a built-in arena or an arena file (a poisson scenario)."""
    generated = args.arena.startswith(GENERATED)
    if args.arena not in arenas.builtin_names() and not generated and not Path(args.arena).exists():
        raise ReciprocityError(f"--arena: no built-in arena or file named {args.arena!r}; built-ins are "
                               f"{', '.join(arenas.builtin_names())} (or give the path of an arena YAML file, "
                               f"or generate:FAMILY:SEED with FAMILY one of {', '.join(arenas.FAMILIES)})")
    plan = _plan(args, args.arena, strategy, params)
    if plan.scenario.world != "poisson":
        raise ReciprocityError(f"--arena {args.arena!r} is a {plan.scenario.world} scenario, not an arena; "
                               "give it with --scenario")
    return plan


def cmd_run(args) -> int:
    if (args.arena is None) == (args.scenario is None):
        raise ReciprocityError("give exactly one of --arena NAME|FILE or --scenario NAME|FILE "
                               "(see `reciprocity arenas` and `reciprocity scenarios`)")
    if args.arena is not None:
        plan = _arena_plan(args, args.strategy, _params(args.set))
    else:
        plan = _plan(args, args.scenario, args.strategy, _params(args.set))
    out = check_output(args.out, "--out", folder=True, error=ReciprocityError) if args.out else None
    json_path = check_output(args.json, "--json", error=ReciprocityError) if args.json else None
    episode = _run_one(args, plan, out)
    if json_path is not None:  # written first: a result is never lost to the table below
        json_path.parent.mkdir(parents=True, exist_ok=True)
        json_path.write_text(episode.to_json(with_trace=False))
    print(_header(episode.summary["world"]))
    print(_summary_line(episode.summary))
    if out is not None:
        print(f"figures and the full trace are in {out}/")
    if json_path is not None:
        print(f"summary written to {json_path}")
    print(_verdict(episode.summary, plan.scenario.success_radius))
    return 0


def cmd_demo(args) -> int:
    from tqdm import tqdm
    args.set = []
    names = ("reciprocity", "gradient")
    plans = [_arena_plan(args, name, {}) for name in names]
    out = check_output(args.out, "--out", folder=True, error=ReciprocityError)
    if not args.quiet:
        print(f"demo: the {args.platform} observer searches arena {plans[0].scenario.name!r} with "
              f"{' and then '.join(names)}; figures into {out}/", flush=True)
    rows = []
    # one bar over the runs, and each run's own bar of steps below it (terminals only, as
    # campaigns): the meshing, solves and car planning before the first step take seconds
    with tqdm(total=len(plans), desc="demo", unit="run", file=sys.stderr, dynamic_ncols=True,
              disable=args.quiet or not sys.stderr.isatty()) as bar:
        for plan in plans:
            bar.set_postfix_str(plan.strategy)
            t0 = time.perf_counter()
            rows.append(_run_one(args, plan, out).summary)
            bar.update(1)
            if not args.quiet:
                bar.write(f"  {plan.strategy}: done in {time.perf_counter() - t0:.0f} s", file=sys.stdout)
    (out / "summary.json").write_text(json.dumps(rows, indent=1))
    src = rows[0]["source"]
    noise = ("sensor noise 12 ADC counts, 1 s dwell" if args.platform == "car"
             else f"noise sigma = {12.0 if args.noise is None else args.noise:g}")
    print(f"arena {rows[0]['arena']!r}, source ({src[0]:.2f}, {src[1]:.2f}) cm, start {rows[0]['start'][:2]}, "
          f"{noise}, seed {args.seed}, {args.platform} observer")
    print("time s: simulated driving and measuring time (car); wall s: computing time; "
          "contacts: collisions with walls (the car)")
    print(_header())
    for s in rows:
        print(_summary_line(s))
    for s, plan in zip(rows, plans):
        print(f"{s['strategy']}: {_verdict(s, plan.scenario.success_radius)}")
    if rows[0]["arena"] == "paper":
        print("for comparison, the paper's own testbed runs (Landa et al., one run each, not ours): "
              "reciprocity 7 measurements, error 4.35 cm; gradient 8 + 5 gradient measurements = "
              "18 samples, error 5.0 cm")
    print(f"figures, traces and summary.json are in {out}/")
    return 0


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--source", help="true source X,Y in cm (default: the arena's)")
    p.add_argument("--strength", type=float, help="true source strength c (default: the arena's)")
    p.add_argument("--start", help="start X,Y[,DEG] in cm and degrees (default: the arena's)")
    p.add_argument("--car", action="append", default=[], metavar="KEY=VALUE",
                   help="car option, e.g. --car planner=bank, --car rho=12 (repeatable; see "
                        "reciprocity.platforms.car.CAR_KEYS)")
    p.add_argument("--no-video", dest="video", action="store_false",
                   help="car and flow runs: do not write the MP4 videos into --out")
    p.add_argument("--seed", type=int, default=0, help="random seed, a whole number >= 0 (default 0)")
    p.add_argument("--mismatch", action="append", default=[], metavar="KEY=VALUE",
                   help="make the true world differ from what the strategy is told, e.g. "
                        "--mismatch strength_factor=1.2,wall_shift=0.3 (repeatable or comma-joined; "
                        "keys: strength_factor, wall_shift in cm, noise_factor, paint_gamma for the car floor)")
    p.add_argument("--noise", type=float, default=None,
                   help="point observer: noise std, signal units (default 12); the car's sensor has "
                        "its own noise, 12 ADC counts")
    p.add_argument("--h", type=float, default=1.0, help="mesh size of the strategy's model in cm (default 1); the truth keeps its own")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


class _Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line on stderr and exit status 2.

    ``declare(parser)``, when given, adds the arguments when the command is chosen or its
    help is asked for, not when the parser is built (the campaign layer's commands: their
    flags are checked by the campaign layer, which ``run`` and ``--help`` never import).
    """

    def __init__(self, *args, declare=None, **kwargs):
        super().__init__(*args, **kwargs)
        self._declare = declare

    def _declared(self) -> None:
        if self._declare is not None:
            declare, self._declare = self._declare, None
            declare(self)

    def parse_known_args(self, args=None, namespace=None):
        self._declared()
        return super().parse_known_args(args, namespace)

    def format_usage(self) -> str:
        self._declared()
        return super().format_usage()

    def format_help(self) -> str:
        self._declared()
        return super().format_help()

    def error(self, message: str):
        self.exit(2, f"error: {message} (see `{self.prog} --help`)\n")


#: The campaign layer's commands and their one-line help; their arguments are declared
#: by :func:`reciprocity.campaign.cli.declare` when one of them is chosen.
CAMPAIGN_COMMANDS = {
    "campaign": "strategies × scenarios × seeds on Dask, results as Parquet (re-run to resume)",
    "report": "tables and figures of a campaign's results",
    "reproduce": "re-run a published table beside the paper's numbers",
}


def _declare_campaign_command(name: str):
    def declare(parser: argparse.ArgumentParser) -> None:
        from .campaign.cli import declare as campaign_declare
        campaign_declare(name, parser)
    return declare


class _Version(argparse.Action):
    """``--version``: the installed version, looked up only when asked for (importlib.metadata
    costs a fifth of the start-up time of every other command)."""

    def __init__(self, option_strings, dest, help="show program's version number and exit"):
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        from importlib.metadata import PackageNotFoundError, version
        try:
            number = version("reciprocity-search")
        except PackageNotFoundError:
            number = "unknown"
        print(f"{parser.prog} {number}")
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="reciprocity", description=(
        "Reciprocity-based source discovery (Landa et al.): FEM adjoint solves, "
        "probability imaging, and a gradient-ascent baseline."))
    parser.add_argument("--version", action=_Version)
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("arenas", help="list the built-in arenas").set_defaults(func=cmd_arenas)
    sub.add_parser("scenarios", help="list the built-in scenarios (every arena, and the "
                   "lattice and plume worlds)").set_defaults(func=cmd_scenarios)
    sub.add_parser("strategies", help="list the strategies and the worlds each applies to"
                   ).set_defaults(func=cmd_strategies)
    run = sub.add_parser("run", help="run one search episode")
    where = run.add_mutually_exclusive_group()
    where.add_argument("--arena", help="built-in arena name, arena YAML file, or a generated arena "
                       "generate:FAMILY[:SEED[:KEY=VALUE,...]], e.g. --arena generate:rooms:3 (a poisson scenario)")
    where.add_argument("--scenario", help="built-in scenario name or scenario YAML file")
    run.add_argument("--strategy", required=True, help="strategy name (see `reciprocity strategies`)")
    run.add_argument("--agents", type=int, help="number of observers (multi-agent strategies)")
    run.add_argument("--out", help="folder for figures, the full trace (and the video on the car)")
    run.add_argument("--platform", help="observer: point, car, walker (default: the scenario's)")
    run.add_argument("--json", help="write the episode summary (JSON) to this file")
    run.add_argument("--random-source", action="store_true",
                     help="draw the true source and the start from --seed (arenas; as reciprocity/Poisson-v0)")
    run.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                     help="strategy parameter, e.g. --set eps=0.1 (repeatable)")
    run.add_argument("--unknown-map", action="store_true",
                     help="map: unknown. Poisson worlds: tell the strategy the outer boundary only "
                          "(the observer maps the obstacles with its range sensor); lattice worlds: the links unknown")
    run.add_argument("--lidar", action="append", default=[], metavar="KEY=VALUE",
                     help="the observer's range sensor, e.g. --lidar beams=64,range=40,noise=0.5 "
                          "(cm; default with --unknown-map: 64 beams, 40 cm, 0.5 cm)")
    _common(run)
    run.set_defaults(func=cmd_run)
    demo = sub.add_parser("demo", help="both strategies on the paper arena (or another), with figures")
    demo.add_argument("--out", default="demo_out", help="output folder (default demo_out)")
    demo.add_argument("--arena", default="paper", help="built-in arena name, arena YAML file or "
                      "generate:FAMILY[:SEED[:KEY=VALUE,...]] (default paper)")
    demo.add_argument("--platform", choices=("point", "car"), default="car",
                      help="observer: the simulated micro-car (default) or a point")
    _common(demo)
    demo.set_defaults(func=cmd_demo)
    for name, text in CAMPAIGN_COMMANDS.items():
        sub.add_parser(name, help=text, declare=_declare_campaign_command(name))
    return parser


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as one line ``warning: ...`` on stderr (the CLI's voice), not Python's two."""
    print(f"warning: {' '.join(str(message).split())}", file=sys.stderr if file is None else file)


def _terminated(signum, frame) -> None:
    """SIGTERM ends a command as Ctrl-C does: what is finished is written before it exits."""
    raise KeyboardInterrupt


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``reciprocity`` console script; returns the exit code."""
    import signal
    import warnings
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a usage error (already printed)
        return int(exc.code or 0)
    warnings.showwarning = _show_warning
    if argv is None:           # the console script, not a caller's thread or test
        signal.signal(signal.SIGTERM, _terminated)
    try:
        return args.func(args)
    except (ArenaError, ReciprocityError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader left (`reciprocity scenarios | head`): no traceback; stdout is pointed
        # at devnull so that the interpreter's final flush does not fail again
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
