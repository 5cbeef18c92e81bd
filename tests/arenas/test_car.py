"""The pymunk micro-car: kinematics, noise, walls, determinism and validation."""

import math

import numpy as np
import pytest
from angles import angle_diff
from shapely.geometry import Polygon

import arenas
from arenas import ArenaError
from arenas.car import WALL_RADIUS, Car, CarSpec

QUIET = CarSpec(steer_noise=0.0, speed_noise=0.0)


@pytest.fixture(scope="module")
def empty():
    return arenas.load("empty")


def test_straight_run_covers_speed_times_time(empty):
    car = Car(empty, QUIET)
    car.reset((20.0, 70.0, 0.0), np.random.default_rng(0))
    car.drive(0.0, 1, 2.0)
    x, y, th = car.pose
    # a first-order speed servo from rest lags by its time constant
    expected = QUIET.speed * (2.0 - QUIET.servo_tau)
    assert abs(x - 20.0 - expected) < QUIET.speed * QUIET.dt
    assert abs(x - 20.0 - 20.0) < 1.0
    assert abs(y - 70.0) < 1e-9 and abs(angle_diff(th, 0.0)) < 1e-9
    assert car.time == pytest.approx(2.0, abs=1e-9)
    assert car.odometer == pytest.approx(x - 20.0, rel=1e-9)
    assert car.velocity[0] == pytest.approx(QUIET.speed, rel=1e-6)


def _fit_circle(points):
    a = np.column_stack([2 * points, np.ones(len(points))])
    b = (points ** 2).sum(axis=1)
    cx, cy, c = np.linalg.lstsq(a, b, rcond=None)[0]
    return np.array([cx, cy]), math.sqrt(c + cx ** 2 + cy ** 2)


@pytest.mark.parametrize("steer", [1.0, -1.0])
def test_full_lock_circle_has_radius_rho(empty, steer):
    car = Car(empty, QUIET)
    car.reset((70.0, 70.0, 0.0), np.random.default_rng(0))
    car.drive(steer, 1, 1.0)  # past the speed transient
    pts = []
    for _ in range(80):
        car.drive(steer, 1, 0.1)
        pts.append(car.pose[:2])
    center, radius = _fit_circle(np.array(pts))
    assert abs(radius - QUIET.rho) < 0.05 * QUIET.rho
    # +1 turns left: the centre is to the left of the initial heading (+x), i.e. above
    assert np.sign(center[1] - 70.0) == np.sign(steer)


def test_default_noise_drifts_a_few_cm_over_50_cm(empty):
    spec = CarSpec()
    car = Car(empty, spec)
    lateral = []
    for seed in range(40):
        car.reset((20.0, 70.0, 0.0), np.random.default_rng(seed))
        car.drive(0.0, 1, 50.0 / spec.speed + spec.servo_tau)
        lateral.append(car.pose[1] - 70.0)
    rms = math.sqrt(np.mean(np.square(lateral)))
    # calibrated to ~2 cm RMS (200 seeds); 40 seeds estimate it within ~+-25 % (2 sigma)
    assert rms > 1.0 and rms < 3.5
    assert np.all(np.abs(lateral) > 0)


def _trajectory(car, seed):
    car.reset((30.0, 30.0, 0.3), np.random.default_rng(seed))
    out = []
    for steer in np.linspace(-1, 1, 21):
        car.drive(steer, 1, 0.25)
        out.append(car.pose)
    return np.array(out)


def test_same_seed_same_trajectory_bit_for_bit(paper):
    car = Car(paper)
    a = _trajectory(car, 7)
    car.drive(0.0, 1, 3.0)  # change the physics state between runs
    b = _trajectory(car, 7)
    c = _trajectory(Car(paper), 7)
    d = _trajectory(car, 8)
    assert np.array_equal(a, b) and np.array_equal(a, c)
    assert not np.allclose(a, d)


def _inside(car, tol):
    return car._free.buffer(tol).contains(Polygon(car.footprint()))


def test_wall_stops_the_car_and_is_recorded(paper):
    car = Car(paper)
    car.reset((70.0, 8.0, 1.5 * math.pi), np.random.default_rng(3))  # heading down, wall y = 0
    for _ in range(60):
        car.drive(0.0, 1, 0.1)
        assert _inside(car, 0.05)
    assert car.pose[1] > QUIET.length / 2 - 0.05
    assert len(car.collisions) == 1
    hit = car.collisions[0]
    assert hit["shape"] == "wall" and hit["index"] == -1
    assert abs(hit["y"]) < WALL_RADIUS + 0.05
    # reaching the wall from y = 8 takes about (8 - 3.5) / speed seconds
    assert 0.3 < hit["time"] < 0.7
    assert set(hit) == {"time", "x", "y", "shape", "index"}


