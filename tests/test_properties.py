"""Property tests: a mutated arena, scenario or campaign file gives a valid run or a clean
error, never anything else.

Hypothesis mutates the valid files of the bad-input corpus (``tests/bad_inputs/``: the base
scenario of every world kind, the base arena and the base campaign spec): a key's value
replaced by a value of another type, sign or size (NaN, infinities, 1e308, huge counts,
nested lists and mappings), a number scaled, a list item replaced, a key removed, an
unknown key added, or a key repeated in the text. A mutated scenario or arena file is
then run by the command line (a step cap of 2 keeps a run short); a campaign spec is
parsed and validated (its episodes are not run). The answer must be exit 0, or exit 2
with one ``error:`` line and nothing else; an exception, a hang or a slow answer fails.
Slow and hung are counted in CPU seconds of this process (the work a run does), never by
the wall clock, so that a machine busy with other work cannot fail a test.

The examples are derandomized (the same on every run) and not shrunk, so that the suite
stays fast; a failure prints the file that caused it.
"""

from __future__ import annotations

import contextlib
import io
import string
import time

import pytest
import yaml
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from test_bad_inputs import ANSWER_S, WATCHDOG_S, Hang, _load, _world_bases, watchdog

#: Properties that fail today: test name -> "owner: what happens". Remove a line when its
#: fix lands (the marks are strict).
XFAIL: dict[str, str] = {}

SETTINGS = settings(max_examples=100, deadline=None, derandomize=True, database=None,
                    phases=[Phase.explicit, Phase.reuse, Phase.generate],
                    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])

_words = st.text(string.ascii_letters + "_ -", max_size=6)
_scalars = st.one_of(
    st.none(), st.booleans(), st.integers(-10**13, 10**13),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([1e308, -1e308, 0.0, -0.0, 1e-300, 10**5, 10**6, 10**12, "lots", ""]),
    _words)
_values = st.recursive(_scalars, lambda c: st.lists(c, max_size=4) | st.dictionaries(
    _words, c, max_size=3), max_leaves=8)
_factors = st.sampled_from([-1.0, 0.0, 1e-9, 1e-3, 10.0, 1e3, 1e9, 1e300])


@st.composite
def mutated(draw, base: dict) -> str:
    """The YAML text of `base` after one or two mutations."""
    data = dict(base)
    repeated = []
    for _ in range(draw(st.integers(1, 2))):
        keys = sorted(data)
        how = draw(st.sampled_from(["value", "scale", "item", "drop", "extra", "repeat"]))
        key = draw(st.sampled_from(keys)) if keys else "extra"
        old = data.get(key)
        if how == "value":
            data[key] = draw(_values)
        elif how == "scale" and isinstance(old, (int, float)) and not isinstance(old, bool):
            data[key] = old * draw(_factors)
        elif how == "item" and isinstance(old, list) and old:
            items = list(old)
            items[draw(st.integers(0, len(items) - 1))] = draw(_values)
            data[key] = items
        elif how == "drop":
            data.pop(key, None)
        elif how == "extra":
            data[draw(st.sampled_from(["colour", "Source", "radius", "world2", "seedz"]))] = draw(_values)
        elif how == "repeat":
            repeated.append({key: draw(_values)})
    text = yaml.safe_dump(data, sort_keys=False)
    return text + "".join(yaml.safe_dump(r) for r in repeated)


def _answer(main, argv: list[str]) -> str | None:
    """What is wrong with how `main(argv)` answers (None: a valid run or a clean error)."""
    out, err = io.StringIO(), io.StringIO()
    t0 = time.process_time()
    try:
        with watchdog(WATCHDOG_S), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(argv)
    except Hang:
        return f"no answer within {WATCHDOG_S:g} CPU s"
    except BaseException as exc:
        return f"raised {type(exc).__name__}: {exc}"[:300]
    lines = err.getvalue().strip().splitlines()
    if code == 2 and (len(lines) != 1 or not lines[0].startswith("error: ")):
        return f"exit 2 with stderr {err.getvalue()[:300]!r}"
    if code not in (0, 2):
        return f"exit {code}: {err.getvalue()[:300]!r}"
    if time.process_time() - t0 > ANSWER_S:
        return f"slow ({time.process_time() - t0:.1f} CPU s)"
    return None


