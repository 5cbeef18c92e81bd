"""The ``reciprocity`` command line: list arenas, run one episode, run the demo."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import yaml

import arenas
from arenas import ArenaError

from .errors import ReciprocityError
from .runner import PLATFORMS, search
from .strategies import STRATEGIES

__all__ = ["main"]


def _floats(text: str, what: str, sizes: tuple[int, ...]) -> list[float]:
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise ReciprocityError(f"{what} must be comma-separated numbers like 70,70; got {text!r}") from None
    if len(vals) not in sizes or not all(math.isfinite(v) for v in vals):
        raise ReciprocityError(f"{what} needs {' or '.join(map(str, sizes))} finite numbers; got {text!r}")
    return vals


def _params(items: list[str], flag: str = "--set", example: str = "eps=0.1") -> dict:
    out = {}
    for item in items:
        if "=" not in item:
            raise ReciprocityError(f"{flag} expects KEY=VALUE (e.g. {flag} {example}); got {item!r}")
        key, value = item.split("=", 1)
        out[key.strip()] = yaml.safe_load(value)
    return out


def _progress(desc: str):
    from tqdm import tqdm
    bar = tqdm(desc=desc, unit="step", leave=False, file=sys.stderr)

    def update(record):
        area = record.get("region_area")
        bar.set_postfix_str(f"area {area:.0f} cm²" if area is not None else f"reading {record['readings'][-1]:.0f}")
        bar.update(1)
    update.close = bar.close
    return update


def _summary_line(s: dict) -> str:
    est = "-" if s["estimate"] is None else f"({s['estimate'][0]:.2f}, {s['estimate'][1]:.2f})"
    err = "-" if s["error"] is None else f"{s['error']:.2f}"
    sim = f"{s['sim_time_s']:.0f}" if "sim_time_s" in s else "-"
    return (f"{s['strategy']:<12} {s['n_measurements']:>5} {s['n_samples']:>7} "
            f"{s['path_length']:>9.1f} {sim:>7} {s['wall_time_s']:>7.1f} {err:>9}  {est:<18} "
            f"{s.get('collisions', 0):>4}  {s['stop_reason']}")


_HEADER = (f"{'strategy':<12} {'meas.':>5} {'samples':>7} {'path cm':>9} {'time s':>7} {'wall s':>7} "
           f"{'error cm':>9}  {'estimate':<18} {'hits':>4}  stop")


def _write_figures(out: Path, episode, strategy, platform, arena, *, video: bool = False) -> list[Path]:
    from .figures import gradient_run_figure, imaging_steps_figure
    out.mkdir(parents=True, exist_ok=True)
    name = episode.summary["strategy"]
    car = platform.name == "car"
    prefix = f"{name}_car" if car else name
    files = []
    if name == "reciprocity":
        fig = imaging_steps_figure(episode, strategy.imaging, arena, eps=strategy.eps)
        files.append(out / f"{prefix}_steps.png")
    else:
        floor = platform.testbed.floor if car else None
        fig = gradient_run_figure(episode, getattr(platform, "field", None), arena, strategy.gradients,
                                  floor=floor)
        files.append(out / f"{prefix}_path.png")
    fig.savefig(files[-1], dpi=150)
    if car:
        files.extend(_write_testbed_files(out, platform))
        if video:
            from .video import write_video
            imaging = strategy.imaging if name == "reciprocity" else None
            files.append(write_video(out / f"{prefix}.mp4", episode, arena, platform.testbed.floor.image,
                                     imaging=imaging))
    return files


def _write_testbed_files(out: Path, platform) -> list[Path]:
    """The painted floor (PNG + sidecar) and the sensor calibration (Fig. 3)."""
    from matplotlib.figure import Figure
    floor_png = out / "floor.png"
    if not floor_png.exists():
        platform.testbed.floor.save(floor_png)
    fig = Figure(figsize=(5, 3.6), layout="constrained")
    platform.testbed.calibration.plot(fig.add_subplot())
    fig.savefig(out / "calibration.png", dpi=150)
    return [floor_png, out / "calibration.png"]


def cmd_arenas(args) -> int:
    print(f"{'name':<8} {'free area cm²':>13}  description")
    for name in arenas.builtin_names():
        a = arenas.load(name)
        print(f"{name:<8} {a.area:>13.0f}  {arenas.builtin_description(name)}")
    return 0


def _run_one(args, arena, strategy: str, params: dict, out: Path | None):
    arena.with_scenario(source=args.source, strength=args.strength, start=args.start)  # validate
    prog = _progress(strategy) if not args.quiet else None
    try:
        episode, strat, plat = search(
            arena, strategy, source=args.source, strength=args.strength, start=args.start,
            platform=args.platform, seed=args.seed, noise=args.noise, h=args.h,
            params=params, car=_params(args.car, "--car", "planner=bank") or None, progress=prog)
    finally:
        if prog is not None:
            prog.close()
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        episode.to_json(out / f"{strategy}_episode.json")
        _write_figures(out, episode, strat, plat, arena.with_scenario(source=args.source, start=args.start),
                       video=args.video)
    return episode


def _resolve(args):
    arena = arenas.load(args.arena)
    args.source = _floats(args.source, "--source", (2,)) if args.source else None
    if args.start:
        st = _floats(args.start, "--start", (2, 3))
        args.start = st[:2] + ([math.radians(st[2])] if len(st) == 3 else [])
    return arena


def cmd_run(args) -> int:
    arena = _resolve(args)
    out = Path(args.out) if args.out else None
    episode = _run_one(args, arena, args.strategy, _params(args.set), out)
    print(_HEADER)
    print(_summary_line(episode.summary))
    if args.json:
        Path(args.json).write_text(episode.to_json(with_trace=False))
    if out is not None:
        print(f"figures and the full trace are in {out}/")
    return 0


def cmd_demo(args) -> int:
    args.arena, args.strategy, args.set = "paper", None, []
    arena = _resolve(args)
    out = Path(args.out)
    rows = []
    for name in STRATEGIES:
        rows.append(_run_one(args, arena, name, {}, out).summary)
    src = rows[0]["source"]
    noise = "sensor noise 12 ADC counts, 1 s dwell" if args.platform == "car" else f"noise sigma = {args.noise:g}"
    print(f"arena 'paper', source ({src[0]:.2f}, {src[1]:.2f}) cm, start {rows[0]['start'][:2]}, "
          f"{noise}, seed {args.seed}, {args.platform} observer")
    print("time s: simulated driving and measuring time (car); wall s: computing time; "
          "hits: collisions with walls")
    print(_HEADER)
    for s in rows:
        print(_summary_line(s))
    print("paper (car testbed): reciprocity 7 measurements, error 4.35 cm; "
          "gradient 8 + 5 gradient measurements = 18 samples, error 5.0 cm")
    (out / "summary.json").write_text(json.dumps(rows, indent=1))
    print(f"figures, traces and summary.json are in {out}/")
    return 0


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--source", help="true source X,Y in cm (default: the arena's)")
    p.add_argument("--strength", type=float, help="true source strength c (default: the arena's)")
    p.add_argument("--start", help="start X,Y[,DEG] in cm and degrees (default: the arena's)")
    p.add_argument("--car", action="append", default=[], metavar="KEY=VALUE",
                   help="car option, e.g. --car planner=bank, --car rho=12 (repeatable; see "
                        "reciprocity.runner.CAR_KEYS)")
    p.add_argument("--no-video", dest="video", action="store_false",
                   help="car runs: do not write the MP4 videos into --out")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--noise", type=float, default=12.0,
                   help="point observer: noise std, signal units (default 12); the car's sensor has "
                        "its own noise, 12 ADC counts")
    p.add_argument("--h", type=float, default=1.0, help="mesh size in cm (default 1)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="reciprocity", description=(
        "Reciprocity-based source discovery (Landa et al.): FEM adjoint solves, "
        "probability imaging, and a gradient-ascent baseline."))
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("arenas", help="list the built-in arenas").set_defaults(func=cmd_arenas)
    run = sub.add_parser("run", help="run one search episode")
    run.add_argument("--arena", required=True, help="built-in name or YAML file")
    run.add_argument("--strategy", required=True, choices=list(STRATEGIES))
    run.add_argument("--out", help="folder for figures, the full trace (and the video on the car)")
    run.add_argument("--platform", choices=PLATFORMS, default="point",
                     help="observer: point, or the simulated micro-car (default point)")
    run.add_argument("--json", help="write the episode summary (JSON) to this file")
    run.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                     help="strategy parameter, e.g. --set eps=0.1 (repeatable)")
    _common(run)
    run.set_defaults(func=cmd_run)
    demo = sub.add_parser("demo", help="both strategies on the paper arena, with figures")
    demo.add_argument("--out", default="demo_out", help="output folder (default demo_out)")
    demo.add_argument("--platform", choices=PLATFORMS, default="car",
                      help="observer: the simulated micro-car (default) or a point")
    _common(demo)
    demo.set_defaults(func=cmd_demo)
    from .campaign.cli import add_commands
    add_commands(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``reciprocity`` console script; returns the exit code."""
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (ArenaError, ReciprocityError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
