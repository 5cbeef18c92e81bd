"""Command line: ``hjplanner solve | path | bank | cache``.

Examples
--------
::

    hjplanner solve --arena paper --target 70,70 --rho 15 --out v.npz
    hjplanner path --value v.npz --start 128,12,135 --plot path.png
    hjplanner bank --arena paper --spacing 12.7 --rho 15 --h 1.5 --ntheta 48 --clearance 4 --reverse
    hjplanner cache --info          # banks in $HJPLANNER_CACHE or ~/.cache/hjplanner, and their size
    hjplanner cache --clear
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import sys
from pathlib import Path

import numpy as np

from .errors import PlanningError
from .limits import MAX_LENGTH, MAX_NTHETA, MIN_NTHETA, check_grid, grid_shape, length

__all__ = ["main"]

CACHE_HELP = "cache directory (default: $HJPLANNER_CACHE, else ~/.cache/hjplanner)"


class _Parser(argparse.ArgumentParser):
    """ArgumentParser that raises instead of exiting, so main() owns the exit code."""

    def error(self, message):
        raise PlanningError(f"{message} (see '{self.prog} --help')")


def _floats(text: str, n: int, what: str) -> tuple[float, ...]:
    """`n` comma-separated finite numbers, each within ±MAX_LENGTH."""
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != n or not np.isfinite(values).all() or np.abs(values).max() > MAX_LENGTH:
        raise PlanningError(f"{what} must be {n} comma-separated numbers within ±{MAX_LENGTH:g}; got {text!r}")
    return values


def _output(path, label: str, *, folder: bool = False):
    """`path` checked writable before any work (see :func:`arenas.files.check_output`)."""
    from arenas.files import check_output
    return check_output(path, label, folder=folder, error=PlanningError)


def _extent(domain) -> tuple[float, float]:
    """Width and height of the domain's bounding box."""
    if hasattr(domain, "boundary"):
        b = np.asarray(domain.boundary, dtype=float)
        return tuple(b.max(axis=0) - b.min(axis=0))
    (x0, x1), (y0, y1) = domain
    return (x1 - x0, y1 - y0)


def _grid(args, domain) -> float:
    """Check the grid flags against the domain before any work; return h."""
    h = _default_h(domain, args.h)
    check_grid(args.rho, h, args.ntheta, args.clearance, _extent(domain))
    return h


def _domain(args):
    if args.arena and args.bounds:
        raise PlanningError("give either --arena or --bounds, not both")
    if args.bounds:
        x0, x1, y0, y1 = _floats(args.bounds, 4, "--bounds X0,X1,Y0,Y1")
        if not (x1 > x0 and y1 > y0):
            raise PlanningError(f"--bounds X0,X1,Y0,Y1 needs X0 < X1 and Y0 < Y1; got {args.bounds!r}")
        return ((x0, x1), (y0, y1))
    if not args.arena:
        raise PlanningError("a domain is needed: --arena NAME|FILE or --bounds X0,X1,Y0,Y1")
    try:
        import arenas
    except ImportError as exc:
        raise PlanningError(f"--arena needs the 'arenas' package, which cannot be imported ({exc}); "
                            "use --bounds X0,X1,Y0,Y1 instead") from None
    try:
        return arenas.load(args.arena)
    except Exception as exc:  # arenas reports its own errors; show them without a traceback
        raise PlanningError(f"cannot load arena {args.arena!r}: {exc}") from None


def _default_h(domain, h):
    if h is not None:
        return h
    if hasattr(domain, "boundary"):
        return 1.0  # cm, the paper's planner resolution
    (x0, x1), (y0, y1) = domain
    return max(x1 - x0, y1 - y0) / 100.0


def _add_grid_arguments(parser):
    parser.add_argument("--arena", help="built-in arena name or YAML file (cm)")
    parser.add_argument("--bounds", help="rectangle X0,X1,Y0,Y1 instead of an arena (--bounds=-1,1,-1,1 if negative)")
    parser.add_argument("--rho", type=float, required=True, help=f"minimum turning radius, in (0, {MAX_LENGTH:g}]")
    parser.add_argument("--h", type=float, default=None,
                        help="grid spacing (default 1 cm for arenas); at most 5e7 nodes x·y·θ")
    parser.add_argument("--ntheta", type=int, default=72,
                        help=f"number of headings, {MIN_NTHETA} to {MAX_NTHETA} (default 72)")
    parser.add_argument("--clearance", type=float, default=0.0, help="inflate obstacles and walls by this (>= 0)")
    parser.add_argument("--reverse", action="store_true", help="allow reverse driving (Reeds-Shepp)")


