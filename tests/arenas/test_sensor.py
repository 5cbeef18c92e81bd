"""The reflectance sensor and its Fig. 3 calibration."""

import json

import matplotlib
import numpy as np
import pytest

from arenas import ArenaError
from arenas.floor import Floor, GreyMapping
from arenas.sensor import CALIBRATION_GREYS, AdcCurve, Calibration, ReflectanceSensor

matplotlib.use("Agg")

SIGMA = 12.0


def uniform_floor(grey: int) -> Floor:
    return Floor(np.full((200, 200), grey, np.uint8), 10.0, (0.0, 0.0), GreyMapping(100.0))


@pytest.fixture(scope="module")
def calibration():
    return ReflectanceSensor().calibrate(np.random.default_rng(7))


# ---------------------------------------------------------------- ADC curve
def test_curve_rises_below_the_knee_and_is_flat_above():
    c = AdcCurve()
    g = np.arange(0.0, 256.0)
    v = c(g)
    assert np.all(np.diff(v) > 0)
    assert v[0] == pytest.approx(110.0) and c(185.0) == pytest.approx(690.0, abs=6.0)
    assert abs(c(255.0) - c(200.0)) < 1.0
    assert np.all(np.diff(v[200:]) < 0.05)
    assert np.all(np.diff(v[:180]) > 2.0)  # good discrimination in the working range


def test_curve_rejects_non_monotone_parameters():
    with pytest.raises(ArenaError, match="curvature"):
        AdcCurve(curvature=1.5)
    with pytest.raises(ArenaError, match="black"):
        AdcCurve(black=800.0)


# ---------------------------------------------------------------- sensor
def test_position_rotates_with_heading():
    s = ReflectanceSensor(offset=(2.0, 1.0))
    poses = np.array([[10.0, 20.0, 0.0], [10.0, 20.0, np.pi / 2], [10.0, 20.0, np.pi]])
    assert np.allclose(s.position(poses), [[12.0, 21.0], [9.0, 22.0], [8.0, 19.0]])
    assert s.position([0.0, 0.0, 0.0]).shape == (1, 2)
    with pytest.raises(ArenaError, match="shape"):
        s.position([[1.0, 2.0]])


def test_read_noise_matches_sigma():
    n = 4000
    s = ReflectanceSensor()
    counts = s.read_grey(np.full(n, 100.0), np.random.default_rng(3))
    assert counts.dtype.kind == "i" and counts.shape == (n,)
    assert abs(counts.std(ddof=1) - SIGMA) < 4 * SIGMA / np.sqrt(2 * n)
    assert abs(counts.mean() - AdcCurve()(100.0)) < 4 * SIGMA / np.sqrt(n)


def test_read_on_a_floor_and_seeding():
    s = ReflectanceSensor()
    f = uniform_floor(120)
    poses = np.tile([10.0, 10.0, 1.0], (500, 1))
    a = s.read(f, poses, np.random.default_rng(5))
    b = s.read(f, poses, np.random.default_rng(5))
    assert np.array_equal(a, b)
    assert abs(a.mean() - AdcCurve()(120.0)) < 4 * SIGMA / np.sqrt(len(a))
    assert s.read(f, [10.0, 10.0, 0.0], np.random.default_rng(0)).shape == (1,)


def test_read_sees_the_spot_under_the_offset():
    img = np.zeros((200, 200), np.uint8)
    img[:, 110:] = 180  # x >= 11 cm is light
    f = Floor(img, 10.0, (0.0, 0.0), GreyMapping(100.0))
    s = ReflectanceSensor(noise=0.0)
    rng = np.random.default_rng(0)
    facing_light, facing_dark = s.read(f, [[10.0, 10.0, 0.0], [10.0, 10.0, np.pi]], rng)
    assert facing_light == round(float(AdcCurve()(180.0)))
    assert facing_dark == round(float(AdcCurve()(0.0)))


def test_read_counts_are_clipped_and_errors_are_clear():
    s = ReflectanceSensor(noise=5000.0)
    c = s.read_grey(np.full(1000, 100.0), np.random.default_rng(0))
    assert c.min() == 0 and c.max() == 1023
    with pytest.raises(ArenaError, match="Generator"):
        s.read_grey([100.0], 3)
    with pytest.raises(ArenaError, match="off the floor"):
        s.read(uniform_floor(100), [50.0, 50.0, 0.0], np.random.default_rng(0))
    with pytest.raises(ArenaError, match="noise"):
        ReflectanceSensor(noise=-1.0)


def test_counts_monotone_below_knee_and_flat_above():
    s = ReflectanceSensor(noise=0.0)
    rng = np.random.default_rng(0)
    below = s.read_grey(np.arange(0.0, 186.0), rng)
    assert np.all(np.diff(below) >= 0) and below[-1] - below[0] > 500
    above = s.read_grey(np.arange(200.0, 256.0), rng)
    assert above.max() - above.min() <= 1