def _run_file(tmp_path_factory, text: str, argv: list[str]) -> None:
    from reciprocity.cli import main
    folder = tmp_path_factory.mktemp("prop")
    path = folder / "input.yaml"
    path.write_text(text)
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(folder)
        problem = _answer(main, [a.replace("@F", str(path)) for a in argv])
    assert problem is None, f"{problem}\n--- file:\n{text}"


def _xfail(name: str):
    return [pytest.mark.xfail(strict=True, reason=XFAIL[name])] if name in XFAIL else []


_RUN = {
    "poisson": ["run", "--scenario", "@F", "--strategy", "random-walk", "--h", "5", "--set", "n_steps=2", "--quiet"],
    "lattice": ["run", "--scenario", "@F", "--strategy", "random-walk", "--set", "n_steps=2", "--quiet"],
    "plume": ["run", "--scenario", "@F", "--strategy", "random-walk", "--set", "n_steps=2", "--quiet"],
    "filament": ["run", "--scenario", "@F", "--strategy", "random-walk", "--set", "n_steps=2", "--quiet"],
}


@pytest.mark.parametrize("world", [pytest.param(w, marks=_xfail(f"scenario-{w}")) for w in _RUN])
def test_mutated_scenario_runs_or_fails_cleanly(world, tmp_path_factory):
    @SETTINGS
    @given(text=mutated(_world_bases()[world]))
    def prop(text):
        _run_file(tmp_path_factory, text, _RUN[world])
    prop()


@pytest.mark.parametrize("entry", [pytest.param(e, marks=_xfail(f"arena-{e}")) for e in ("run", "hj-solve")])
def test_mutated_arena_runs_or_fails_cleanly(entry, tmp_path_factory):
    base = _load("arena.yaml")["base"]

    @SETTINGS
    @given(text=mutated(base))
    def prop(text):
        if entry == "run":
            _run_file(tmp_path_factory, text, ["run", "--arena", "@F", "--strategy", "random-walk",
                                               "--h", "5", "--set", "n_steps=2", "--quiet"])
            return
        from hjplanner.cli import main
        folder = tmp_path_factory.mktemp("prop")
        (folder / "arena.yaml").write_text(text)
        problem = _answer(main, ["solve", "--arena", str(folder / "arena.yaml"), "--target", "100,100",
                                 "--rho", "15", "--h", "5", "--ntheta", "8", "--out", str(folder / "v.npz")])
        assert problem is None, f"{problem}\n--- file:\n{text}"
    prop()


@pytest.mark.parametrize("_", [pytest.param(0, marks=_xfail("campaign"), id="campaign")])
def test_mutated_campaign_spec_loads_or_fails_cleanly(_, tmp_path_factory):
    from arenas import ArenaError
    from reciprocity.campaign.spec import load_spec
    from reciprocity.errors import ReciprocityError
    base = _load("campaign.yaml")["base"]
    folder = tmp_path_factory.mktemp("spec")
    for name, data in _world_bases().items():
        (folder / f"{name}.yaml").write_text(yaml.safe_dump(data))

    @SETTINGS
    @given(text=mutated(base))
    def prop(text):
        path = folder / "spec.yaml"
        path.write_text(text)
        try:
            with watchdog(WATCHDOG_S):
                load_spec(path)
        except (ReciprocityError, ArenaError) as exc:
            assert str(exc) and "\n" not in str(exc), f"a message of several lines\n--- file:\n{text}"
        except Hang:
            pytest.fail(f"no answer within {WATCHDOG_S:g} CPU s\n--- file:\n{text}")
        except Exception as exc:
            pytest.fail(f"raised {type(exc).__name__}: {exc}\n--- file:\n{text}"[:2000])
    prop()