def _cmd_solve(args) -> int:
    from .solver import solve
    domain = _domain(args)
    h = _grid(args, domain)
    target = _floats(args.target, 2, "--target X,Y")
    if args.tol is not None:
        length(args.tol, "--tol", zero=True)
    out = _output(args.out, "--out")
    with _sweep_bar(domain, h, args.ntheta) as progress:
        vf = solve(domain, target, args.rho, h, args.ntheta, clearance=args.clearance,
                   tol=args.tol, reverse=args.reverse, progress=progress)
    out.parent.mkdir(parents=True, exist_ok=True)
    vf.save(out)
    g = vf.grid
    finite = np.isfinite(vf.values)
    print(f"solved {vf.meta['domain']} target ({target[0]:g}, {target[1]:g}) on {g.nx} x {g.ny} x {g.ntheta} "
          f"in {vf.meta['solve_time_s']:.2f} s ({vf.meta['sweeps']} sweeps); "
          f"reachable {finite.mean():.1%} of states; max finite phi {vf.values[finite].max():.4g}")
    print(f"wrote {args.out}")
    return 0


#: Grids of more nodes than this show a progress bar over the sweeps (a few seconds and up).
BAR_NODES = 2_000_000


@contextlib.contextmanager
def _sweep_bar(domain, h: float, ntheta: int):
    """A progress bar over the sweeps of a large solve, with the blocks of the grid still
    changing (they fall to 0 as it converges); None for a small grid."""
    nx, ny = grid_shape(_extent(domain), h)
    if nx * ny * ntheta <= BAR_NODES:
        yield None
        return
    from tqdm import tqdm
    with tqdm(unit="sweep", desc="HJ sweeps", file=sys.stderr) as bar:
        def progress(sweeps: int, changed: int, blocks: int) -> None:
            bar.set_postfix_str(f"blocks still changing {changed}/{blocks}", refresh=False)
            bar.update(sweeps - bar.n)
        yield progress


def _cmd_path(args) -> int:
    from .value_function import ValueFunction
    x, y, deg = _floats(args.start, 3, "--start X,Y,DEG")
    if args.plot is not None:
        _check_figure(args.plot)
    vf = ValueFunction.load(args.value)
    h = vf.grid.h
    if args.ds is not None and not (np.isfinite(args.ds) and h / 100 <= args.ds <= 100 * h):
        raise PlanningError(f"--ds must be a number from h/100 to 100 h ({h / 100:g} to {100 * h:g}); "
                            f"got {args.ds!r}")
    path = vf.path((x, y, np.radians(deg)), ds=args.ds)
    words = {1: "L", 0: "S", -1: "R"}
    gears = {1: "", -1: "-"}  # reverse runs carry a minus sign: "-R4.2"
    summary = dict(start=[x, y, deg], target=vf.target.tolist(), phi_start=path.value_start, length=path.length,
                   reached=path.reached, steps=len(path.steering),
                   controls=" ".join(f"{gears[v]}{words[u]}{length:.3g}" for u, v, length in path.segments))
    print(json.dumps(summary))
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 5))
        vf.plot_slice(np.radians(deg), ax=ax)
        ax.plot(path.xy[:, 0], path.xy[:, 1], "w-", lw=2)
        ax.plot(x, y, "wo")
        Path(args.plot).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(args.plot, dpi=120, bbox_inches="tight")
        plt.close(fig)
        print(f"wrote {args.plot}")
    if not path.reached:
        print("error: the path did not reach the target", file=sys.stderr)
        return 1
    return 0