# ---------------------------------------------------------------- calibration
def test_calibration_shape_and_pooled_noise(calibration):
    cal = calibration
    assert np.array_equal(cal.greys, CALIBRATION_GREYS) and cal.samples == 30
    assert cal.knee == 185.0
    dof = len(cal.greys) * (cal.samples - 1)
    assert abs(cal.noise - SIGMA) < 4 * SIGMA / np.sqrt(2 * dof)


def test_calibration_recovers_grey_on_the_working_range(calibration):
    curve = AdcCurve()
    g = np.linspace(0.0, 185.0, 371)
    slope = np.gradient(curve(g), g)
    err = np.abs(calibration.grey(curve(g)) - g)
    # a patch mean has standard error sigma / sqrt(samples) counts, i.e. that / slope greys
    assert np.all(err <= 4.5 * SIGMA / np.sqrt(calibration.samples) / slope)


def test_calibrated_grey_is_monotone_and_bounded(calibration):
    counts = np.arange(0, 1024)
    g = calibration.grey(counts)
    assert np.all(np.diff(g) >= 0)
    assert g[0] == 0.0 and g[-1] == 185.0
    assert calibration.grey(5) == 0.0


def test_saturation_flags(calibration):
    curve = AdcCurve()
    assert calibration.saturated(curve([200.0, 230.0, 255.0])).all()
    assert not calibration.saturated(curve([0.0, 100.0, 150.0])).any()
    # averaging narrows the margin: a reading just below the plateau is flagged alone only
    just_below = calibration.knee_counts - 10.0
    assert calibration.saturated(just_below, n=1) and not calibration.saturated(just_below, n=30)
    # readings on a white patch, averaged in tens, are all flagged
    readings = ReflectanceSensor().read_grey(np.full((200, 10), 255.0), np.random.default_rng(1))
    assert calibration.saturated(readings.mean(axis=1), n=10).all()
    with pytest.raises(ArenaError, match="positive integer"):
        calibration.saturated(600.0, n=0)


def test_intensity_flags_instead_of_clipping(calibration):
    m = GreyMapping(u_max=300.0)
    curve = AdcCurve()
    values, flags = calibration.intensity(curve([100.0, 255.0]), m)
    assert flags.tolist() == [False, True]
    assert values[1] == m.u_max
    assert values[0] == pytest.approx(float(m.signal(100.0)), rel=0.05)


def test_to_dict_round_trip(calibration):
    d = json.loads(json.dumps(calibration.to_dict()))
    back = Calibration.from_dict(d)
    counts = np.linspace(0, 1023, 200)
    assert np.array_equal(back.grey(counts), calibration.grey(counts))
    assert back.noise == calibration.noise and back.knee_counts == calibration.knee_counts
    with pytest.raises(ArenaError, match="keys"):
        Calibration.from_dict({"greys": [0, 1]})


def test_flat_calibration_is_rejected():
    with pytest.raises(ArenaError, match="do not rise"):
        Calibration([0.0, 100.0, 200.0], [500.0, 500.0, 500.0], [1.0, 1.0, 1.0], 30)


def test_fig3_plot_has_the_knee_line(calibration):
    import matplotlib.pyplot as plt

    ax = calibration.plot()
    knee = [ln for ln in ax.get_lines() if "working range" in ln.get_label()]
    assert len(knee) == 1 and list(knee[0].get_xdata()) == [185.0, 185.0]
    assert "grey" in ax.get_xlabel() and "ADC counts" in ax.get_ylabel()
    plt.close(ax.figure)


def test_signal_noise_predicts_the_spread_of_calibrated_dwell_readings():
    """Each trial: a new calibration and one 30-sample dwell at grey 100 of an unquantised
    floor. The spread of the signals over the trials is the calibrated noise without the
    quantisation term, to the sampling error of 300 trials (3.5 % per sigma of a std)
    plus the slope's variation over the working range."""
    sensor, mapping = ReflectanceSensor(), GreyMapping(u_max=290.0)
    rng = np.random.default_rng(11)
    values = []
    for _ in range(300):
        cal = sensor.calibrate(rng)
        counts = sensor.read_grey(np.full(30, 100.0), rng)
        values.append(float(cal.intensity(counts.mean(), mapping, n=30)[0]))
    predicted = np.sqrt(cal.signal_noise(mapping, 30) ** 2 - (1.0 / np.sqrt(12.0) / mapping.slope) ** 2)
    assert np.std(values, ddof=1) == pytest.approx(predicted, rel=0.2)
    assert cal.signal_noise(mapping, 30) < cal.signal_noise(mapping, 1)
    with pytest.raises(ArenaError, match="positive integer"):
        cal.signal_noise(mapping, 0)
