"""Scenarios: a world kind and its parameters, by name or from a YAML file.

A scenario file is YAML (safe-loaded)::

    description: the paper arena with walls 2 mm off and a 20 % stronger source
    world: poisson            # the world kind: poisson, lattice, plume, filament, flow, ...
    arena: paper              # ... then that world's own parameters; a generated arena is
                              # {generate: rooms, seed: 3} (+ size keys, see arenas.generate)
    source: [70.21, 70.21]
    noise: 12
    mismatch: {strength_factor: 1.2, wall_shift: 0.2}
    platform: point           # the default platform (point | car | walker)
    start: [128, 12, 135]     # x, y[, heading in degrees]; one per agent for several
    success_radius: 5         # a converged estimate this close succeeds
    max_steps: 300            # step cap of the episode (optional)

Every built-in arena is a ``poisson`` scenario of its own name; the other built-ins are
the files of ``reciprocity/data/scenarios``. World kinds are registered with
:func:`register_world`, which says how to validate parameters (cheaply), build a world
(from a seed, for worlds with random parts), and build each platform they support.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from importlib import resources
from pathlib import Path
from typing import Callable

import math
from numbers import Real

import numpy as np
import arenas
from arenas.families import PREFIX as GENERATED
from arenas.files import load_yaml
from arenas.poses import pose_from_degrees

from .errors import SearchError
from .registry import LazyRegistry
from .seeds import EpisodeSeeds
from .validation import MAX_AGENTS, MAX_COORD, number, whole

__all__ = ["Scenario", "WorldKind", "WORLD_KINDS", "check_keys", "register_world", "load_scenario",
           "scenario_names", "scenario_description"]

#: Keys every scenario file may have; the rest are the world's own parameters.
COMMON_KEYS = ("name", "description", "world", "platform", "start", "success_radius",
               "max_steps", "agents")
#: Largest step cap of one episode.
MAX_STEPS = 1_000_000


@dataclass(frozen=True)
class WorldKind:
    """How to make worlds of one kind.

    Attributes
    ----------
    name : str
        The ``world:`` value of scenario files.
    check : callable
        ``check(params) -> params``: validate and normalise the world's parameters
        cheaply (no meshing or solving); raise SearchError with a one-line message.
    build : callable
        ``build(params, rng) -> World``; `rng` draws the world's random parts.
    platforms : dict
        Platform name -> ``factory(world, scenario, options) -> Platform``.
    default_start : callable, optional
        ``default_start(world, rng) -> (3,)`` pose when the scenario gives none.
    check_start : callable, optional
        ``check_start(params, starts)``: refuse start poses (n, 3) outside the world that
        `params` (checked) describe, cheaply, before any world is built.
    check_observers : callable, optional
        ``check_observers(params, n)``: refuse a world that cannot be what `params` says
        with `n` observers (e.g. a sensor fault given to an observer the run does not have).
    """

    name: str
    check: Callable
    build: Callable
    platforms: dict
    default_start: Callable | None = None
    check_start: Callable | None = None
    check_observers: Callable | None = None


#: World kinds by name; a built-in kind's module is imported on first use of its name.
WORLD_KINDS: LazyRegistry = LazyRegistry("reciprocity.wiring", {
    "poisson": "POISSON", "lattice": "LATTICE", "plume": "PLUME", "filament": "FILAMENT", "flow": "FLOW"})

#: Built-in scenario files by name (filled by :func:`_scenario_files`).
_FILES: dict[str, object] = {}


def check_keys(params: dict, allowed, what: str) -> None:
    """Refuse parameters not in `allowed`, naming the valid ones (``what``: e.g.
    ``"plume world parameter"``)."""
    unknown = set(params) - set(allowed)
    if unknown:
        raise SearchError(f"unknown {what}(s) {', '.join(sorted(unknown))}; choose from {', '.join(allowed)}")


def register_world(kind: WorldKind) -> WorldKind:
    """Register a world kind (see :class:`WorldKind`)."""
    WORLD_KINDS[kind.name] = kind
    return kind


@dataclass
class Scenario:
    """A named world with its parameters (see the module doc for the file format).

    Attributes
    ----------
    name, description : str
    world : str
        World kind.
    params : dict
        The world's parameters (validated).
    platform : str
        Default platform.
    starts : ndarray, shape (n, 3) or None
        Start poses (x, y, heading rad); None: the world's default.
    success_radius : float
    max_steps : int or None
    agents : int
        Default number of observers.
    """

    name: str
    world: str
    params: dict = field(default_factory=dict)
    platform: str = "point"
    starts: np.ndarray | None = None
    success_radius: float = 5.0
    max_steps: int | None = None
    agents: int = 1
    description: str = ""

    @cached_property
    def kind(self) -> WorldKind:
        """The :class:`WorldKind` of :attr:`world` (looked up once per scenario)."""
        return WORLD_KINDS[self.world]

    @property
    def arena(self):
        """The scenario's arena (poisson worlds), else None."""
        return self.params.get("arena")

    def with_world(self, overrides: dict | None) -> "Scenario":
        """A copy with world parameters (and ``start``) overridden, validated.

        ``start`` is ``(x, y[, heading])`` with the heading in **radians**, like every angle
        of the Python API (scenario files write it in degrees).
        """
        if not overrides:
            return self
        over = dict(overrides)
        starts = self.starts
        if "start" in over:
            starts = _starts(over.pop("start"), f"scenario {self.name!r}", degrees=False)
        params = dict(self.params)
        # another arena brings its own source (the old one may lie in its walls)
        if over.get("arena") is not None and over.get("source") is None and over.get("sources") is None:
            for key in ("source", "sources", "strengths"):
                params.pop(key, None)
        # one source given replaces several, and several replace one (with their strengths)
        if over.get("source") is not None:
            params.pop("sources", None)
            params.pop("strengths", None)
        if over.get("sources") is not None:
            params.pop("source", None)
        params.update(over)
        kind = self.kind
        params = kind.check(params)
        _check_starts(kind, params, starts, f"scenario {self.name!r}")
        return Scenario(self.name, self.world, params, self.platform, starts,
                        self.success_radius, self.max_steps, self.agents, self.description)

    def with_limits(self, *, max_steps=None, success_radius=None) -> "Scenario":
        """A copy with the scenario's round budget and success radius replaced (None: kept),
        bounded as in scenario files."""
        from dataclasses import replace
        pre = f"scenario {self.name!r}: "
        out = self
        if max_steps is not None:
            out = replace(out, max_steps=whole(max_steps, "max_steps", 1, MAX_STEPS, where=pre))
        if success_radius is not None:
            out = replace(out, success_radius=number(success_radius, "success_radius", 0.0, MAX_COORD, where=pre,
                                                     lo_open=True))
        return out

    def check_observers(self, n: int) -> None:
        """Refuse running this scenario's world with `n` observers when its parameters
        need others (SearchError naming the key); cheap, before any world is built."""
        check = self.kind.check_observers
        if check is not None:
            try:
                check(self.params, n)
            except SearchError as exc:
                raise SearchError(f"scenario {self.name!r}: {exc}") from None

    def build_world(self, seed: int | EpisodeSeeds):
        """The world of an episode with seed `seed` (its random parts drawn from it), or
        with the seed tree `seed` an environment derived already."""
        seeds = seed if isinstance(seed, EpisodeSeeds) else EpisodeSeeds.from_seed(seed, 0)
        world = self.kind.build(self.params, seeds.rng(seeds.build))
        world.success_radius = self.success_radius
        return world

    def start_poses(self, world, n_agents: int, seed: int | EpisodeSeeds) -> np.ndarray:
        """Start poses (n_agents, 3): the scenario's (one pose shared by all agents, or the
        first `n_agents` of its list), else the world's default, drawn from episode `seed`
        (or its seed tree)."""
        if self.starts is not None:
            s = self.starts
            return np.array([s[min(k, len(s) - 1)] for k in range(n_agents)], dtype=float)
        default_start = self.kind.default_start
        if default_start is None:
            raise SearchError(f"scenario {self.name!r} has no start: give start: [x, y]")
        seeds = seed if isinstance(seed, EpisodeSeeds) else EpisodeSeeds.from_seed(seed, 0)
        rng = seeds.rng(seeds.starts)
        return np.array([default_start(world, rng) for _ in range(n_agents)], dtype=float)


