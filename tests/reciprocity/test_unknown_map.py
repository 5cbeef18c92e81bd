"""Unknown obstacles (issue 23, part 1): the range sensor, the scenario keys, the occupancy
grid, and the reciprocity search on a believed map that never holds the true walls."""

import numpy as np
import pytest
from shapely.geometry import Point, Polygon
from shapely.ops import unary_union

import arenas
from reciprocity.cli import main
from reciprocity.env import SearchEnv, rollout
from reciprocity.errors import SearchError
from reciprocity.intents import Measure, Survey
from reciprocity.observations import readings_of
from reciprocity.platforms.lidar import LIDAR_DEFAULTS, Lidar, ray_ranges, wall_segments
from reciprocity.spaces.occupancy import OccupancyGrid
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.agent import StrategyAgent
from reciprocity.strategies.mapping import MapKeeper

SQUARE = [[0, 0], [100, 0], [100, 100], [0, 100]]


# -- the sensor (truth) -------------------------------------------------------------------
def test_ray_ranges_are_exact_against_a_square_and_a_wall():
    arena = arenas.Arena.from_polygons(SQUARE, [[[60, 40], [70, 40], [70, 60], [60, 60]]])
    a, b = wall_segments(arena)
    angles = np.array([0.0, np.pi / 2, np.pi, 3 * np.pi / 2, np.pi / 4])
    r, hit = ray_ranges((20.0, 50.0), angles, a, b, 200.0)
    np.testing.assert_allclose(r[:4], [40.0, 50.0, 20.0, 50.0])
    assert hit.all()
    r, hit = ray_ranges((20.0, 50.0), angles, a, b, 30.0)          # capped: the range, flagged
    np.testing.assert_allclose(r, [30.0, 30.0, 20.0, 30.0, 30.0])
    assert hit.tolist() == [False, False, True, False, False]


def test_lidar_noise_comes_from_the_given_generator_and_spares_missed_beams():
    arena = arenas.load("empty")
    lidar = Lidar(beams=16, range=50.0, noise=0.5)
    s1 = lidar.scan(arena, (20.0, 70.0, 0.0), np.random.default_rng(3))
    s2 = lidar.scan(arena, (20.0, 70.0, 0.0), np.random.default_rng(3))
    np.testing.assert_array_equal(s1.ranges, s2.ranges)
    assert np.all(s1.ranges[~s1.hit] == 50.0) and s1.hit.any() and (~s1.hit).any()
    exact = lidar.scan(arena, (20.0, 70.0, 0.0), np.random.default_rng(3)).ranges
    assert np.all(np.abs(s1.ranges - exact) < 3.0)


# -- the scenario keys and the command line -----------------------------------------------
def test_unknown_map_tells_the_boundary_and_the_default_lidar():
    env = SearchEnv("deep_u", world={"map": "unknown"})
    _, info = env.reset(seed=0)
    nominal = info["task"].world_nominal
    assert nominal["map"] == "unknown" and nominal["arena"].obstacles == []
    assert nominal["lidar"] == LIDAR_DEFAULTS
    assert len(env.world.true_arena.obstacles) == 1
    known = SearchEnv("deep_u").reset(seed=0)[1]["task"].world_nominal
    assert "map" not in known and "lidar" not in known and len(known["arena"].obstacles) == 1


def test_a_partial_map_file_is_told(tmp_path):
    part = tmp_path / "part.yaml"
    part.write_text("boundary: [[0, 0], [140, 0], [140, 140], [0, 140]]\n"
                    "obstacles:\n  - [[0, 32], [108, 32], [108, 38], [0, 38]]\n")
    env = SearchEnv("maze", world={"map": {"known": str(part)}, "lidar": {"beams": 32}})
    nominal = env.reset(seed=0)[1]["task"].world_nominal
    assert nominal["map"] == "unknown" and len(nominal["arena"].obstacles) == 1
    assert nominal["lidar"] == {"beams": 32, "range": 40.0, "noise": 0.5}


