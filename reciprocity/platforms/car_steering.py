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

#: Where every command of the planned gear would bring the body within BODY_MARGIN of a wall
#: in the next BODY_LOOKAHEAD of driving, closer than it is, and the body is already within
#: BACK_OFF_GAP (cm) of one, with no change of gear planned within CUSP_SLACK, the car backs
#: off BACK_OFF cm in the other gear and plans again; after MAX_BACK_OFFS of them on the way
#: to one target it measures where it stands (the plan, which keeps the centre, not the
#: body, off the walls, leads its body into the same wall from there).
BACK_OFF_GAP, BACK_OFF, MAX_BACK_OFFS = 1.0, 3.0, 3

#: Six bang-bang actions (steer, direction): left / straight / right x forward / reverse.
ACTIONS = tuple((u, v) for v in (1, -1) for u in (1, 0, -1))

#: Ticks of the car's own trail kept for the way back (at 30 Hz, about a minute of driving).
TRAIL_TICKS = 2000
#: The way back goes at most this far along the trail (cm).
RETRACE_MAX = 400.0
#: Pure pursuit of the way back: the point tracked lies this far ahead along it (cm), and
#: the car gives up when it strays this far from it (cm).
RETRACE_LOOKAHEAD, RETRACE_STRAY = 3.0, 4.0
#: Stretches of the trail shorter than this (cm) are not driven back (a manoeuvre's jiggle),
#: and a stretch is driven back once the car is nearest to its last RETRACE_END cm.
RETRACE_SKIP, RETRACE_END = 3.0, 1.0


