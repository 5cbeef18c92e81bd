"""The episode runner: a world, a strategy, one or more platforms, and the trace.

One episode reads like the search loop of every paper::

    reset the world and the platforms; start the strategy with what it is told
    while the strategy has intents:
        each platform carries out its observer's intent and returns observations
        the strategy updates its belief from them
    summarise: estimate, error, counts, path, typed outcome, success

The strategy sees the world's nominal description and its observations only; the
platforms and the world never see the strategy's belief.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from .errors import SearchError, UnreachableTarget
from .intents import Intent
from .observations import MessageLog, Observation
from .outcome import Stop, StopReason, is_success
from .platforms.base import Platform
from .strategies.base import SearchContext, Strategy
from .worlds.base import World

__all__ = ["Episode", "StepRecord", "run_episode", "SUMMARY_KEYS"]

#: Keys every episode summary has (the public contract, ../shared/DESIGN.md).
SUMMARY_KEYS = ("strategy", "arena", "world", "seed", "source", "estimate", "error", "n_measurements",
                "n_samples", "steps", "path_length", "converged", "success", "stop_reason",
                "region_area", "sim_time_s", "wall_time_s")


def _jsonable(x):
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, (np.floating, np.integer, np.bool_)):
        return x.item()
    if isinstance(x, Observation):
        return x.as_dict()
    if isinstance(x, float) and not np.isfinite(x):
        return None
    raise TypeError(f"not JSON serialisable: {type(x).__name__}")


@dataclass
class StepRecord:
    """What happened for one intent of one observer.

    The strategy's own records (``belief``) and the platform's (``platform``) are kept
    apart; :meth:`as_dict` flattens them for figures and JSON and refuses a key that two
    of them share instead of letting one overwrite the other.
    """

    step: int
    agent: int
    intent: str
    kind: str
    targets: np.ndarray
    observations: list
    pose: np.ndarray
    route: np.ndarray
    path_length: float
    time: float
    estimate: np.ndarray | None = None
    region_area: float | None = None
    message: str | None = None
    belief: dict = field(default_factory=dict)
    platform: dict = field(default_factory=dict)

    @property
    def points(self) -> np.ndarray:
        return np.array([o.position for o in self.observations]).reshape(-1, 2)

    @property
    def readings(self) -> np.ndarray:
        return np.array([o.value for o in self.observations], dtype=float)

    def as_dict(self) -> dict:
        out = dict(step=self.step, agent=self.agent, intent=self.intent, kind=self.kind,
                   targets=np.atleast_2d(self.targets), points=self.points, readings=self.readings,
                   saturated=[bool(o.saturated) for o in self.observations],
                   observed_at=[float(o.time) for o in self.observations],
                   pose=self.pose, route=self.route, path_length=self.path_length, time=self.time,
                   estimate=self.estimate, region_area=self.region_area)
        if self.message is not None:
            out["message"] = self.message
        for source, extra in (("strategy", self.belief), ("platform", self.platform)):
            clash = set(extra) & set(out)
            if clash:
                raise SearchError(f"the {source} record key(s) {sorted(clash)} clash with the trace's")
            out.update(extra)
        return out


@dataclass
class Episode:
    """The result of one search: the contract's summary, the typed records and messages."""

    summary: dict
    records: list = field(default_factory=list)
    messages: MessageLog = field(default_factory=MessageLog)

    @property
    def trace(self) -> list[dict]:
        """The records as flat dicts (figures, video, JSON); an episode read back from
        JSON holds the dicts themselves."""
        return [r.as_dict() if isinstance(r, StepRecord) else r for r in self.records]

    def to_json(self, path=None, *, with_trace: bool = True) -> str:
        """JSON text of the summary (and trace); also written to `path` when given."""
        data = dict(self.summary)
        if with_trace:
            data["trace"] = self.trace
            data["message_log"] = [m.__dict__ for m in self.messages.messages]
        text = json.dumps(data, default=_jsonable, indent=1)
        if path is not None:
            Path(path).write_text(text)
        return text


def _intents(proposal, n_agents: int) -> dict[int, Intent]:
    if isinstance(proposal, Intent):
        return {0: proposal}
    if isinstance(proposal, dict) and all(isinstance(v, Intent) for v in proposal.values()):
        bad = [a for a in proposal if not 0 <= int(a) < n_agents]
        if bad:
            raise SearchError(f"intent for observer {bad[0]}, but there are {n_agents}")
        return {int(a): v for a, v in proposal.items()}
    raise SearchError(f"a strategy must propose an Intent or a mapping agent -> Intent; got {proposal!r}")