@pytest.mark.parametrize("world, match", [
    ({"map": "partly"}, "map must be one of known, unknown"),
    ({"map": {"known": 3}}, "map: known must name an arena file"),
    ({"lidar": {"beams": 3}}, "lidar beams must be a whole number from 4"),
    ({"lidar": {"range": 0}}, "lidar range must be a number in (0, 1000] cm; got 0"),
    ({"lidar": {"noise": -1}}, "lidar noise must be a number in [0, 100] cm"),
    ({"lidar": {"colour": 1}}, "unknown lidar key(s) colour"),
    ({"lidar": [64]}, "lidar must be a mapping"),
])
def test_bad_map_and_lidar_values_are_refused(world, match):
    with pytest.raises(SearchError, match=None) as exc:
        SearchEnv("paper", world=world)
    assert match in str(exc.value)


@pytest.mark.parametrize("flags, match", [
    (["--lidar", "beams=2"], "lidar beams must be a whole number from 4 to 4096; got 2"),
    (["--lidar", "beams=64,range=-1"], "lidar range must be"),
    (["--lidar", "beams"], "--lidar expects KEY=VALUE"),
])
def test_cli_lidar_errors_exit_2(flags, match, capsys):
    argv = ["run", "--arena", "paper", "--strategy", "reciprocity", "--unknown-map", *flags, "--quiet"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and match in err and err.count("\n") == 1


# -- the point observer's scans -----------------------------------------------------------
def test_the_point_observer_scans_after_its_reading_and_only_with_a_lidar():
    env = SearchEnv("paper", world={"map": "unknown", "lidar": {"beams": 8}})
    env.reset(seed=0)
    obs = env.step(Measure(np.array([128.0, 20.0])))[0][0].observations
    assert [o.kind for o in obs] == ["signal", "scan"]
    assert len(obs[1].data["ranges"]) == 8 and obs[1].data["max_range"] == 40.0
    plain = SearchEnv("paper")
    plain.reset(seed=0)
    assert [o.kind for o in plain.step(Measure(np.array([128.0, 20.0])))[0][0].observations] == ["signal"]


def test_a_survey_moves_and_scans_without_a_reading_and_only_with_a_lidar():
    env = SearchEnv("paper", world={"map": "unknown", "lidar": {"beams": 8}})
    _, info = env.reset(seed=0)
    assert "survey" in info["task"].intents and "measure" in info["task"].intents
    percept = env.step(Survey(np.array([128.0, 20.0])))[0][0]
    assert [o.kind for o in percept.observations] == ["scan"]
    assert np.allclose(percept.observations[0].position, [128.0, 20.0])
    plain = SearchEnv("paper")
    _, info = plain.reset(seed=0)
    assert "survey" not in info["task"].intents
    with pytest.raises(SearchError, match="range sensor"):
        plain.step(Survey(np.array([128.0, 20.0])))


@pytest.mark.slow
def test_on_an_unknown_map_the_search_explores_by_surveys_that_are_no_readings():
    """Surveys (scan, no reading) carry the search round the spiral: fewer readings than
    reading at every frontier point, each survey a round of its own, never a reading."""
    from reciprocity.scenarios import load_scenario
    scenario = load_scenario(arenas.generate("spiral", 0))
    runs = {}
    for survey in (True, False):
        env = SearchEnv(scenario, world={"map": "unknown"})
        # the prior over the whole free region, as when this draw was chosen (the arena's
        # source_clearance would change the path; tests/reciprocity/test_source_clearance.py)
        agent = StrategyAgent(STRATEGIES["reciprocity"], {"survey": survey, "h": 2.0, "source_clearance": 0})
        runs[survey] = rollout(env, agent, seed=0).summary
    on, off = runs[True], runs[False]
    assert on["surveys"] > 0 and off["surveys"] == 0
    # every round is a reading, a survey or a target the platform refused
    assert on["steps"] == on["n_measurements"] + on["surveys"] + on.get("n_rejected", 0)
    assert on["converged"] and on["n_measurements"] < off["n_measurements"]


def test_the_signal_readings_do_not_change_when_a_lidar_is_added():
    """The scan draws its noise after the reading: the first reading is the same."""
    values = []
    for world in ({}, {"lidar": {"beams": 8}}):
        env = SearchEnv("paper", world=world)
        env.reset(seed=4)
        values.append(readings_of(env.step(Measure(np.array([128.0, 20.0])))[0][0].observations)[0].value)
    assert values[0] == values[1]


def test_a_strategy_that_does_not_map_never_sees_a_scan():
    seen = []

    class Spy(STRATEGIES["gradient"]):
        def observe(self, observations, intent, agent=0):
            seen.extend(o.kind for o in observations)
            super().observe(observations, intent, agent)

    ep = rollout(SearchEnv("empty", world={"map": "unknown"}), StrategyAgent(Spy, {"max_steps": 3}), seed=1)
    assert seen and "scan" not in seen
    assert ep.summary["map"] == "unknown" and ep.trace[0]["scans"]


# -- the occupancy grid (belief) -----------------------------------------------------------
def test_the_grid_believes_a_wall_where_the_beams_hit_it_and_keeps_its_arena_when_unchanged():
    true = arenas.Arena.from_polygons(SQUARE, [[[60, 20], [66, 20], [66, 80], [60, 80]]])
    grid = OccupancyGrid(arenas.Arena.from_polygons(SQUARE))
    lidar = Lidar(beams=128, range=60.0, noise=0.0)
    scan = lidar.scan(true, (30.0, 50.0, 0.0), np.random.default_rng(0))
    grid.update((30.0, 50.0), scan.angles, scan.ranges, scan.hit, scan.max_range)
    arena = grid.believed_arena()
    assert grid.revision == 1 and len(arena.obstacles) == 1
    wall = Polygon(arena.obstacles[0])
    assert wall.distance(Polygon([[60, 20], [66, 20], [66, 80], [60, 80]])) == 0
    assert 57.0 < wall.bounds[0] < 60.5 and wall.bounds[2] < 64.0     # the side seen, not the far side
    assert not grid.seen_at([[80.0, 50.0]])[0] and grid.free_at([[40.0, 50.0]])[0]
    assert grid.frontier().any()
    grid.update((30.0, 50.0), scan.angles, scan.ranges, scan.hit, scan.max_range)
    assert grid.believed_arena() is arena and grid.revision == 1


# -- the search: truth never reaches the strategy ------------------------------------------
def test_reciprocity_on_an_unknown_map_holds_only_walls_the_lidar_saw():
    """Fails if the true walls leak into the strategy: its solver's walls must all lie
    where its scans reached, and the task's arena holds none."""
    env = SearchEnv("deep_u", world={"map": "unknown"})
    agent = StrategyAgent(STRATEGIES["reciprocity"], {"h": 2.0, "max_steps": 4})
    ep = rollout(env, agent, seed=0)
    strat = agent.strategy
    assert isinstance(strat.mapping, MapKeeper)
    assert strat.solver.arena is strat.mapping.arena is not env.world.true_arena
    scanned = unary_union([Polygon(np.asarray(s["position"]) + np.column_stack(
        [np.cos(s["angles"]), np.sin(s["angles"])]) * np.asarray(s["ranges"])[:, None]).buffer(3.0)
        for rec in ep.trace for s in rec.get("scans", [])])
    believed = unary_union([Polygon(o) for o in strat.solver.arena.obstacles])
    assert believed.area > 0 and believed.difference(scanned).area < 1.0
    true = Polygon(env.world.true_arena.obstacles[0])
    assert true.difference(believed).area > 0.3 * true.area       # the unseen part is not there
    assert ep.summary["n_measurements"] == 4 or ep.summary["converged"]


def test_run_with_unknown_map_writes_the_mapping_figure(tmp_path, capsys):
    rc = main(["run", "--arena", "deep_u", "--strategy", "reciprocity", "--unknown-map", "--lidar", "beams=32",
               "--h", "3", "--set", "max_steps=3", "--out", str(tmp_path), "--quiet", "--json",
               str(tmp_path / "s.json")])
    assert rc == 0, capsys.readouterr().err
    assert (tmp_path / "reciprocity_map_steps.png").stat().st_size > 10_000
    import json
    summary = json.loads((tmp_path / "s.json").read_text())
    assert summary["map"] == "unknown" and summary["lidar"]["beams"] == 32


def test_a_partial_map_stays_in_the_believed_arena(tmp_path):
    part = tmp_path / "part.yaml"
    part.write_text("boundary: [[0, 0], [140, 0], [140, 140], [0, 140]]\n"
                    "obstacles:\n  - [[32, 68], [140, 68], [140, 74], [32, 74]]\n")
    env = SearchEnv("maze", world={"map": {"known": str(part)}})
    agent = StrategyAgent(STRATEGIES["reciprocity"], {"h": 3.0, "max_steps": 2})
    ep = rollout(env, agent, seed=0)
    told = Polygon([[32, 68], [140, 68], [140, 74], [32, 74]])
    believed = unary_union([Polygon(o) for o in agent.strategy.solver.arena.obstacles])
    assert told.difference(believed).area < 1.0
    assert ep.summary["map"] == "partial"


# -- the strategy's choices on hand-built beliefs ---------------------------------------------
def _keeper_after_one_scan():
    """A map of a 100 cm square seen from (20, 50) with a 30 cm lidar: the right part unseen."""
    square = arenas.Arena.from_polygons(SQUARE)
    keeper = MapKeeper(square, {"beams": 64, "range": 30.0, "noise": 0.0})
    scan = Lidar(64, 30.0, 0.0).scan(square, (20.0, 50.0, 0.0), np.random.default_rng(0))
    from reciprocity.observations import Observation
    keeper.update([Observation((20.0, 50.0), 0.0, kind="scan", data=scan.as_data())])
    return keeper


def test_the_frontier_point_serves_mass_behind_unseen_space_and_only_then():
    from reciprocity.spaces import mesh_space
    keeper = _keeper_after_one_scan()
    space = mesh_space(keeper.arena, 4.0)
    allowed = keeper.admissible(space.points)
    assert allowed.any() and not keeper.admissible(np.array([[80.0, 50.0]]))[0]
    far = np.exp(-np.sum((space.points - [85.0, 50.0]) ** 2, axis=1) / 50.0)   # mass behind the unseen
    near_mass = lambda y: np.array([far[np.sum((space.points - p) ** 2, axis=1) < 400].sum() for p in y])
    point = keeper.frontier_point(space, far, allowed, (20.0, 50.0), near_mass)
    assert point is not None and point[0] > 40.0 and abs(point[1] - 50.0) < 10.0
    home = np.exp(-np.sum((space.points - [20.0, 50.0]) ** 2, axis=1) / 50.0)  # mass in seen space
    assert keeper.frontier_point(space, home, allowed, (20.0, 50.0), near_mass) is None


def test_the_model_error_narrows_as_the_map_is_seen():
    keeper = _keeper_after_one_scan()
    wide = keeper.model_error()
    assert 0.05 < wide < 0.35 and keeper.model_error(0.5) == pytest.approx(np.hypot(0.5, wide))   # in quadrature
    square = arenas.Arena.from_polygons(SQUARE)
    from reciprocity.observations import Observation
    for p in [(50.0, 50.0), (80.0, 20.0), (80.0, 80.0), (20.0, 80.0), (20.0, 20.0)]:
        scan = Lidar(64, 60.0, 0.0).scan(square, (*p, 0.0), np.random.default_rng(0))
        keeper.update([Observation(p, 0.0, kind="scan", data=scan.as_data())])
    assert keeper.model_error() < wide


def test_imaging_on_the_same_solver_gives_the_same_map():
    import reciprocity
    solver = reciprocity.GreenSolver(arenas.load("empty"), h=6.0)
    u = solver.field((90.0, 60.0), strength=600.0)
    im = reciprocity.ImagingMap(solver, sigma=12.0, strength=600.0, combine="product", model_error=0.1)
    for z in [(30.0, 30.0), (60.0, 100.0), (110.0, 30.0)]:
        im.add(z, float(u([z])[0]))
    np.testing.assert_allclose(im.on(solver).values(), im.values())
    assert im.on(solver, model_error=0.3).model_error == 0.3


def test_a_shortfall_forgives_readings_below_the_open_model_and_only_those():
    """Walls not yet seen can only lower the signal: with a shortfall, a reading below the
    prediction costs less, one above it the same; without one, the map is unchanged."""
    import reciprocity
    from reciprocity.strategies.mapping import ShortfallImaging
    solver = reciprocity.GreenSolver(arenas.load("empty"), h=6.0)
    u = solver.field((90.0, 60.0), strength=600.0)
    zs = [(30.0, 30.0), (60.0, 100.0), (110.0, 30.0)]
    im = reciprocity.ImagingMap(solver, sigma=12.0, strength=600.0, combine="product", model_error=0.05)
    for z in zs:
        im.add(z, 0.5 * float(u([z])[0]))                # every reading half the open model's
    flat = ShortfallImaging.of(im, 0.0)
    np.testing.assert_allclose(flat.values(), im.values())
    src = solver.locator.locate(np.array([[90.0, 60.0]]))
    node = int(np.argmin(np.sum((solver.nodes - [90.0, 60.0]) ** 2, axis=1)))
    r = im._residuals()
    assert np.all(r[node] > 0) and src[0] >= 0                   # the model over-predicts there
    short = ShortfallImaging.of(im, 0.5)
    assert short._correlated_misfit(r)[node] < im._correlated_misfit(r)[node]
    above = -r                                                   # the same misfits, readings above
    np.testing.assert_array_less(im._correlated_misfit(above)[node] - 1e-9, short._correlated_misfit(above)[node])
    assert isinstance(short.on(solver), ShortfallImaging) and short.on(solver).shortfall == 0.5


@pytest.mark.slow            # about 11 s: a whole car episode on an unknown map
def test_the_car_on_an_unknown_map_plans_on_what_it_has_seen():
    """The car is told the boundary only: it plans on its own occupancy grid, re-plans as
    walls appear, returns its scans to the strategy, and never learns a wall its beams did
    not reach; the true walls stay with the testbed's physics."""
    from reciprocity.env import SearchEnv, rollout
    from reciprocity.scenarios import from_dict
    from reciprocity.strategies import STRATEGIES
    from reciprocity.strategies.agent import StrategyAgent
    sc = from_dict(dict(world="poisson", arena={"name": "box-car", "boundary": [[0, 0], [100, 0], [100, 80], [0, 80]],
                                                "obstacles": [[[40, 20], [60, 20], [60, 50], [40, 50]]],
                                                "strength": 600, "source": [20, 30], "start": [80, 30, 90]},
                        map="unknown", lidar={"beams": 32, "range": 40, "noise": 0.5}), name="box-car")
    env = SearchEnv(sc, platform="car")
    env.reset(seed=0)
    car = env.platforms[0]
    assert not car.arena.obstacles and car.grid is not None          # told the boundary only
    episode = rollout(env, StrategyAgent(STRATEGIES["reciprocity"]), 0)
    s = episode.summary
    car = env.platforms[0]                                               # this episode's car
    assert s["success"] and s["collisions"] == 0
    assert car.grid.revision >= 1 and car.arena.obstacles                 # walls it has seen
    true = Polygon([[40, 20], [60, 20], [60, 50], [40, 50]])
    believed = np.vstack([np.asarray(o) for o in car.arena.obstacles])
    assert max(true.exterior.distance(Point(*p)) for p in believed) <= 3.5   # only walls that are there (cell 1 cm, dilated)
    events = [e["text"] for r in episode.records for e in (r.platform or {}).get("events", [])]
    assert any("re-planning" in e for e in events)
    scans = [o for r in episode.records for o in r.observations if o.kind == "scan"]
    assert len(scans) >= s["n_measurements"]                             # the strategy got them too
    surveyed = [r for r in episode.records if r.intent == "survey"]
    assert len(surveyed) == s["surveys"] and all(o.kind == "scan" for r in surveyed for o in r.observations)


def test_a_value_function_bank_needs_a_known_map():
    from reciprocity.env import SearchEnv
    from reciprocity.errors import SearchError
    env = SearchEnv("paper", platform="car", world={"map": "unknown"}, platform_options={"planner": "bank"})
    with pytest.raises(SearchError, match="planner=on-demand"):
        env.reset(seed=0)


# -- the car's own map: the corridor it drove, the scanned walls, refused targets ----------
BOX = [[0, 0], [100, 0], [100, 60], [0, 60]]
#: a wall across the box with a 12 cm gap: open at the car's 4 cm clearance on the true
#: walls and on the scanned ones, closed on the believed (dilated) ones. (An 11 cm gap
#: passed on the scanned walls only while scans eroded the wall ends beside it, see
#: ``test_a_wall_corner_is_not_cleared_by_the_beams_that_pass_it``; on its true width in
#: cells it leaves the planner a band one node wide.)
GAP_WALLS = [[[48, 0], [54, 0], [54, 24], [48, 24]], [[48, 36], [54, 36], [54, 60], [48, 60]]]


def _scanned_grid(true, positions, beams=64):
    grid = OccupancyGrid(arenas.Arena.from_polygons(true.boundary))
    lidar, rng = Lidar(beams=beams, range=40.0, noise=0.5), np.random.default_rng(0)
    for p in positions:
        scan = lidar.scan(true, (*p, 0.0), rng)
        grid.update(p, scan.angles, scan.ranges, scan.hit, scan.max_range)
    return grid


def test_the_scanned_walls_keep_a_gap_the_believed_walls_close():
    from hjplanner import OnDemandPlanner
    from reciprocity.platforms.car import _finite_somewhere
    true = arenas.Arena.from_polygons(BOX, GAP_WALLS)
    grid = _scanned_grid(true, [(x, y) for x in range(15, 41, 5) for y in (20.0, 30.0, 40.0)])
    through = {}
    for name, arena in (("true", true), ("believed", grid.believed_arena()), ("scanned", grid.scanned_arena())):
        planner = OnDemandPlanner(arena, rho=15.0, h=1.5, ntheta=48, clearance=4.0, reverse=True, maxsize=1)
        through[name] = bool(_finite_somewhere(planner.get(np.array([80.0, 30.0])), np.array([[20.0, 30.0]]))[0])
    assert through == {"true": True, "believed": False, "scanned": True}
    raw, believed = grid.obstacle_mask(dilate=False), grid.obstacle_mask()
    assert raw.sum() < believed.sum() and not (raw & ~believed).any()       # thinner, never elsewhere
    assert grid.scanned_arena() is grid.scanned_arena()                      # kept while unchanged


def test_a_wall_corner_is_not_cleared_by_the_beams_that_pass_it():
    """Scans from beside a wall's bottom face: a beam that passes the corner and its
    neighbour that hits the wall are not joined by a chord (it would run through the wall
    behind the corner and clear its cells, scan after scan, as it erased the corner the car
    hit on ``paper``). With the old chords (no silhouette cut) the corner's row is cleared."""
    from reciprocity.spaces import occupancy
    true = arenas.Arena.from_polygons(BOX, [[[40, 30], [46, 30], [46, 50], [40, 50]]])
    positions = [(x, y) for x in (8.0, 14.0, 20.0, 26.0) for y in (29.0, 31.0, 32.5)]

    def wall_cells_believed_free(silhouette):
        old, occupancy.SILHOUETTE_CELLS = occupancy.SILHOUETTE_CELLS, silhouette
        try:
            grid = _scanned_grid(true, positions)
        finally:
            occupancy.SILHOUETTE_CELLS = old
        centres = grid.centres().reshape(-1, 2)
        return int((grid.free.ravel() & grid.inside.ravel() & ~true.contains(centres)).sum())

    assert wall_cells_believed_free(np.inf) >= 8          # the bottom row of the wall, cleared
    assert wall_cells_believed_free(occupancy.SILHOUETTE_CELLS) <= 1


def test_the_visibility_outline_keeps_chords_along_a_wall_and_cuts_them_past_a_corner():
    from reciprocity.spaces.occupancy import visibility_outline
    ang = np.radians([0.0, 10.0, 20.0, 30.0])
    d = np.column_stack([np.cos(ang), np.sin(ang)])
    # a wall x = 10 seen at growing range: every chord lies on it, nothing is cut
    along = 10.0 / np.cos(ang)
    out = visibility_outline(np.zeros(2), d, along, np.ones(4, bool), 2.0)
    np.testing.assert_allclose(out, along[:, None] * d)
    # beam 2 passes the wall's end and reaches 40 cm: cut back to the nearer reach
    past = along.copy()
    past[2] = 40.0
    out = visibility_outline(np.zeros(2), d, past, np.array([True, True, False, True]), 2.0)
    assert len(out) == 4 + 2
    np.testing.assert_allclose(out[2], along[1] * d[2])           # in at beam 1's reach
    np.testing.assert_allclose(out[4], past[3] * d[2])            # out at beam 3's reach


def test_the_cells_a_body_swept_are_never_walls():
    true = arenas.Arena.from_polygons(SQUARE, [[[60, 20], [66, 20], [66, 80], [60, 80]]])
    grid = _scanned_grid(true, [(30.0, 50.0)], beams=128)
    at = lambda mask, x, y: bool(mask[int(y), int(x)])                       # cell 1 cm, origin 0
    assert at(grid.obstacle_mask(), 58.5, 50.5) and at(grid.obstacle_mask(dilate=False), 60.5, 50.5)
    body = [[56.0, 40.0], [59.4, 40.0], [59.4, 60.0], [56.0, 60.0]]          # beside the wall, as a car's
    grid.sweep([body])
    believed = grid.obstacle_mask()
    assert not believed[40:60, 56:59].any() and grid.visited[40:60, 56:59].all()
    assert believed[40:60, 59:62].any() and believed[20:40, 58].any()       # the wall itself stays


def test_the_car_passes_a_gap_its_believed_walls_close_and_keeps_its_corridor_free():
    """The true walls leave a 12 cm gap; the car's believed walls close it at its 4 cm
    clearance once it has seen them. It drives through on its scanned walls (logged, for
    the video), and every cell under its body on the way stays free in its grid."""
    from reciprocity.platforms.car import SWEEP_MARGIN, make_car_platform
    from reciprocity.worlds import PoissonWorld
    from arenas.car import car_footprint
    true = arenas.Arena.from_polygons(BOX, GAP_WALLS, name="gap", source=(85.0, 30.0), strength=500.0)
    world = PoissonWorld(true, h=1.5, believed=arenas.Arena.from_polygons(BOX, name="gap"),
                         lidar={"beams": 64, "range": 40.0, "noise": 0.5})
    car = make_car_platform(world, px_per_mm=0.5)
    car.reset([20.0, 30.0, 0.0], world, np.random.default_rng(3))
    target = np.array([80.0, 30.0])
    car.execute(Measure(target))
    log = car.step_log()
    assert np.hypot(*(log["true_poses"][-1][:2] - target)) < car.options.stop_tol + 1.5
    assert car.scanned_plans >= 1 and car.summary()["scanned_plans"] == car.scanned_plans
    assert any("scanned walls" in e["text"] for e in log["events"])
    assert [m["walls"] for m in log["maps"]][-1] == "scanned" and log["maps"][-1]["obstacles"]
    assert len(car.testbed.car.collisions) == 0
    spec, grid = car.testbed.spec, car.grid
    mask = grid.obstacle_mask()
    for pose in log["estimated_poses"][::5]:
        body = car_footprint(pose, spec.length - 2 * SWEEP_MARGIN, spec.width - 2 * SWEEP_MARGIN)
        inside = arenas.Arena.from_polygons(body).contains(grid.centres().reshape(-1, 2)).reshape(mask.shape)
        assert grid.visited[inside].all() and not mask[inside].any()


def test_a_refused_target_is_remembered_until_the_walls_near_it_go():
    true = arenas.Arena.from_polygons(SQUARE, [[[60, 20], [66, 20], [66, 80], [60, 80]]])
    keeper = MapKeeper(arenas.Arena.from_polygons(SQUARE), {"beams": 64, "range": 40.0, "noise": 0.5})
    lidar, rng = Lidar(beams=128, range=40.0, noise=0.5), np.random.default_rng(0)
    for y in (40.0, 50.0, 60.0):
        scan = lidar.scan(true, (45.0, y, 0.0), rng)
        keeper.grid.update((45.0, y), scan.angles, scan.ranges, scan.hit, scan.max_range)
    assert keeper.refuse([75.0, 50.0], 3.0) == 3.0
    assert [(p.tolist(), r) for p, r in keeper.refused()] == [([75.0, 50.0], 3.0)]
    scan = lidar.scan(true, (45.0, 30.0, 0.0), rng)                      # more walls seen: still refused
    keeper.grid.update((45.0, 30.0), scan.angles, scan.ranges, scan.hit, scan.max_range)
    assert len(keeper.refused()) == 1
    keeper.grid.sweep([[[55, 45], [62, 45], [62, 46], [55, 46]]])       # a few cm² of wall gone: still refused
    assert len(keeper.refused()) == 1
    keeper.grid.sweep([[[55, 46], [62, 46], [62, 52], [55, 52]]])       # a way through: tried again
    assert keeper.refused() == []


def test_refusals_that_cluster_keep_a_growing_region_out():
    keeper = MapKeeper(arenas.Arena.from_polygons(SQUARE), {"beams": 64, "range": 40.0, "noise": 0.5})
    radii = [keeper.refuse(p, 3.0) for p in ([70, 70], [74, 70], [80, 72], [60, 60], [20, 20], [90, 90])]
    assert radii == [3.0, 6.0, 12.0, 20.0, 3.0, 20.0]          # doubled near earlier ones, up to range / 2


def test_a_target_the_platform_refused_stays_out_of_reach_after_a_remesh():
    """``_remesh`` rebuilds the reachable set on the new mesh; the neighbourhoods of the
    targets the platform refused are taken out of it again."""
    from reciprocity.env.rollout import Rollout
    env = SearchEnv("deep_u", world={"map": "unknown"})
    agent = StrategyAgent(STRATEGIES["reciprocity"], {"h": 2.0})
    run = Rollout(env, agent)
    run.start(0)
    for _ in range(2):
        run.advance(agent.act())
    strat = agent.strategy
    assert not strat.done and strat.mapping.revision >= 1
    point = strat.space.points[np.flatnonzero(strat.reachability.reachable)[len(np.flatnonzero(strat.reachability.reachable)) // 2]].copy()
    strat.reject(Measure(point), point, "behind a gap narrower than twice the clearance")
    around = lambda: strat.space.around(point, max(0.5 * strat.d, strat.solver.h))
    assert around().any() and not strat.reachability.reachable[around()].any()
    strat._remesh(strat._here)
    assert around().any() and not strat.reachability.reachable[around()].any()
    strat.mapping._refused.clear()                                        # forgotten: reachable again
    strat._remesh(strat._here)
    assert strat.reachability.reachable[around()].any()
