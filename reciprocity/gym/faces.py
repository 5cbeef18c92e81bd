"""How each world kind looks through Gymnasium: its action and observation spaces, and
the translation between a space's elements and the intents of :mod:`reciprocity.intents`.

A face holds only public state (the observer's reported position and heading, the
task's nominal description); it never sees the truth. Every face has a *stop* action:
with it the policy ends its search and declares its estimate (the Box faces: the point
given; the Discrete faces: where the observer stands).
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from ..intents import Intent, Measure, Move, Stay
from ..observations import readings_of
from ..spaces.lattice import CONTROLS
from ..spaces.walker import all_moves, n_moves, turn_inward

__all__ = ["Face", "PointFace", "LatticeFace", "WalkerFace", "face_for", "STOP"]

#: What a face's :meth:`Face.intent` returns for the stop action.
STOP = "stop"
_INF = np.inf


def _box(low, high, dtype=np.float64) -> spaces.Box:
    return spaces.Box(np.asarray(low, dtype=dtype), np.asarray(high, dtype=dtype), dtype=dtype)


class Face:
    """Base of the faces: one observer's view of one world kind.

    Parameters
    ----------
    nominal : dict
        The world's public description (``World.nominal()``).
    """

    #: Keys of the observation Dict every face has.
    common = ("position", "reading", "time")

    def __init__(self, nominal: dict):
        self.nominal = dict(nominal)
        self.position = np.zeros(2)
        self.heading = 0.0
        self.reading = 0.0
        self.time = 0.0
        self.extra: dict = {}

    # -- spaces -------------------------------------------------------------------------
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper corners of the places an observer can be (world units)."""
        (x0, x1), (y0, y1) = self.nominal["bounds"]
        return np.array([x0, y0], dtype=float), np.array([x1, y1], dtype=float)

    def observation_space(self) -> spaces.Dict:
        lo, hi = self.bounds()
        return spaces.Dict({"position": _box(lo, hi), "reading": _box([-_INF], [_INF]),
                            "time": _box([0.0], [_INF]), **self.extra_spaces()})

    def extra_spaces(self) -> dict:
        return {}

    def action_space(self) -> spaces.Space:
        raise NotImplementedError

    # -- state ---------------------------------------------------------------------------
    def reset(self, pose) -> dict:
        """Start from `pose` (x, y, heading) as the task gives it; the first observation."""
        self.position = np.asarray(pose[:2], dtype=float).copy()
        self.heading = float(pose[2]) if len(pose) > 2 else 0.0
        self.reading, self.time = 0.0, 0.0
        self.extra = {k: np.zeros(s.shape, dtype=s.dtype) for k, s in self.extra_spaces().items()}
        return self.observation()

    def observe(self, percept, intent: Intent) -> dict:
        """Take in one percept of this observer (after `intent`); the next observation."""
        if percept.unreachable is None and readings_of(percept.observations):
            last = readings_of(percept.observations)[-1]
            self.position = np.asarray(last.position, dtype=float).copy()
            self.reading = float(last.value)
            self.time = float(last.time + last.dwell)
            self.take_data(last)
        return self.observation()

    def take_data(self, obs) -> None:
        """Structured parts of a reading (links, wind) into the extra observation keys."""

    def observation(self) -> dict:
        lo, hi = self.bounds()
        return {"position": np.clip(self.position, lo, hi), "reading": np.array([self.reading]),
                "time": np.array([self.time]), **{k: v.copy() for k, v in self.extra.items()}}

    # -- actions ---------------------------------------------------------------------------
    def intent(self, action) -> Intent | tuple:
        """The intent an action stands for, or ``(STOP, estimate)``."""
        raise NotImplementedError

    def action_of(self, intent: Intent):
        """The action that stands for `intent` (what :class:`StrategyPolicy` returns)."""
        raise NotImplementedError

    def stop_action(self, estimate=None):
        """The action that stops the search (declaring `estimate` where the face can)."""
        raise NotImplementedError

    def moved(self, intent: Intent) -> None:
        """Update the public heading after `intent` was carried out."""


class PointFace(Face):
    """Continuous worlds (the Poisson arena, point or car; the filament plume): the action
    is ``[x, y, stop]``, the next point in the world's unit (cm on the arenas) and a stop
    flag; with ``stop >= 0.5`` the search ends and ``(x, y)`` is the declared estimate.

    Parameters
    ----------
    nominal : dict
    max_step : float, optional
        Longest move of the observer (the filament vehicle); a farther point is approached
        by this much along the straight line.
    """

    def __init__(self, nominal: dict, *, max_step: float | None = None):
        super().__init__(nominal)
        self.max_step = max_step

    def bounds(self):
        if "arena" in self.nominal:
            (x0, x1), (y0, y1) = self.nominal["arena"].bounds
            return np.array([x0, y0], dtype=float), np.array([x1, y1], dtype=float)
        return super().bounds()

    def action_space(self) -> spaces.Box:
        lo, hi = self.bounds()
        return _box([lo[0], lo[1], 0.0], [hi[0], hi[1], 1.0])

    def intent(self, action):
        a = np.asarray(action, dtype=float).reshape(-1)
        point = a[:2]
        if a[2] >= 0.5:
            return STOP, point.copy()
        if self.max_step is None:
            return Measure(point)
        d = point - self.position
        n = float(np.hypot(*d))
        if n > self.max_step:
            point = self.position + d * (self.max_step / n)
        return Move(point)

    def action_of(self, intent: Intent):
        if isinstance(intent, (Measure, Move)):
            return np.array([intent.point[0], intent.point[1], 0.0])
        return intent                    # richer intents (gradient samples) pass as they are

    def stop_action(self, estimate=None):
        p = self.position if estimate is None else np.asarray(estimate, dtype=float)
        lo, hi = self.bounds()
        p = np.clip(p, lo, hi)
        return np.array([p[0], p[1], 1.0])