def run_episode(world: World, strategy: Strategy, platforms: Platform | Sequence[Platform], *,
                starts, seed: int = 0, max_steps: int | None = None, scenario: str | None = None,
                progress=None) -> Episode:
    """Run `strategy` with `platforms` in `world` until the strategy stops.

    Parameters
    ----------
    world : World
        The truth.
    strategy : Strategy
        The search strategy.
    platforms : Platform or sequence of Platform
        One per observer.
    starts : array_like, shape (n_agents, 2 or 3)
        Start poses (x, y[, heading rad]).
    seed : int
        Seed of the episode: the world's, the platforms' and the strategy's generators
        are spawned from it, so each draws its own reproducible stream.
    max_steps : int, optional
        Cap on rounds (one intent per observer each); hitting it stops the search with
        ``StopReason.STEP_CAP`` (never a success).
    scenario : str, optional
        Scenario name for the summary (default: the world's).
    progress : callable, optional
        Called with each :class:`StepRecord`.

    Returns
    -------
    Episode
    """
    plats = [platforms] if isinstance(platforms, Platform) else list(platforms)
    starts = np.atleast_2d(np.asarray(starts, dtype=float))
    if len(starts) != len(plats):
        raise SearchError(f"{len(plats)} platforms but {len(starts)} start poses")
    if strategy.agents is not None and strategy.agents != len(plats):
        raise SearchError(f"strategy {strategy.name!r} directs {strategy.agents} observer(s); got {len(plats)}")
    if world.kind not in strategy.worlds:
        raise SearchError(f"strategy {strategy.name!r} does not apply to {world.kind!r} worlds "
                          f"(it supports {', '.join(strategy.worlds)})")
    if not np.all(world.contains(starts[:, :2])):
        raise SearchError("a start pose is not in the free region")
    seq = np.random.SeedSequence(int(seed))
    world_ss, strat_ss, *plat_ss = seq.spawn(2 + len(plats))
    t0 = time.perf_counter()
    world.reset(np.random.default_rng(world_ss))
    for k, (p, s, ss) in enumerate(zip(plats, starts, plat_ss)):
        p.agent = k
        p.reset(s if len(s) == 3 else np.append(s, 0.0), world, np.random.default_rng(ss))
    messages = MessageLog()
    # the strategy sees the world's nominal description and what the (first) platform
    # knows of its own readings (its calibration), never the truth
    ctx = SearchContext(world.kind, {**world.nominal(), **plats[0].nominal()},
                        np.array([p.pose.copy() for p in plats]),
                        np.random.default_rng(strat_ss), messages)
    strategy.start(ctx)
    # the evaluator classifies the source before the run: can the first observer reach it?
    reach = plats[0].reachable(np.asarray(world.source, dtype=float)[None])
    source_reachable = True if reach is None else bool(reach[0])
    for p in plats:
        strategy.restrict(p.reachable)
    records: list[StepRecord] = []
    rounds, found_by = 0, None
    while not strategy.done:
        proposal = strategy.propose()
        if proposal is None:
            break
        if max_steps is not None and rounds >= max_steps:
            strategy.stop(StopReason.STEP_CAP, f"{max_steps} steps")
            break
        rounds += 1
        for agent, intent in _intents(proposal, len(plats)).items():
            plat = plats[agent]
            try:
                obs = plat.execute(intent)
            except UnreachableTarget as exc:
                strategy.reject(intent, exc.point, str(exc), agent)
                records.append(StepRecord(len(records) + 1, agent, intent.name, "unreachable",
                                          intent.point, [], plat.pose.copy(), np.asarray(plat.last_route),
                                          plat.path_length, plat.time, message=str(exc),
                                          platform=plat.step_log()))
                continue
            strategy.observe(obs, intent, agent)
            st = strategy.status
            rec = StepRecord(len(records) + 1, agent, intent.name, obs[0].kind if obs else "none",
                             intent.point, obs, plat.pose.copy(), np.asarray(plat.last_route),
                             plat.path_length, plat.time,
                             None if st.estimate is None else np.asarray(st.estimate, dtype=float),
                             st.region_area, belief=dict(st.extra), platform=plat.step_log())
            records.append(rec)
            if found_by is None and world.found(plat.true_position):
                found_by = agent
            if progress is not None:
                progress(rec)
        if world.found_radius is not None and found_by is not None and not strategy.done:
            strategy.stop(StopReason.FOUND, f"observer {found_by} reached the source")
    if strategy.outcome is None:
        strategy.stop(StopReason.GAVE_UP, "the strategy proposed nothing more")
    est = strategy.estimate
    err = float(np.hypot(*(np.asarray(est, dtype=float) - world.source))) if est is not None else None
    stop: Stop = strategy.outcome
    found = world.found_radius is not None
    summary = dict(
        strategy=strategy.name, arena=scenario or getattr(getattr(world, "arena", None), "name", world.kind),
        world=world.kind, seed=int(seed), source=np.asarray(world.source).tolist(),
        estimate=None if est is None else np.asarray(est, dtype=float).tolist(), error=err,
        n_measurements=int(strategy.n_measurements), n_samples=int(strategy.n_samples),
        steps=int(rounds), path_length=float(sum(p.path_length for p in plats)),
        converged=stop.reason.converged,
        success=is_success(stop, err, world.success_radius, found=found),
        stop_reason=str(stop), stop=stop.reason.value,
        region_area=strategy.status.region_area, sim_time_s=float(max(p.time for p in plats)),
        wall_time_s=time.perf_counter() - t0,
        start=starts[0].tolist(), params=strategy.params(), n_rejected=int(strategy.n_rejected),
        source_reachable=source_reachable,
        platform=plats[0].name, **world.describe(), **plats[0].summary())
    if len(plats) > 1 or strategy.agents != 1:
        summary.update(n_agents=len(plats), messages=len(messages), starts=starts.tolist())
    summary.update(_assessment(summary, strategy, plats))
    return Episode(summary, records, messages)


def _assessment(summary: dict, strategy: Strategy, platforms: list) -> dict:
    """What only the evaluator may compute, once the search is over, from the final belief
    and the observers' *true* positions (which a strategy never sees while searching):

    - ``distance_at_stop``: from the source to the nearest observer's true position;
    - the keys of ``strategy.assess(summary, true_positions)`` when the strategy defines
      it: a paper's own test of the belief against the truth, e.g. the self-localisation
      of Ristic et al. (2014) Sec. 5.1, whose ``success`` replaces the summary's
      (:meth:`reciprocity.strategies.rbpf.RBPFStrategy.assess`).
    """
    true = np.array([p.true_position[:2] for p in platforms], dtype=float)
    out = {"distance_at_stop": float(np.min(np.hypot(*(true - np.asarray(summary["source"])).T)))}
    assess = getattr(strategy, "assess", None)
    if callable(assess):
        out.update(assess(summary, true))
    return out
