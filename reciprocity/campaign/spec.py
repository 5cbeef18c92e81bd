"""Campaign specifications: which strategies, scenarios, platform and seeds to run.

A specification is a YAML mapping, read strictly (:func:`arenas.files.load_yaml`: a size
cap, duplicate keys refused)::

    name: paper-vs-maze            # optional; default: the file's stem
    seed: 2026                     # campaign seed (default 0); --seed overrides it
    seeds: 20                      # episodes per (scenario, strategy variant)
    platform: point                # point | car | omitted: the scenario's default
    platform_options:              # optional: options of that platform, e.g. the car's
      planner: bank                # (reciprocity.platforms.car.CAR_KEYS); needs platform
    agents: 3                      # optional: number of observers
    random_source: true            # optional: draw source and start per seed (see below)
    pairs: supported               # optional: run only the (scenario, strategy) pairs that
                                   # apply (default: every pair, and an unsupported one is an error),
                                   # or a list [[scenario label, variant label], ...]: only those
    strategies: [reciprocity, gradient]
    #   or a mapping name -> {parameter: value or [grid values]}:
    #   strategies:
    #     reciprocity: {eps: [0.05, 0.1], h: 4.0}   # two variants
    #     gradient: {}
    scenarios:
      - paper                      # a built-in name or a YAML file (relative to the spec)
      - name: maze
        label: maze-noisy          # optional: the name used in results (default: the name)
        world: {noise: 20}         # optional: overrides of the world (mismatch options);
                                   # start: [x, y, heading] with the heading in degrees,
                                   # as in scenario files
        random_source: false       # optional: per scenario
      - name: farrell
        random_start: true         # optional: ignore the scenario's start (see below)
      - my_arena.yaml              # a plain arena file (boundary, obstacles, source, ...)
      - generate:rooms:3           # a generated arena (arenas.generate), labelled rooms-3;
                                   # generate:maze:7:cols=6,rows=6 sets size keys
    scheduler:                     # optional: a running Dask scheduler (see
      address: tls://10.0.0.5:8786 # reciprocity.campaign.cluster); --workers or
      tls:                         # --scheduler on the command line win
        ca_file: ca.pem            # files relative to the spec
        cert: client.pem
        key: client.key

Bounds, checked when the spec is parsed: ``seeds`` from 1 to :data:`MAX_SEEDS`,
``seed`` from 0 to 2**63 - 1, ``agents`` from 1 to :data:`MAX_AGENTS`, at most
:data:`MAX_PAIRS` (scenario, strategy variant) pairs and :data:`MAX_EPISODES` episodes.
The whole spec is validated before the first episode: every scenario is loaded and
checked with every strategy variant and the platform (:func:`reciprocity.api.check`;
nothing is meshed or solved).

A list value in a strategy mapping is a grid axis: the variants are the cartesian
product of all axes (to pass a list as a single value, wrap it: ``[[1, 2]]``).

``random_source: true`` (arena scenarios): every seed index draws the true source at
least :data:`SOURCE_CLEARANCE` cm from the walls (a scenario with ``sources`` draws as
many, :data:`SOURCE_SEPARATION` cm apart) and the start at least
:data:`START_CLEARANCE` cm from them with a uniform heading, from a stream derived from
the episode seed, so all strategies of a scenario meet the same world on the same seed.

``random_start: true`` (per scenario, any world kind with a default start): the
scenario's ``start`` is dropped, so every episode starts where the world kind's
``default_start(world, rng)`` puts it, drawn from the episode seed
(:meth:`reciprocity.scenarios.Scenario.start_poses`): all strategies of a scenario start
from the same place on the same seed index, a new place on every index.
"""

from __future__ import annotations

import dataclasses
import hashlib
import inspect
import itertools
import json
import math
import re
from collections.abc import Iterator, Mapping
from numbers import Real
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from arenas.families import PREFIX as GENERATED
from arenas.files import load_yaml, read_text
from arenas.poses import pose_from_degrees

from ..errors import SearchError
from ..validation import MAX_AGENTS
from ..scenarios import Scenario, load_scenario, scenario_names
from .cluster import TLSFiles, check_address

__all__ = ["CampaignSpec", "ScenarioEntry", "StrategyVariant", "EpisodeTask", "load_spec",
           "parse_spec", "episode_seed", "entry_scenario", "world_overrides", "SOURCE_CLEARANCE",
           "START_CLEARANCE", "MAX_SEEDS", "MAX_SEED", "MAX_EPISODES", "MAX_PAIRS", "MAX_AGENTS",
           "LABEL"]

