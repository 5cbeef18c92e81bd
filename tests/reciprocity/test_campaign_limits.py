"""Campaign commands refuse bad numbers, addresses and output folders before any work, and
a report reads only the campaign's own files."""

import os
import pathlib
import shutil

import duckdb
import numpy as np
import pytest

from reciprocity.campaign import ResultStore, build_report, parse_spec
from reciprocity.campaign.cluster import max_workers
from reciprocity.campaign.store import episodes_sql, result_files
from reciprocity.cli import main

SPEC_TEXT = "strategies: [reciprocity]\nscenarios: [empty]\nseeds: 2\n"


@pytest.fixture
def spec_file(tmp_path):
    f = tmp_path / "c.yaml"
    f.write_text(SPEC_TEXT)
    return f


def _exit_2_one_line(capsys, argv, match: str) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    assert match in err, err
    return err


@pytest.mark.parametrize("flags, match", [
    (["--workers", "100000"], f"--workers: must be a whole number from 1 to {max_workers()}; got '100000'"),
    (["--workers", "0"], "--workers: must be a whole number from 1"),
    (["--workers", "two"], "--workers: must be a whole number from 1"),
    (["--seed", "-3"], "--seed: must be a whole number from 0 to 9223372036854775807"),
    (["--scheduler", "nowhere"], "tcp://HOST:PORT, tls://HOST:PORT, inproc://... or HOST:PORT"),
    (["--scheduler", "tcp://127.0.0.1:99999"], "port 1 to 65535"),
    (["--scheduler", "tls://127.0.0.1:8786"], "needs TLS files: --tls-ca-file, --tls-cert and --tls-key"),
    (["--tls-cert", "c.pem"], "give --tls-ca-file, --tls-cert and --tls-key together"),
    (["--workers", "1", "--tls-ca-file", "a", "--tls-cert", "b", "--tls-key", "c"],
     "TLS files apply to a tls:// scheduler"),
    (["--scheduler", "tcp://127.0.0.1:8786", "--tls-ca-file", "a", "--tls-cert", "b",
      "--tls-key", "c"], "is not tls://"),
    (["--scheduler", "tls://127.0.0.1:8786", "--tls-ca-file", "missing.pem", "--tls-cert", "b",
      "--tls-key", "c"], "cannot read --tls-ca-file 'missing.pem'"),
])
def test_campaign_flags_are_bounded_before_any_work(tmp_path, capsys, spec_file, flags, match):
    out = tmp_path / "out"
    _exit_2_one_line(capsys, ["campaign", str(spec_file), "--out", str(out), "--quiet", *flags], match)
    assert not out.exists()


@pytest.mark.parametrize("runs", ["0", "100001", "1000000000"])
def test_reproduce_runs_are_bounded(tmp_path, capsys, runs):
    out = tmp_path / "r"
    _exit_2_one_line(capsys, ["reproduce", "landa2020-testbed", "--runs", runs, "--out", str(out)],
                     f"--runs: must be a whole number from 1 to 100000; got '{runs}'")
    assert not out.exists()


def test_output_folders_are_checked_before_any_work(tmp_path, capsys, spec_file, campaign_dir):
    afile = tmp_path / "afile"
    afile.write_text("x")
    _exit_2_one_line(capsys, ["campaign", str(spec_file), "--out", str(afile)], "is a file; give a folder")
    _exit_2_one_line(capsys, ["campaign", str(spec_file), "--out", "/proc/no/such"], "cannot write into")
    _exit_2_one_line(capsys, ["reproduce", "landa2020-testbed", "--out", str(afile / "x")],
                     "afile' is a file, so no folder can be made there")
    _exit_2_one_line(capsys, ["report", str(campaign_dir), "--out", str(afile)], "is a file")
    assert not (campaign_dir / "report").exists()
    # a folder that already holds other things is not taken for a campaign's
    other = tmp_path / "other"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    _exit_2_one_line(capsys, ["campaign", str(spec_file), "--out", str(other), "--quiet"],
                     "holds other files and no campaign.json")
    assert [p.name for p in other.iterdir()] == ["notes.txt"]


def _row(i):
    return {"campaign": "c", "episode_id": f"empty/reciprocity/{i}", "scenario": "empty",
            "variant": "reciprocity", "seed_index": i, "strategy": "reciprocity", "arena": "empty",
            "seed": 11, "source": np.array([1.0, 2.0]), "error": 0.5, "n_samples": 4,
            "steps": 3, "success": True, "converged": True, "error_message": None}


@pytest.fixture
def campaign_dir(tmp_path):
    """A campaign folder with two rows, and stray Parquet files a report must not read."""
    d = tmp_path / "camp"
    spec = parse_spec({"strategies": ["reciprocity"], "scenarios": ["empty"], "seeds": 2})
    with ResultStore.open(d, spec) as store:
        (part,) = store.write([_row(0), _row(1)])
    for stray in (d / "stray" / "x.parquet",                                   # not a partition
                  part.parent / "nested" / "part-0123456789abcdef.parquet",    # below one
                  d / "scenario=maze" / "strategy=gradient" / part.name):      # not of the spec
        stray.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(part, stray)
    (part.parent / "part-fedcba9876543210.parquet").symlink_to(part)           # not a file
    return d


def test_report_reads_only_the_campaigns_own_files(campaign_dir, tmp_path, capsys):
    (part,) = result_files(campaign_dir)
    assert part.parent == campaign_dir / "scenario=empty" / "strategy=reciprocity"
    assert [r["runs"] for r in build_report(campaign_dir).summary] == [2]
    n = duckdb.connect().execute(f"SELECT count(*) FROM {episodes_sql(campaign_dir)}").fetchone()
    assert n == (2,)
    assert main(["report", str(campaign_dir), "--out", str(tmp_path / "rep")]) == 0
    assert "| empty | reciprocity | 2 |" in capsys.readouterr().out


@pytest.mark.parametrize("folder", ["/", "."])
def test_report_of_a_folder_without_campaign_json_never_walks_it(monkeypatch, capsys, folder):
    def walk(*args, **kwargs):
        raise AssertionError("the file system was walked")
    for name in ("glob", "rglob", "iterdir"):
        monkeypatch.setattr(pathlib.Path, name, walk)
    for name in ("walk", "scandir", "listdir"):
        monkeypatch.setattr(os, name, walk)
    _exit_2_one_line(capsys, ["report", folder], "is not a campaign folder: it has no campaign.json")


def test_a_damaged_campaign_json_is_one_line(tmp_path, capsys):
    (tmp_path / "campaign.json").write_text('{"spec": {"scenarios": [{"label": "../../etc"}], '
                                            '"strategies": {}}}')
    _exit_2_one_line(capsys, ["report", str(tmp_path)], "names partition '../../etc', not a label")
    (tmp_path / "campaign.json").write_text("[1, 2")
    _exit_2_one_line(capsys, ["report", str(tmp_path)], "is damaged")
