"""`reciprocity campaign` killed with SIGKILL mid-way and started again: every episode is
stored exactly once (none lost, none repeated)."""

import os
import signal
import subprocess
import sys
import time

import duckdb
import pytest

from reciprocity.campaign import load_spec
from reciprocity.campaign.store import episodes_sql, result_files

#: A safety net against a hung subprocess only, never a performance bound: the resumed
#: campaign's work is bounded by its 80 episodes.
HANG_S = 600

# a new random lattice per seed (~0.1 s an episode): 80 episodes outlast the driver's
# first 5-second batch, so the kill lands between batches
SPEC = """\
name: resume
seed: 11
seeds: 40
strategies: {random-walk: {n_steps: [4, 8]}}
scenarios: [ristic-lattice]
"""


def _command(spec, out) -> list[str]:
    return [sys.executable, "-m", "reciprocity.cli", "campaign", str(spec), "--out", str(out),
            "--workers", "1", "--quiet"]


@pytest.mark.slow
def test_a_killed_campaign_command_resumes_with_no_episode_lost_or_repeated(tmp_path):
    spec = tmp_path / "resume.yaml"
    spec.write_text(SPEC)
    out = tmp_path / "out"
    proc = subprocess.Popen(_command(spec, out), start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 600  # a safety net against a hang, not a speed check
        while not (out / "campaign.json").exists() or not result_files(out):
            assert proc.poll() is None, "the driver ended before its first batch"
            assert time.monotonic() < deadline, "no batch written in 10 minutes"
            time.sleep(0.05)
        os.kill(proc.pid, signal.SIGKILL)        # the driver dies mid-campaign
        proc.wait()
    finally:
        os.killpg(proc.pid, signal.SIGKILL)      # its orphaned Dask worker processes
    con = duckdb.connect()
    before = con.execute(f"SELECT count(*) FROM {episodes_sql(out)}").fetchone()[0]
    assert 0 < before < 80

    again = subprocess.run(_command(spec, out), capture_output=True, text=True, timeout=HANG_S)
    assert again.returncode == 0, again.stderr
    assert f"{80 - before} episodes run (0 failed), {before} already in" in again.stdout

    rows = con.execute(f"""SELECT strategy, scenario, variant, seed_index, count(*) AS n
                           FROM {episodes_sql(out)} GROUP BY ALL""").fetchall()
    assert {n for *_, n in rows} == {1}                                  # 0 repeated
    expected = {(t.variant.strategy, t.scenario.label, t.variant.label, t.seed_index)
                for t in load_spec(spec).tasks()}
    assert {tuple(r[:4]) for r in rows} == expected and len(expected) == 80   # 0 lost
