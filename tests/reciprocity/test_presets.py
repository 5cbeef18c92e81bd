"""The reciprocity search as an assembly of parts: presets are named tables of part
settings, every constructor keyword reaches its part, and the strategy reads the parts'
settings as its own (reciprocity.strategies.imaging_search.presets)."""

import inspect

import numpy as np
import pytest

from reciprocity.errors import SearchError
from reciprocity.strategies.imaging_search.presets import DEFAULTS, PARTS, PRESETS, settings
from reciprocity.strategies.reciprocity import PARAM_ORDER, ReciprocityStrategy

#: Keywords the mesh part takes, and the assembly's own.
MESH = {"h", "solver", "source_clearance", "survey"}


def test_every_keyword_has_one_home():
    keywords = set(inspect.signature(ReciprocityStrategy.__init__).parameters) - {"self"}
    homes = set().union(*PARTS.values()) | MESH | {"preset"}
    assert keywords == homes
    assert set(DEFAULTS) <= set().union(*PARTS.values()) and set(PRESETS["paper"]) <= set(DEFAULTS)


def test_settings_default_then_preset_then_given():
    assert settings(None, {})["rule"] == "axis"
    assert settings("paper", {})["rule"] == "nearest" and settings("paper", dict(rule="info"))["rule"] == "info"
    assert settings("paper", dict(eps=None))["eps"] == PRESETS["paper"]["eps"]
    with pytest.raises(SearchError, match=r"preset must be one of \('paper',\) or None; got 'testbed'"):
        settings("testbed", {})


def test_the_strategy_reads_its_parts_settings():
    s = ReciprocityStrategy(preset="paper", sigma=17.0, clearance=2.0, more_tol=0.1, h=2.0)
    assert (s.rule, s.d, s.eps, s.sigma, s.clearance, s.more_tol, s.h) == ("nearest", 12.7, 0.7, 17.0, 2.0, 0.1, 2.0)
    assert s.stop_rule.extent_tol == s.extent_tol == np.inf and s.next_point_rule.rule == s.rule
    assert list(s.params()) == list(PARAM_ORDER) and s.params()["sigma_used"] is None
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        s.nothing


@pytest.mark.parametrize("key, value, message", [
    ("rule", "spiral", "rule must be one of"), ("combine", "max", "combine must be one of"),
    ("eps", 2.0, "eps must lie strictly between 0 and 1"), ("h", -1.0, "h must be a positive number"),
    ("strength_range", "wide", "strength_range must be"), ("max_sources", 0, "max_sources must be"),
    ("source_clearance", "far", "source_clearance must be")])
def test_each_bad_keyword_is_named_by_its_part(key, value, message):
    with pytest.raises(SearchError, match=message):
        ReciprocityStrategy(**{key: value})
