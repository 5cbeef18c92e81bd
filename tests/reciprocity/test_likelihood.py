"""The likelihood part of the reciprocity search: eq. (7)'s sigma, the error terms, the
strength prior (reciprocity.strategies.imaging_search.likelihood)."""

import numpy as np
import pytest

import arenas
from reciprocity.errors import SearchError
from reciprocity.models.green import cached_solver
from reciprocity.strategies.imaging_search.likelihood import (CALIBRATED_MODEL_ERROR, MIN_NOISE, PAPER_NOISE,
                                                              RELATIVE_TERMS, Likelihood)


@pytest.fixture(scope="module")
def solver():
    return cached_solver(arenas.load("empty").without_scenario(), 4.0)


WORLD = dict(strength=850.0, noise=5.0)
CAR = dict(strength=850.0, noise=12.0, reading_noise=2.0, reading_bias=1.2)


@pytest.mark.parametrize("rule, nominal, sigma", [
    ("auto", WORLD, 5.0 * np.sqrt(2.0)), ("noise", WORLD, 5.0), ("calibrated", WORLD, 5.0 * np.sqrt(2.0)),
    ("auto", {}, PAPER_NOISE * np.sqrt(2.0)), ("noise", dict(noise=0.0), MIN_NOISE), (17.0, CAR, 17.0),
    # the car's own noise, less its shared part (imaged as one offset)
    ("calibrated", CAR, np.sqrt(2.0 ** 2 - 1.2 ** 2) * np.sqrt(2.0)), ("auto", CAR, 12.0 * np.sqrt(2.0))])
def test_reading_sigma_follows_its_rule(rule, nominal, sigma):
    assert Likelihood(sigma=rule).reading_sigma(nominal) == pytest.approx(sigma, rel=1e-12)


def test_only_a_calibrated_platform_has_a_shared_offset():
    assert Likelihood().reading_bias(CAR) == 1.2
    assert Likelihood(sigma="auto").reading_bias(CAR) == 0.0 and Likelihood().reading_bias(WORLD) == 0.0


def test_error_terms_estimate_or_fixed(solver):
    terms = Likelihood(strength_error=0.1).error_terms(CAR, 1.2, solver, 4.0)
    assert terms["noise"] == pytest.approx(4.0 / np.sqrt(2.0)) and terms["offset"] == 1.2
    assert terms["platform"] == CALIBRATED_MODEL_ERROR and 0 < terms["discretisation"] < 0.2
    assert terms["strength"] == 0.1 and set(terms) - {"noise", "offset"} <= set(RELATIVE_TERMS)
    fixed = Likelihood(model_error=0.03).error_terms(CAR, 0.0, solver, 4.0)
    assert fixed["fixed"] == 0.03 and "discretisation" not in fixed and "platform" not in fixed


@pytest.mark.parametrize("given, nominal, prior", [
    ("decade", dict(strength=600.0), (60.0, 6000.0)), ("decade", dict(strength=float("nan")), None),
    ("decade", {}, None), ("fit", dict(strength=600.0), None), ((1.0, 5.0), {}, (1.0, 5.0))])
def test_prior_range(given, nominal, prior):
    assert Likelihood(strength=None, strength_range=given).prior_range(nominal) == prior


def test_belief_carries_the_terms_only_where_they_apply(solver):
    b = Likelihood().belief(solver, CAR, 850.0, "product")
    disc = b.error_terms["discretisation"]
    assert b.imaging.model_error == pytest.approx(np.hypot(disc, CALIBRATED_MODEL_ERROR)) == b.model_error
    assert b.imaging.offset_sd == 1.2 and b.strength == 850.0
    mean = Likelihood().belief(solver, CAR, 850.0, "mean")            # eq. (8) has none
    assert mean.error_terms == {} and mean.imaging.model_error == 0.0 and mean.imaging.offset_sd == 0.0
    unknown = Likelihood(strength=None).belief(solver, CAR, 850.0, "product")
    assert unknown.imaging.strength_range == (85.0, 8500.0) and unknown.error_terms == {}
    widened = Likelihood().belief(solver, CAR, 850.0, "product", widen=lambda e: 2 * e)
    assert widened.imaging.model_error == pytest.approx(2 * widened.model_error)


@pytest.mark.parametrize("bad, message", [
    (dict(sigma="wide"), "sigma must be"), (dict(sigma=-1.0), "sigma must be"),
    (dict(strength_range="wide"), "strength_range must be"), (dict(strength_range=(5.0, 1.0)), "lo < hi"),
    (dict(model_error=1.5), "model_error must be"), (dict(strength_error=True), "strength_error must be")])
def test_bad_settings_name_the_key(bad, message):
    with pytest.raises(SearchError, match=message):
        Likelihood(**bad)