class Steering:
    """Steering by the value function, with the band and body guards (a mixin of
    :class:`~reciprocity.platforms.car.CarPlatform`, whose state it uses)."""

    #: The last answer of :meth:`_gaps_ahead` with what it was computed from.
    _gaps_memo: tuple | None = None

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

    def _backs_off(self, v: int) -> bool:
        """Whether the body is within BACK_OFF_GAP of a wall and every command in gear `v`
        brings it closer, within BODY_MARGIN (see BACK_OFF_GAP)."""
        gaps = self._gaps_ahead(self.testbed.estimate, v)
        return gaps is not None and gaps[0] < BACK_OFF_GAP and all(g < min(BODY_MARGIN, gaps[0])
                                                                   for g in gaps[1].values())

    def _back_off(self, v: int) -> None:
        """Drive BACK_OFF cm in the gear other than `v`, each tick with the command that keeps
        the body farthest from the walls (ties to driving straight)."""
        tb = self.testbed
        self._event(f"back off: {BACK_OFF:g} cm {'forward' if v < 0 else 'in reverse'}, the body "
                    f"{self._body_gap(tb.estimate):.2f} cm from a wall")
        for _ in range(self._ticks_for(BACK_OFF)):
            est = tb.estimate
            gaps = {c: self._body_gap(dead_reckon(est, c, -v, BODY_LOOKAHEAD, tb.spec.rho)) for c in (0.0, -1.0, 1.0)}
            self._tick(max(gaps, key=gaps.get), -v)

    def _boxed_in(self, v: int) -> bool:
        """Whether every command in gear `v` brings the body within BODY_MARGIN of a wall
        in the next BODY_LOOKAHEAD of driving, closer than it is."""
        gaps = self._gaps_ahead(self.testbed.estimate, v)
        return gaps is not None and all(g < min(BODY_MARGIN, gaps[0]) for g in gaps[1].values())

    def _gaps_ahead(self, here: np.ndarray, v: int) -> tuple[float, dict] | None:
        """The body's distance to the walls at `here` and after BODY_LOOKAHEAD of driving
        in gear `v` with each command (-1, 0, +1), cm; None when no command can bring it
        within BODY_MARGIN in that distance.

        The guards of one tick (:meth:`_backs_off` or :meth:`_boxed_in`, then
        :meth:`_keep_body_off`) ask at the same pose and gear: the last answer is kept,
        for the exact pose, the gear, the map object (an unknown map is replaced by a
        new :class:`~arenas.Arena` when it changes, never changed in place) and the car's
        specification, everything :meth:`_body_gap` reads."""
        here = np.asarray(here, dtype=float)
        spec = self.testbed.spec
        key = (here.tobytes(), int(v))
        memo = self._gaps_memo
        if memo is None or memo[0] != key or memo[1] is not self.arena or memo[2] is not spec:
            memo = self._gaps_memo = (key, self.arena, spec, self._gaps_at(here, v))
        gaps = memo[3]
        return None if gaps is None else (gaps[0], dict(gaps[1]))

    def _gaps_at(self, here: np.ndarray, v: int) -> tuple[float, dict] | None:
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

    def _retrace(self, vf) -> bool:
        """No path from the pose, nor from a short move (:meth:`_unstick`): drive back the
        way the car came, along its own trail, to the newest pose of it at most RETRACE_MAX
        cm back from which φ is finite (a gap the believed walls closed behind the car, a
        dead end too narrow to turn in: the car has been there, so the way back is open).
        Each stretch driven in one gear is tracked back in the other (:meth:`_track_back`).
        False when no pose of the trail has a finite φ, or the car ends where neither it
        nor a short move has."""
        trail = self._trail
        if len(trail) < 2:
            return False
        poses = np.array([p for p, _, _ in trail])
        gears = np.array([g for _, _, g in trail])
        steps = np.hypot(*np.diff(poses[:, :2], axis=0).T)
        back = np.append(np.cumsum(steps[::-1])[::-1], 0.0)      # cm from each pose to the newest
        phi = np.asarray(vf(poses[:, 0], poses[:, 1], poses[:, 2]), dtype=float).ravel()
        ok = np.isfinite(phi) & (back > 0) & (back <= RETRACE_MAX)
        if not ok.any():
            return False
        i = int(np.flatnonzero(ok)[-1])
        self._event(f"retrace: back {back[i]:.0f} cm along the way the car came")
        self._retracing, back_home = True, True
        try:
            b = len(poses) - 1
            while b > i:                  # ticks a..b were driven in one gear, from pose a - 1 to pose b
                a = b
                while a - 1 > i and gears[a - 1] == gears[b]:
                    a -= 1
                # a stretch shorter than RETRACE_SKIP (the jiggle of a manoeuvre) is not driven again
                if back[a - 1] - back[b] >= RETRACE_SKIP and \
                        not self._track_back(poses[a - 1:b + 1][::-1], -int(gears[b])):
                    back_home = False
                    break
                b = a - 1
        finally:
            self._retracing = False
            if back_home:
                while len(trail) > i + 1:
                    trail.pop()
            else:                         # the car is off its trail: it is no way back any more
                trail.clear()
        return self._unstick(vf)

    def _track_back(self, waypoints: np.ndarray, gear: int) -> bool:
        """Drive in `gear` along `waypoints` (m, 3) from near the first to the last, by pure
        pursuit of a point RETRACE_LOOKAHEAD cm ahead along them; False when the car strays
        more than RETRACE_STRAY cm from them or the stretch takes twice its length."""
        tb = self.testbed
        xy = waypoints[:, :2]
        s = np.append(0.0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T)))
        step = tb.spec.speed * tb.period
        k, driven = 0, 0.0
        while True:
            est = tb.estimate
            window = slice(k, min(len(xy), k + 40))
            k += int(np.argmin(np.hypot(*(xy[window] - est[:2]).T)))
            near = float(np.hypot(*(xy[k] - est[:2])))
            if near > RETRACE_STRAY or driven > 2.0 * s[-1] + 10.0:
                self._event(f"retrace: strayed {near:.1f} cm from the way back")
                return False
            if s[-1] - s[k] <= RETRACE_END:         # the nearest point is at the end: back there
                return True
            goal = xy[min(int(np.searchsorted(s, s[k] + RETRACE_LOOKAHEAD)), len(xy) - 1)]
            dx, dy = goal - est[:2]
            c, sn = np.cos(est[2]), np.sin(est[2])
            lateral, dist2 = -sn * dx + c * dy, dx * dx + dy * dy
            u = float(np.clip(2.0 * tb.spec.rho * lateral / max(dist2, 1e-9), -1.0, 1.0))
            self._tick(u, gear)
            driven += step

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
