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