#: Minimum wall distance of a drawn source, cm: closer to a Dirichlet wall the signal is
#: buried in the noise everywhere.
SOURCE_CLEARANCE = 8.0
#: Minimum wall distance of a drawn start, cm.
START_CLEARANCE = 5.0
#: Minimum distance between drawn sources of a scenario with several (``sources``), cm:
#: "well separated" in the sense of the issue that asked for them.
SOURCE_SEPARATION = 40.0

#: Most seeds (episodes per scenario and strategy variant); also ``reproduce --runs``.
MAX_SEEDS = 100_000
#: Most episodes of one campaign (seeds x variants x scenarios).
MAX_EPISODES = 1_000_000
#: Most (scenario, strategy variant) pairs: each is checked before the first episode.
MAX_PAIRS = 10_000
#: Largest campaign seed.
MAX_SEED = 2**63 - 1

_TOP_KEYS = {"name", "seed", "seeds", "platform", "platform_options", "agents", "random_source",
             "strategies", "scenarios", "pairs", "scheduler"}
_SCENARIO_KEYS = {"name", "label", "world", "random_source", "random_start"}
_SCHEDULER_KEYS = {"address", "tls"}
_TLS_KEYS = ("ca_file", "cert", "key")
#: What campaign names, scenario labels (and so partition folder names) look like.
LABEL = re.compile(r"^[A-Za-z][A-Za-z0-9_.+-]*$")


@dataclass(frozen=True)
class StrategyVariant:
    """One point of a strategy's parameter grid.

    Attributes
    ----------
    strategy : str
        Strategy name (a key of :data:`reciprocity.strategies.STRATEGIES`).
    params : dict
        Parameter values of this variant.
    label : str
        ``name`` alone, or ``name[k=v,...]`` with the grid axes' values.
    """

    strategy: str
    params: dict
    label: str


@dataclass(frozen=True)
class ScenarioEntry:
    """A scenario of the campaign.

    Attributes
    ----------
    ref : str
        Built-in scenario name, or the absolute path of a scenario file.
    label : str
        The name under which results are stored (``scenario`` column, partition).
    world : dict
        Overrides of the world's parameters passed to :func:`reciprocity.api.run`.
    random_source : bool
        Draw the true source and start per seed index.
    file_digest : str or None
        SHA-256 of the scenario file (None for a built-in), part of the spec hash.
    random_start : bool
        Drop the scenario's start: the world kind's default start, drawn per episode seed.
    """

    ref: str
    label: str
    world: dict
    random_source: bool
    file_digest: str | None = None
    random_start: bool = False


@dataclass(frozen=True)
class EpisodeTask:
    """Everything a worker needs to run one episode (small; pickled into a Dask task).

    Attributes
    ----------
    campaign : str
        Campaign name.
    episode_id : str
        ``scenario/variant/seed_index``, unique in a campaign.
    scenario : ScenarioEntry
        The scenario.
    variant : StrategyVariant
        The strategy and its parameters.
    platform, agents
        As in the spec (None: the scenario's or strategy's default).
    seed_index : int
        Index of the seed, 0 ... seeds - 1.
    seed : int
        Episode seed, from :func:`episode_seed`.
    platform_options : dict, optional
        The platform's options (the spec's ``platform_options``; None: its defaults).
    """

    campaign: str
    episode_id: str
    scenario: ScenarioEntry
    variant: StrategyVariant
    platform: str | None
    agents: int | None
    seed_index: int
    seed: int
    platform_options: dict | None = None


def episode_seed(campaign_seed: int, seed_index: int) -> int:
    """The integer seed of every episode with seed index `seed_index`.

    It depends only on the campaign seed and the index, never on the worker or the
    order of execution; all strategies and scenarios share it (paired comparisons).

    Parameters
    ----------
    campaign_seed : int
        The campaign's seed (non-negative).
    seed_index : int
        Index of the episode's seed, 0 ... seeds - 1.

    Returns
    -------
    int
        A seed in [0, 2**63).

    Examples
    --------
    >>> episode_seed(0, 3) == episode_seed(0, 3) != episode_seed(1, 3)
    True
    """
    ss = np.random.SeedSequence(campaign_seed, spawn_key=(seed_index,))
    return int(ss.generate_state(1, dtype=np.uint64)[0] >> np.uint64(1))