def test_obstacle_contact_names_the_obstacle_and_sliding_is_one_contact(paper):
    car = Car(paper)
    # above the L's horizontal arm (top edge y = 20), heading down and a little left
    car.reset((33.0, 30.0, 1.5 * math.pi - 0.5), np.random.default_rng(4))
    for _ in range(40):
        car.drive(0.0, 1, 0.1)
        assert _inside(car, 0.05)
    obstacle_hits = [c for c in car.collisions if c["shape"] == "obstacle"]
    assert len(obstacle_hits) == 1 and obstacle_hits[0]["index"] == 1
    assert abs(obstacle_hits[0]["y"] - 20.0) < 0.2


def test_reverse_drives_backwards(empty):
    car = Car(empty, QUIET)
    car.reset((70.0, 70.0, math.pi / 2), np.random.default_rng(0))
    car.drive(0.0, -1, 1.0)
    x, y, th = car.pose
    assert abs(x - 70.0) < 1e-9
    assert abs(70.0 - y - QUIET.speed * (1.0 - QUIET.servo_tau)) < QUIET.speed * QUIET.dt
    assert abs(angle_diff(th, math.pi / 2)) < 1e-9
    assert car.velocity[0] < 0 and car.odometer > 0


def test_stop_brings_the_car_to_rest(empty):
    car = Car(empty)
    car.reset((30.0, 70.0, 0.0), np.random.default_rng(1))
    car.drive(0.5, 1, 1.0)
    car.drive(0.5, 0, 1.0)
    assert np.all(np.abs(car.velocity) < 1e-6)
    before = car.pose
    car.drive(-1.0, 0, 1.0)
    assert np.allclose(car.pose, before, atol=1e-6)


def test_duration_rounds_up_to_whole_steps(empty):
    car = Car(empty)
    car.reset((30.0, 70.0, 0.0), np.random.default_rng(1))
    car.drive(0.0, 1, 0.0)
    assert car.time == 0.0
    car.drive(0.0, 1, 0.1)  # exactly 12 steps of 1/120 s, not 13
    assert car.time == pytest.approx(12 / 120)
    car.drive(0.0, 1, 0.001)  # a fraction of a step is one step
    assert car.time == pytest.approx(13 / 120)


@pytest.mark.parametrize("steer, direction, duration", [
    (1.5, 1, 1.0), (float("nan"), 1, 1.0), ("left", 1, 1.0), (0.0, 2, 1.0), (0.0, 0.5, 1.0),
    (0.0, True, 1.0), (0.0, 1, -0.1), (0.0, 1, float("inf")),
])
def test_bad_commands_raise(empty, steer, direction, duration):
    car = Car(empty)
    car.reset((30.0, 70.0, 0.0), np.random.default_rng(1))
    with pytest.raises(ArenaError):
        car.drive(steer, direction, duration)


def test_bad_set_up_raises(paper):
    car = Car(paper)
    with pytest.raises(ArenaError, match="reset"):
        car.drive(0.0, 1, 1.0)
    with pytest.raises(ArenaError, match="reset"):
        _ = car.pose
    with pytest.raises(ArenaError, match="wall"):
        car.reset((70.0, 1.0, 0.0), np.random.default_rng(0))
    with pytest.raises(ArenaError, match="outside"):
        car.reset((-10.0, 70.0, 0.0), np.random.default_rng(0))
    with pytest.raises(ArenaError, match="pose"):
        car.reset((70.0, 70.0), np.random.default_rng(0))
    with pytest.raises(ArenaError, match="Generator"):
        car.reset((70.0, 70.0, 0.0), 42)
    with pytest.raises(ArenaError, match="speed"):
        CarSpec(speed=-1.0)
    with pytest.raises(ArenaError, match="steer_noise"):
        CarSpec(steer_noise=float("nan"))
    with pytest.raises(ArenaError, match="Arena"):
        Car("paper")


def test_builtin_starts_are_valid_car_poses():
    for name in arenas.builtin_names():
        arena = arenas.load(name)
        Car(arena).reset(arena.start, np.random.default_rng(0))