def _starts(value, where: str, *, degrees: bool) -> np.ndarray:
    """Start poses (n, 3) from ``[x, y[, heading]]`` or a list of such, each number finite and
    coordinates within ±:data:`~reciprocity.validation.MAX_COORD`."""
    poses = value if isinstance(value, (list, tuple, np.ndarray)) and len(value) and isinstance(
        value[0], (list, tuple, np.ndarray)) else [value]
    ok = 1 <= len(poses) <= MAX_AGENTS and all(
        isinstance(p, (list, tuple, np.ndarray)) and len(p) in (2, 3) and all(
            isinstance(v, Real) and not isinstance(v, bool) and math.isfinite(float(v))
            and abs(float(v)) <= MAX_COORD for v in p) for p in poses)
    if not ok or len({len(p) for p in poses}) != 1:
        raise SearchError(f"{where}: start must be [x, y] or [x, y, heading_deg] (numbers within ±{MAX_COORD:g}), "
                          f"or a list of at most {MAX_AGENTS} of them; got {value!r}")
    arr = np.array(poses, dtype=float)
    if arr.shape[1] == 2:
        arr = np.column_stack([arr, np.zeros(len(arr))])
    elif degrees:
        arr = pose_from_degrees(arr)
    return arr


def _check_starts(kind: WorldKind, params: dict, starts, where: str) -> None:
    """Refuse start poses outside the world (the kind's own check)."""
    if starts is not None and kind.check_start is not None:
        try:
            kind.check_start(params, starts)
        except SearchError as exc:
            raise SearchError(f"{where}: {exc}") from None


