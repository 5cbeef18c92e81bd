"""How the car steers along a value function: the feedback law of eq. (15), its pose in
the clearance band, and the guards that keep its body off the walls (a part of
:class:`~reciprocity.platforms.car.CarPlatform`)."""

from __future__ import annotations

import numpy as np

from arenas.car import car_footprint
from arenas.testbed import dead_reckon
from hjplanner import PlanningError, optimal_path, steering

#: Inside the clearance band the car turns its motion away from the wall until it leaves
#: at a slope (sine of the angle to the wall) of at least 0.05 + depth / 4 cm, and at most
#: this: the steering law of the band's edge cannot see drift deeper into it.
BAND_EXIT_SLOPE = 0.3

#: The car keeps its body at least this far (cm) from the walls of its map where its
#: steering can: the planner's clearance disc leaves a corner turned toward a wall no
#: margin (the half-diagonal of the 7 x 3.8 cm body is 3.98 cm).
BODY_MARGIN = 0.5

#: How far ahead (cm of driving) the body's distance to the walls is foreseen.
BODY_LOOKAHEAD = 2.0

#: Where a path changes gear within this many cm of driving, the car changes gear at once
#: when every command in the present gear would bring its body within BODY_MARGIN of a wall
#: (the planner's cusp lies where the disc of the clearance touches the band's edge).
CUSP_SLACK = 3.0

#: Where along each side of the body its distance to the walls is taken (0: the corner).
BODY_SIDE_SAMPLES = (0.0, 0.25, 0.5, 0.75)

#: Six bang-bang actions (steer, direction): left / straight / right x forward / reverse.
ACTIONS = tuple((u, v) for v in (1, -1) for u in (1, 0, -1))


