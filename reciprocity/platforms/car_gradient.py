"""Algorithm 2 of Landa et al. on the car: the gradient manoeuvre and bang-bang steps (a part
of :class:`~reciprocity.platforms.car.CarPlatform`)."""

from __future__ import annotations

import numpy as np

from arenas.testbed import dead_reckon

from .car_steering import ACTIONS


class GradientManoeuvre:
    """The paper's gradient manoeuvre and bang-bang steps (a mixin of
    :class:`~reciprocity.platforms.car.CarPlatform`, whose state it uses)."""

    # -- Algorithm 2: gradient manoeuvre and bang-bang steps ---------------------------
    def _drive(self, steer: float, direction: int, distance: float) -> None:
        for _ in range(self._ticks_for(distance)):
            self._tick(steer, direction)

    def _in_free_region(self, point: np.ndarray) -> bool:
        """Whether `point` lies in the free region of the believed walls, or (on an
        unknown map) of the scanned ones."""
        if self._maps["believed"][0].contains(point[None])[0]:
            return True
        return self.grid is not None and self.grid.scanned_arena().contains(point[None])[0]

    def _free(self, pose: np.ndarray, margin: float) -> bool:
        return bool(self.arena.contains(pose[None, :2], margin)[0])

    def _manoeuvre(self, n: int) -> list:
        """The paper's gradient manoeuvre: a short reverse, measure; forward and to the
        side, measure. Where a wall is behind, the mirror image (forward, then reverse to
        the side). Returns the measurements."""
        o, tb = self.options, self.testbed
        rho, margin = tb.spec.rho, 0.5 * np.hypot(tb.spec.length, tb.spec.width)
        est = tb.estimate.copy()
        plans = []
        for first in (-1, 1):
            a = dead_reckon(est, 0.0, first, o.manoeuvre_reverse, rho)
            for side in (1, -1):
                b = dead_reckon(a, side, -first, o.manoeuvre_forward, rho)
                mid = dead_reckon(a, side, -first, 0.5 * o.manoeuvre_forward, rho)
                if all(self._free(p, margin) for p in (a, b, mid)):
                    plans.append((first, side, self.arena.wall_distance(b[None, :2])[0]))
        if not plans:
            self._event("no room for the gradient manoeuvre: measuring in place")
            first, side = -1, 1
            legs = [(0.0, first, 0.3 * o.manoeuvre_reverse), (side, -first, 0.3 * o.manoeuvre_forward)]
        else:
            first, side, _ = max(plans, key=lambda p: (p[0] == -1, p[2]))
            legs = [(0.0, first, o.manoeuvre_reverse), (side, -first, o.manoeuvre_forward)]
        measured = []
        for steer, direction, dist in legs[:n]:
            self._drive(steer, direction, dist)
            measured.append(self._measure())
        return measured

    def _bang_bang(self, target: np.ndarray) -> None:
        """Step the sensor toward `target` choosing, every `bang_step` cm, the one of the
        six actions whose chord points nearest to the target's direction (section II of
        the paper)."""
        o, tb = self.options, self.testbed
        # the whole body, not just its width, must stay clear along the step (half the
        # width let the corners scrape: 16 wall contacts in 24 gradient runs on the car)
        rho, margin = tb.spec.rho, 0.5 * np.hypot(tb.spec.length, tb.spec.width) + 0.3
        est = tb.estimate.copy()
        length = float(np.hypot(*(target - tb.sensor.position(est)[0])))
        driven = 0.0
        while driven < length:
            spot = tb.sensor.position(est)[0]
            if np.hypot(*(target - spot)) <= 0.5 * o.bang_step:
                break
            want = np.arctan2(*(target - spot)[::-1])
            best, best_gap = None, np.inf
            for u, v in ACTIONS:
                end = dead_reckon(est, u, v, o.bang_step, rho)
                mid = dead_reckon(est, u, v, 0.5 * o.bang_step, rho)
                if not (self._free(end, margin) and self._free(mid, margin)):
                    continue
                chord = tb.sensor.position(end)[0] - spot
                gap = abs((np.arctan2(chord[1], chord[0]) - want + np.pi) % (2 * np.pi) - np.pi)
                if gap < best_gap:
                    best, best_gap = (u, v), gap
            if best is None:
                self._event("bang-bang step blocked by walls")
                break
            self._drive(*best, o.bang_step)
            driven += o.bang_step
            est = tb.estimate.copy()
