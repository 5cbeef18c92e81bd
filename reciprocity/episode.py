"""An episode's record: the summary the environment judged, the step trace and the messages.

Episodes are run by :func:`reciprocity.env.rollout` (a :class:`~reciprocity.env.SearchEnv`
and an agent); this module holds what they produce: :class:`Episode`, one
:class:`StepRecord` per percept, and the contract's :data:`SUMMARY_KEYS`.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import SearchError
from .observations import MessageLog, Observation, readings_of, scans_of

__all__ = ["Episode", "StepRecord", "SUMMARY_KEYS"]

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
        """Where the source was read (scans left out), shape (n, 2)."""
        return np.array([o.position for o in readings_of(self.observations)]).reshape(-1, 2)

    @property
    def readings(self) -> np.ndarray:
        """The source readings (scans left out), shape (n,)."""
        return np.array([o.value for o in readings_of(self.observations)], dtype=float)

    def as_dict(self) -> dict:
        out = dict(step=self.step, agent=self.agent, intent=self.intent, kind=self.kind,
                   targets=np.atleast_2d(self.targets), points=self.points, readings=self.readings,
                   saturated=[bool(o.saturated) for o in readings_of(self.observations)],
                   observed_at=[float(o.time) for o in readings_of(self.observations)],
                   pose=self.pose, route=self.route, path_length=self.path_length, time=self.time,
                   estimate=self.estimate, region_area=self.region_area)
        if self.message is not None:
            out["message"] = self.message
        scans = scans_of(self.observations)
        if scans:
            out["scans"] = [dict(o.data, position=o.position.tolist()) for o in scans]
        for source, extra in (("strategy", self.belief), ("platform", self.platform)):
            clash = set(extra) & set(out)
            if clash:
                raise SearchError(f"the {source} record key(s) {sorted(clash)} clash with the trace's")
            out.update(extra)
        return out


@dataclass
class Episode:
    """The result of one search: the contract's summary, the typed records and messages.

    When the episode was run to draw figures (``rollout(..., figures=True)``), `belief`
    holds what they draw of the strategy's belief at the end (its
    :meth:`~reciprocity.strategies.base.Strategy.figure_record`: e.g. ``imaging``, ``eps``,
    ``gradients``) and `truth` what they draw of the truth (the environment's
    :meth:`~reciprocity.env.SearchEnv.figure_record`: e.g. ``field``, ``true_arena``,
    ``floor``). Neither is written to JSON; the strategy never saw `truth`.
    """

    summary: dict
    records: list = field(default_factory=list)
    messages: MessageLog = field(default_factory=MessageLog)
    belief: dict = field(default_factory=dict)
    truth: dict = field(default_factory=dict)

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