@dataclass(frozen=True)
class CampaignSpec:
    """A validated campaign: strategy variants × scenarios × seeds.

    Attributes
    ----------
    name : str
        Campaign name (the ``campaign`` column).
    seed : int
        Campaign seed.
    seeds : int
        Episodes per (scenario, variant).
    platform : str or None
        Observer platform; None: each scenario's default.
    agents : int or None
        Number of observers; None: each strategy's default.
    variants : tuple of StrategyVariant
    scenarios : tuple of ScenarioEntry
    source : dict
        The normalized specification (what :attr:`digest` hashes), JSON-compatible.
    skip : frozenset
        (scenario label, variant label) pairs not run (``pairs: supported``).
    scheduler : str or None
        Address of the Dask scheduler to run on by default (not part of the digest:
        where episodes run does not change them).
    tls : TLSFiles or None
        Client certificate for a ``tls://`` `scheduler`.
    platform_options : dict or None
        Options of `platform` (the car's :data:`~reciprocity.platforms.car.CAR_KEYS`, the
        point observer's ``dwell``, ``route_h``); None: its defaults.
    """

    name: str
    seed: int
    seeds: int
    platform: str | None
    agents: int | None
    variants: tuple[StrategyVariant, ...]
    scenarios: tuple[ScenarioEntry, ...]
    source: dict = field(repr=False)
    skip: frozenset = frozenset()
    scheduler: str | None = None
    tls: TLSFiles | None = None
    platform_options: dict | None = None

    @property
    def n_episodes(self) -> int:
        """Number of episodes of the campaign."""
        return self.seeds * (len(self.variants) * len(self.scenarios) - len(self.skip))

    @property
    def digest(self) -> str:
        """SHA-256 of the normalized spec without ``seeds`` (so a campaign may grow).

        Two specs with the same digest produce the same row for the same episode id.
        """
        body = {k: v for k, v in self.source.items() if k != "seeds"}
        return hashlib.sha256(json.dumps(body, sort_keys=True).encode()).hexdigest()

    def tasks(self) -> Iterator[EpisodeTask]:
        """All episodes, lazily: per scenario, per seed index, every variant in turn.

        The variants of one seed come together, so the pairs of a paired comparison
        finish close in time.
        """
        for sc in self.scenarios:
            for i in range(self.seeds):
                seed = episode_seed(self.seed, i)
                for v in self.variants:
                    if (sc.label, v.label) in self.skip:
                        continue
                    yield EpisodeTask(self.name, f"{sc.label}/{v.label}/{i}", sc, v,
                                      self.platform, self.agents, i, seed, self.platform_options)


def load_spec(path, *, seed: int | None = None) -> CampaignSpec:
    """Read and validate a campaign spec file.

    Parameters
    ----------
    path : str or os.PathLike
        YAML file.
    seed : int, optional
        Overrides the spec's campaign seed.

    Returns
    -------
    CampaignSpec

    Raises
    ------
    SearchError
        Unreadable, binary or too large file, malformed YAML or duplicate keys, or an
        invalid spec (see :func:`parse_spec`).
    """
    p = Path(path)
    data = load_yaml(p, f"campaign spec {str(p)!r}", error=SearchError)
    if not isinstance(data, Mapping):
        raise SearchError(f"campaign spec {str(p)!r} must be a YAML mapping with strategies, "
                          "scenarios and seeds")
    data = dict(data)
    data.setdefault("name", p.stem)
    if seed is not None:
        data["seed"] = seed
    return parse_spec(data, base_dir=p.parent)


