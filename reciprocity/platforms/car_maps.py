"""The walls the car plans on and the value functions it drives with: the known walls, or on
an unknown map its believed and scanned walls, re-planned as its scans change them (a part
of :class:`~reciprocity.platforms.car.CarPlatform`)."""

from __future__ import annotations

import numpy as np

from arenas import Arena
from arenas.car import car_footprint
from hjplanner import OnDemandPlanner, PlanningError

from ..errors import UnreachableTarget
from ..observations import Observation

#: With a range sensor the car scans every this many cm driven (cm), and at every re-plan:
#: a scan per camera frame (30 Hz) would come every 0.3 cm at the car's speed and add
#: nothing a sensor of tens of cm has not seen.
SCAN_EVERY = 5.0

#: On an unknown map the cells under the car's body at each pose it drove through (as the
#: camera estimates it) are free for certain; the body is drawn this much smaller on every
#: side (cm), for the estimate's error and the car's contacts with walls.
SWEEP_MARGIN = 0.5

#: The scanned walls (hit cells as they are) reach on average half a cell into the free
#: space (a wall's surface lies anywhere in the cell its beams hit, and the walls are
#: traced along the cells' edges): the car keeps its clearance less this share of a cell
#: from them, its clearance from the true walls on average.
SCANNED_BIAS_CELLS = 0.5


