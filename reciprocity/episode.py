"""The episode runner: a strategy, a platform, and the trace of what happened."""

from __future__ import annotations

import json
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from arenas import Arena

from .errors import UnreachableTarget
from .platforms import Platform
from .strategies.base import Strategy

__all__ = ["Episode", "run_episode"]


def _jsonable(x):
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    if isinstance(x, float) and not np.isfinite(x):
        return None
    raise TypeError(f"not JSON serialisable: {type(x).__name__}")


@dataclass
class Episode:
    """The result of one search: the contract's summary and a per-request trace."""

    summary: dict
    trace: list = field(default_factory=list)

    def to_json(self, path=None, *, with_trace: bool = True) -> str:
        """JSON text of the summary (and trace); also written to `path` when given."""
        data = dict(self.summary)
        if with_trace:
            data["trace"] = self.trace
        text = json.dumps(data, default=_jsonable, indent=1)
        if path is not None:
            Path(path).write_text(text)
        return text


def run_episode(arena: Arena, strategy: Strategy, platform: Platform, *, start=None,
                seed: int = 0, success_radius: float = 5.0, progress=None) -> Episode:
    """Run `strategy` on `platform` in `arena` until the strategy stops.

    Parameters
    ----------
    arena : Arena
        The arena (its start pose is used when `start` is None).
    strategy : Strategy
        The search strategy.
    platform : Platform
        The observer; it holds the true source.
    start : array_like, shape (2,) or (3,), optional
        Start pose (x, y cm[, heading rad]).
    seed : int
        Seed of the episode's random generator (noise, actuation).
    success_radius : float
        A run succeeds when the strategy stops by its own criterion with an estimate
        within this distance (cm) of the true source.
    progress : callable, optional
        Called as ``progress(step_record)`` after every request.

    Returns
    -------
    Episode
    """
    if start is None:
        start = arena.start if arena.start is not None else arena.random_free_points(
            1, np.random.default_rng(seed))[0]
    start = np.asarray(start, dtype=float).ravel()
    if len(start) == 2:
        start = np.append(start, 0.0)
    arena.with_scenario(start=start)  # validates the start
    rng = np.random.default_rng(seed)
    t0 = time.perf_counter()
    platform.reset(start, rng)
    # the strategy sees the geometry and the nominal strength, never the true source
    strategy.start(replace(arena, source=None), platform.pose.copy(), rng)
    strategy.restrict(platform.reachable)
    trace = []
    while (request := strategy.propose()) is not None:
        try:
            points, readings = platform.visit(request)
        except UnreachableTarget as exc:
            # the platform says why; the strategy picks another point
            strategy.reject(request, exc.point, str(exc))
            record = dict(step=len(trace) + 1, kind="unreachable", motion=request.motion,
                          targets=request.points, message=str(exc), pose=platform.pose.copy(),
                          route=np.asarray(platform.last_route), path_length=platform.path_length,
                          **platform.step_log())
            trace.append(record)
            continue
        strategy.observe(request, points, readings)
        st = strategy.status
        record = dict(step=len(trace) + 1, kind=request.kind, motion=request.motion,
                      targets=request.points, points=points, readings=readings,
                      pose=platform.pose.copy(), route=np.asarray(platform.last_route),
                      path_length=platform.path_length,
                      estimate=None if st.estimate is None else np.asarray(st.estimate),
                      region_area=st.region_area, **st.extra, **platform.step_log())
        trace.append(record)
        if progress is not None:
            progress(record)
    est = strategy.estimate
    err = float(np.hypot(*(np.asarray(est) - platform.source))) if est is not None else None
    stopped_ok = strategy.stop_reason not in ("", "max_steps reached") and \
        not strategy.stop_reason.startswith("no admissible")
    summary = dict(
        strategy=strategy.name, arena=arena.name, seed=int(seed),
        source=platform.source.tolist(), estimate=None if est is None else np.asarray(est).tolist(),
        error=err, n_measurements=strategy.n_measurements, n_samples=strategy.n_samples,
        path_length=float(platform.path_length),
        success=bool(stopped_ok and err is not None and err <= success_radius),
        region_area=strategy.status.region_area, wall_time_s=time.perf_counter() - t0,
        start=start.tolist(), stop_reason=strategy.stop_reason, params=strategy.params(),
        n_rejected=strategy.n_rejected, platform=platform.name, **platform.summary(),
    )
    return Episode(summary, trace)