def _scenario_files() -> dict:
    if not _FILES:
        folder = resources.files("reciprocity") / "data" / "scenarios"
        # by name, so that a scenario comes before its variants (hajieghrary, hajieghrary-dead-sensor)
        for entry in sorted(folder.iterdir(), key=lambda e: e.name.removesuffix(".yaml")):
            if entry.name.endswith(".yaml"):
                _FILES[entry.name[:-5]] = entry
    return _FILES


def scenario_names() -> list[str]:
    """Names of the built-in scenarios: every built-in arena, then the scenario files."""
    return list(arenas.builtin_names()) + [n for n in _scenario_files() if n not in arenas.builtin_names()]


def scenario_description(name: str) -> str:
    """One line describing a built-in scenario."""
    if name in _scenario_files():
        return str(_read(_FILES[name], name).get("description", ""))
    return arenas.builtin_description(name)


def _read(src, label: str) -> dict:
    """The mapping of a scenario file, or of a plain arena file as a ``poisson`` scenario."""
    data = load_yaml(src, f"scenario file {label!r}", error=SearchError)
    if isinstance(data, dict) and "world" not in data and ("boundary" in data or "disk" in data):
        return _arena_scenario(data, src, label)
    if arenas.is_ros_map(data) and "world" not in data and isinstance(src, Path):
        try:                                  # a ROS map_server map: an arena, its image beside it
            arena = arenas.load(src)
        except arenas.ArenaError as exc:
            raise SearchError(str(exc)) from None
        return {"world": "poisson", "arena": arena, "name": arena.name,
                "description": str(data.get("description", f"ROS map {label}"))}
    if not isinstance(data, dict) or "world" not in data:
        raise SearchError(f"scenario file {label!r} must be a mapping with a 'world:' kind "
                          f"({', '.join(WORLD_KINDS)}), or an arena file with 'boundary:' or 'disk:'")
    return data


def _arena_scenario(data: dict, src, label: str) -> dict:
    """A plain arena file (boundary, obstacles, source, strength, start) as a poisson scenario;
    its ``sources``, ``strengths`` and ``max_sources`` (several sources) are the world's."""
    arena = dict(data)
    name = str(arena.get("name") or Path(str(src)).stem)
    arena["name"] = name
    several = {key: arena.pop(key) for key in ("sources", "strengths", "max_sources") if key in arena}
    return {"world": "poisson", "arena": arena, "name": name,
            "description": str(arena.pop("description", f"arena file {label}")), **several}


