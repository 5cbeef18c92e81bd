"""The campaign, report and reproduce commands: exit codes and one-line errors."""


import pytest

from reciprocity.campaign import dask_client
from reciprocity.cli import main
from reciprocity.errors import SearchError


def _spec(tmp_path, text="strategies: [reciprocity]\nscenarios: [empty]\nseeds: 2\n"):
    f = tmp_path / "c.yaml"
    f.write_text(text)
    return f


@pytest.mark.parametrize("text, match", [
    ("strategies: [nope]\nscenarios: [empty]\nseeds: 2\n", "unknown strategy 'nope'"),
    ("strategies: [gradient]\nscenarios: [atlantis]\nseeds: 2\n", "unknown scenario 'atlantis'"),
    ("strategies: {gradient: {d: []}}\nscenarios: [empty]\nseeds: 2\n", "empty grid"),
])
def test_bad_spec_exits_2_before_anything_runs(tmp_path, capsys, text, match):
    out = tmp_path / "out"
    assert main(["campaign", str(_spec(tmp_path, text)), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and match in err and err.count("\n") == 1
    assert not out.exists()


def test_unwritable_out_and_foreign_spec_exit_2(tmp_path, capsys):
    (tmp_path / "file").write_text("x")
    assert main(["campaign", str(_spec(tmp_path)), "--out", str(tmp_path / "file" / "o")]) == 2
    assert "is a file, so no folder can be made there" in capsys.readouterr().err
    (tmp_path / "o").mkdir()
    (tmp_path / "o" / "campaign.json").write_text('{"name": "x", "spec_hash": "abc"}')
    assert main(["campaign", str(_spec(tmp_path)), "--out", str(tmp_path / "o")]) == 2
    assert "different spec" in capsys.readouterr().err


def test_report_and_reproduce_errors_exit_2(tmp_path, capsys):
    assert main(["report", str(tmp_path)]) == 2
    assert "is not a campaign folder: it has no campaign.json" in capsys.readouterr().err
    assert main(["reproduce", "no-such-table"]) == 2
    assert "unknown table 'no-such-table'" in capsys.readouterr().err
    assert main(["reproduce", "landa2020-testbed", "--runs", "0"]) == 2


def test_reproduce_list_names_the_tables(capsys):
    assert main(["reproduce", "--list"]) == 0
    assert "landa2020-testbed" in capsys.readouterr().out


def test_workers_and_scheduler_are_exclusive(tmp_path):
    try:  # a usage error: argparse exits 2 (main may catch and return it)
        rc = main(["campaign", str(_spec(tmp_path)), "--out", str(tmp_path), "--workers", "2",
                   "--scheduler", "tcp://127.0.0.1:1"])
    except SystemExit as exc:
        rc = exc.code
    assert rc == 2


def test_silent_scheduler_fails_fast_with_a_clear_message():
    """The connection is given the timeout asked for (checked by its message, not by the
    wall clock, which a busy machine stretches)."""
    with pytest.raises(SearchError, match="no Dask scheduler answers at 'tcp://127.0.0.1:9' within 1 s"):
        with dask_client(scheduler="tcp://127.0.0.1:9", timeout=1.0):
            pass