def parse_spec(data: Mapping, *, base_dir=None) -> CampaignSpec:
    """Validate a spec mapping (the parsed YAML) without running anything heavy.

    Every (scenario, variant) pair is checked with :func:`reciprocity.api.check`.

    Parameters
    ----------
    data : Mapping
        The specification (see the module docstring).
    base_dir : path-like, optional
        Folder that relative scenario files are resolved against (default: the
        current directory).

    Returns
    -------
    CampaignSpec

    Raises
    ------
    SearchError
        One line saying what is wrong: unknown key, strategy, scenario or parameter,
        an empty grid, a number out of its bounds, a strategy that does not apply to a
        scenario's world, a scenario that does not load, ...
    """
    if not isinstance(data, Mapping):
        raise SearchError("a campaign spec must be a mapping with strategies, scenarios and seeds")
    unknown = sorted(set(map(str, data)) - _TOP_KEYS)
    if unknown:
        raise SearchError(f"unknown campaign spec key(s) {', '.join(map(repr, unknown))}; "
                          f"allowed: {', '.join(sorted(_TOP_KEYS))}")
    for key in ("strategies", "scenarios", "seeds"):
        if key not in data:
            raise SearchError(f"the campaign spec needs {key!r}")
    base = Path(base_dir or ".")
    name = _label(data.get("name", "campaign"), "campaign name")
    seed = _int(data.get("seed", 0), "seed", 0, MAX_SEED)
    seeds = _int(data["seeds"], "seeds", 1, MAX_SEEDS)
    platform = data.get("platform")
    if platform is not None and not isinstance(platform, str):
        raise SearchError(f"platform must be a name (point, car, walker, ...); got {platform!r}")
    platform_options = _platform_options(data.get("platform_options"), platform)
    agents = None if data.get("agents") is None else _int(data["agents"], "agents", 1, MAX_AGENTS)
    random_source = _bool(data.get("random_source", False), "random_source")
    scheduler, tls = _scheduler(data.get("scheduler"), base)
    variants = _variants(data["strategies"])
    _bounded_size(seeds, len(variants), data["scenarios"])
    scenarios = _scenarios(data["scenarios"], random_source, base)
    pairs = data.get("pairs", "all")
    only = _only_pairs(pairs, scenarios, variants) if isinstance(pairs, list) else None
    if only is None and pairs not in ("all", "supported"):
        raise SearchError("pairs must be 'all', 'supported' or a list of [scenario label, variant label] "
                          f"pairs; got {pairs!r}")
    if only is not None:
        scenarios = [s for s in scenarios if any(s.label == p[0] for p in only)]
        variants = [v for v in variants if any(v.label == p[1] for p in only)]
    skip = _check_pairs(scenarios, variants, platform, agents, supported_only=pairs == "supported",
                        platform_options=platform_options)
    if only is not None:
        skip |= {(s.label, v.label) for s in scenarios for v in variants} - only
    source = dict(name=name, seed=seed, seeds=seeds, platform=platform, agents=agents,
                  strategies={v.label: {"strategy": v.strategy, "params": v.params}
                              for v in variants},
                  scenarios=[dict(ref=s.ref, label=s.label, world=s.world,
                                  random_source=s.random_source, file_digest=s.file_digest,
                                  # only when set: the hashes of earlier campaigns stay valid
                                  **({"random_start": True} if s.random_start else {}))
                             for s in scenarios],
                  **({"pairs": "supported"} if pairs == "supported" else {}),
                  # only when set: the hashes of earlier campaigns stay valid
                  **({"platform_options": platform_options} if platform_options else {}),
                  **({"pairs": sorted(map(list, only))} if only is not None else {}))
    _jsonable(source)
    return CampaignSpec(name, seed, seeds, platform, agents, tuple(variants), tuple(scenarios),
                        source, frozenset(skip), scheduler, tls, platform_options or None)


def _platform_options(value, platform: str | None) -> dict:
    """The spec's ``platform_options``: a mapping of option names to plain values, given
    only with ``platform`` (each option is checked with every scenario, by the platform)."""
    if value is None:
        return {}
    if platform is None:
        raise SearchError("platform_options needs platform (point, car, ...): options belong to one platform")
    if not isinstance(value, Mapping) or not all(isinstance(k, str) for k in value):
        raise SearchError(f"platform_options must be a mapping of option names to values; got {value!r}")
    return dict(value)


def _only_pairs(pairs: list, scenarios, variants) -> set[tuple[str, str]]:
    """The pairs of a ``pairs: [[scenario label, variant label], ...]`` list, checked
    against the spec's labels."""
    labels = {s.label for s in scenarios}
    names = {v.label for v in variants}
    out = set()
    for p in pairs:
        if not (isinstance(p, list) and len(p) == 2 and all(isinstance(x, str) for x in p)):
            raise SearchError(f"each entry of pairs must be [scenario label, variant label]; got {p!r}")
        if p[0] not in labels:
            raise SearchError(f"pairs names scenario {p[0]!r}; the spec's scenarios are "
                              f"{', '.join(sorted(labels))}")
        if p[1] not in names:
            raise SearchError(f"pairs names strategy variant {p[1]!r}; the spec's variants are "
                              f"{', '.join(sorted(names))}")
        out.add((p[0], p[1]))
    if not out:
        raise SearchError("pairs is an empty list; name at least one [scenario label, variant label] pair")
    return out


