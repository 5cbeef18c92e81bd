"""The directional hit rate of papers/001, eq. (14)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import k0

from reciprocity.models.directional import directional_rate
from reciprocity.models.plume import PlumeParams, plume_rate

P = PlumeParams(rate=2.0, a=1.0, D=1.0, tau=100.0, V=0.5)


def eq14(r, r0, v, p):
    """Eq. (14) as typeset: R / ln(λ/a) exp(V/(2D) (r − r0)·v) K0(|r − r0| / λ)."""
    lam = p.length
    d = r - r0
    return p.rate / np.log(lam / p.a) * np.exp(p.V / (2 * p.D) * d @ v) * k0(np.hypot(*d) / lam)


@pytest.mark.parametrize("heading", [0.0, 0.7, np.pi, 4.0])
def test_printed_sense_reads_eq_14(heading):
    r, r0 = np.array([30.0, 40.0]), np.array([37.0, 31.0])
    v = np.array([np.cos(heading), np.sin(heading)])
    got = directional_rate(r[None], [heading], r0[None], P, sense="printed")[0, 0]
    assert got == pytest.approx(eq14(r, r0, v, P), rel=1e-12)
    toward = directional_rate(r[None], [heading], r0[None], P, sense="toward")[0, 0]
    assert toward == pytest.approx(eq14(r, r0, -v, P), rel=1e-12)


def test_facing_the_source_reads_more_in_the_papers_words():
    r, r0 = np.array([[0.0, 0.0]]), np.array([[10.0, 0.0]])
    facing, away = directional_rate(r, [0.0], r0, P)[0, 0], directional_rate(r, [np.pi], r0, P)[0, 0]
    assert facing > away
    assert facing / away == pytest.approx(np.exp(P.V / P.D * 10.0))


def test_without_flow_the_sensor_has_no_direction():
    calm = PlumeParams(rate=2.0, a=1.0, D=1.0, tau=100.0, V=0.0)
    at, src = np.array([[5.0, 5.0], [50.0, 20.0]]), np.array([[10.0, 12.0], [0.5, 5.0], [5.2, 5.1]])
    for sense in ("toward", "printed"):
        assert directional_rate(at, [0.3, 2.0], src, calm, sense) == pytest.approx(plume_rate(at, src, calm))


def test_unknown_sense_is_refused():
    with pytest.raises(ValueError, match="sense must be one of toward, printed"):
        directional_rate([[0.0, 0.0]], [0.0], [[1.0, 1.0]], P, sense="backward")


# -- the world and its wiring -------------------------------------------------------------
from dataclasses import replace  # noqa: E402

from reciprocity.api import run  # noqa: E402
from reciprocity.errors import SearchError  # noqa: E402
from reciprocity.scenarios import from_dict, load_scenario  # noqa: E402


def test_the_directional_world_reads_more_facing_the_source():
    """Mean hits over n reads, facing the source and facing away, differ as eq. (14) says
    (margin: 5 standard errors of the difference)."""
    w = load_scenario("hajieghrary-directional").build_world(0)
    at, n = w.sources[0] - [6.0, 0.0], 4000
    rng = np.random.default_rng(0)
    facing = np.mean([w.read(at, time=0, dwell=1, rng=rng, course=0.0).value for _ in range(n)])
    away = np.mean([w.read(at, time=0, dwell=1, rng=rng, course=np.pi).value for _ in range(n)])
    exact = [directional_rate(at[None], [c], w.sources, w.truth)[0, 0] for c in (0.0, np.pi)]
    se = np.sqrt((exact[0] + exact[1]) / n)
    assert abs((facing - away) - (exact[0] - exact[1])) < 5 * se and exact[0] > exact[1]
    with pytest.raises(SearchError, match="needs the observer's course"):
        w.read(at, time=0, dwell=1, rng=rng)


def test_the_team_runs_in_the_directional_world_and_the_default_world_has_no_direction():
    sc = replace(load_scenario("hajieghrary-directional"), max_steps=3)
    ep = run(sc, "voi", seed=0, params=dict(preset="paper", basis=40, share="all"))
    assert ep.summary["steps"] == 3
    assert load_scenario("hajieghrary").build_world(0).sense is None
    with pytest.raises(SearchError, match="needs belief='gaussian-basis'"):
        run(sc, "voi", seed=0, params=dict(particles=100))


@pytest.mark.parametrize("keys, match", [
    (dict(sensor="funnel"), "plume sensor must be one of isotropic, directional"),
    (dict(sense="toward"), "plume sense applies only with sensor: directional"),
    (dict(sensor="directional", sense="sideways"), "plume sense must be one of toward, printed"),
])
def test_bad_sensor_keys_are_refused(keys, match):
    base = dict(world="plume", bounds=[0, 50, 0, 50], source=[25, 25], platform="walker", motion="reach")
    with pytest.raises(SearchError, match=match):
        from_dict({**base, **keys}, "bad")