def _check_figure(path: str) -> None:
    """A figure file name matplotlib can write, in a writable place."""
    _output(path, "--plot")
    formats = ("png", "pdf", "svg", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp", "pgf")
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in formats:
        raise PlanningError(f"--plot {path!r}: unknown figure format {suffix!r}; end the name with one of "
                            f"{', '.join('.' + f for f in formats)}")


#: Most targets of one bank.
MAX_TARGETS = 10_000


def _cmd_bank(args) -> int:
    from .bank import ValueFunctionBank, default_cache_dir, folder_bytes
    domain = _domain(args)
    h = _grid(args, domain)
    spacing = length(args.spacing, "--spacing")
    w, ht = _extent(domain)
    n = (math.floor(w / spacing) + 1) * (math.floor(ht / spacing) + 1)
    if spacing < h or n > MAX_TARGETS:
        raise PlanningError(f"--spacing must be at least h ({h:g}) and give at most {MAX_TARGETS} targets "
                            f"(about {n} here); got {args.spacing!r}")
    cores = os.cpu_count() or 1
    if args.workers is not None and not 1 <= args.workers <= min(64, 4 * cores):
        raise PlanningError(f"--workers must be a whole number from 1 to {min(64, 4 * cores)} "
                            f"(4 per core); got {args.workers}")
    _output(args.cache or default_cache_dir(), "--cache" if args.cache else "the cache folder (HJPLANNER_CACHE)",
            folder=True)
    bank = ValueFunctionBank(domain, spacing, rho=args.rho, h=h, ntheta=args.ntheta,
                             clearance=args.clearance, reverse=args.reverse, cache_dir=args.cache)
    n_missing = len(bank.missing())
    seconds = bank.build(workers=args.workers, progress=not args.quiet)
    size = folder_bytes(bank.directory)
    print(f"bank of {len(bank)} targets (spacing {args.spacing:g}) in {bank.directory}: "
          f"{n_missing} solved in {seconds:.1f} s, {len(bank) - n_missing} from cache; {size / 1e6:.2f} MB")
    return 0


def _cmd_cache(args) -> int:
    from .bank import cache_info, clear_cache, default_cache_dir
    root = args.cache or default_cache_dir()
    if Path(root).exists() and not Path(root).is_dir():
        raise PlanningError(f"--cache {str(root)!r} is a file; give the cache folder")
    if args.clear:
        print(f"freed {clear_cache(root) / 1e6:.2f} MB in {root}")
        return 0
    entries = cache_info(root)
    banks = [e for e in entries if e["key"] != "legacy"]
    total = sum(e["bytes"] for e in entries)
    print(f"{len(banks)} bank{'s' if len(banks) != 1 else ''}, {total / 1e6:.2f} MB in {root}")
    for e in entries:
        if e["key"] == "legacy":
            print(f"  {e['files']} files of an older hjplanner (no longer read): {e['bytes'] / 1e6:.2f} MB")
            continue
        p = e["params"]
        if e["damaged"]:
            print(f"  {e['key']}  damaged (no readable bank.json): {e['files']} files, {e['bytes'] / 1e6:.2f} MB; "
                  "'hjplanner cache --clear' removes it")
            continue
        print(f"  {e['key']}  {e['domain']}  spacing {p['spacing']:g} rho {p['rho']:g} h {p['h']:g} "
              f"ntheta {p['ntheta']} clearance {p['clearance']:g}{' reverse' if p['reverse'] else ''}: "
              f"{e['files']}/{e['targets']} value functions, {e['bytes'] / 1e6:.2f} MB")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="hjplanner", description="Hamilton-Jacobi value functions and paths for the simple car.")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser)
    p = sub.add_parser("solve", help="solve a value function and write it to .npz")
    _add_grid_arguments(p)
    p.add_argument("--target", required=True, help="target X,Y (--target=-1,2 if negative)")
    p.add_argument("--tol", type=float, default=None, help="target radius (default: point target)")
    p.add_argument("--out", required=True, help="output .npz file")
    p.set_defaults(run=_cmd_solve)
    p = sub.add_parser("path", help="optimal path from a start pose")
    p.add_argument("--value", required=True, help=".npz written by 'hjplanner solve'")
    p.add_argument("--start", required=True,
                   help="start pose X,Y,DEG, heading in degrees (--start=-1,2,90 if negative)")
    p.add_argument("--ds", type=float, default=None, help="arc-length step, h/100 to 100 h (default h/2)")
    p.add_argument("--plot", help="write a figure (.png, .pdf, .svg...)")
    p.set_defaults(run=_cmd_path)
    p = sub.add_parser("bank", help="precompute value functions on a lattice of targets")
    _add_grid_arguments(p)
    p.add_argument("--spacing", type=float, required=True, help="lattice spacing of the targets")
    p.add_argument("--cache", default=None, help=CACHE_HELP)
    p.add_argument("--workers", type=int, default=None, help="processes, 1 to 4 per core (default: CPU count)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(run=_cmd_bank)
    p = sub.add_parser("cache", help="show (default) or clear the value-function banks in the cache")
    p.add_argument("--cache", default=None, help=CACHE_HELP)
    action = p.add_mutually_exclusive_group()
    action.add_argument("--info", action="store_true", help="list the banks and their size (the default)")
    action.add_argument("--clear", action="store_true", help="delete every bank (only hjplanner's files)")
    p.set_defaults(run=_cmd_cache)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``hjplanner`` console script; returns the exit code (2 on bad input)."""
    import signal
    import warnings
    parser = build_parser()
    warnings.showwarning = _show_warning
    if argv is None:           # the console script: SIGTERM stops the workers and cleans up, as Ctrl-C does
        signal.signal(signal.SIGTERM, _terminated)
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            raise PlanningError("a command is needed: solve, path, bank or cache (see 'hjplanner --help')")
        return int(args.run(args))
    except (PlanningError, ValueError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as one line ``warning: ...`` on stderr."""
    print(f"warning: {' '.join(str(message).split())}", file=sys.stderr if file is None else file)


def _terminated(signum, frame) -> None:
    raise KeyboardInterrupt


if __name__ == "__main__":
    sys.exit(main())