class Steering:
    """Steering by the value function, with the band and body guards (a mixin of
    :class:`~reciprocity.platforms.car.CarPlatform`, whose state it uses)."""

    def _virtual(self, vf, est: np.ndarray) -> np.ndarray:
        """The pose the controller steers from: the estimate, or, when drift has taken it
        into the clearance band around the walls (where φ = inf; optimal paths run
        along the band's edge), the estimate moved out of the band along the wall
        normal, by at most 3 cm."""
        est = np.asarray(est, dtype=float)
        if np.isfinite(vf(*est)):
            return est.copy()
        normal = self._wall_normal(est[:2])
        if normal is None:
            return est.copy()
        for shift in np.arange(0.25, 3.01, 0.25):
            moved = np.array([est[0] + shift * normal[0], est[1] + shift * normal[1], est[2]])
            if np.isfinite(vf(*moved)):
                return moved
        return est.copy()

    def _replan(self, vf, est: np.ndarray):
        """The optimal path from the estimated pose: (arc length at the end of each gear
        stretch, gear of each stretch), or None if the pose cannot reach the target."""
        try:
            path = optimal_path(vf, est)
        except PlanningError:
            return None
        self._log["replans"].append(est.tolist())
        self._log["plans"].append(path.xy[:: max(1, len(path.xy) // 60)].tolist())
        if len(path.direction) == 0:
            return np.array([np.inf]), np.array([1])
        s = np.cumsum(path.step_lengths)
        switch = np.flatnonzero(np.diff(path.direction)) if len(path.direction) > 1 else np.array([], int)
        ends = np.append(s[switch], np.inf)
        gears = np.append(path.direction[switch], path.direction[-1])
        return ends, gears

    def _steer(self, vf, est: np.ndarray, v: int) -> float:
        """Eq. (15) for gear v: ``u = -v sign(φ_θ)``, straight inside the dead band (the
        planner's one steering law, :func:`hjplanner.steering`), at the pose `est` the
        controller steers from (:meth:`_virtual`), with two guards the law cannot give:

        - Inside the clearance band the law steers from the band's edge, where the
          optimal path runs along the wall, and so cannot see drift that takes the car
          deeper in: there the car turns its motion away from the wall until it leaves
          the band at least at BAND_EXIT_SLOPE (steeper the deeper it is).
        - The planner keeps the car's centre `clearance` from the walls, a disc as wide
          as the body's half-diagonal: a corner turned toward a wall has no margin left.
          Where the law's command would bring the body within BODY_MARGIN of a wall in
          the next BODY_LOOKAHEAD of driving, the command that keeps it farthest is
          taken instead.
        """
        u = float(steering(vf, est, self.dead_band, direction=v))
        here = self.testbed.estimate
        u = self._out_of_band(here, u, v)
        return self._keep_body_off(here, u, v)

    def _out_of_band(self, here: np.ndarray, u: float, v: int) -> float:
        """`u`, or the turn that takes the motion out of the clearance band (see :meth:`_steer`)."""
        depth = self._clearance() - float(self.arena.wall_distance(here[None, :2])[0])
        if depth <= 0.0:
            return u
        normal = self._wall_normal(here[:2])
        if normal is None:
            return u
        motion = v * np.array([np.cos(here[2]), np.sin(here[2])])
        side = 1.0 if motion[0] * normal[1] - motion[1] * normal[0] >= 0.0 else -1.0  # +1: away is left
        # the motion turns at v u / rho (counter-clockwise positive), away from the wall
        # when v u has the sign of `side`
        if float(motion @ normal) < min(BAND_EXIT_SLOPE, 0.05 + depth / 4.0) and v * u * side <= 0.0:
            return float(v * side)
        return u

    def _keep_body_off(self, here: np.ndarray, u: float, v: int) -> float:
        """`u`, or the command that keeps the body farther from the walls (see :meth:`_steer`)."""
        gaps = self._gaps_ahead(here, v)
        if gaps is None:
            return u
        now, ahead = gaps
        if ahead[u] >= BODY_MARGIN or ahead[u] >= now:
            return u
        ahead = {u: ahead[u], **ahead}                  # the law's command first among equals
        best = max(ahead, key=ahead.get)
        return best if ahead[best] > ahead[u] else u

    def _boxed_in(self, v: int) -> bool:
        """Whether every command in gear `v` brings the body within BODY_MARGIN of a wall
        in the next BODY_LOOKAHEAD of driving, closer than it is."""
        gaps = self._gaps_ahead(self.testbed.estimate, v)
        return gaps is not None and all(g < min(BODY_MARGIN, gaps[0]) for g in gaps[1].values())

    def _gaps_ahead(self, here: np.ndarray, v: int) -> tuple[float, dict] | None:
        """The body's distance to the walls at `here` and after BODY_LOOKAHEAD of driving
        in gear `v` with each command (-1, 0, +1), cm; None when no command can bring it
        within BODY_MARGIN in that distance."""
        now = self._body_gap(here)
        if now >= BODY_MARGIN + BODY_LOOKAHEAD:
            return None
        rho = self.testbed.spec.rho
        return now, {c: self._body_gap(dead_reckon(here, c, v, BODY_LOOKAHEAD, rho)) for c in (-1.0, 0.0, 1.0)}

    def _body_gap(self, pose: np.ndarray) -> float:
        """The distance (cm) from the car's body at `pose` to the nearest wall of its map,
        over the corners and along the sides of the body."""
        spec = self.testbed.spec
        corners = car_footprint(pose, spec.length, spec.width)
        sides = np.concatenate([corners + t * (np.roll(corners, -1, axis=0) - corners) for t in BODY_SIDE_SAMPLES])
        return float(self.arena.wall_distance(sides).min())

    def _wall_normal(self, xy: np.ndarray) -> np.ndarray | None:
        """The unit normal pointing away from the nearest wall at `xy` (cm), from the
        wall distance's differences; None where it has no direction."""
        e = 0.05
        d = self.arena.wall_distance(xy + e * np.array([[1, 0], [-1, 0], [0, 1], [0, -1]]))
        normal = np.array([d[0] - d[1], d[2] - d[3]])
        size = float(np.hypot(*normal))
        return normal / size if size > 0 else None

    def _unstick(self, vf, attempts: int = 8) -> bool:
        """Drift brought the estimated pose where φ = inf (inside the clearance band, or
        facing a wall too close to turn): back out with the straight move that leads to
        a finite φ. False if none does."""
        tb = self.testbed
        for _ in range(attempts):
            est = tb.estimate
            if np.isfinite(vf(*self._virtual(vf, est))):
                return True
            best, best_val = None, np.inf
            for u, v in ACTIONS:
                for dist in (2.0, 4.0, 6.0):
                    end = dead_reckon(est, u, v, dist, tb.spec.rho)
                    if not self._free(end, 0.5 * tb.spec.width):
                        continue
                    val = float(vf(*self._virtual(vf, end)))
                    if val + dist < best_val:
                        best, best_val = (u, v, dist), val + dist
            if best is None:
                return False
            u, v, dist = best
            self._event(f"unstick: {'reverse' if v < 0 else 'forward'} {dist:g} cm, steer {u:+d}")
            for _ in range(self._ticks_for(dist)):
                self._tick(u, v)
        return bool(np.isfinite(vf(*self._virtual(vf, tb.estimate))))
