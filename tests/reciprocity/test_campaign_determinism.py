"""The same seed gives the same episode JSON: run twice, on one worker and on two."""

import json

import duckdb
import pytest

from reciprocity.campaign import parse_spec, run_campaign
from reciprocity.campaign.store import episodes_sql
from reciprocity.campaign.worker import run_task

# three world kinds with random parts drawn from the seed: otto's drawn source, a new
# random lattice per seed, a filament plume
SPEC = {"name": "det", "seed": 5, "seeds": 2, "pairs": "supported",
        "strategies": {"random-walk": {"n_steps": 5}, "infotaxis": {}, "surge-cast": {}},
        "scenarios": ["otto-2d", "ristic-lattice", "farrell"]}


def _timing(key: str) -> bool:
    """Keys that measure the computer, not the episode."""
    return "wall_time" in key


def _json(row: dict) -> str:
    return json.dumps({k: v for k, v in row.items() if not _timing(k)}, sort_keys=True,
                      default=lambda x: x.tolist() if hasattr(x, "tolist") else str(x))


def _episodes(directory) -> dict[str, str]:
    """Episode id -> the row as JSON, without timing keys."""
    cur = duckdb.connect().execute(f"SELECT * FROM {episodes_sql(directory)}")
    names = [d[0] for d in cur.description]
    out = {}
    for values in cur.fetchall():
        row = dict(zip(names, values))
        assert row["error_message"] is None, row["error_message"]
        out[row["episode_id"]] = _json(row)
    return out


@pytest.fixture(scope="module")
def spec():
    return parse_spec(SPEC)


@pytest.mark.slow
def test_episode_json_is_the_same_across_runs_and_worker_counts(spec, tmp_path):
    one = run_campaign(spec, tmp_path / "one", workers=1, progress=False)
    two = run_campaign(spec, tmp_path / "two", workers=2, progress=False)
    assert one.n_run == two.n_run == spec.n_episodes == 10
    a, b = _episodes(tmp_path / "one"), _episodes(tmp_path / "two")
    assert len(a) == 10 and a == b
    assert len({json.loads(r)["seed"] for r in a.values()}) == 2      # two seeds, shared


def test_an_episode_run_twice_in_one_process_gives_the_same_summary(spec):
    for task in list(spec.tasks())[::3]:
        first, second = run_task(task), run_task(task)
        assert first["error_message"] is None
        assert _json(first) == _json(second)