class FilamentFace(PointFace):
    """The filament plume: a point face whose observation adds the measured ``wind``."""

    def extra_spaces(self) -> dict:
        return {"wind": _box([-_INF, -_INF], [_INF, _INF])}

    def take_data(self, obs) -> None:
        if obs.data and "wind" in obs.data:
            self.extra["wind"] = np.asarray(obs.data["wind"], dtype=float)


class LatticeFace(Face):
    """The random lattice: ``Discrete(6)``: stay, east, west, north, south (the controls of
    :data:`reciprocity.spaces.lattice.CONTROLS`), and 5 = stop. The observation adds
    the link sensor's ``primary`` and ``secondary`` readings per direction (E, W, N, S):
    1 present, 0 absent, -1 not observable."""

    def bounds(self):
        r = float(self.nominal["radius"]) + 1.0
        return np.array([-r, -r]), np.array([r, r])

    def extra_spaces(self) -> dict:
        return {"primary": spaces.Box(0, 1, (4,), dtype=np.int64),
                "secondary": spaces.Box(-1, 1, (4,), dtype=np.int64)}

    def take_data(self, obs) -> None:
        if obs.data:
            self.extra["primary"] = np.asarray(obs.data["primary"], dtype=np.int64)
            self.extra["secondary"] = np.asarray(obs.data["secondary"], dtype=np.int64)

    def observation_space(self) -> spaces.Dict:
        out = super().observation_space()
        out["reading"] = _box([0.0], [_INF])
        return out

    def action_space(self) -> spaces.Discrete:
        return spaces.Discrete(len(CONTROLS) + 1)

    def intent(self, action):
        k = int(action)
        if k == len(CONTROLS):
            return STOP, self.position.copy()
        if k == 0:
            return Stay(self.position.copy())
        return Move(self.position + CONTROLS[k])

    def action_of(self, intent: Intent):
        if isinstance(intent, Stay):
            return 0
        u = np.rint(intent.point - self.position).astype(int)
        k = np.flatnonzero(np.all(CONTROLS == u, axis=1))
        if k.size == 0:
            return intent
        return int(k[0])

    def stop_action(self, estimate=None):
        return len(CONTROLS)


class WalkerFace(Face):
    """The plume worlds: ``Discrete(n + 2)``: the walker's n moves of
    :func:`reciprocity.spaces.walker.all_moves` (turns relative to its heading, or grid
    directions), then stay, then stop. A move that would leave the area stays. The
    observation adds the ``heading`` (rad, in [0, 2π))."""

    def extra_spaces(self) -> dict:
        return {"heading": _box([0.0], [2 * np.pi])}

    def observation_space(self) -> spaces.Dict:
        out = super().observation_space()
        out["reading"] = _box([0.0], [_INF])
        return out

    def observation(self) -> dict:
        self.extra["heading"] = np.array([self.heading % (2 * np.pi)])
        return super().observation()

    @property
    def n(self) -> int:
        return n_moves(self.nominal)

    def action_space(self) -> spaces.Discrete:
        return spaces.Discrete(self.n + 2)

    def _moves(self):
        return all_moves(self.nominal, self.position, self.heading)

    def _inside(self, p) -> bool:
        (x0, x1), (y0, y1) = self.nominal["bounds"]
        return bool(x0 <= p[0] <= x1 and y0 <= p[1] <= y1)

    def intent(self, action):
        k = int(action)
        if k == self.n + 1:
            return STOP, self.position.copy()
        if k < self.n:
            pts, hds = self._moves()
            if self._inside(pts[k]):
                self._next_heading = float(hds[k])
                return Move(pts[k])
        self._next_heading = self._stay_heading()
        return Stay(self.position.copy())

    def _stay_heading(self) -> float:
        if self.nominal["motion"] == "turn":
            return float(turn_inward(self.nominal, self.position, self.heading))
        return self.heading

    def moved(self, intent: Intent) -> None:
        self.heading = getattr(self, "_next_heading", self.heading)

    def action_of(self, intent: Intent):
        if isinstance(intent, Stay):
            return self.n
        pts, _ = self._moves()
        same = np.flatnonzero(np.all(pts == intent.point, axis=1))
        if same.size:
            return int(same[0])
        d = np.hypot(*(pts - intent.point).T)
        return int(np.argmin(d)) if d.min() < 1e-9 * max(1.0, float(np.abs(pts).max())) else intent

    def stop_action(self, estimate=None):
        return self.n + 1


def face_for(kind: str, platform: str, nominal: dict) -> Face:
    """The face of world `kind` seen from `platform`, for a world of this `nominal`."""
    if kind in ("poisson", "flow"):
        return PointFace(nominal)
    if kind == "lattice":
        return LatticeFace(nominal)
    if kind == "plume":
        return WalkerFace(nominal)
    if kind == "filament":
        return FilamentFace(nominal, max_step=float(nominal["max_step"]))
    raise ValueError(f"no Gymnasium face for world kind {kind!r}")
