"""The truth side of a search: :class:`SearchEnv`, with Gymnasium's reset/step meaning.

The environment owns the world (the true source, walls, noise), the platforms (true
poses), the clock, the budget and the episode's seed tree, and it alone judges the
outcome. What leaves it is a :class:`~reciprocity.task.Task` at reset, one
:class:`~reciprocity.task.Percept` per observer and intent at each step, and, once the
agent has declared its :class:`~reciprocity.task.Report`, the episode summary.
"""

from __future__ import annotations

import time

import numpy as np

from ..errors import SearchError, UnreachableTarget
from ..intents import Intent
from ..outcome import is_success, match_sources
from ..scenarios import Scenario
from ..seeds import EpisodeSeeds
from ..task import Percept, Report, Task
from .spec import EpisodeSpec, checked_seed, environment_spec

__all__ = ["SearchEnv", "intents_of"]


def intents_of(action, n_agents: int) -> dict[int, Intent]:
    """An action as a mapping observer -> intent (one intent means observer 0)."""
    if isinstance(action, Intent):
        return {0: action}
    if isinstance(action, dict) and all(isinstance(v, Intent) for v in action.values()):
        bad = [a for a in action if not 0 <= int(a) < n_agents]
        if bad:
            raise SearchError(f"intent for observer {bad[0]}, but there are {n_agents}")
        return {int(a): v for a, v in action.items()}
    raise SearchError(f"an action is an Intent or a mapping observer -> Intent; got {action!r}")


def _limits(platform) -> dict:
    """Platform limits a strategy should respect: on the car, its clearance (cm) and the
    top of the sensor's calibrated range (the paper's ``I_max``)."""
    if platform.name == "car":
        return {"clearance": float(platform.options.clearance), "i_max": float(platform.testbed.floor.mapping.u_max)}
    return {}