def _int(value, what: str, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        raise SearchError(f"{what} must be a whole number from {lo} to {hi}; got {value!r}")
    return value


def _bounded_size(seeds: int, n_variants: int, scenarios) -> None:
    """Refuse a campaign too large to check or run, before loading its scenarios."""
    n_scenarios = len(scenarios) if isinstance(scenarios, list) else 1
    if n_variants * n_scenarios > MAX_PAIRS:
        raise SearchError(f"the campaign has {n_variants} strategy variants x {n_scenarios} "
                          f"scenarios = {n_variants * n_scenarios} pairs; at most {MAX_PAIRS} "
                          "are allowed (shrink the parameter grids)")
    if seeds * n_variants * n_scenarios > MAX_EPISODES:
        raise SearchError(f"the campaign has {seeds} seeds x {n_variants} strategy variants x "
                          f"{n_scenarios} scenarios = {seeds * n_variants * n_scenarios} episodes; "
                          f"at most {MAX_EPISODES} are allowed")


def _scheduler(value, base_dir: Path) -> tuple[str | None, TLSFiles | None]:
    """The spec's ``scheduler``: an address, or ``{address: ..., tls: {ca_file, cert, key}}``."""
    if value is None:
        return None, None
    if isinstance(value, str):
        value = {"address": value}
    if not isinstance(value, Mapping) or "address" not in value:
        raise SearchError("scheduler must be an address (tls://HOST:PORT) or a mapping "
                          f"{{address: ..., tls: {{ca_file: ..., cert: ..., key: ...}}}}; got {value!r}")
    unknown = sorted(set(map(str, value)) - _SCHEDULER_KEYS)
    if unknown:
        raise SearchError(f"unknown key(s) {', '.join(map(repr, unknown))} in scheduler; "
                          f"allowed: {', '.join(sorted(_SCHEDULER_KEYS))}")
    address = check_address(value["address"])
    tls = value.get("tls")
    if tls is None:
        return address, None
    if not isinstance(tls, Mapping) or set(map(str, tls)) != set(_TLS_KEYS) or not all(
            isinstance(tls[k], str) and tls[k] for k in _TLS_KEYS):
        raise SearchError(f"scheduler tls must be a mapping of the files {', '.join(_TLS_KEYS)} "
                          f"(paths relative to the spec); got {tls!r}")
    return address, TLSFiles(*(str(base_dir / tls[k]) for k in _TLS_KEYS))


def _bool(value, what: str) -> bool:
    if not isinstance(value, bool):
        raise SearchError(f"{what} must be true or false; got {value!r}")
    return value


def _label(value, what: str) -> str:
    if not isinstance(value, str) or not LABEL.match(value):
        raise SearchError(f"{what} must start with a letter and hold only letters, digits and "
                          f"_ . + -; got {value!r}")
    return value


def _jsonable(source: dict) -> None:
    try:
        json.dumps(source)
    except TypeError as exc:
        raise SearchError(f"campaign spec values must be numbers, strings, booleans, lists or "
                          f"mappings: {exc}") from None


def _variants(strategies) -> list[StrategyVariant]:
    from ..strategies import STRATEGIES
    if isinstance(strategies, str):
        strategies = [strategies]
    if isinstance(strategies, list):
        if not all(isinstance(s, str) for s in strategies):
            raise SearchError(f"strategies must be a list of names; got {strategies!r}")
        dup = sorted({s for s in strategies if strategies.count(s) > 1})
        if dup:
            raise SearchError(f"strategy {', '.join(map(repr, dup))} is listed twice in the "
                              "campaign spec; list each once (a grid gives several variants)")
        strategies = {s: {} for s in strategies}
    if not isinstance(strategies, Mapping) or not strategies:
        raise SearchError("strategies must be a non-empty list of names or a mapping "
                          "name -> {parameter: value or [grid values]}")
    grids = []
    for name, params in strategies.items():
        if name not in STRATEGIES:
            raise SearchError(f"unknown strategy {name!r} in the campaign spec; choose from "
                              f"{', '.join(STRATEGIES)}")
        params = params or {}
        if not isinstance(params, Mapping):
            raise SearchError(f"parameters of strategy {name!r} must be a mapping "
                              f"parameter -> value or [grid values]; got {params!r}")
        _check_param_names(name, STRATEGIES[name], params)
        axes = {k: v for k, v in params.items() if isinstance(v, list)}
        for k, v in axes.items():
            if not v:
                raise SearchError(f"empty grid: strategy {name!r} parameter {k!r} lists no values")
        grids.append((name, {k: v for k, v in params.items() if k not in axes}, axes))
    n = sum(math.prod(len(v) for v in axes.values()) for _, _, axes in grids)
    if n > MAX_PAIRS:
        raise SearchError(f"the strategy grids give {n} variants; at most {MAX_PAIRS} are "
                          "allowed (shrink the grids)")
    out = []
    for name, fixed, axes in grids:
        for combo in itertools.product(*axes.values()):
            grid = dict(zip(axes, combo))
            label = name if not grid else name + "[" + ",".join(
                f"{k}={_short(v)}" for k, v in grid.items()) + "]"
            out.append(StrategyVariant(name, {**fixed, **grid}, label))
    labels = [v.label for v in out]
    dup = sorted({x for x in labels if labels.count(x) > 1})
    if dup:
        raise SearchError(f"strategy variant(s) {', '.join(dup)} appear twice: a grid lists a "
                          "value twice; list each value once")
    return out


def _short(value) -> str:
    return json.dumps(value, separators=(",", ":")).replace('"', "")


def _check_param_names(name: str, cls, params: Mapping) -> None:
    sig = inspect.signature(cls.__init__)
    if any(p.kind is p.VAR_KEYWORD for p in sig.parameters.values()):
        return
    allowed = [p for p in sig.parameters if p not in ("self", "solver")]
    bad = sorted(set(params) - set(allowed))
    if bad:
        raise SearchError(f"strategy {name!r} has no parameter(s) {', '.join(map(repr, bad))}; "
                          f"its parameters are {', '.join(allowed)}")


def _scenarios(scenarios, random_source: bool, base_dir: Path) -> list[ScenarioEntry]:
    if isinstance(scenarios, str):
        scenarios = [scenarios]
    if not isinstance(scenarios, list) or not scenarios:
        raise SearchError("scenarios must be a non-empty list of names, files or mappings "
                          "{name: ..., label: ..., world: {...}}")
    out = []
    for item in scenarios:
        entry = {"name": item} if isinstance(item, str) else item
        if not isinstance(entry, Mapping) or not isinstance(entry.get("name"), str):
            raise SearchError(f"a scenario must be a name or a mapping with 'name'; got {item!r}")
        unknown = sorted(set(map(str, entry)) - _SCENARIO_KEYS)
        if unknown:
            raise SearchError(f"unknown key(s) {', '.join(map(repr, unknown))} in scenario "
                              f"{entry['name']!r}; allowed: {', '.join(sorted(_SCENARIO_KEYS))}")
        ref, digest = _resolve_scenario(str(entry["name"]), base_dir)
        default_label = Path(ref).stem if digest is not None else (
            load_scenario(ref).name if ref.startswith(GENERATED) else ref)
        label = _label(entry.get("label", default_label), "scenario label")
        world = entry.get("world") or {}
        if not isinstance(world, Mapping):
            raise SearchError(f"world of scenario {label!r} must be a mapping; got {world!r}")
        rs = _bool(entry.get("random_source", random_source), f"random_source of {label!r}")
        if rs and ({"source", "start"} & set(world)):
            raise SearchError(f"scenario {label!r}: random_source draws the source and start; "
                              "remove them from world or set random_source: false")
        rst = _bool(entry.get("random_start", False), f"random_start of {label!r}")
        if rst and rs:
            raise SearchError(f"scenario {label!r}: random_source already draws the start; "
                              "drop random_start")
        if rst and "start" in world:
            raise SearchError(f"scenario {label!r}: random_start draws the start; remove start "
                              "from world or set random_start: false")
        out.append(ScenarioEntry(ref, label, dict(world), rs, digest, rst))
    labels = [s.label for s in out]
    dup = sorted({x for x in labels if labels.count(x) > 1})
    if dup:
        raise SearchError(f"scenario label(s) {', '.join(dup)} appear twice; give each entry "
                          "a distinct label")
    return out


def _resolve_scenario(name: str, base_dir: Path) -> tuple[str, str | None]:
    if name in scenario_names() or name.startswith(GENERATED):
        return name, None
    path = Path(name) if Path(name).is_absolute() else base_dir / name
    if not path.exists():
        raise SearchError(f"unknown scenario {name!r} in the campaign spec: not a built-in "
                          f"({', '.join(scenario_names())}) nor a file")
    text = read_text(path, f"scenario file {name!r}", error=SearchError)
    return str(path.resolve()), hashlib.sha256(text.encode()).hexdigest()


def world_overrides(world: Mapping) -> dict:
    """A spec's ``world:`` overrides as the Python API takes them.

    A spec is a file format, so a ``start`` heading in it is in degrees, as in scenario
    files; :meth:`reciprocity.scenarios.Scenario.with_world` takes radians.

    Parameters
    ----------
    world : mapping
        The ``world`` of a :class:`ScenarioEntry`.

    Returns
    -------
    dict
        The same overrides, a start heading converted to radians.
    """
    def pose(p):
        if isinstance(p, (list, tuple)) and len(p) == 3 and not isinstance(p[0], (list, tuple)):
            return pose_from_degrees(p).tolist() if all(isinstance(v, Real) and not isinstance(v, bool) for v in p) else p
        return p                       # (x, y) or malformed: with_world says what is wrong

    out = dict(world)
    start = out.get("start")
    if isinstance(start, (list, tuple)) and start and isinstance(start[0], (list, tuple)):
        out["start"] = [pose(p) for p in start]
    elif start is not None:
        out["start"] = pose(start)
    return out


def entry_scenario(entry: ScenarioEntry, scenario: Scenario | None = None) -> Scenario:
    """The scenario an entry runs: `scenario` (default: loaded from ``entry.ref``), without
    its start when ``entry.random_start``.

    Parameters
    ----------
    entry : ScenarioEntry
    scenario : Scenario, optional
        The loaded scenario (a worker passes its cached object).

    Returns
    -------
    Scenario

    Raises
    ------
    SearchError
        ``random_start`` on a world kind without a default start.
    """
    sc = load_scenario(entry.ref) if scenario is None else scenario
    if not entry.random_start:
        return sc
    if sc.kind.default_start is None:
        raise SearchError(f"scenario {entry.label!r}: world {sc.world!r} has no default start, "
                          "so random_start cannot apply; give start in the scenario")
    return dataclasses.replace(sc, starts=None)


def _check_pairs(scenarios, variants, platform, agents, *, supported_only: bool = False,
                 platform_options: dict | None = None) -> set:
    """Check every pair; return the (scenario label, variant label) pairs to skip (with
    `supported_only`, those whose strategy does not apply to the scenario's world)."""
    skip = set()
    for sc in scenarios:
        try:
            skip |= _check_scenario(sc, variants, platform, agents, supported_only, platform_options)
        except SearchError:
            raise
        except (TypeError, ValueError) as exc:   # a value of the wrong type deep in a world
            raise SearchError(f"scenario {sc.label!r}: {' '.join(str(exc).split())}") from None
    return skip


def _check_scenario(sc: ScenarioEntry, variants, platform, agents, supported_only: bool,
                    platform_options: dict | None = None) -> set:
    from .. import api
    from ..strategies import STRATEGIES
    scenario = entry_scenario(sc)
    if sc.random_source and scenario.world != "poisson":
        raise SearchError(f"scenario {sc.label!r}: random_source applies to arena scenarios "
                          f"(world 'poisson'), not to world {scenario.world!r}")
    # the world overrides once per scenario (they are checked with the world's rules)
    scenario = scenario.with_world(world_overrides(sc.world))
    skip = set()
    for v in variants:
        worlds = getattr(STRATEGIES[v.strategy], "worlds", ("poisson",))
        if scenario.world not in worlds and supported_only:
            skip.add((sc.label, v.label))
            continue
        if scenario.world not in worlds:
            raise SearchError(f"strategy {v.strategy!r} does not apply to scenario "
                              f"{sc.label!r} (world {scenario.world!r}); it applies to "
                              f"{', '.join(worlds)}")
        api.check(scenario, v.strategy, params=v.params, platform=platform, agents=agents,
                  platform_options=platform_options)
    if len(skip) == len(variants):
        raise SearchError(f"no strategy of the spec applies to scenario {sc.label!r} "
                          f"(world {scenario.world!r})")
    return skip