class WallMaps:
    """Which walls the car plans on and the value function of each target (a mixin of
    :class:`~reciprocity.platforms.car.CarPlatform`, whose state it uses)."""

    def _plan(self, target: np.ndarray):
        """The value function the car drives to `target` with, from its pose: on the
        believed walls, or on an unknown map, when they shut the target out, on the scanned
        walls (the map it then drives on). Drift into a wall's clearance band is backed
        out of (:meth:`_unstick`) only when no map has a path from the pose itself, and
        the car drives back the way it came (:meth:`_retrace`) only when no short move
        gives one. UnreachableTarget when no map has a path."""
        candidates, failure = [], None
        for walls in ("believed", "scanned") if self.grid is not None else ("believed",):
            self._plan_on(walls)
            try:
                vf = self._solve(target)
            except UnreachableTarget as exc:
                failure = exc
                continue
            if np.isfinite(vf(*self._virtual(vf, self.testbed.estimate))):
                return self._driving_on(walls, vf)
            candidates.append((walls, vf))
        for walls, vf in candidates:
            self._plan_on(walls)
            est = self._virtual(vf, self.testbed.estimate)
            if self._unstick(vf):
                return self._driving_on(walls, vf)
            failure = UnreachableTarget(target, (
                f"target ({target[0]:.1f}, {target[1]:.1f}) cm cannot be reached from the car's "
                f"pose ({est[0]:.1f}, {est[1]:.1f}): it is enclosed, or behind a gap narrower "
                f"than twice the clearance of {self._clearance():g} cm"))
        for walls, vf in candidates:          # the way back: where the car came from, φ may be finite
            self._plan_on(walls)
            if self._retrace(vf):
                return self._driving_on(walls, vf)
        raise failure

    def _solve(self, target: np.ndarray):
        """The value function of `target` (or the nearest standable point) on the map the
        car plans on now; UnreachableTarget when there is none."""
        goal = self._standable(target)
        try:
            return self._value_for(goal)
        except PlanningError as exc:
            raise UnreachableTarget(target, f"no value function for target ({target[0]:.1f}, "
                                    f"{target[1]:.1f}) cm: {exc}") from None

    def _replan_target(self, target: np.ndarray):
        """After the map changed on the way: the target's value function on the new map,
        or on the scanned walls when the believed ones now shut it out from the pose;
        UnreachableTarget when neither has it."""
        failure = vf = None
        try:
            vf = self._solve(target)
        except UnreachableTarget as exc:
            failure = exc
        if self.walls == "believed" and self.grid is not None and (
                vf is None or not np.isfinite(vf(*self._virtual(vf, self.testbed.estimate)))):
            self._plan_on("scanned")
            try:
                alt = self._solve(target)
                if np.isfinite(alt(*self._virtual(alt, self.testbed.estimate))):
                    return self._driving_on("scanned", alt)
            except UnreachableTarget:
                pass
            self._plan_on("believed")
        if vf is None:
            raise UnreachableTarget(target, f"target ({target[0]:.1f}, {target[1]:.1f}) cm is "
                                    f"behind walls the car has just seen: {failure}") from None
        return vf

    def _driving_on(self, walls: str, vf):
        """Note that the car drives on `walls` with `vf` (returned)."""
        if walls == "scanned":
            self.scanned_plans += 1
            self._event("the believed walls shut the target out: driving on the scanned walls")
        self._note_map()
        return vf

    def _plan_on(self, walls: str) -> None:
        """Plan on `walls` ("believed", or "scanned": brought up to the grid first)."""
        if walls == "scanned":
            self._refresh("scanned")
        arena, planner = self._maps[walls]
        self.walls = walls
        if arena is not self.arena:
            self.arena, self.planner = arena, planner
            self._value_function = planner.get

    def _refresh(self, walls: str) -> bool:
        """Bring the map of `walls` up to the grid; True when it changed. A new map that
        puts the car's position in a wall is not taken."""
        here = self.testbed.estimate[:2].copy()
        old = self._maps[walls][0]
        new = (self.grid.believed_arena() if walls == "believed" else self.grid.scanned_arena()).without_scenario()
        if new is old or _same_walls(new, old) or not new.contains(here[None])[0]:
            return False
        options = dict(self._planner_options, clearance=self._clearance(walls))
        self._maps[walls] = (new, OnDemandPlanner(new, maxsize=8, **options))
        return True

    def _clearance(self, walls: str | None = None) -> float:
        """The clearance the car keeps from `walls` (default: the walls it plans on), cm."""
        if (walls or self.walls) == "scanned":
            return self.options.clearance - SCANNED_BIAS_CELLS * self.grid.cell
        return self.options.clearance

    def _note_map(self) -> None:
        """Log the walls the car plans on, with the time they became current (for the
        video), when they differ from the last logged."""
        if self.grid is None or self.arena is self._noted:
            return
        self._noted = self.arena
        self._log.setdefault("maps", []).append(dict(
            time=self.testbed.time, walls=self.walls,
            obstacles=[np.round(np.asarray(o, dtype=float), 3).tolist() for o in self.arena.obstacles]))

    def _value_for(self, goal: np.ndarray):
        """The value function the car drives to `goal` with. On demand with a `window`:
        solved in the rectangle of the car and the goal widened by the window, unless the
        car's pose cannot reach the goal inside it; then on the whole map."""
        o = self.options
        if o.planner == "bank" or o.window is None:
            return self._value_function(goal)
        vf = self.planner.get(goal, near=self.testbed.estimate[:2], margin=o.window)
        if "window" not in vf.meta or np.isfinite(vf(*self._virtual(vf, self.testbed.estimate))):
            return vf
        return self._value_function(goal)

    def _sense(self) -> bool:
        """One scan of the true walls from the true pose, kept for the strategy; on an
        unknown map, taken into the car's grid at the camera's estimate. True when the
        believed walls changed (the planner then works on the new map)."""
        self._since_scan = 0.0
        tb = self.testbed
        scan = self.lidar.scan(self.world.true_arena, tb.car.pose, self.rng)
        here = tb.estimate[:2].copy()
        self._scans.append(Observation(here, float(scan.ranges.min()), tb.time, 0.0, "scan", agent=self.agent,
                                       data=scan.as_data()))
        if self.grid is None:
            return False
        spec = tb.spec
        bodies = [car_footprint(p, spec.length - 2 * SWEEP_MARGIN, spec.width - 2 * SWEEP_MARGIN)
                  for p in self._swept if np.all(np.isfinite(p))]
        self._swept = []
        self.grid.sweep(bodies)
        self.grid.update(here, scan.angles, scan.ranges, scan.hit, scan.max_range)
        changed = self._refresh("believed")
        if self.walls == "scanned":
            changed = self._refresh("scanned")
        if not changed:
            return False
        self._plan_on(self.walls)
        self._note_map()
        self._event(f"map changed at ({here[0]:.1f}, {here[1]:.1f}): re-planning on "
                    f"{len(self.arena.obstacles)} {self.walls} obstacle(s)")
        return True


def _same_walls(a: Arena, b: Arena) -> bool:
    """Whether two arenas have the same boundary and obstacles."""
    return (np.array_equal(a.boundary, b.boundary) and len(a.obstacles) == len(b.obstacles)
            and all(np.array_equal(x, y) for x, y in zip(a.obstacles, b.obstacles)))