class SearchEnv:
    """One scenario as an environment: ``reset(seed)``, then ``step(action)`` until done.

    Parameters
    ----------
    scenario : str, Scenario, arenas.Arena or EpisodeSpec
        The checked :class:`EpisodeSpec` (:func:`reciprocity.api.check`), taken as it is;
        or a built-in scenario name, a scenario or arena YAML file, a Scenario, or an
        arena, checked here once with the keywords below
        (:func:`~reciprocity.env.spec.environment_spec`).
    platform : str, optional
        The platform (default: the scenario's).
    agents : int, optional
        Number of observers (default: the scenario's).
    world : dict, optional
        Overrides of the scenario's world parameters (``source``, ``strength``, ``start``
        with the heading in radians, ``mismatch``, ...).
    platform_options : dict, optional
        Options of the platform (e.g. the car's ``planner``).

    Notes
    -----
    ``step`` returns ``(percepts, reward, terminated, truncated, info)``: the percepts of
    the observers that acted; a reward of -1 per round (the papers count rounds);
    ``terminated`` when an observer reached the source in worlds that end so;
    ``truncated`` when the round budget is spent. The agent then declares its
    :class:`Report` with :meth:`judge`, which returns the episode summary.
    """

    def __init__(self, scenario: str | Scenario | EpisodeSpec, *, platform: str | None = None,
                 agents: int | None = None, world: dict | None = None, platform_options: dict | None = None):
        if isinstance(scenario, EpisodeSpec):
            if platform is not None or agents is not None or world or platform_options:
                raise SearchError("an EpisodeSpec is checked already: give it alone, or give the scenario "
                                  "with platform, agents, world and platform_options")
            spec = scenario
        else:
            spec = environment_spec(scenario, platform=platform, agents=agents, world=world,
                                    platform_options=platform_options)
        self.spec = spec
        self.scenario = spec.scenario
        self.platform_name = spec.platform
        self.n_agents = spec.agents
        self.platform_options = dict(spec.platform_options)
        self.max_steps = self.scenario.max_steps
        self._world = None
        self._platforms: list = []

    # -- Gymnasium's protocol -----------------------------------------------------------
    def reset(self, seed: int | None = None, options: dict | None = None) -> tuple[list[Percept], dict]:
        """Start an episode.

        Parameters
        ----------
        seed : int, optional
            The episode seed; None draws one from the operating system.
        options : dict, optional
            ``{"progress": True}`` lets the car report its progress.

        Returns
        -------
        observation : list of Percept
            Empty (no reading has been made yet).
        info : dict
            ``task`` (the public :class:`Task`) and ``agent_seed`` (the agent's stream).
        """
        if seed is None:
            seed = int(np.random.SeedSequence().generate_state(1, dtype=np.uint64)[0] >> 1)
        elif not (type(seed) is int and seed in self.spec.seeds):       # the spec's seeds are checked
            seed = checked_seed(seed)
        sc, n = self.scenario, self.n_agents
        self.seeds = seeds = EpisodeSeeds.from_seed(int(seed), n)
        world = sc.build_world(seeds)
        opts = dict(self.platform_options)
        if self.platform_name == "car" and (options or {}).get("progress"):
            opts["progress"] = True
        factory = sc.kind.platforms[self.platform_name]
        plats = [factory(world, sc, dict(opts)) for _ in range(n)]
        starts = np.atleast_2d(np.asarray(sc.start_poses(world, n, seeds), dtype=float))
        if len(starts) != n:
            raise SearchError(f"{n} observers but {len(starts)} start poses")
        if not np.all(world.contains(starts[:, :2])):
            raise SearchError("a start pose is not in the free region")
        self._t0 = time.perf_counter()
        world.reset(seeds.rng(seeds.world))
        for k, (p, s, ss) in enumerate(zip(plats, starts, seeds.platforms)):
            p.agent = k
            p.reset(s if len(s) == 3 else np.append(s, 0.0), world, seeds.rng(ss))
        self._world, self._platforms, self._starts = world, plats, starts
        self._rounds, self._found_by, self._summary = 0, None, None
        # the evaluator classifies the source before the run: can the first observer reach it
        # on the true walls? (the agent gets only the platform's own reachability, on its map)
        reach = plats[0].truly_reachable(world.sources)
        self._source_reachable = True if reach is None else bool(np.all(reach))
        # a platform that reads the world its own way restates what its readings are
        world_nominal = {k: v for k, v in world.nominal().items() if k not in plats[0].restates}
        task = Task(world=world.kind, scenario=sc.name, world_nominal=world_nominal,
                    platform=self.platform_name, platform_nominal=plats[0].nominal(),
                    limits=_limits(plats[0]), starts=np.array([p.pose.copy() for p in plats]),
                    max_steps=self.max_steps, reachable=plats[0].reachable, intents=plats[0].takes())
        return [], {"task": task, "agent_seed": seeds.agent}

    def step(self, action) -> tuple[list[Percept], float, bool, bool, dict]:
        """Carry out one round: each observer's intent, in observer order.

        Returns
        -------
        percepts : list of Percept
        reward : float
            -1 (one round spent).
        terminated : bool
            An observer reached the source (worlds with a ``found_radius``).
        truncated : bool
            The round budget is spent.
        info : dict
            ``records``: per percept, the platform's log for the episode trace (true
            pose, route, path length, clock); for the evaluator's trace, never for the agent.
        """
        self._check_running()
        return self._carry_out(intents_of(action, self.n_agents))

    def carry_out(self, intents: dict[int, Intent]) -> tuple[list[Percept], float, bool, bool, dict]:
        """:meth:`step` for an action already read as a mapping observer -> intent
        (:func:`intents_of`; what :class:`~reciprocity.env.Rollout` passes, so that a step
        reads its action once)."""
        self._check_running()
        return self._carry_out(intents)

    def _check_running(self) -> None:
        if self._world is None:
            raise SearchError("call reset() before step()")
        if self._summary is not None:
            raise SearchError("the episode is over; call reset()")

    def _carry_out(self, intents: dict[int, Intent]) -> tuple[list[Percept], float, bool, bool, dict]:
        self._rounds += 1
        percepts, records = [], []
        for agent, intent in intents.items():
            plat = self._platforms[agent]
            try:
                obs = plat.execute(intent)
                percepts.append(Percept(agent, obs))
            except UnreachableTarget as exc:
                percepts.append(Percept(agent, [], (np.asarray(exc.point, dtype=float), str(exc))))
            records.append(dict(pose=plat.pose.copy(), route=np.asarray(plat.last_route),
                                path_length=plat.path_length, time=plat.time, log=plat.step_log()))
            if percepts[-1].unreachable is None and self._found_by is None \
                    and self._world.found(plat.true_position):
                self._found_by = agent
        terminated = self._world.found_radius is not None and self._found_by is not None
        truncated = not terminated and self.max_steps is not None and self._rounds >= self.max_steps
        return percepts, -1.0, terminated, truncated, {"records": records, "found_by": self._found_by}

    @property
    def rounds(self) -> int:
        """Rounds carried out so far in this episode."""
        return self._rounds

    @property
    def source_reachable(self) -> bool:
        """The evaluator's judgement of this episode's source, made at :meth:`reset`: can
        the first observer reach it on the true walls (the summary's ``source_reachable``;
        truth side, never shown to an agent)."""
        return self._source_reachable

    @property
    def budget_spent(self) -> bool:
        """The round budget is spent (no further step is allowed)."""
        return self.max_steps is not None and self._rounds >= self.max_steps

    # -- the judgement ------------------------------------------------------------------
    def judge(self, report: Report) -> dict:
        """The episode summary for the agent's final `report`: the contract's keys
        (``../shared/DESIGN.md``), judged against the truth here and nowhere else."""
        if self._world is None:
            raise SearchError("call reset() before judge()")
        world, plats, stop = self._world, self._platforms, report.stop
        est = None if report.estimate is None else np.asarray(report.estimate, dtype=float)
        err = float(np.hypot(*(est - world.source))) if est is not None else None
        found = world.found_radius is not None
        summary = dict(
            strategy=report.strategy, arena=self.scenario.name or getattr(getattr(world, "arena", None), "name",
                                                                          world.kind),
            world=world.kind, seed=self.seeds.seed, source=np.asarray(world.source).tolist(),
            estimate=None if est is None else est.tolist(), error=err,
            n_measurements=int(report.n_measurements), n_samples=int(report.n_samples),
            steps=int(self._rounds), path_length=float(sum(p.path_length for p in plats)),
            converged=stop.reason.converged,
            success=is_success(stop, err, world.success_radius, found=found),
            stop_reason=str(stop), stop=stop.reason.value,
            region_area=report.region_area, sim_time_s=float(max(p.time for p in plats)),
            wall_time_s=time.perf_counter() - self._t0,
            start=self._starts[0].tolist(), params=dict(report.params), n_rejected=int(report.n_rejected),
            source_reachable=self._source_reachable,
            platform=plats[0].name, **world.describe(), **world.describe_start(self._starts[0]),
            **plats[0].summary())
        clash = set(report.notes) & set(summary)
        if clash:
            raise SearchError(f"the agent's note(s) {sorted(clash)} clash with the summary's keys")
        summary.update(report.notes)
        if len(plats) > 1 or report.agents != 1:
            summary.update(n_agents=len(plats), messages=len(report.messages), starts=self._starts.tolist())
        true = np.array([p.true_position[:2] for p in plats], dtype=float)
        sources = world.sources
        summary["distance_at_stop"] = float(np.min(np.hypot(*(true[:, None] - sources[None]).T)))
        if world.max_sources > 1 or len(sources) > 1:
            summary.update(self._several(report, est, sources, stop, world.success_radius))
        if report.position_support is not None:
            # Ristic et al. (2014) Sec. 5.1: success also needs the true node among the
            # searcher's own position particles
            support = np.atleast_2d(np.asarray(report.position_support, dtype=float))
            localised = bool(np.any(np.all(np.isclose(support, true[0]), axis=1)))
            summary.update(reached=bool(summary["success"]), self_localised=localised,
                           success=bool(summary["success"]) and localised)
        self._summary = summary
        return summary

    @staticmethod
    def _several(report: Report, est, sources: np.ndarray, stop, radius: float) -> dict:
        """The summary keys of a world with several sources: every estimate, the error of
        each true source by optimal assignment (None: missed), and success only when the
        number of sources is right and every one lies within `radius`."""
        ests = report.estimates if report.estimates is not None else ([] if est is None else [est])
        ests = np.asarray(ests, dtype=float).reshape(-1, 2)
        errors = match_sources(sources, ests)
        right = len(ests) == len(sources) and all(e is not None for e in errors)
        out = dict(estimates=ests.tolist(), errors=errors, n_sources_estimated=len(ests),
                   n_sources_right=len(ests) == len(sources),
                   error=max(errors) if right else None,
                   success=bool(stop.reason.converged and right and max(errors) <= radius))
        if report.estimates_sd is not None:
            out["estimates_sd"] = [float(v) for v in report.estimates_sd]
        return out

    def figure_record(self) -> dict:
        """What the episode's figures draw of the truth, after the episode: the world's
        (e.g. the true field and walls) and the first observer's platform's (e.g. the car's
        painted floor); see :attr:`reciprocity.episode.Episode.truth`."""
        return {**self._world.figure_record(), **self._platforms[0].figure_record()}

    @property
    def summary(self) -> dict | None:
        """The summary of the finished episode (None until :meth:`judge`)."""
        return self._summary

    @property
    def platforms(self) -> list:
        """The platforms (truth side: for figures and videos after the episode)."""
        return self._platforms

    @property
    def world(self):
        """The world (truth side: for figures after the episode)."""
        return self._world
