"""The ``lattice`` world kind of scenario files: parameters, world, platforms.

``sources: [[x, y], ...]`` (1 to MAX_SOURCES distinct transient nodes, instead of
``source``) places several sources whose mean counts add up; ``strengths: [A0, ...]``
are their release rates (particles per step at unit F, default: each ``strength``, which
stays the nominal rate); ``max_sources`` (default 1 with ``source``, MAX_SOURCES with
``sources``) is the bound a strategy is told. Every source shares the entry's cluster of
links, as ``source`` does.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse.csgraph import connected_components

from ..errors import SearchError
from ..scenarios import WorldKind, check_keys, register_world
from ..spaces.lattice import LatticeSpace
from ..validation import number, point
from ..worlds.lattice import PERCOLATION_THRESHOLD, LatticeWorld, clusters, draw_links
from .sources import source_list, source_strengths

__all__ = ["LATTICE", "LATTICE_KEYS", "MIN_RADIUS", "MAX_RADIUS"]

#: Parameters of a ``lattice`` scenario.
LATTICE_KEYS = ("radius", "p", "source", "strength", "entry", "slip", "primary", "secondary",
                "connectivity", "lattice_seed", "map", "localisation", "links", "sources", "strengths",
                "max_sources")
#: Smallest lattice radius accepted.
MIN_RADIUS = 2
#: Largest lattice radius accepted (about 32,000 nodes and 64,000 links).
MAX_RADIUS = 100
#: Largest release rate A0.
MAX_STRENGTH = 1e6


def _number(params, key, default, lo, hi, what, *, lo_open=False, hi_open=False):
    v = params.get(key, default)
    bad = isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v)
    if not bad:
        bad = (v <= lo if lo_open else v < lo) or (v >= hi if hi_open else v > hi)
    if bad:
        raise SearchError(f"{key} must be {what}; got {v!r}")
    return float(v)


def _node(space: LatticeSpace, value, key: str, *, transient: bool) -> list:
    try:
        arr = point(value, key)
    except SearchError:
        raise SearchError(f"{key} must be a lattice node [x, y] (integers); got {value!r}") from None
    i = int(space.index_of(arr)[0])
    ring = "x² + y² <= R0²" if transient else "x² + y² < (R0 + 1)²"
    if i < 0 or (transient and not space.transient[i]):
        raise SearchError(f"{key} {arr.tolist()} is not a node of the lattice: integers with {ring}, "
                          f"R0 = {space.radius:g}")
    return arr.tolist()


def _pair(params, key, default) -> tuple:
    v = params.get(key, default)
    try:
        pd, pfa = (float(x) for x in v)
    except (TypeError, ValueError):
        raise SearchError(f"{key} must be [p_d, p_fa], two probabilities; got {v!r}") from None
    if not (0 <= pd <= 1 and 0 <= pfa <= 1):
        raise SearchError(f"{key} must be [p_d, p_fa], two probabilities in [0, 1]; got {v!r}")
    return pd, pfa


def _sources(space: LatticeSpace, params: dict) -> list | None:
    """The ``sources`` key as a list of distinct transient nodes, or None."""
    return source_list(params, lambda q, key: _node(space, q, key, transient=True), what="lattice nodes")


def _several(params: dict, sources: list | None, strength: float) -> dict:
    """``sources``, ``strengths`` (release rates A0) and ``max_sources``."""
    return source_strengths(params, sources, strength,
                            lambda c, key: number(c, key, 0.0, MAX_STRENGTH, lo_open=True), each="release rate A0")


def _kept_nodes(space: LatticeSpace, params: dict) -> list:
    """Node indices that must share a cluster of links: every source, then the entry."""
    ends = params["sources"] if params.get("sources") is not None else [params["source"]]
    if params.get("entry") is not None:
        ends = [*ends, params["entry"]]
    return [int(i) for i in space.index_of(ends)]


def _check(params: dict) -> dict:
    check_keys(params, LATTICE_KEYS, "lattice world parameter")
    out = dict(params)
    out["radius"] = _number(params, "radius", 9, MIN_RADIUS, MAX_RADIUS,
                            f"a lattice radius R0 in [{MIN_RADIUS}, {MAX_RADIUS}]")
    out["p"] = _number(params, "p", 0.35, 0.0, PERCOLATION_THRESHOLD,
                       "a fraction of missing links in [0, 0.5) (below the percolation threshold 1/2)",
                       hi_open=True)
    out["strength"] = _number(params, "strength", 12.0, 0.0, MAX_STRENGTH,
                              f"a release rate A0 in (0, {MAX_STRENGTH:g}]", lo_open=True)
    out["slip"] = _number(params, "slip", 0.04, 0.0, 1.0, "a probability p_e in [0, 1)", hi_open=True)
    space = LatticeSpace(out["radius"])
    sources = _sources(space, params)
    out["source"] = _node(space, params.get("source") if sources is None else sources[0], "source", transient=True)
    out.update(_several(params, sources, out["strength"]))
    if params.get("entry") is not None:
        out["entry"] = _node(space, params["entry"], "entry", transient=False)
    out["primary"] = _pair(params, "primary", (1.0, 0.0))
    out["secondary"] = _pair(params, "secondary", (0.8, 0.1))
    conn = params.get("connectivity", "all")
    if conn not in ("all", "nodes"):
        raise SearchError(f"connectivity must be 'all' (every node inside R0 connected) or 'nodes' "
                          f"(source and entry connected); got {conn!r}")
    out["connectivity"] = conn
    ls = params.get("lattice_seed")
    if ls is not None and (isinstance(ls, bool) or not isinstance(ls, int) or ls < 0):
        raise SearchError(f"lattice_seed must be a non-negative whole number (one lattice for every "
                          f"episode, as the paper's Fig. 2) or null (a lattice per episode); got {ls!r}")
    out["lattice_seed"] = ls
    mp = params.get("map", "unknown")
    if mp not in ("unknown", "known"):
        raise SearchError(f"map must be 'unknown' (the searcher knows only the complete lattice, the "
                          f"paper) or 'known' (it is told which links exist); got {mp!r}")
    out["map"] = mp
    loc = params.get("localisation", "unknown")
    if loc not in ("unknown", "known"):
        raise SearchError(f"localisation must be 'unknown' (the searcher estimates its own node, the paper) or "
                          f"'known' (each reading carries the true node: an oracle); got {loc!r}")
    out["localisation"] = loc
    links = params.get("links")
    if links is not None:
        if ls is not None:
            raise SearchError("give either links (one lattice from a file) or lattice_seed (one drawn lattice), "
                              "not both")
        present = lattice_links(links, space)
        lab = clusters(space.with_links(present))
        if len({int(lab[i]) for i in _kept_nodes(space, out)}) != 1:
            what = "the sources and the entry are" if sources is not None else "the source and the entry are"
            raise SearchError(f"links {links!r}: {what} not connected on that lattice")
        out["links"] = str(links)
    return out


#: Folder of the built-in lattices (``links: NAME``).
LATTICES = "lattices"


def lattice_links(name: str, space: LatticeSpace) -> np.ndarray:
    """The links mask of a built-in lattice (``reciprocity/data/lattices/NAME.npz``) or of an
    ``.npz`` file with a boolean array ``present`` of one entry per link of `space`."""
    import zipfile
    from importlib import resources
    from pathlib import Path
    if not isinstance(name, str) or not name:
        raise SearchError(f"links must be a built-in lattice name or an .npz file; got {name!r}")
    builtin = resources.files("reciprocity") / "data" / LATTICES / f"{name}.npz"
    path = Path(str(builtin)) if builtin.is_file() else Path(name)
    if path.suffix != ".npz" or not path.is_file():
        folder = resources.files("reciprocity") / "data" / LATTICES
        names = sorted(p.name[:-4] for p in folder.iterdir() if p.name.endswith(".npz")) if folder.is_dir() else []
        raise SearchError(f"links {name!r} is neither a built-in lattice ({', '.join(names)}) nor an .npz file")
    if path.stat().st_size > 1_000_000:
        raise SearchError(f"links file {name!r} is larger than 1 MB; a lattice's links mask is a few kB")
    try:
        with np.load(path, allow_pickle=False) as data:
            present = np.asarray(data["present"])
    except (OSError, ValueError, KeyError, zipfile.BadZipFile) as exc:
        raise SearchError(f"links file {name!r} is not an .npz with a boolean array 'present': {exc}") from None
    if present.dtype != bool or present.shape != (len(space.links),):
        raise SearchError(f"links file {name!r}: 'present' must be {len(space.links)} booleans (the links of "
                          f"R0 = {space.radius:g}); got {present.dtype} of shape {present.shape}")
    return present


def _build(params: dict, rng: np.random.Generator) -> LatticeWorld:
    full = LatticeSpace(params["radius"])
    keep = _kept_nodes(full, params)
    if params.get("links") is not None:               # one lattice from a file (the paper's Fig. 2)
        present, draws = lattice_links(params["links"], full), 0
    else:
        if params.get("lattice_seed") is not None:    # one drawn lattice for all episodes
            rng = np.random.default_rng(np.random.SeedSequence([int(params["lattice_seed"]), 0x1A77]))
        present, draws = draw_links(full, params["p"], rng, connectivity=params["connectivity"], keep=tuple(keep))
    return LatticeWorld(full.with_links(present), params["source"], params["strength"],
                        primary=params["primary"], secondary=params["secondary"], p=params["p"],
                        slip=params["slip"], draws=draws, map_known=params.get("map") == "known",
                        localisation_known=params.get("localisation") == "known", sources=params.get("sources"),
                        strengths=params.get("strengths"), max_sources=params.get("max_sources"))


def _starts_on_lattice(params: dict, starts: np.ndarray) -> None:
    """Refuse starts that are not nodes of the lattice of `params` (before any draw)."""
    space = LatticeSpace(params["radius"])
    for s in starts:
        if int(space.index_of(s[:2])[0]) < 0:
            raise SearchError(f"start ({s[0]:g}, {s[1]:g}) is not a lattice node (integers, "
                              f"x² + y² < (R0 + 1)², R0 = {space.radius:g})")


def _check_start(world: LatticeWorld, scenario) -> None:
    starts = scenario.starts if scenario is not None and scenario.starts is not None else None
    if starts is None:
        return
    lab = connected_components(world.space.adjacency, directed=False)[1]
    for s in starts:
        i = int(world.space.index_of(s[:2])[0])
        if i < 0:
            raise SearchError(f"start ({s[0]:g}, {s[1]:g}) is not a lattice node (integers, "
                              f"x² + y² < (R0 + 1)², R0 = {world.space.radius:g})")
        if lab[i] != lab[world.source_node]:
            raise SearchError(f"start ({s[0]:g}, {s[1]:g}) is cut off from the source in this lattice; "
                              "give the world the same entry: [x, y] so the draw keeps them connected")


def _lattice(world: LatticeWorld, scenario, options: dict):
    from ..platforms.lattice import LatticePlatform
    if options:
        raise SearchError(f"unknown lattice-platform option(s) {', '.join(sorted(options))}; "
                          "it has none (p_e is the world's slip)")
    _check_start(world, scenario)
    return LatticePlatform(world.space, slip=world.slip)


def _walker(world: LatticeWorld, scenario, options: dict):
    from ..platforms.walker import WalkerPlatform
    if options:
        raise SearchError(f"unknown walker option(s) {', '.join(sorted(options))}; it has none here")
    _check_start(world, scenario)
    return WalkerPlatform(world.space, slip=world.slip)


def _default_start(world: LatticeWorld, rng: np.random.Generator) -> np.ndarray:
    lab = connected_components(world.space.adjacency, directed=False)[1]
    ring = np.flatnonzero(~world.space.transient & (lab == lab[world.source_node]))
    p = world.space.points[ring[rng.integers(ring.size)]]
    return np.array([p[0], p[1], 0.0])


LATTICE = register_world(WorldKind("lattice", _check, _build, {"lattice": _lattice, "walker": _walker},
                                   _default_start, _starts_on_lattice))
