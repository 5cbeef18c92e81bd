"""What runs inside a worker process: one episode task in, one result row out.

Expensive set-up (meshes, factorized Green's solvers, painted floors, planner banks) lives
in module-level caches of the framework (``functools.lru_cache``) keyed on the arena
object; :func:`scenario` keeps one Scenario object per worker process so that every
episode on the same scenario hits those caches. Nothing heavy is shipped in a task.

A row is the episode summary (which holds the evaluator's columns: see
:func:`reciprocity.episode.run_episode`) plus the campaign's own columns.
"""

from __future__ import annotations

import functools
import json
import math
import sys
import traceback
from pathlib import Path

import numpy as np

from ..scenarios import Scenario, load_scenario
from ..errors import SearchError
from .spec import SOURCE_CLEARANCE, SOURCE_SEPARATION, START_CLEARANCE, EpisodeTask, entry_scenario, world_overrides

__all__ = ["run_task", "run_tasks", "execute_task", "failure_row", "scenario", "world_draw",
           "cache_stats"]

#: Stream of the episode seed that the world draws (source, start) come from; the
#: episode itself uses the seed directly, so the draws and the noise are independent.
_WORLD_STREAM = 1


@functools.lru_cache(maxsize=32)
def scenario(ref: str) -> Scenario:
    """The scenario `ref`, loaded once per worker process.

    Parameters
    ----------
    ref : str
        Built-in name or absolute path of a scenario file.

    Returns
    -------
    Scenario
        The same object on every call, so caches keyed on its arena are reused.
    """
    return load_scenario(ref)


def world_draw(sc: Scenario, seed: int) -> dict:
    """Random true source and start of an arena scenario for episode seed `seed`.

    Parameters
    ----------
    sc : Scenario
        An arena scenario.
    seed : int
        Episode seed.

    Returns
    -------
    dict
        ``{"source": [x, y], "start": [x, y, heading], "source_clearance": c}``: cm, cm,
        radians, cm. The source is at least :data:`SOURCE_CLEARANCE` cm and the start
        :data:`START_CLEARANCE` cm from the walls; the heading is uniform in [0, 2π). The
        task says so (``source_clearance``, public): a strategy may take it as its prior.
    """
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(_WORLD_STREAM,)))
    several = sc.params.get("sources")
    if several:
        sources = _separated_points(sc, len(several), rng)
    else:
        source = sc.arena.random_free_points(1, rng, clearance=SOURCE_CLEARANCE)[0]
    start = sc.arena.random_free_points(1, rng, clearance=START_CLEARANCE)[0]
    heading = rng.uniform(0.0, 2.0 * math.pi)
    if several:
        return {"sources": sources, "start": [*start.tolist(), heading], "source_clearance": SOURCE_CLEARANCE}
    return {"source": source.tolist(), "start": [*start.tolist(), heading], "source_clearance": SOURCE_CLEARANCE}


def _separated_points(sc: Scenario, k: int, rng: np.random.Generator) -> list:
    """`k` random sources of an arena scenario, each SOURCE_CLEARANCE cm from the walls and
    SOURCE_SEPARATION cm from one another (drawn again, whole, until they are)."""
    for _ in range(1000):
        pts = sc.arena.random_free_points(k, rng, clearance=SOURCE_CLEARANCE)
        gaps = np.hypot(*(pts[:, None] - pts[None]).transpose(2, 0, 1))[np.triu_indices(k, 1)]
        if not gaps.size or gaps.min() >= SOURCE_SEPARATION:
            return pts.tolist()
    raise SearchError(f"could not draw {k} sources {SOURCE_SEPARATION:g} cm apart in arena {sc.arena.name!r} "
                      "in 1000 tries")


def execute_task(task: EpisodeTask, *, figures: bool = False):
    """Run the episode of `task` exactly as a campaign does.

    Parameters
    ----------
    task : EpisodeTask
    figures : bool
        Keep what the figures draw in the episode (:attr:`Episode.truth
        <reciprocity.episode.Episode.truth>`, :attr:`Episode.belief
        <reciprocity.episode.Episode.belief>`); the episode is the same.

    Returns
    -------
    (Episode, Strategy, list of Platform)
        As :func:`reciprocity.api.execute` (e.g. to redraw a campaign's episode).
    """
    from .. import api
    sc = entry_scenario(task.scenario, scenario(task.scenario.ref))
    world = world_overrides(task.scenario.world)          # a start heading: degrees -> radians
    if task.scenario.random_source:
        world.update(world_draw(sc, task.seed))
    return api.execute(sc, task.variant.strategy, seed=task.seed, params=dict(task.variant.params),
                       platform=task.platform, agents=task.agents, world=world or None,
                       platform_options=task.platform_options, figures=figures)


def run_task(task: EpisodeTask) -> dict:
    """Run one episode; never raises for a failing episode.

    Parameters
    ----------
    task : EpisodeTask

    Returns
    -------
    dict
        The row: the campaign columns (``campaign``, ``episode_id``, ``scenario``,
        ``variant``, ``seed_index``), the episode summary, and ``error_message`` (None, or the exception's type and
        message when the episode failed; the summary keys are then absent).
    """
    try:
        summary = execute_task(task)[0].summary
    except Exception as exc:  # a failing episode is a result, not the end of the campaign
        return failure_row(task, _one_line(exc))
    return {**_task_columns(task), **summary, "error_message": None}


def run_tasks(tasks: list[EpisodeTask]) -> list[dict]:
    """:func:`run_task` for each of `tasks`, in order: one Dask task for several short
    episodes, so that the scheduler's per-task cost is paid once for all of them."""
    return [run_task(task) for task in tasks]


def failure_row(task: EpisodeTask, message: str) -> dict:
    """The row of an episode that raised `message` (or whose worker died).

    Parameters
    ----------
    task : EpisodeTask
    message : str
        One line: what went wrong.

    Returns
    -------
    dict
    """
    return {**_task_columns(task), "strategy": task.variant.strategy,
            "arena": Path(task.scenario.ref).stem, "seed": task.seed, "params": json.dumps(task.variant.params, sort_keys=True),
            "error_message": message}


def _task_columns(task: EpisodeTask) -> dict:
    return dict(campaign=task.campaign, episode_id=task.episode_id, scenario=task.scenario.label,
                variant=task.variant.label, seed_index=task.seed_index)


def _one_line(exc: BaseException) -> str:
    frame = traceback.extract_tb(exc.__traceback__)[-1] if exc.__traceback__ else None
    where = f" (at {frame.filename.rsplit('/', 1)[-1]}:{frame.lineno})" if frame else ""
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}{where}"


def cache_stats() -> dict[str, tuple[int, int]]:
    """Hits and misses of every module-level ``lru_cache`` of the toolkit in this process.

    Run on each worker (``client.run(cache_stats)``) to verify that set-up is reused.

    Returns
    -------
    dict
        ``"module.function" -> (hits, misses)`` for the caches of ``arenas``,
        ``reciprocity`` and ``hjplanner`` that were used at least once.
    """
    out = {}
    for modname, mod in list(sys.modules.items()):
        if mod is None or modname.split(".")[0] not in ("arenas", "reciprocity", "hjplanner"):
            continue
        for attr, obj in list(vars(mod).items()):
            info = getattr(obj, "cache_info", None)
            if callable(info) and getattr(obj, "__module__", None) == modname:
                ci = info()
                if ci.hits or ci.misses:
                    out[f"{modname}.{attr}"] = (ci.hits, ci.misses)
    return out
