"""The believed map of a search on an unknown map, step by step, as records for figures.

A strategy with a :class:`~reciprocity.strategies.mapping.MapKeeper` reports what it was
told (``mapping``: the known walls, the lidar, the cell, the mesh size, the model error)
and its final imaging map (``imaging``). :func:`with_map_steps` rebuilds from the percepts
the strategy received the believed map and the imaging on it after a few steps, as plain
records (``map_steps``) that :func:`reciprocity.viz.mapping.mapping_steps_figure` draws
without knowing the keeper.
"""

from __future__ import annotations

import numpy as np

from ..beliefs.imaging import ImagingMap
from ..models.green import cached_solver
from ..observations import Observation, readings_of, scans_of
from .mapping import MapKeeper

__all__ = ["default_steps", "map_replay", "with_map_steps"]


def default_steps(n: int) -> list[int]:
    """The steps drawn of an `n`-step search (1-based): 1, 2, the middle one, the last."""
    return sorted({1, min(2, n), max(1, (n + 1) // 2), n})


def _scans(percept) -> list[Observation]:
    """The scans of one percept as the episode's trace holds them (``dict(data, position)``)."""
    out = []
    for o in scans_of(percept.observations if percept.unreachable is None else []):
        s = dict(o.data, position=o.position.tolist())
        out.append(Observation(s["position"], min(s["ranges"]), kind="scan", data=s))
    return out


def _readings(percept) -> tuple[np.ndarray, np.ndarray]:
    """Where and what one percept read (scans left out), as the trace's ``points`` and ``readings``."""
    obs = readings_of(percept.observations) if percept.unreachable is None else []
    points = np.array([o.position for o in obs]).reshape(-1, 2)
    return points, np.array([o.value for o in obs], dtype=float)


def map_replay(told: dict, imaging: ImagingMap, percepts: list, k: int) -> tuple[MapKeeper, ImagingMap]:
    """The believed map and the imaging map of the strategy after step `k`, rebuilt from
    the percepts as the strategy built them (the same occupancy updates, the same believed
    arena, the solver on it), the readings imaged with the model error and shortfall of
    the map after step `k` (the strategy updates them only when the believed walls
    change, so they may differ slightly).

    Parameters
    ----------
    told : dict
        The strategy's ``mapping`` record: ``known``, ``lidar``, ``cell``, ``h`` (cm),
        ``model_error``.
    imaging : ImagingMap
        The strategy's final imaging map (for its likelihood).
    percepts : list of Percept
        The percepts of the episode, one per step of its trace, in order.
    k : int
        Step, 1-based.
    """
    keeper = MapKeeper(told["known"], told["lidar"], told["cell"])
    for percept in percepts[:k]:
        keeper.update(_scans(percept))
    read = [_readings(p) for p in percepts[:k]]
    points = np.vstack([pts for pts, _ in read])
    values = np.concatenate([vals for _, vals in read])
    product = imaging.combine == "product" and imaging.strength_range is None
    error = keeper.model_error(told["model_error"]) if product else imaging.model_error
    out = ImagingMap(cached_solver(keeper.arena, told["h"]), imaging.sigma, strength=imaging.strength,
                     combine=imaging.combine, strength_range=imaging.strength_range,
                     offset_sd=imaging.offset_sd, model_error=error)
    out = keeper.imaging(out)
    for z, r in zip(points, values):
        out.add(z, float(r))
    return keeper, out


def _snapshot(k: int, keeper: MapKeeper, imaging: ImagingMap) -> dict:
    """What the figure draws of the believed map after step `k`."""
    grid = keeper.grid
    extent = (grid.origin[0], grid.origin[0] + grid.nx * grid.cell,
              grid.origin[1], grid.origin[1] + grid.ny * grid.cell)
    return dict(step=k, arena=keeper.arena, bounds=grid.known.bounds, extent=extent,
                unseen=(grid.inside & ~grid.seen).astype(int), frontier=grid.centres()[grid.frontier()],
                seen_fraction=float(grid.seen_fraction), revision=keeper.revision, imaging=imaging)


def with_map_steps(record: dict, percepts: list) -> dict:
    """`record` (a strategy's figure record) with ``map_steps`` when it holds ``mapping``:
    one snapshot per step of :func:`default_steps` (``step``, the believed ``arena``, the
    known ``bounds``, the grid's ``extent``, the ``unseen`` cells inside, the ``frontier``
    points, ``seen_fraction``, the map's ``revision`` and its ``imaging`` map)."""
    if "mapping" not in record or not percepts:
        return record
    snaps = [_snapshot(k, *map_replay(record["mapping"], record["imaging"], percepts, k))
             for k in default_steps(len(percepts))]
    return {**record, "map_steps": snaps}