def from_dict(data: dict, name: str = "scenario") -> Scenario:
    """A :class:`Scenario` from the mapping of a scenario file.

    The common keys are bounded: ``success_radius`` in (0, 1e5], ``max_steps`` from 1 to
    1e6, ``agents`` from 1 to 64, one start or one per agent, inside the world.
    """
    data = dict(data)
    where = f"scenario {name!r}"
    kind = data.pop("world")
    wk = WORLD_KINDS.get(kind) if isinstance(kind, str) else None      # one look-up
    if wk is None:
        raise SearchError(f"{where}: unknown world kind {kind!r}; choose one of {', '.join(WORLD_KINDS)}")
    common = {k: data.pop(k) for k in COMMON_KEYS if k in data}
    platform = common.get("platform", next(iter(wk.platforms)))
    if not isinstance(platform, str) or platform not in wk.platforms:
        raise SearchError(f"{where}: platform {platform!r} does not apply to {kind} worlds; "
                          f"choose one of {', '.join(wk.platforms)}")
    pre = f"{where}: "
    radius = number(common.get("success_radius", 5.0), "success_radius", 0.0, MAX_COORD, where=pre,
                    lo_open=True)
    cap = common.get("max_steps")
    cap = None if cap is None else whole(cap, "max_steps", 1, MAX_STEPS, where=pre)
    agents = whole(common.get("agents", 1), "agents", 1, MAX_AGENTS, where=pre)
    starts = _starts(common["start"], where, degrees=True) if common.get("start") is not None else None
    if starts is not None and 1 < len(starts) < agents:
        raise SearchError(f"{where}: start gives {len(starts)} poses for {agents} agents; give one pose "
                          "(shared) or one per agent")
    params = wk.check(data)
    _check_starts(wk, params, starts, where)
    text = {k: common.get(k, d) for k, d in (("name", name), ("description", ""))}
    for k, v in text.items():
        if not isinstance(v, (str, int, float)) or isinstance(v, bool):
            raise SearchError(f"{where}: {k} must be text; got {v!r}")
    return Scenario(str(text["name"]), kind, params, platform, starts, radius, cap, agents,
                    str(text["description"]))


def load_scenario(name_or_path, *, source=None) -> Scenario:
    """The built-in scenario `name_or_path`, one read from a YAML file, a generated arena
    ``generate:FAMILY[:SEED[:KEY=VALUE,...]]`` (:func:`arenas.generate`; the scenario is
    named after the arena, e.g. ``rooms-3``), or the poisson scenario of an
    :class:`arenas.Arena` (its source, strength and start).

    `source` ``(x, y)`` is the true source of a poisson file that gives none (an arena
    file or a ROS map without ``source:``; the command line's ``--source``); a file's own
    source is kept (override it with :meth:`Scenario.with_world`).

    Raises
    ------
    SearchError
        Unknown name, unreadable or malformed file, invalid parameters.
    """
    if isinstance(name_or_path, arenas.Arena):      # an arena built in Python: a poisson scenario
        return from_dict({"world": "poisson", "arena": name_or_path, "name": name_or_path.name})
    text = str(name_or_path)
    if text.startswith(GENERATED):                  # generate:FAMILY[:SEED[:KEY=VALUE,...]]
        try:
            arena = arenas.load(text)
        except arenas.ArenaError as exc:
            raise SearchError(f"{text}: {exc}") from None
        return from_dict({"world": "poisson", "arena": arena, "name": arena.name})
    if text in arenas.builtin_names():
        return from_dict({"world": "poisson", "arena": text, "name": text})
    if text in _scenario_files():
        return from_dict(_read(_FILES[text], text), text)
    path = Path(text)
    if not path.exists():
        raise SearchError(f"no built-in scenario or file named {text!r}; built-ins are "
                          f"{', '.join(scenario_names())} (or give the path of a YAML scenario file)")
    data = _read(path, text)
    if source is not None and data.get("world") == "poisson" and not {"source", "sources"} & set(data):
        arena = data.get("arena")
        if isinstance(arena, arenas.Arena):
            told = arena.source
        else:
            told = arena.get("source") if isinstance(arena, dict) else None
        if told is None:
            data["source"] = [float(v) for v in source]
    return from_dict(data, path.stem)
